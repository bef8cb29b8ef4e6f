//! Generalized spheres (docs/METHOD.md §3): the sphere through a point `A`, centred on the line
//! `A + λ·m` (`m` unit) and passing through a second point `B`, written by its signed curvature
//! so that the flat limit (a plane) needs no division by zero.
//!
//! `κ = 2 (B − A)·m / |B − A|²`, and the sphere is `κ |x − A|² − 2 (x − A)·m = 0`.

use crate::num::real::Real;
use crate::num::vec::V3;

/// Signed curvature `κ = 2 (b − a)·m / |b − a|²` of the sphere anchored at `a` with unit axis `m`
/// passing through `b`. Returns `0` (the plane) when `b == a`.
///
/// # Accuracy
/// A few ulps relative to `1/|b − a|`.
/// # Panics
/// Never.
#[inline(always)]
pub fn curvature<T: Real>(a: V3<T>, m: V3<T>, b: V3<T>) -> T {
    let w = b - a;
    let l2 = w.length2();
    if l2.re() > <T::F as crate::num::real::Float>::ZERO {
        let two = T::lit(2.0);
        two * w.dot(m) / l2
    } else {
        T::zero()
    }
}

/// Parameter `s` of the intersection of the line `base + s·g` with the generalized sphere
/// (anchor `a`, unit axis `m`, curvature `kappa`) nearest to `s = 0`.
///
/// Uses the cancellation-free form `s = c / (−b − sign(b)·√max(b² − a·c, 0))` of
/// `a s² + 2 b s + c = 0`, valid for `a = 0` (the plane). When the line misses the sphere the
/// discriminant is clamped (the result is then `c / −b`, finite, outside the paper's domain); when the line is
/// parallel to a plane (`q = 0`), the result is `0`; so is it when the line is tangent to the
/// sphere at a point of it (a double root at 0, where `c` and `b` are both rounding noise).
///
/// # Accuracy
/// The root is computed with relative error of a few ulps of the inputs' scale (no
/// catastrophic cancellation between `−b` and the square root).
/// # Panics
/// Never; the result is finite for finite input.
#[inline(always)]
pub fn nearest_root<T: Real>(base: V3<T>, g: V3<T>, a: V3<T>, m: V3<T>, kappa: T) -> T {
    let w = base - a;
    let qa = kappa * g.length2();
    let qb = kappa * w.dot(g) - g.dot(m);
    let qc = kappa * w.length2() - T::lit(2.0) * w.dot(m);
    let disc = (qb * qb - qa * qc).max0();
    let sq = disc.sqrt0();
    let q = if qb.re() < <T::F as crate::num::real::Float>::ZERO {
        sq - qb
    } else {
        -qb - sq
    };
    // A line through a point of the sphere and tangent to it there has a double root at s = 0;
    // then `c` and `b` are both rounding noise and `c / q` is noise over noise. Detect it
    // (both below 16 ε of their natural scale) and return the root 0.
    let tol = T::cst(<T::F as crate::num::real::Float>::EPSILON) * T::lit(16.0);
    let (w2, g2) = (w.length2(), g.length2());
    let k2 = kappa * kappa;
    let c_scale = T::lit(2.0) * (k2 * w2 * w2 + T::lit(4.0) * w2);
    let b_scale = T::lit(2.0) * (k2 * w2 * g2 + g2);
    let noise = |v: T, scale: T| (v * v).re() <= (tol * tol * scale).re();
    if noise(qc, c_scale) && noise(qb, b_scale) {
        return T::zero();
    }
    if q.re() != <T::F as crate::num::real::Float>::ZERO {
        let s = qc / q;
        if s.all_finite() { s } else { T::zero() }
    } else {
        T::zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn root_of_unit_sphere_from_outside() {
        // Sphere of radius 1 centred at (0,0,1): anchor origin, axis +z, through (0,0,2).
        let a = V3::new(0.0, 0.0, 0.0);
        let m = V3::new(0.0, 0.0, 1.0);
        let k = curvature(a, m, V3::new(0.0, 0.0, 2.0));
        assert!((k - 1.0_f64).abs() < 1e-15);
        // Line from (0.5, 0, -3) upward: hits where z = 1 - sqrt(1 - 0.25).
        let s = nearest_root(V3::new(0.5, 0.0, -3.0), V3::new(0.0, 0.0, 1.0), a, m, k);
        let want = 3.0 + 1.0 - (0.75f64).sqrt();
        assert!((s - want).abs() < 1e-14, "{s} vs {want}");
    }

    #[test]
    fn plane_limit_and_miss_are_finite() {
        let a = V3::new(0.0, 0.0, 0.0);
        let m = V3::new(0.0, 0.0, 1.0);
        let s = nearest_root(V3::new(1.0, 2.0, -3.0), V3::new(0.0, 0.0, 2.0), a, m, 0.0);
        assert!((s - 1.5_f64).abs() < 1e-15);
        // Miss: line far from a small sphere gives the closest approach, finite.
        let s = nearest_root(V3::new(10.0, 0.0, -3.0), V3::new(0.0, 0.0, 1.0), a, m, 1.0);
        assert!(s.is_finite());
        // Parallel to the plane: 0, not NaN.
        let s = nearest_root(V3::new(1.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0), a, m, 0.0);
        assert_eq!(s, 0.0);
    }
}
