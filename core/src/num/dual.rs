//! Forward-mode dual numbers `a + b·ε` (ε² = 0): exact first derivatives through any formula
//! written over [`Real`]. Nesting (`Dual<Dual<f64>>`) gives second derivatives.

use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::num::real::{Real, sealed::Sealed};

/// A dual number: value `re` and derivative `du` along one direction.
///
/// # Accuracy
/// Derivatives are exact up to the rounding of the arithmetic (no truncation error).
/// # Panics
/// Never.
#[derive(Clone, Copy, Debug, Default)]
pub struct Dual<T> {
    /// Value.
    pub re: T,
    /// Derivative.
    pub du: T,
}

impl<T: Real> Dual<T> {
    /// A variable: value `re`, derivative one.
    #[inline(always)]
    pub fn var(re: T) -> Self {
        Dual { re, du: T::one() }
    }
    /// A constant: value `re`, derivative zero.
    #[inline(always)]
    pub fn constant(re: T) -> Self {
        Dual { re, du: T::zero() }
    }
}

impl<T: Real> PartialEq for Dual<T> {
    #[inline(always)]
    fn eq(&self, o: &Self) -> bool {
        self.re == o.re
    }
}
impl<T: Real> PartialOrd for Dual<T> {
    #[inline(always)]
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        self.re.partial_cmp(&o.re)
    }
}

impl<T: Real> Add for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Dual {
            re: self.re + o.re,
            du: self.du + o.du,
        }
    }
}
impl<T: Real> Sub for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Dual {
            re: self.re - o.re,
            du: self.du - o.du,
        }
    }
}
impl<T: Real> Mul for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Dual {
            re: self.re * o.re,
            du: self.du * o.re + self.re * o.du,
        }
    }
}
impl<T: Real> Div for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let q = self.re / o.re;
        Dual {
            re: q,
            du: (self.du - q * o.du) / o.re,
        }
    }
}
impl<T: Real> Neg for Dual<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Dual {
            re: -self.re,
            du: -self.du,
        }
    }
}
impl<T: Real> AddAssign for Dual<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl<T: Real> SubAssign for Dual<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}
impl<T: Real> MulAssign for Dual<T> {
    #[inline(always)]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl<T: Real> Sealed for Dual<T> {}

impl<T: Real> Real for Dual<T> {
    type F = T::F;
    #[inline(always)]
    fn cst(x: T::F) -> Self {
        Dual::constant(T::cst(x))
    }
    #[inline(always)]
    fn re(self) -> T::F {
        self.re.re()
    }
    #[inline(always)]
    fn sqrt0(self) -> Self {
        let r = self.re.sqrt0();
        if r > T::zero() {
            Dual {
                re: r,
                du: self.du / (r + r),
            }
        } else {
            Dual::constant(T::zero())
        }
    }
    #[inline(always)]
    fn all_finite(self) -> bool {
        self.re.all_finite() && self.du.all_finite()
    }
}

/// Splits a vector of dual numbers into its value and derivative vectors.
#[inline(always)]
pub(crate) fn split<T: Real>(
    v: crate::num::vec::V3<Dual<T>>,
) -> (crate::num::vec::V3<T>, crate::num::vec::V3<T>) {
    (
        crate::num::vec::V3::new(v.x.re, v.y.re, v.z.re),
        crate::num::vec::V3::new(v.x.du, v.y.du, v.z.du),
    )
}
