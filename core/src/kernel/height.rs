//! The kernel's specialised height evaluation `σS(X)`: the same surface as
//! [`crate::surface`] (docs/METHOD.md §5), written for speed in plain scalar arithmetic.
//!
//! Differences from the generic evaluation (which stays the reference and serves the public
//! evaluation API):
//! - no dual numbers: the edge tangent `c′(t)` that the edge normal `n*` needs (eq. (3)) is the
//!   hand-written forward derivative of the two edge-sphere roots, the very arithmetic the dual
//!   numbers perform, without carrying derivatives through everything else;
//! - the generator line of an edge is linear in `t`, so `w = p(t) − anchor` is `t·e` or
//!   `(t − 1)·e` and its derivative is the edge vector `e`: no lerps of anchors;
//! - the normal `n*` is left unnormalised where the formulas are homogeneous in it (the
//!   curvature through a point scales with the axis, and so do all three coefficients of the
//!   line quadratic, so the root does not change; the double-root test is scaled to match).
//!
//! # Accuracy
//! Equal to [`crate::surface`]'s height within rounding: within
//! [`KERNEL_HEIGHT_VS_SURFACE`](crate::accuracy::KERNEL_HEIGHT_VS_SURFACE) of the triangle's
//! size on random patches (the unit test below).

use crate::patch::Patch;
use crate::real::Float;
use crate::vec::V3;

/// Root `s` nearest 0 of `qa s² + 2 qb s + qc = 0` for the line `base + s·g` and the sphere
/// anchored at `a` with axis `m` (of length `|m|`, not necessarily unit) and curvature
/// `kappa` (scaled by `|m|` like the axis): [`crate::sphere::nearest_root`] without dual
/// numbers. Returns `(s, q)` with `q` the denominator (`s = qc / q`), for derivatives.
#[inline(always)]
fn root<F: Float>(w: V3<F>, g: V3<F>, m: V3<F>, m2: F, kappa: F) -> (F, F, [F; 3]) {
    let g2 = g.length2();
    let w2 = w.length2();
    let qa = kappa * g2;
    let qb = kappa * w.dot(g) - g.dot(m);
    let qc = kappa * w2 - F::from_f64(2.0) * w.dot(m);
    let disc = (qb * qb - qa * qc).max(F::ZERO);
    let sq = if disc > F::ZERO { disc.sqrt() } else { F::ZERO };
    let q = if qb < F::ZERO { sq - qb } else { -qb - sq };
    // Double root at s = 0 (the line tangent to the sphere at a point of it): `qc` and `qb`
    // are rounding noise; see `nearest_root`. Scales carry |m|² where the axis enters.
    let tol = F::EPSILON * F::from_f64(16.0);
    let k2 = kappa * kappa;
    let c_scale = F::from_f64(2.0) * (k2 * w2 * w2 + F::from_f64(4.0) * w2 * m2);
    let b_scale = F::from_f64(2.0) * (k2 * w2 * g2 + g2 * m2);
    let noise = |v: F, scale: F| v * v <= tol * tol * scale;
    if (noise(qc, c_scale) && noise(qb, b_scale)) || q == F::ZERO {
        return (F::ZERO, F::ZERO, [qa, qb, qc]);
    }
    let s = qc / q;
    if s.is_fin() {
        (s, q, [qa, qb, qc])
    } else {
        (F::ZERO, F::ZERO, [qa, qb, qc])
    }
}

/// Derivative `s′` of a root `s = qc / q` of [`root`] given the coefficients' derivatives
/// (forward mode, the same arithmetic as dual numbers: `sqrt` has derivative 0 where the
/// discriminant is clamped).
#[inline(always)]
fn root_derivative<F: Float>(s: F, q: F, c: [F; 3], dc: [F; 3]) -> F {
    if q == F::ZERO {
        return F::ZERO;
    }
    let [qa, qb, qc] = c;
    let [da, db, dcc] = dc;
    let disc = qb * qb - qa * qc;
    let ddisc = F::from_f64(2.0) * qb * db - da * qc - qa * dcc;
    let dsq = if disc > F::ZERO {
        ddisc / (F::from_f64(2.0) * disc.sqrt())
    } else {
        F::ZERO
    };
    let dq = if qb < F::ZERO { dsq - db } else { -db - dsq };
    let ds = (dcc - s * dq) / q;
    if ds.is_fin() { ds } else { F::ZERO }
}

/// Coefficient derivatives of the edge-sphere quadratic along the edge parameter: the line's
/// offset from the anchor moves with `e` (`w′ = e`) and its direction with `gd` (`g′ = gd`).
#[inline(always)]
fn coeff_derivatives<F: Float>(
    w: V3<F>,
    g: V3<F>,
    e: V3<F>,
    gd: V3<F>,
    m: V3<F>,
    kappa: F,
) -> [F; 3] {
    let two = F::from_f64(2.0);
    [
        two * kappa * g.dot(gd),
        kappa * (e.dot(g) + w.dot(gd)) - gd.dot(m),
        two * kappa * w.dot(e) - two * e.dot(m),
    ]
}

