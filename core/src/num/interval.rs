//! Interval arithmetic over `f64` with outward rounding: `Iv` encloses every real value a
//! formula can take when its inputs range over intervals. It is the scalar of the certificate
//! of [`crate::surface::certify`]; nesting it in [`Dual`](crate::num::dual::Dual) encloses derivatives too.
//!
//! Outward rounding without access to the FPU's rounding mode: every operation's bounds are
//! computed in round-to-nearest and then moved out by `2^-52` of their magnitude plus
//! `f64::MIN_POSITIVE`, more than the half-ulp a rounded operation can err by (and than an
//! underflow's absolute error). An operation whose result is not defined over the whole
//! enclosure (a division by an interval holding 0, an overflow, `∞ − ∞`) returns the entire
//! line, so every decision drawn from an enclosure stays sound; it is only less sharp.

use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::num::real::{Float, Real, sealed::Sealed};

/// A closed interval `[lo, hi]` of `f64` that encloses a real quantity.
///
/// Comparisons (`<`, `>`, …, required by [`Real`]) compare midpoints and mean nothing for a
/// certificate: decisions read [`Iv::lo`] and [`Iv::hi`].
///
/// # Accuracy
/// Enclosures are sound (outward rounded) and, for a formula evaluated once over inputs of
/// width `w`, `O(w)` wide plus a few ulps (the usual overestimation of interval arithmetic when
/// an input appears more than once).
/// # Panics
/// Never.
#[derive(Clone, Copy, Debug)]
pub struct Iv {
    lo: f64,
    hi: f64,
}

/// Relative outward step per operation: two half-ulps of `f64`.
const REL: f64 = f64::EPSILON;

impl Iv {
    /// The whole real line: what an undefined operation returns.
    pub const ENTIRE: Iv = Iv {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The interval `[lo, hi]` as given (no rounding step): `[min, max]` of the two, or
    /// [`Iv::ENTIRE`] when either is NaN.
    #[inline]
    pub fn new(lo: f64, hi: f64) -> Iv {
        if lo.is_nan() || hi.is_nan() {
            Iv::ENTIRE
        } else {
            Iv {
                lo: lo.min(hi),
                hi: lo.max(hi),
            }
        }
    }

    /// The bounds moved outward by one rounding step.
    #[inline]
    fn out(lo: f64, hi: f64) -> Iv {
        let l = lo - (lo.abs() * REL + f64::MIN_POSITIVE);
        let h = hi + (hi.abs() * REL + f64::MIN_POSITIVE);
        if l.is_nan() || h.is_nan() {
            Iv::ENTIRE
        } else {
            Iv { lo: l, hi: h }
        }
    }

    /// Upper bound.
    #[inline]
    pub fn hi(self) -> f64 {
        self.hi
    }

    /// `true` when every value is `> 0`.
    #[inline]
    pub fn positive(self) -> bool {
        self.lo > 0.0
    }

    /// `true` when 0 is not in the interval (all values of one strict sign).
    #[inline]
    pub fn excludes_zero(self) -> bool {
        self.lo > 0.0 || self.hi < 0.0
    }
}

impl PartialEq for Iv {
    #[inline]
    fn eq(&self, o: &Self) -> bool {
        self.re() == o.re()
    }
}
impl PartialOrd for Iv {
    #[inline]
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        self.re().partial_cmp(&o.re())
    }
}

impl Add for Iv {
    type Output = Iv;
    #[inline]
    fn add(self, o: Iv) -> Iv {
        Iv::out(self.lo + o.lo, self.hi + o.hi)
    }
}
impl Sub for Iv {
    type Output = Iv;
    #[inline]
    fn sub(self, o: Iv) -> Iv {
        Iv::out(self.lo - o.hi, self.hi - o.lo)
    }
}
impl Mul for Iv {
    type Output = Iv;
    #[inline]
    fn mul(self, o: Iv) -> Iv {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|v| v.is_nan()) {
            return Iv::ENTIRE;
        }
        let lo = p.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        let hi = p.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
        Iv::out(lo, hi)
    }
}
impl Div for Iv {
    type Output = Iv;
    #[inline]
    fn div(self, o: Iv) -> Iv {
        if o.excludes_zero() {
            self * Iv::out(1.0 / o.hi, 1.0 / o.lo)
        } else {
            Iv::ENTIRE
        }
    }
}
impl Neg for Iv {
    type Output = Iv;
    #[inline]
    fn neg(self) -> Iv {
        Iv {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}
impl AddAssign for Iv {
    #[inline]
    fn add_assign(&mut self, o: Iv) {
        *self = *self + o;
    }
}
impl SubAssign for Iv {
    #[inline]
    fn sub_assign(&mut self, o: Iv) {
        *self = *self - o;
    }
}
impl MulAssign for Iv {
    #[inline]
    fn mul_assign(&mut self, o: Iv) {
        *self = *self * o;
    }
}

impl Sealed for Iv {}

impl Real for Iv {
    type F = f64;
    #[inline]
    fn cst(x: f64) -> Iv {
        Iv::new(x, x)
    }
    /// The midpoint (infinite or NaN for unbounded intervals).
    #[inline]
    fn re(self) -> f64 {
        0.5 * self.lo + 0.5 * self.hi
    }
    #[inline]
    fn sqrt0(self) -> Iv {
        let r = Iv::out(Float::sqrt(self.lo.max(0.0)), Float::sqrt(self.hi.max(0.0)));
        Iv {
            lo: r.lo.max(0.0),
            hi: r.hi,
        }
    }
    #[inline]
    fn all_finite(self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }
    #[inline]
    fn max0(self) -> Iv {
        Iv {
            lo: self.lo.max(0.0),
            hi: self.hi.max(0.0),
        }
    }
    #[inline]
    fn abs(self) -> Iv {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            -self
        } else {
            Iv {
                lo: 0.0,
                hi: (-self.lo).max(self.hi),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contains(i: Iv, x: f64) -> bool {
        i.lo <= x && x <= i.hi
    }

    #[test]
    fn operations_enclose_their_samples() {
        let a = Iv::new(-1.5, 2.0);
        let b = Iv::new(0.25, 3.0);
        let xs = [-1.5, -0.3, 0.0, 1.0, 2.0];
        let ys = [0.25, 1.0, 2.9, 3.0];
        for &x in &xs {
            for &y in &ys {
                assert!(contains(a + b, x + y));
                assert!(contains(a - b, x - y));
                assert!(contains(a * b, x * y));
                assert!(contains(a / b, x / y));
                assert!(contains(b.sqrt0(), Float::sqrt(y)));
                assert!(contains(a.abs(), x.abs()));
            }
        }
        // Division by an interval holding 0 is the whole line; so is ∞ − ∞.
        assert!(!(b / a).all_finite());
        let inf = Iv::new(1.0, f64::INFINITY);
        assert!(!(inf - inf).all_finite());
        assert!(!(inf * Iv::cst(0.0)).all_finite());
    }

    #[test]
    fn rounding_moves_outward() {
        // The doubles 0.1 and 0.2 sum to 0.3000000000000000166…, which rounds up to
        // 0.30000000000000004: the enclosure must reach below it, to the double under it.
        let s = Iv::cst(0.1) + Iv::cst(0.2);
        assert!(s.lo <= 0.3 && s.hi >= 0.1 + 0.2);
        assert!(Iv::cst(1.0).positive() && !Iv::new(0.0, 1.0).positive());
        assert!(Iv::new(-2.0, -1.0).excludes_zero() && !Iv::new(-1.0, 1.0).excludes_zero());
    }
}
