//! Edge conjugation lines (docs/METHOD.md §4, the paper's eqs. (1)–(3)).
//!
//! Edge `i` runs from `Pi` to `Pi+1`. Its generator line at parameter `t` starts at
//! `p(t) = lerp(Pi, Pi+1, t)` with direction `g(t) = lerp(di, di+1, t)`. It meets the sphere `S¹i`
//! (anchor `Pi`, axis `ni`, through `Pi+1`) at `s1` and `S²i` (anchor `Pi+1`, axis `ni+1`, through
//! `Pi`) at `s2`; the conjugation line is `c(t) = p(t) + ((1 − t)·s1 + t·s2)·g(t)` (eq. (2)) and
//! its normal `n*(t) = normalize(g − T (T·g)/|T|²)` with `T = c′(t)` exact (eq. (3)).

use crate::geometry::{EdgeView, Shape};
use crate::num::dual::{Dual, split};
use crate::num::real::{Float, Real};
use crate::num::vec::V3;
use crate::surface::sphere::{curvature, nearest_root};

/// Curvatures `[κ(S¹j), κ(S²j)]` of the two spheres of each edge `j` of the triangle with local
/// vertices `p` and unit normals `n` (`S¹j`: anchor `Pj`, axis `nj`, through `Pj+1`; `S²j`:
/// anchor `Pj+1`, axis `nj+1`, through `Pj`): the `k` of a [`Shape`].
#[inline(always)]
pub(crate) fn sphere_curvatures<F: Float>(p: [V3<F>; 3], n: [V3<F>; 3]) -> [[F; 2]; 3] {
    let [p0, p1, p2] = p;
    let [n0, n1, n2] = n;
    let k = |a: V3<F>, na: V3<F>, b: V3<F>, nb: V3<F>| [curvature(a, na, b), curvature(b, nb, a)];
    [k(p0, n0, p1, n1), k(p1, n1, p2, n2), k(p2, n2, p0, n0)]
}

/// Conjugation-line point `c(t)` (eq. (2)) and the generator direction `g(t)`.
#[inline(always)]
pub(crate) fn edge_point<S: Real>(e: &EdgeView<S::F>, t: S) -> (V3<S>, V3<S>) {
    let a = V3::<S>::lift(e.a);
    let b = V3::<S>::lift(e.b);
    let p = a.lerp(b, t);
    let g = V3::<S>::lift(e.da).lerp(V3::lift(e.db), t);
    let s1 = nearest_root(p, g, a, V3::lift(e.na), S::cst(e.k1));
    let s2 = nearest_root(p, g, b, V3::lift(e.nb), S::cst(e.k2));
    let s = (S::one() - t) * s1 + t * s2;
    (p + g * s, g)
}

/// Conjugation-line point `c(t)` and its unit normal `n*(t)` (eq. (3), exact derivative by
/// dual numbers, oriented so that `n*·g > 0`).
///
/// Falls back to `normalize(g)` where the tangent vanishes (never for an accepted patch).
#[inline(always)]
pub(crate) fn edge_point_normal<S: Real>(e: &EdgeView<S::F>, t: S) -> (V3<S>, V3<S>) {
    let (c, g) = edge_point::<Dual<S>>(e, Dual::var(t));
    let (c, tan) = split(c);
    let (g, _) = split(g);
    let tt = tan.length2();
    let n = if tt.re() > <S::F as Float>::ZERO {
        g - tan * (tan.dot(g) / tt)
    } else {
        g
    };
    let n = match n.try_normalize() {
        Some(n) => n,
        None => g
            .try_normalize()
            .unwrap_or(V3::new(S::zero(), S::zero(), S::one())),
    };
    (c, n)
}

/// Point of edge `j`'s conjugation line (`j` taken mod 3) at `t ∈ [0, 1]` (`t` clamped; a
/// non-finite `t` means 0) with its unit normal, in the local frame.
#[inline(always)]
pub(crate) fn clamped_point_normal<F: Float>(shape: &Shape<F>, j: usize, t: F) -> (V3<F>, V3<F>) {
    let t = if t.is_fin() {
        t.max(F::ZERO).min(F::ONE)
    } else {
        F::ZERO
    };
    edge_point_normal::<F>(&shape.edge(j % 3), t)
}
