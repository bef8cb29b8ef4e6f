//! The shell: the prism-like region `{ P(X) + σ·D(X) : X in the triangle, σmin ≤ σ ≤ σmax }` that
//! contains the patch (docs/METHOD.md §2). Its cross-section at height `σ` is the triangle
//! `Ai(σ) = Pi + σ·di`; its side walls are the ruled surfaces `Xi = 0`.
//!
//! # How the height range is bounded
//! The surface height is zero at the vertices, equals the conjugation lines' heights on the
//! edges and is smooth inside. The patch constructor samples it at [`SAMPLES`] fixed points (edge
//! points at `t = 0.1, ¼, ½, ¾, 0.9` and four interior points) in four calls of the eight-lane
//! height evaluation (`core/src/surface/lanes/`, equal to the generic scalar evaluation within
//! rounding: a unit test below) and widens the sampled range by [`MARGIN_REL`] of the range plus
//! [`MARGIN_ABS`] of the triangle's size. The margin is
//! validated, not proven: `tests/suite/shell.rs` samples 2000 random well-shaped patches with normals
//! up to 50° from the face on a 861-point grid and checks that every point lies inside, at least
//! `SHELL_CLEARANCE` (tests/suite/common/pins.rs) of the range's width away from its
//! faces. Beyond about 55° the surface itself can become wild (the
//! nearest sphere roots switch branches, docs/METHOD.md §7) and may leave the shell: that is outside
//! the method's domain and is measured in the reliability study (`tests/suite/domain.rs`). Even below
//! 50° the construction has rare isolated spikes where a sphere root switches branch (2 in
//! 7.8·10⁵ random patches with normals ≤ 50°, `tests/suite/robustness.rs`); no sampling bound can
//! contain those, and rays may miss the spike.

use crate::aabb::Aabb;
use crate::geometry::{Frame, Shape};
use crate::num::lanes::{LANES, Lane};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::edge::edge_point;
use crate::surface::lanes::Prepared;
use crate::surface::scalar::height;

/// Number of surface samples used to bound the height range.
pub const SAMPLES: usize = 19;
/// Relative widening of the sampled height range (fraction of its width).
pub const MARGIN_REL: f64 = 0.5;
/// Absolute widening as a fraction of the triangle's longest edge.
pub const MARGIN_ABS: f64 = 1e-4;

