//! The analytic torus, traced exactly in `f64`: the reference surface of the measurements
//! (the torus meshes of the repository sample it: major radius `R` around the z axis, minor
//! radius `r`).
//!
//! A point `x` lies on the torus where `(|x|² + R² − r²)² = 4R²(x² + y²)`. Along a ray
//! `o + t·d` that is a quartic in `t`. Its real roots are isolated exactly by recursion on the
//! derivative: the roots of the derivative split the range into pieces on which the polynomial
//! is monotone, and each piece with a sign change holds one root, found by bisection with
//! Newton steps to full `f64` precision; a critical value within rounding of zero is a double
//! root (a ray tangent to the torus).

use glam::DVec3;

/// A torus around the z axis through the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Torus {
    /// Major radius `R` (centre of the tube to the axis).
    pub major: f64,
    /// Minor radius `r` (the tube's).
    pub minor: f64,
}

/// `p(x)` for coefficients lowest first.
fn eval(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
}

/// The real roots of the polynomial `c` (lowest coefficient first, degree ≤ 4) in `[lo, hi]`,
/// ascending, written to `out`; returns their count.
fn roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
    let deg = c.iter().rposition(|&k| k != 0.0).unwrap_or(0);
    let c = &c[..=deg];
    if deg == 0 {
        return 0;
    }
    if deg == 1 {
        let x = -c[0] / c[1];
        if x >= lo && x <= hi {
            out[0] = x;
            return 1;
        }
        return 0;
    }
    let dc: Vec<f64> = (1..=deg).map(|i| c[i] * i as f64).collect();
    let mut crit = [0.0; 4];
    let nc = roots_in(&dc, lo, hi, &mut crit);
    let scale: f64 = c
        .iter()
        .enumerate()
        .map(|(i, k)| k.abs() * lo.abs().max(hi.abs()).max(1.0).powi(i as i32))
        .sum();
    let mut ends = vec![lo];
    ends.extend_from_slice(&crit[..nc]);
    ends.push(hi);
    let mut n = 0;
    let mut push = |x: f64, n: &mut usize| {
        if *n < 4 && (*n == 0 || x > out[*n - 1]) {
            out[*n] = x;
            *n += 1;
        }
    };
    for w in ends.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (fa, fb) = (eval(c, a), eval(c, b));
        if fa == 0.0 {
            push(a, &mut n);
            continue;
        }
        if fa.signum() != fb.signum() && fb != 0.0 {
            let (mut a, mut b, mut fa) = (a, b, fa);
            let mut x = 0.5 * (a + b);
            for _ in 0..200 {
                let fx = eval(c, x);
                if fx == 0.0 {
                    break;
                }
                if fx.signum() == fa.signum() {
                    (a, fa) = (x, fx);
                } else {
                    b = x;
                }
                let dx = eval(&dc, x);
                let newton = x - fx / dx;
                x = if dx != 0.0 && newton > a && newton < b {
                    newton
                } else {
                    0.5 * (a + b)
                };
                if b - a <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
                    break;
                }
            }
            push(x, &mut n);
        } else if w[1] < hi && fb.abs() <= 64.0 * f64::EPSILON * scale {
            // A critical point on the axis: a double root.
            push(b, &mut n);
        }
    }
    if eval(c, hi) == 0.0 {
        push(hi, &mut n);
    }
    n
}

impl Torus {
    /// The nearest hit of `o + t·d` with `t` in `[t_min, t_max]`: `t` and the unit outward
    /// normal there.
    ///
    /// # Accuracy
    /// `t` to a few ulps of the ray's distance to the origin (the quartic's roots polished by
    /// Newton steps inside their brackets); tangent rays are found where the quartic's value at
    /// its critical point is within 64 ε of its scale.
    /// # Panics
    /// Never.
    pub fn closest_hit(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<(f64, DVec3)> {
        let dd = d.dot(d);
        if !(dd > 0.0) || !o.is_finite() || !d.is_finite() {
            return None;
        }
        // Shift the origin to the ray's point nearest the torus's centre (better conditioned).
        let t0 = -o.dot(d) / dd;
        let o = o + d * t0;
        let (rr, r2) = (self.major * self.major, self.minor * self.minor);
        let (g, h, k) = (dd, 2.0 * o.dot(d), o.dot(o) + rr - r2);
        let dxy = d.x * d.x + d.y * d.y;
        let oxy = o.x * o.x + o.y * o.y;
        let odxy = o.x * d.x + o.y * d.y;
        let c = [
            k * k - 4.0 * rr * oxy,
            2.0 * h * k - 8.0 * rr * odxy,
            h * h + 2.0 * g * k - 4.0 * rr * dxy,
            2.0 * g * h,
            g * g,
        ];
        let reach = (self.major + self.minor) / dd.sqrt() * (1.0 + 1e-9) + 1e-12;
        let (lo, hi) = ((t_min - t0).max(-reach), (t_max - t0).min(reach));
        if !(lo <= hi) {
            return None;
        }
        let mut roots = [0.0; 4];
        let n = roots_in(&c, lo, hi, &mut roots);
        let t = *roots.get(..n)?.first()?;
        let x = o + d * t;
        Some((t + t0, self.normal_at(x)))
    }

    /// The unit outward normal of the torus point nearest `x` (the direction from the tube's
    /// centre circle to `x`).
    ///
    /// # Panics
    /// Never.
    pub fn normal_at(&self, x: DVec3) -> DVec3 {
        let ring = DVec3::new(x.x, x.y, 0.0)
            .try_normalize()
            .unwrap_or(DVec3::X)
            * self.major;
        (x - ring).try_normalize().unwrap_or(DVec3::Z)
    }

    /// The distance of `x` to the torus.
    ///
    /// # Panics
    /// Never.
    pub fn distance(&self, x: DVec3) -> f64 {
        let q = (x.x * x.x + x.y * x.y).sqrt() - self.major;
        ((q * q + x.z * x.z).sqrt() - self.minor).abs()
    }
}
