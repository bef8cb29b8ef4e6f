//! Edge conjugation lines (docs/METHOD.md §4, the paper's eqs. (1)–(3)).
//!
//! Edge `i` runs from `Pi` to `Pi+1`. Its generator line at parameter `t` starts at
//! `p(t) = lerp(Pi, Pi+1, t)` with direction `g(t) = lerp(di, di+1, t)`. It meets the sphere `S¹i`
//! (anchor `Pi`, axis `ni`, through `Pi+1`) at `s1` and `S²i` (anchor `Pi+1`, axis `ni+1`, through
//! `Pi`) at `s2`; the conjugation line is `c(t) = p(t) + ((1 − t)·s1 + t·s2)·g(t)` (eq. (2)) and
//! its normal `n*(t) = normalize(g − T (T·g)/|T|²)` with `T = c′(t)` exact (eq. (3)).

use crate::dual::{Dual, split};
use crate::real::{Float, Real};
use crate::sphere::nearest_root;
use crate::vec::V3;

/// The data of one edge of a patch, in the patch's local frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgeView<F> {
    /// Start vertex `Pi`.
    pub a: V3<F>,
    /// End vertex `Pi+1`.
    pub b: V3<F>,
    /// Direction field at the start, `di` (unit height).
    pub da: V3<F>,
    /// Direction field at the end, `di+1`.
    pub db: V3<F>,
    /// Unit normal at the start.
    pub na: V3<F>,
    /// Unit normal at the end.
    pub nb: V3<F>,
    /// Curvature of `S¹i`.
    pub k1: F,
    /// Curvature of `S²i`.
    pub k2: F,
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
