//! The surface point and normal (docs/METHOD.md §5, the paper's eqs. (4)–(5), with the ½ that makes
//! the weights sum to one).
//!
//! For barycentrics `X`, `P = Σ Xi Pi` and `D = Σ Xi di / Σ Xi di.z` (the line field of unit
//! height, [`crate::surface::field`]). For each vertex `i`, the edge opposite
//! it (edge `i+1`) gives `Ci = c(ti)`, `Ni = n*(ti)` with `ti = Xi+2 / (Xi+1 + Xi+2)`; the spheres
//! `Ŝ¹` (anchor `Pi`, axis `ni`, through `Ci`) and `Ŝ²` (anchor `Ci`, axis `Ni`, through `Pi`)
//! meet the line `P + s·D` at `s¹`, `s²`. The surface is the height field
//! `σS(X) = ½ Σ [Xi·s¹ + ((1 − Xi)/2)·s²]` and `pS = P + σS·D`.

use crate::geometry::Shape;
use crate::num::dual::{Dual, split};
use crate::num::real::{Float, Real};
use crate::num::vec::V3;
use crate::surface::edge::edge_point_normal;
use crate::surface::field::unit_height_dir;
use crate::surface::sphere::{curvature, nearest_root};

/// Barycentrics projected onto the triangle: non-finite components become 0, negative ones are
/// clamped to 0, and the three are renormalised to sum to one (the centroid if all vanish).
#[inline(always)]
pub(crate) fn project_bary<F: Float>(w1: F, w2: F) -> [F; 3] {
    let clean = |x: F| {
        if x.is_fin() && x > F::ZERO {
            x
        } else {
            F::ZERO
        }
    };
    let w0r = F::ONE - w1 - w2;
    let (a, b, c) = (clean(w0r), clean(w1), clean(w2));
    // Divide by the largest first, so subnormal sums cannot overflow `1 / sum`.
    let m = a.max(b).max(c);
    if m > F::ZERO && m.is_fin() {
        let (a, b, c) = (a / m, b / m, c / m);
        let inv = F::ONE / (a + b + c);
        [a * inv, b * inv, c * inv]
    } else {
        let third = F::from_f64(1.0 / 3.0);
        [third, third, third]
    }
}

/// The local-frame line `P(X) + s·D(X)` of barycentrics `x`, `D` of unit height
/// ([`unit_height_dir`]), so `s` is the height over the triangle's plane.
#[inline(always)]
fn base_line<S: Real>(shape: &Shape<S::F>, x: [S; 3]) -> (V3<S>, V3<S>) {
    let [x0, x1, x2] = x;
    let [p0, p1, p2] = shape.p.map(V3::<S>::lift);
    (p0 * x0 + p1 * x1 + p2 * x2, unit_height_dir(shape, x))
}

/// The term of vertex `i` in eq. (5): `½ (Xi·s¹ + ((1 − Xi)/2)·s²)`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn vertex_term<S: Real>(
    shape: &Shape<S::F>,
    opposite_edge: usize,
    pi: V3<S::F>,
    ni: V3<S::F>,
    xi: S,
    xa: S,
    xb: S,
    base: V3<S>,
    dir: V3<S>,
) -> S {
    let den = xa + xb;
    let t = if den.re() > <S::F as Float>::EPSILON {
        xb / den
    } else {
        S::lit(0.5)
    };
    let (c, nc) = edge_point_normal(&shape.edge(opposite_edge), t);
    let pi = V3::<S>::lift(pi);
    let ni = V3::<S>::lift(ni);
    let k1 = curvature(pi, ni, c);
    let s1 = nearest_root(base, dir, pi, ni, k1);
    let k2 = curvature(c, nc, pi);
    let s2 = nearest_root(base, dir, c, nc, k2);
    S::lit(0.5) * xi * s1 + S::lit(0.25) * (S::one() - xi) * s2
}