/// Edge parameters `t` of the edge samples (on each of the three edges).
pub const EDGE_T: [f64; EDGE_SAMPLES] = [0.1, 0.25, 0.5, 0.75, 0.9];
/// Samples per edge: [`samples`]' first `3 · EDGE_SAMPLES` are on the edges.
pub(crate) const EDGE_SAMPLES: usize = 5;
/// Barycentrics of the interior samples: towards each vertex, and the centroid.
const INTERIOR: [[f64; 3]; 4] = [
    [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
];

const _: () = assert!(3 * EDGE_T.len() + INTERIOR.len() == SAMPLES);
const _: () = assert!(EDGE_T.len() <= LANES && INTERIOR.len() <= LANES);

/// Eight lanes from their values.
#[inline(always)]
fn lanes<F: Float>(f: impl Fn(usize) -> F) -> F::L8 {
    F::L8::from_array(core::array::from_fn(f))
}

/// Conservative `[σmin, σmax]` of the surface of `shape` from its [`samples`]' `heights`: their
/// range, widened.
pub(crate) fn bounds_of<F: Float>(shape: &Shape<F>, heights: &[F; SAMPLES]) -> [F; 2] {
    let mut lo = F::ZERO;
    let mut hi = F::ZERO;
    for &h in heights {
        lo = lo.min(h);
        hi = hi.max(h);
    }
    let size = longest_edge(shape);
    let m = F::from_f64(MARGIN_REL) * (hi - lo) + F::from_f64(MARGIN_ABS) * size;
    [lo - m, hi + m]
}

/// Lanes of [`samples`]' interior call that its points leave free.
pub(crate) const SPARE: usize = LANES - INTERIOR.len();

/// The surface height at the [`SAMPLES`] points of `shape` (prepared as `pr`), by the lane
/// evaluation ([`crate::surface::lanes`]): edge `j`'s points (`t` of [`EDGE_T`]) at
/// `5j .. 5j + 5`, one lane call per edge, then the [`INTERIOR`] points in one call, whose free
/// lanes return the heights at the barycentrics `spare` (the predictor's interior nodes,
/// [`crate::surface::predictor`]). Equal to [`sample_scalar`] within rounding; where a lane is
/// not finite (never seen for an accepted patch) it is replaced by [`sample_scalar`].
#[inline(always)]
pub(crate) fn samples<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    spare: [[F; 3]; SPARE],
) -> ([F; SAMPLES], [F; SPARE]) {
    let mut out = [F::ZERO; SAMPLES];
    let mut slots = out.iter_mut();
    let t = lanes(|i| F::from_f64(EDGE_T.get(i).or(EDGE_T.last()).copied().unwrap_or(0.5)));
    for edge in 0..3 {
        let h = pr.edge_heights(edge, t).to_array();
        for (h, slot) in h.into_iter().take(EDGE_T.len()).zip(slots.by_ref()) {
            *slot = h;
        }
    }
    let bary = |c: usize| {
        lanes(|i| match INTERIOR.get(i) {
            Some(x) => F::from_f64(x.get(c).copied().unwrap_or_default()),
            None => spare
                .get(i.saturating_sub(INTERIOR.len()))
                .and_then(|x| x.get(c))
                .copied()
                .unwrap_or(F::ZERO),
        })
    };
    let h = pr.heights([bary(0), bary(1), bary(2)]).to_array();
    let mut extra = [F::ZERO; SPARE];
    for (h, slot) in h.iter().zip(slots) {
        *slot = *h;
    }
    for (h, slot) in h.iter().skip(INTERIOR.len()).zip(extra.iter_mut()) {
        *slot = *h;
    }
    for (i, v) in out.iter_mut().enumerate() {
        if !v.is_fin() {
            *v = sample_scalar(shape, i);
        }
    }
    (out, extra)
}

/// The barycentrics of sample `i` of [`samples`]: edge `j`'s points at `(1 − t)·Pj + t·Pj+1`,
/// then the interior points (anything past the last means the last).
pub(crate) fn sample_bary<F: Float>(i: usize) -> [F; 3] {
    let n = EDGE_T.len();
    let x = match i.checked_sub(3 * n) {
        None => {
            let t = EDGE_T.get(i % n).copied().unwrap_or(0.5);
            match i / n {
                0 => [1.0 - t, t, 0.0],
                1 => [0.0, 1.0 - t, t],
                _ => [t, 0.0, 1.0 - t],
            }
        }
        Some(k) => INTERIOR
            .get(k)
            .or(INTERIOR.last())
            .copied()
            .unwrap_or([1.0 / 3.0; 3]),
    };
    x.map(F::from_f64)
}

/// Sample `i` of [`samples`] by the generic (scalar) evaluation: the edge point's height
/// [`edge_point`]`.z` or the interior height [`height`].
#[inline(never)]
pub(crate) fn sample_scalar<F: Float>(shape: &Shape<F>, i: usize) -> F {
    let n = EDGE_T.len();
    match i.checked_sub(3 * n) {
        None => {
            let t = EDGE_T.get(i % n).copied().unwrap_or(0.5);
            edge_point::<F>(&shape.edge(i / n), F::from_f64(t)).0.z
        }
        Some(k) => {
            let x = INTERIOR.get(k).copied().unwrap_or([1.0 / 3.0; 3]);
            height(shape, x.map(F::from_f64))
        }
    }
}