/// Conjugation point `c(t)` of edge `j` and its (unnormalised, positively scaled) normal
/// `n*(t)·|c′|²`.
#[inline(always)]
fn edge_point_normal<F: Float>(patch: &Patch<F>, j: usize, t: F) -> (V3<F>, V3<F>) {
    let ev = patch.edge(j);
    let e = ev.b - ev.a;
    let gd = ev.db - ev.da;
    let g = ev.da + gd * t;
    let w1 = e * t;
    let w2 = e * (t - F::ONE);
    let (s1, q1, c1) = root(w1, g, ev.na, F::ONE, ev.k1);
    let (s2, q2, c2) = root(w2, g, ev.nb, F::ONE, ev.k2);
    let ds1 = root_derivative(s1, q1, c1, coeff_derivatives(w1, g, e, gd, ev.na, ev.k1));
    let ds2 = root_derivative(s2, q2, c2, coeff_derivatives(w2, g, e, gd, ev.nb, ev.k2));
    let u = F::ONE - t;
    let s = u * s1 + t * s2;
    let ds = u * ds1 + t * ds2 + (s2 - s1);
    let c = ev.a + w1 + g * s;
    // c′ = e + g′·s + g·s′.
    let tan = e + gd * s + g * ds;
    let tt = tan.length2();
    // n* ∝ g − T (T·g)/|T|², scaled by |T|² > 0.
    let n = if tt > F::ZERO {
        g * tt - tan * tan.dot(g)
    } else {
        g
    };
    // Where the tangent is parallel to g (never for an accepted patch), fall back to g as the
    // generic evaluation does.
    if n.length2() > F::ZERO {
        (c, n)
    } else {
        (c, g)
    }
}

/// The term of vertex `i` in eq. (5): `½ (Xi·s¹ + ((1 − Xi)/2)·s²)`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn vertex_term<F: Float>(
    patch: &Patch<F>,
    opposite_edge: usize,
    pi: V3<F>,
    ni: V3<F>,
    xi: F,
    xa: F,
    xb: F,
    base: V3<F>,
    dir: V3<F>,
) -> F {
    let den = xa + xb;
    let t = if den > F::EPSILON {
        xb / den
    } else {
        F::from_f64(0.5)
    };
    let (c, nc) = edge_point_normal(patch, opposite_edge, t);
    let two = F::from_f64(2.0);
    // Ŝ¹: anchor Pi, unit axis ni, through c.
    let wc = c - pi;
    let l2 = wc.length2();
    let k1 = if l2 > F::ZERO {
        two * wc.dot(ni) / l2
    } else {
        F::ZERO
    };
    let (s1, _, _) = root(base - pi, dir, ni, F::ONE, k1);
    // Ŝ²: anchor c, axis n* (scaled), through Pi; the curvature scales with the axis.
    let nc2 = nc.length2();
    let k2 = if l2 > F::ZERO {
        -two * wc.dot(nc) / l2
    } else {
        F::ZERO
    };
    let (s2, _, _) = root(base - c, dir, nc, nc2, k2);
    F::from_f64(0.5) * xi * s1 + F::from_f64(0.25) * (F::ONE - xi) * s2
}

/// Height `σS(X)` of the surface over the triangle's plane at barycentrics `x` (summing to one,
/// inside the triangle).
#[inline(always)]
pub(crate) fn height<F: Float>(patch: &Patch<F>, x: [F; 3]) -> F {
    let [x0, x1, x2] = x;
    let [p0, p1, p2] = patch.p;
    let [d0, d1, d2] = patch.d;
    let [n0, n1, n2] = patch.n;
    let base = p0 * x0 + p1 * x1 + p2 * x2;
    let dir = d0 * x0 + d1 * x1 + d2 * x2;
    vertex_term(patch, 1, p0, n0, x0, x1, x2, base, dir)
        + vertex_term(patch, 2, p1, n1, x1, x2, x0, base, dir)
        + vertex_term(patch, 0, p2, n2, x2, x0, x1, base, dir)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface;
    use glam::DVec3;

    /// SplitMix64, for reproducible random patches without extra dependencies.
    struct Rng(u64);
    impl Rng {
        fn unit(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn vec(&mut self) -> DVec3 {
            DVec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - DVec3::ONE
        }
    }

    #[test]
    fn equals_the_generic_height_within_rounding() {
        let mut rng = Rng(7);
        let mut worst = 0.0f64;
        let mut tested = 0;
        for _ in 0..400 {
            let p = [rng.vec() * 3.0, rng.vec() * 3.0, rng.vec() * 3.0];
            let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let n = [0, 1, 2].map(|_| (nf + rng.vec() * 0.6).normalize_or_zero());
            let Ok(patch) = Patch::<f64>::new(p, n) else {
                continue;
            };
            tested += 1;
            let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
            for i in 0..=10 {
                for j in 0..=(10 - i) {
                    let (w1, w2) = (i as f64 / 10.0, j as f64 / 10.0);
                    let x = [1.0 - w1 - w2, w1, w2];
                    let a = height(&patch, x);
                    let b = surface::height(&patch, x);
                    worst = worst.max((a - b).abs() / size);
                }
            }
        }
        assert!(tested > 300, "{tested}");
        assert!(
            worst < crate::accuracy::KERNEL_HEIGHT_VS_SURFACE,
            "worst {worst:e}"
        );
    }
}
