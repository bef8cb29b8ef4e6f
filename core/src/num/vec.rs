//! A minimal 3-vector generic over [`Real`], so the same formulas run in `f32`, `f64` and dual
//! numbers. The public API speaks glam (`Vec3`, `DVec3`); this type is the internal workhorse.

use core::ops::{Add, Mul, Neg, Sub};

pub(crate) use crate::num::real::V3;
use crate::num::real::{Float, Real};

impl<T: Real> V3<T> {
    /// From components.
    #[inline(always)]
    pub const fn new(x: T, y: T, z: T) -> Self {
        V3 { x, y, z }
    }
    /// Zero vector.
    #[inline(always)]
    pub fn zero() -> Self {
        V3::new(T::zero(), T::zero(), T::zero())
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Squared length.
    #[inline(always)]
    pub fn length2(self) -> T {
        self.dot(self)
    }
    /// Length.
    #[inline(always)]
    pub fn length(self) -> T {
        self.length2().sqrt0()
    }
    /// `self·(1−t) + o·t`.
    #[inline(always)]
    pub fn lerp(self, o: Self, t: T) -> Self {
        self + (o - self) * t
    }
    /// Lifts a primitive vector into this number type (derivatives zero).
    #[inline(always)]
    pub fn lift(v: V3<T::F>) -> Self {
        V3::new(T::cst(v.x), T::cst(v.y), T::cst(v.z))
    }
    /// The value part.
    #[inline(always)]
    pub fn re(self) -> V3<T::F> {
        V3::new(self.x.re(), self.y.re(), self.z.re())
    }
    /// `true` when every component (and derivative part) is finite.
    #[inline(always)]
    pub fn all_finite(self) -> bool {
        self.x.all_finite() && self.y.all_finite() && self.z.all_finite()
    }
    /// Unit vector along `self`, or `None` when the length is zero or not finite.
    #[inline(always)]
    pub fn try_normalize(self) -> Option<Self> {
        let l = self.length();
        if l.re() > <T::F as Float>::ZERO && l.all_finite() {
            let v = self * (T::one() / l);
            if v.all_finite() { Some(v) } else { None }
        } else {
            None
        }
    }
}

impl<T: Real> Add for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<T: Real> Sub for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<T: Real> Mul<T> for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}
impl<T: Real> Neg for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}