/// Longest edge of the triangle.
pub(crate) fn longest_edge<F: Float>(shape: &Shape<F>) -> F {
    // The local frame's exact zeros (`P0 = 0`, `P1.y = P1.z = P2.z = 0`) left out: the same
    // squared lengths bit for bit (adding a zero square to a sum of squares changes nothing).
    let [_, p1, p2] = shape.p;
    let (x1, x2, y2) = (p1.x, p2.x, p2.y);
    let dx = x2 - x1;
    (x1 * x1)
        .max(dx * dx + y2 * y2)
        .max(x2 * x2 + y2 * y2)
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

/// The range of the line parameter `λ` over the shell of height range `sigma`: `λ = z / Vz(X)`
/// with `Vz` between the smallest and the largest `di.z` (all positive), so
/// `[σmin, σmax] / min(di.z)` contains it (`σmin ≤ 0 ≤ σmax`); `sigma` itself for parallel
/// sections (`di.z = 1`).
pub(crate) fn lambda_range<F: Float>(shape: &Shape<F>, sigma: [F; 2]) -> [F; 2] {
    let [d0, d1, d2] = shape.d;
    let dz = d0.z.min(d1.z).min(d2.z);
    sigma.map(|s| s / dz)
}

/// The minimum of `c0 + c1·s + c2·s²` over `[lo, hi]`.
fn quadratic_min<F: Float>([c0, c1, c2]: [F; 3], [lo, hi]: [F; 2]) -> F {
    let eval = |s: F| c0 + s * (c1 + s * c2);
    let mut m = eval(lo).min(eval(hi));
    if c2 != F::ZERO {
        let v = -c1 / (c2 + c2);
        if v > lo && v < hi {
            m = m.min(eval(v));
        }
    }
    m
}

/// The shell of `shape` over the height range `sigma` is valid when its cross-section keeps at
/// least a quarter of the triangle's area (same orientation) over the whole range. For tilted
/// sections ([`crate::surface::field`]) the measure is the map's orientation
/// `det[A1 − A0, A2 − A0, V(X)] = K(λ)·V(X)` (quadratic in `λ`, linear in `X`, so checked at
/// the three vertices over [`lambda_range`]): at least a quarter of its value on the triangle.
pub(crate) fn is_valid<F: Float>(shape: &Shape<F>, sigma: [F; 2]) -> bool {
    if crate::surface::field::parallel(shape) {
        let c = section_area_poly(shape);
        let [c0, _, _] = c;
        return quadratic_min(c, sigma) >= F::from_f64(0.25) * c0 && c0 > F::ZERO;
    }
    let sec = crate::surface::field::Section::new(shape);
    let [k0, k1, k2] = sec.k;
    let range = lambda_range(shape, sigma);
    shape.d.iter().all(|&d| {
        let c = [k0.dot(d), k1.dot(d), k2.dot(d)];
        let [c0, _, _] = c;
        range.iter().all(|l| l.is_fin())
            && c0 > F::ZERO
            && quadratic_min(c, range) >= F::from_f64(0.25) * c0
    })
}

/// The corners of the triangle whose walls `Xk = 0` are moved out to `Xk = −margin_k`, as
/// barycentrics: corner `i` has `Xk = −margin_k` for the two other vertices `k`.
#[inline(always)]
pub(crate) fn moved_corners<F: Float>(margin: [F; 3]) -> [[F; 3]; 3] {
    let [m0, m1, m2] = margin;
    [
        [F::ONE + m1 + m2, -m1, -m2],
        [-m0, F::ONE + m0 + m2, -m2],
        [-m0, -m1, F::ONE + m0 + m1],
    ]
}

/// Axis-aligned box of the six corners of the shell of `shape` over the height range `sigma`,
/// its side walls `Xk = 0` moved outward to `Xk = −reach_k`, world coordinates (`frame` maps
/// the local frame to them).
pub(crate) fn aabb<F: Float>(
    shape: &Shape<F>,
    sigma: [F; 2],
    frame: &Frame<F>,
    reach: [F; 3],
) -> Aabb<F> {
    // Every shell point is `P(X) + λ·V(X)` with `λ` in `lambda_range` (`sigma` itself for
    // parallel sections): a convex combination of the six corners.
    let [lo_s, hi_s] = lambda_range(shape, sigma);
    let mut b = Aabb::EMPTY;
    for x in moved_corners(reach) {
        for s in [lo_s, hi_s] {
            let mut q = V3::zero();
            for ((p, d), w) in shape.p.iter().zip(shape.d.iter()).zip(x) {
                q = q + (*p + *d * s) * w;
            }
            b = b.grow(frame.local_to_world(q));
        }
    }
    // Widen by a few ulps of the box so rounding of the frame cannot exclude a surface point.
    let (lo, hi) = (b.lo, b.hi);
    let pad = |a: F, b: F| (a.abs().max(b.abs())) * F::from_f64(8.0) * F::EPSILON;
    let e = V3::new(pad(lo.x, hi.x), pad(lo.y, hi.y), pad(lo.z, hi.z));
    Aabb::from_corners(lo - e, hi + e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::{F32_VS_F64_POINT, KERNEL_HEIGHT_VS_SURFACE};
    use crate::patch::Patch;
    use crate::testing::random_patches;

    /// Worst difference, relative to `size`, between the lane samples of `shape` and the
    /// scalar ones; asserts that every lane sample is finite.
    fn worst_sample_difference<F: Float>(shape: &Shape<F>, size: f64) -> f64 {
        let third = F::ONE / F::from_f64(3.0);
        let lanes = samples(shape, &Prepared::new(shape), [[third; 3]; SPARE]).0;
        let mut worst = 0.0f64;
        for (i, a) in lanes.into_iter().enumerate() {
            assert!(a.is_fin(), "sample {i} not finite");
            let b = sample_scalar(shape, i);
            worst = worst.max((a.to_f64() - b.to_f64()).abs() / size);
        }
        worst
    }

    #[test]
    fn lane_samples_equal_the_scalar_samples_within_rounding() {
        let (mut worst64, mut worst32, mut tested) = (0.0f64, 0.0f64, 0);
        for (patch, size) in random_patches(5, 600) {
            tested += 1;
            worst64 = worst64.max(worst_sample_difference(&patch.shape, size));
            let p32 = Patch::<f32>::new(
                patch.vertices().map(|v| v.as_vec3()),
                patch.normals().map(|v| v.as_vec3()),
            );
            if let Ok(p32) = p32 {
                worst32 = worst32.max(worst_sample_difference(&p32.shape, size));
            }
            // The sampled range is the scalar samples' range.
            let shape = &patch.shape;
            let heights = samples(shape, &Prepared::new(shape), [[0.25; 3]; SPARE]).0;
            let [lo, hi] = bounds_of(shape, &heights);
            let (mut slo, mut shi) = (0.0f64, 0.0f64);
            for i in 0..SAMPLES {
                let h = sample_scalar(&patch.shape, i);
                (slo, shi) = (slo.min(h), shi.max(h));
            }
            let m = MARGIN_REL * (shi - slo) + MARGIN_ABS * longest_edge(&patch.shape);
            let tol = 2.0 * KERNEL_HEIGHT_VS_SURFACE * size;
            assert!((lo - (slo - m)).abs() < tol && (hi - (shi + m)).abs() < tol);
        }
        assert!(tested > 450, "{tested}");
        assert!(worst64 < KERNEL_HEIGHT_VS_SURFACE, "f64 worst {worst64:e}");
        // Two f32 evaluations of the same surface, each within F32_VS_F64_POINT of f64.
        assert!(worst32 < 2.0 * F32_VS_F64_POINT, "f32 worst {worst32:e}");
    }
}
