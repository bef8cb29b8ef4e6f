//! The exact intersection of a ray with a quadratic triangular patch ([`QuadPatch`]), the one
//! solver behind both peers.
//!
//! 1. **Two conics.** The ray `o + t·d` is the intersection of two planes through `o` whose
//!    normals `m_1, m_2` are perpendicular to `d`. A patch point `x(u, v)` lies on the ray
//!    exactly when `m_k·(x(u, v) − o) = 0` for `k = 1, 2`: two conics in the parameter plane,
//!    `(u, v, 1) M_k (u, v, 1)ᵀ = 0`, with `M_k` symmetric 3×3 (each scaled to a largest entry
//!    of 1).
//! 2. **The pencil's cubic.** The conics `M_1 + λ M_2` all pass through the (up to four)
//!    common points. `det(M_1 + λ M_2)` is a cubic in `λ`; at its roots the member is
//!    degenerate: a pair of lines through the common points. The cubic is solved in closed form
//!    (Cardano with one real root, Viète's trigonometric form with three), in the variable
//!    whose leading coefficient is the larger (`λ` or `1/λ`), then polished by Newton's method.
//! 3. **Lines.** Of the real roots, the one whose degenerate member is most clearly a pair of
//!    real lines (the adjugate `adj(D) = −p pᵀ` is then negative semidefinite, `p` the lines'
//!    common point) is split: `D + [p]_×` has rank one, its largest row and column are the two
//!    lines (Richter-Gebert, *Perspectives on Projective Geometry*, 2011, §11.3). A member of
//!    rank one is a double line.
//! 4. **Quadratics.** Each line meets the other conic of the pencil in up to two points
//!    (a quadratic along the line, solved in the stable form).
//! 5. **Polish and choose.** Each point near the triangle is refined by Newton's method on the
//!    3×3 system `x(u, v) − o − t·d = 0` ([`NEWTON_STEPS`] steps); the points inside the
//!    triangle (to [`DOMAIN_ULPS`] ε) with `t` in range and a residual within [`RESIDUAL_ULPS`]
//!    ε of the patch's scale are kept, and the one of least `t` is the hit.
//!
//! Two real common points and two complex ones: the cubic has one real root and its member is
//! the real line pair through the real points. Four real points: three real roots, each a real
//! pair. No real point: the real pair's lines meet the conic in complex points only. So the
//! real pair always holds every real intersection.

use smoothtri::{Hit, Ray};

use crate::quadratic::QuadPatch;
use crate::real::{Real, V3};

/// Newton steps that polish each candidate on the parametric surface (each roughly doubles
/// the correct digits; the algebraic candidates already carry most of them).
pub const NEWTON_STEPS: usize = 2;
/// How far outside the triangle (in ε of the barycentrics) a hit is still taken: neighbours
/// share their edge curves exactly, so this keeps rays through shared edges from slipping
/// between two patches' roundings.
pub const DOMAIN_ULPS: f64 = 64.0;
/// The residual `|x(u, v) − o − t·d|` a polished candidate may keep, in ε of the patch's
/// scale (grazing rays converge slowly at their double roots).
pub const RESIDUAL_ULPS: f64 = 4096.0;

type M3<F> = [[F; 3]; 3];