/// Height `σS(X)` of the surface over the triangle's plane at barycentrics `x` (summing to one,
/// inside the triangle), with the line `P + s·D` it lies on.
#[inline(always)]
pub(crate) fn height_line<S: Real>(shape: &Shape<S::F>, x: [S; 3]) -> (S, V3<S>, V3<S>) {
    let (base, dir) = base_line(shape, x);
    let [x0, x1, x2] = x;
    let [p0, p1, p2] = shape.p;
    let [n0, n1, n2] = shape.n;
    let h = vertex_term(shape, 1, p0, n0, x0, x1, x2, base, dir)
        + vertex_term(shape, 2, p1, n1, x1, x2, x0, base, dir)
        + vertex_term(shape, 0, p2, n2, x2, x0, x1, base, dir);
    (h, base, dir)
}

/// Height `σS(X)` only.
#[inline(always)]
pub(crate) fn height<F: Float>(shape: &Shape<F>, x: [F; 3]) -> F {
    height_line(shape, x).0
}

/// Local-frame surface point `pS = P + σS·D` of barycentrics `x` from its height `h` (e.g.
/// from the eight-lane evaluation of `crate::surface::lanes`).
#[inline(always)]
pub(crate) fn point_from_height<F: Float>(shape: &Shape<F>, x: [F; 3], h: F) -> V3<F> {
    let (base, dir) = base_line(shape, x);
    base + dir * h
}

/// Local-frame surface point `pS = P + σS·D`.
#[inline(always)]
pub(crate) fn point_local<S: Real>(shape: &Shape<S::F>, x: [S; 3]) -> V3<S> {
    let (h, base, dir) = height_line(shape, x);
    base + dir * h
}

/// Local-frame surface point and the exact partial derivatives `∂pS/∂X1`, `∂pS/∂X2`
/// (with `X0 = 1 − X1 − X2`).
#[inline(always)]
pub(crate) fn point_derivs_local<F: Float>(shape: &Shape<F>, x: [F; 3]) -> [V3<F>; 3] {
    let [x0, x1, x2] = x;
    let one = Dual::<F>::var(x1);
    let d1 = point_local(
        shape,
        [
            Dual {
                re: x0,
                du: -F::ONE,
            },
            one,
            Dual::constant(x2),
        ],
    );
    let d2 = point_local(
        shape,
        [
            Dual {
                re: x0,
                du: -F::ONE,
            },
            Dual::constant(x1),
            Dual::var(x2),
        ],
    );
    let (p, du1) = split(d1);
    let (_, du2) = split(d2);
    [p, du1, du2]
}

/// Local-frame unit normal at barycentrics `x` (projected), oriented like the vertex normals.
/// Falls back to the normalised interpolated vertex normal where the derivatives degenerate
/// (exactly at a vertex, it is that vertex's normal).
#[inline(always)]
pub(crate) fn normal_local<F: Float>(shape: &Shape<F>, x: [F; 3], du1: V3<F>, du2: V3<F>) -> V3<F> {
    let [x0, x1, x2] = x;
    let [n0, n1, n2] = shape.n;
    let phong = n0 * x0 + n1 * x1 + n2 * x2;
    let cr = du1.cross(du2);
    match cr.try_normalize() {
        Some(n) => {
            if n.dot(phong) < F::ZERO {
                -n
            } else {
                n
            }
        }
        None => phong
            .try_normalize()
            .unwrap_or(V3::new(F::ZERO, F::ZERO, F::ONE)),
    }
}

/// Local-frame surface point and unit normal at barycentrics `x` (projected).
#[inline(always)]
pub(crate) fn point_normal_local<F: Float>(shape: &Shape<F>, x: [F; 3]) -> (V3<F>, V3<F>) {
    let [p, du1, du2] = point_derivs_local(shape, x);
    (p, normal_local(shape, x, du1, du2))
}

/// Local-frame partial derivatives `∂pS/∂X1`, `∂pS/∂X2` at barycentrics `x` (projected); where
/// they overflow, the flat triangle's edge vectors `P1 − P0`, `P2 − P0` (finite).
#[inline(always)]
pub(crate) fn derivatives_local<F: Float>(shape: &Shape<F>, x: [F; 3]) -> [V3<F>; 2] {
    let [_, du1, du2] = point_derivs_local(shape, x);
    if du1.all_finite() && du2.all_finite() {
        [du1, du2]
    } else {
        // Overflow of the dual parts (extreme f32 magnitudes within ~1e-30 of a vertex):
        // the flat triangle's edge vectors, finite.
        let [p0, p1, p2] = shape.p;
        [p1 - p0, p2 - p0]
    }
}
