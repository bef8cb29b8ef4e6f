//! The shell: the prism-like region `{ P(X) + σ·D(X) : X in the triangle, σmin ≤ σ ≤ σmax }` that
//! contains the patch (docs/METHOD.md §2). Its cross-section at height `σ` is the triangle
//! `Ai(σ) = Pi + σ·di`; its side walls are the ruled surfaces `Xi = 0`.
//!
//! # How the height range is bounded
//! The surface height is zero at the vertices, equals the conjugation lines' heights on the
//! edges and is smooth inside. The patch constructor samples it at [`SAMPLES`] fixed points (edge
//! points at `t = 0.1, ¼, ½, ¾, 0.9` and four interior points) and widens the sampled range by
//! [`MARGIN_REL`] of the range plus [`MARGIN_ABS`] of the triangle's size. The margin is
//! validated, not proven: `tests/shell.rs` samples 2000 random well-shaped patches with normals
//! up to 50° from the face on a 861-point grid and checks that every point lies inside, at least
//! [`SHELL_CLEARANCE`](crate::accuracy::SHELL_CLEARANCE) of the range's width away from its
//! faces. Beyond about 55° the surface itself can become wild (the
//! nearest sphere roots switch branches, docs/METHOD.md §7) and may leave the shell: that is outside
//! the method's domain and is measured in the reliability study (`tests/domain.rs`). Even below
//! 50° the construction has rare isolated spikes where a sphere root switches branch (2 in
//! 7.8·10⁵ random patches with normals ≤ 50°, `tests/robustness.rs`); no sampling bound can
//! contain those, and rays may miss the spike.

use crate::aabb::Aabb;
use crate::edge::edge_point;
use crate::geometry::{Frame, Shape};
use crate::real::Float;
use crate::surface::height;
use crate::vec::V3;

/// Number of surface samples used to bound the height range.
pub const SAMPLES: usize = 19;
/// Relative widening of the sampled height range (fraction of its width).
pub const MARGIN_REL: f64 = 0.5;
/// Absolute widening as a fraction of the triangle's longest edge.
pub const MARGIN_ABS: f64 = 1e-4;

/// Conservative `[σmin, σmax]` of the surface of `shape`.
pub(crate) fn height_bounds<F: Float>(shape: &Shape<F>) -> [F; 2] {
    let mut lo = F::ZERO;
    let mut hi = F::ZERO;
    let mut acc = |h: F| {
        lo = lo.min(h);
        hi = hi.max(h);
    };
    for j in 0..3 {
        for t in [0.1, 0.25, 0.5, 0.75, 0.9] {
            acc(edge_point::<F>(&shape.edge(j), F::from_f64(t)).0.z);
        }
    }
    let a = F::from_f64(2.0 / 3.0);
    let b = F::from_f64(1.0 / 6.0);
    let c = F::from_f64(1.0 / 3.0);
    for x in [[a, b, b], [b, a, b], [b, b, a], [c, c, c]] {
        acc(height(shape, x));
    }
    let size = longest_edge(shape);
    let m = F::from_f64(MARGIN_REL) * (hi - lo) + F::from_f64(MARGIN_ABS) * size;
    [lo - m, hi + m]
}

/// Longest edge of the triangle.
pub(crate) fn longest_edge<F: Float>(shape: &Shape<F>) -> F {
    let [p0, p1, p2] = shape.p;
    (p1 - p0)
        .length2()
        .max((p2 - p1).length2())
        .max((p0 - p2).length2())
        .sqrt()
}

/// Twice the signed area of the cross-section triangle `A(σ)`, as the coefficients of the
/// quadratic `c0 + c1·σ + c2·σ²`.
pub(crate) fn section_area_poly<F: Float>(shape: &Shape<F>) -> [F; 3] {
    let [p0, p1, p2] = shape.p;
    let [d0, d1, d2] = shape.d;
    let (u0, u1) = (p1 - p0, d1 - d0);
    let (v0, v1) = (p2 - p0, d2 - d0);
    cross2_poly(u0, u1, v0, v1)
}

/// Coefficients of `cross2(u0 + t·u1, v0 + t·v1)` (the z-component of the 2D cross product).
#[inline(always)]
pub(crate) fn cross2_poly<F: Float>(u0: V3<F>, u1: V3<F>, v0: V3<F>, v1: V3<F>) -> [F; 3] {
    let c = |a: V3<F>, b: V3<F>| a.x * b.y - a.y * b.x;
    [c(u0, v0), c(u0, v1) + c(u1, v0), c(u1, v1)]
}

/// The shell of `shape` over the height range `sigma` is valid when its cross-section keeps at
/// least a quarter of the triangle's area (same orientation) over the whole range.
pub(crate) fn is_valid<F: Float>(shape: &Shape<F>, sigma: [F; 2]) -> bool {
    let [c0, c1, c2] = section_area_poly(shape);
    let [lo, hi] = sigma;
    let eval = |s: F| c0 + s * (c1 + s * c2);
    let mut m = eval(lo).min(eval(hi));
    if c2 != F::ZERO {
        let v = -c1 / (c2 + c2);
        if v > lo && v < hi {
            m = m.min(eval(v));
        }
    }
    m >= F::from_f64(0.25) * c0 && c0 > F::ZERO
}

/// Axis-aligned box of the six corners of the shell of `shape` over the height range `sigma`,
/// world coordinates (`frame` maps the local frame to them).
pub(crate) fn aabb<F: Float>(shape: &Shape<F>, sigma: [F; 2], frame: &Frame<F>) -> Aabb<F> {
    let [lo_s, hi_s] = sigma;
    let mut b = Aabb::EMPTY;
    for (p, d) in shape.p.iter().zip(shape.d.iter()) {
        for s in [lo_s, hi_s] {
            b = b.grow(frame.local_to_world(*p + *d * s));
        }
    }
    // Widen by a few ulps of the box so rounding of the frame cannot exclude a surface point.
    let (lo, hi) = (b.lo, b.hi);
    let pad = |a: F, b: F| (a.abs().max(b.abs())) * F::from_f64(8.0) * F::EPSILON;
    let e = V3::new(pad(lo.x, hi.x), pad(lo.y, hi.y), pad(lo.z, hi.z));
    Aabb::from_corners(lo - e, hi + e)
}