#[inline(always)]
fn det3<F: Real>(m: &M3<F>) -> F {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The adjugate of a symmetric matrix (symmetric).
#[inline(always)]
fn adj3<F: Real>(m: &M3<F>) -> M3<F> {
    let c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    let c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    let c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    let c11 = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    let c12 = m[0][1] * m[2][0] - m[0][0] * m[2][1];
    let c22 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    [[c00, c01, c02], [c01, c11, c12], [c02, c12, c22]]
}

#[inline(always)]
fn frob<F: Real>(a: &M3<F>, b: &M3<F>) -> F {
    let mut s = F::ZERO;
    for i in 0..3 {
        for j in 0..3 {
            s += a[i][j] * b[i][j];
        }
    }
    s
}

#[inline(always)]
fn lin<F: Real>(a: &M3<F>, s: F, b: &M3<F>, r: F) -> M3<F> {
    let mut m = [[F::ZERO; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = a[i][j] * s + b[i][j] * r;
        }
    }
    m
}

#[inline(always)]
fn max_abs<F: Real>(m: &M3<F>) -> F {
    let mut s = F::ZERO;
    for r in m {
        for &x in r {
            s = s.max(x.absf());
        }
    }
    s
}

/// The conic `m·(x(u, v) − o) = 0` (with `o` relative to the patch's `a`), scaled to a largest
/// entry of 1; `None` when it vanishes (the patch's every coefficient lies in the plane).
#[inline(always)]
fn conic<F: Real>(p: &QuadPatch<F>, m: V3<F>, o: V3<F>) -> Option<M3<F>> {
    let h = F::from_f64(0.5);
    let (a, b, c) = (m.dot(p.buu), m.dot(p.buv) * h, m.dot(p.bvv));
    let (d, e, f) = (m.dot(p.bu) * h, m.dot(p.bv) * h, -m.dot(o));
    let k = [[a, b, d], [b, c, e], [d, e, f]];
    let s = max_abs(&k);
    (s > F::ZERO && s.is_fin()).then(|| lin(&k, F::ONE / s, &k, F::ZERO))
}

/// The real roots of `c3 x³ + c2 x² + c1 x + c0` (closed form, then one Newton step each);
/// `|c3|` is expected to be the largest or near it. Returns the roots and their count.
#[inline(always)]
fn cubic_roots<F: Real>(c3: F, c2: F, c1: F, c0: F) -> ([F; 3], usize) {
    let mut out = [F::ZERO; 3];
    let scale = c3.absf().max(c2.absf()).max(c1.absf()).max(c0.absf());
    if !(scale > F::ZERO) || !scale.is_fin() {
        return (out, 0);
    }
    let two = F::ONE + F::ONE;
    let three = two + F::ONE;
    let mut n = 0;
    if c3.absf() <= F::from_f64(1e-3) * F::EPSILON * scale {
        // Degree drop: a quadratic (the dropped root is at infinity, the other form's zero).
        let (a, b, c) = (c2, c1 * F::from_f64(0.5), c0);
        if a.absf() <= F::EPSILON * scale {
            if b != F::ZERO {
                out[0] = -c / (two * b);
                n = 1;
            }
        } else {
            let disc = b * b - a * c;
            if disc >= F::ZERO {
                let q = -(b + disc.sqrt() * if b < F::ZERO { -F::ONE } else { F::ONE });
                out[0] = q / a;
                n = 1;
                if q != F::ZERO {
                    out[1] = c / q;
                    n = 2;
                }
            }
        }
    } else {
        // Depressed cubic y³ + p y + q = 0 with x = y − a/3.
        let (a, b, c) = (c2 / c3, c1 / c3, c0 / c3);
        let a3 = a / three;
        let p = b - a * a3;
        let q = two * a3 * a3 * a3 - a3 * b + c;
        let disc = (q / two) * (q / two) + (p / three) * (p / three) * (p / three);
        if disc > F::ZERO {
            let s = disc.sqrt();
            let u = (-q / two + s).cbrt();
            let v = (-q / two - s).cbrt();
            out[0] = u + v - a3;
            n = 1;
        } else if p == F::ZERO {
            out[0] = -a3;
            n = 1;
        } else {
            // Three real roots (two or three equal when disc = 0).
            let r = (-p / three).sqrt();
            let phi = ((three * q) / (two * p * r)).acos_clamped() / three;
            let tau = F::from_f64(2.0 * core::f64::consts::PI / 3.0);
            for (k, x) in out.iter_mut().enumerate() {
                *x = two * r * (phi - tau * F::from_f64(k as f64)).cos() - a3;
            }
            n = 3;
        }
        // One Newton step on the original cubic.
        for x in out.iter_mut().take(n) {
            let f = ((c3 * *x + c2) * *x + c1) * *x + c0;
            let df = (three * c3 * *x + two * c2) * *x + c1;
            if df != F::ZERO {
                let nx = *x - f / df;
                if nx.is_fin() {
                    *x = nx;
                }
            }
        }
    }
    (out, n)
}

/// The up to two real lines of the degenerate conic `d` (line `(g0, g1, g2)`:
/// `g0 u + g1 v + g2 = 0`), or none when its lines are complex.
#[inline(always)]
fn split<F: Real>(d: &M3<F>) -> ([[F; 3]; 2], usize) {
    let b = adj3(d);
    let dm = max_abs(d);
    let tiny = F::from_f64(64.0) * F::EPSILON * dm * dm;
    let mut k = 0;
    for i in 1..3 {
        if b[i][i].absf() > b[k][k].absf() {
            k = i;
        }
    }
    let bkk = b[k][k];
    if bkk.absf() <= tiny {
        // Rank one: d = ±l lᵀ, a double line.
        let mut j = 0;
        for i in 1..3 {
            if d[i][i].absf() > d[j][j].absf() {
                j = i;
            }
        }
        let s = d[j][j].absf().sqrt();
        if !(s > F::ZERO) {
            return ([[F::ZERO; 3]; 2], 0);
        }
        return ([[d[j][0] / s, d[j][1] / s, d[j][2] / s], [F::ZERO; 3]], 1);
    }
    if bkk > F::ZERO {
        return ([[F::ZERO; 3]; 2], 0);
    }
    let beta = (-bkk).sqrt();
    let p = [b[0][k] / beta, b[1][k] / beta, b[2][k] / beta];
    // C = d + [p]_×: rank one, C = l mᵀ.
    let c = [
        [d[0][0], d[0][1] - p[2], d[0][2] + p[1]],
        [d[1][0] + p[2], d[1][1], d[1][2] - p[0]],
        [d[2][0] - p[1], d[2][1] + p[0], d[2][2]],
    ];
    let (mut bi, mut bj, mut best) = (0, 0, F::ZERO);
    for (i, row) in c.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            if x.absf() > best {
                (bi, bj, best) = (i, j, x.absf());
            }
        }
    }
    if !(best > F::ZERO) {
        return ([[F::ZERO; 3]; 2], 0);
    }
    let row = c[bi];
    let col = [c[0][bj], c[1][bj], c[2][bj]];
    ([row, col], 2)
}

/// The points `(u, v)` where line `g` meets conic `k` (up to two).
#[inline(always)]
fn line_conic<F: Real>(g: [F; 3], k: &M3<F>) -> ([(F, F); 2], usize) {
    let mut out = [(F::ZERO, F::ZERO); 2];
    let s = g[0] * g[0] + g[1] * g[1];
    if !(s > F::ZERO) || !s.is_fin() {
        return (out, 0);
    }
    // The line's point nearest the origin and its direction.
    let (p0, p1) = (-g[2] * g[0] / s, -g[2] * g[1] / s);
    let (e0, e1) = (-g[1], g[0]);
    // K(p + τe) = α τ² + 2β τ + γ.
    let kp = [
        k[0][0] * p0 + k[0][1] * p1 + k[0][2],
        k[1][0] * p0 + k[1][1] * p1 + k[1][2],
        k[2][0] * p0 + k[2][1] * p1 + k[2][2],
    ];
    let alpha = e0 * (k[0][0] * e0 + k[0][1] * e1) + e1 * (k[1][0] * e0 + k[1][1] * e1);
    let beta = e0 * kp[0] + e1 * kp[1];
    let gamma = p0 * kp[0] + p1 * kp[1] + kp[2];
    let mut disc = beta * beta - alpha * gamma;
    let noise = F::from_f64(64.0) * F::EPSILON * (beta * beta + (alpha * gamma).absf());
    if disc < F::ZERO {
        if disc < -noise {
            return (out, 0);
        }
        disc = F::ZERO;
    }
    let q = -(beta + disc.sqrt() * if beta < F::ZERO { -F::ONE } else { F::ONE });
    let mut n = 0;
    if alpha != F::ZERO {
        let tau = q / alpha;
        out[n] = (p0 + tau * e0, p1 + tau * e1);
        n += 1;
    }
    if q != F::ZERO {
        let tau = gamma / q;
        out[n] = (p0 + tau * e0, p1 + tau * e1);
        n += 1;
    }
    (out, n)
}

/// The nearest hit `(t, u, v)` of `o + t·d` on `p` with `t` in `[t_min, t_max]` (see the
/// module docs).
#[inline(never)]
pub(crate) fn closest_hit<F: Real>(
    p: &QuadPatch<F>,
    o: V3<F>,
    d: V3<F>,
    t_min: F,
    t_max: F,
) -> Option<(F, F, F)> {
    if !o.is_finite() || !d.is_finite() || t_min.is_nan() || t_max.is_nan() {
        return None;
    }
    let dn = d.try_normalize()?;
    // Two unit normals perpendicular to the ray: `dn × e_k` for the axis of the smallest
    // component, then `dn × m1`.
    let (ax, ay, az) = (dn.x.absf(), dn.y.absf(), dn.z.absf());
    let e = if ax <= ay && ax <= az {
        V3::new(F::ONE, F::ZERO, F::ZERO)
    } else if ay <= az {
        V3::new(F::ZERO, F::ONE, F::ZERO)
    } else {
        V3::new(F::ZERO, F::ZERO, F::ONE)
    };
    let m1 = dn.cross(e).try_normalize()?;
    let m2 = dn.cross(m1);
    let rel = o - p.a;
    let k1 = conic(p, m1, rel)?;
    let k2 = conic(p, m2, rel)?;
    // det(k1 + λ k2) = c3 λ³ + c2 λ² + c1 λ + c0.
    let (a1, a2) = (adj3(&k1), adj3(&k2));
    let c0 = det3(&k1);
    let c1 = frob(&a1, &k2);
    let c2 = frob(&a2, &k1);
    let c3 = det3(&k2);
    // In the variable with the larger leading coefficient: D = k1 + λ k2 (then the points lie on
    // k2), or D = μ k1 + k2 (on k1).
    let lambda_form = c3.absf() >= c0.absf();
    let (roots, nr) = if lambda_form {
        cubic_roots(c3, c2, c1, c0)
    } else {
        cubic_roots(c0, c1, c2, c3)
    };
    let member = |r: F| {
        if lambda_form {
            lin(&k1, F::ONE, &k2, r)
        } else {
            lin(&k1, r, &k2, F::ONE)
        }
    };
    let other = if lambda_form { &k2 } else { &k1 };
    // The root whose member is most clearly a real line pair: the least largest-diagonal of
    // the adjugate, relative to the member's size.
    let mut best: Option<(F, M3<F>)> = None;
    for &r in roots.iter().take(nr) {
        let dm = member(r);
        let s = max_abs(&dm);
        if !(s > F::ZERO) || !s.is_fin() {
            continue;
        }
        let b = adj3(&dm);
        let score = b[0][0].max(b[1][1]).max(b[2][2]) / (s * s);
        if best.as_ref().is_none_or(|(bs, _)| score < *bs) {
            best = Some((score, dm));
        }
    }
    let (_, dm) = best?;
    let (lines, nl) = split(&dm);
    let eps = F::EPSILON;
    let slack = F::from_f64(DOMAIN_ULPS) * eps;
    let loose = F::from_f64(0.25);
    let max_res = F::from_f64(RESIDUAL_ULPS) * eps * p.scale;
    let dd = d.dot(d);
    let mut hit: Option<(F, F, F)> = None;
    for g in lines.iter().take(nl) {
        let (pts, np) = line_conic(*g, other);
        for &(mut u, mut v) in pts.iter().take(np) {
            if !(u >= -loose && v >= -loose && u + v <= F::ONE + loose) {
                continue;
            }
            let mut t = d.dot(p.point_v(u, v) - o) / dd;
            let mut r = p.point_v(u, v) - o - d * t;
            let mut rn = r.max_abs();
            for _ in 0..NEWTON_STEPS {
                // x(u, v) − o − t d = 0: J = [x_u, x_v, −d]; a step is kept only when it
                // shrinks the residual (at a tangent point J is singular).
                let (xu, xv) = p.derivs_v(u, v);
                let nd = -d;
                let det = xu.dot(xv.cross(nd));
                if det == F::ZERO || !det.is_fin() {
                    break;
                }
                let inv = F::ONE / det;
                // Cramer: J Δ = −r.
                let u2 = u - r.dot(xv.cross(nd)) * inv;
                let v2 = v - xu.dot(r.cross(nd)) * inv;
                let t2 = t - xu.dot(xv.cross(r)) * inv;
                let r2 = p.point_v(u2, v2) - o - d * t2;
                let rn2 = r2.max_abs();
                if !(rn2 < rn) {
                    break;
                }
                (u, v, t, r, rn) = (u2, v2, t2, r2, rn2);
            }
            let _ = r;
            if !(u >= -slack && v >= -slack && u + v <= F::ONE + slack) {
                continue;
            }
            if !(t >= t_min && t <= t_max) || hit.is_some_and(|(bt, ..)| t >= bt) {
                continue;
            }
            if !(rn <= max_res) {
                continue;
            }
            let (u, v) = (u.max(F::ZERO), v.max(F::ZERO));
            let s = u + v;
            let (u, v) = if s > F::ONE { (u / s, v / s) } else { (u, v) };
            hit = Some((t, u, v));
        }
    }
    hit
}

impl<F: Real> QuadPatch<F> {
    /// The nearest intersection of `ray` with the patch for `t` in `[t_min, t_max]`, exact up
    /// to rounding (this module): `t`, the point `ray.at(t)`, the geometric
    /// normal ([`QuadPatch::normal`]), the barycentrics `w1, w2` of the hit on this patch,
    /// `front_face` (the ray arrives against the geometric normal), `t_error` 0 (the peers
    /// certify nothing) and `patch` 0.
    ///
    /// # Accuracy
    /// Within a few ulps of the patch's scale of the `f64` reference (dense sampling plus
    /// Newton's method on the parametric surface; `peers/tests/`); grazing rays and double
    /// roots included.
    /// # Panics
    /// Never.
    pub fn closest_hit(&self, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        let o = F::v3(ray.origin);
        let d = F::v3(ray.dir);
        let (t, u, v) = closest_hit(self, o, d, t_min, t_max)?;
        let n = self.normal_v(u, v);
        Some(Hit {
            t,
            t_error: F::ZERO,
            point: F::glam(o + d * t),
            normal: F::glam(n),
            w1: u,
            w2: v,
            front_face: n.dot(d) < F::ZERO,
            patch: 0,
        })
    }
}
