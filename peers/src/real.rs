//! The scalar the peers compute in (`f32` or `f64`, through smoothtri's [`Float`]) and a
//! small 3-vector over it.

use core::ops::{Add, Mul, Neg, Sub};

use smoothtri::Float;

/// `f32` or `f64`: smoothtri's [`Float`] plus the conversions and the few functions of `std`
/// the solvers need.
pub trait Real: Float {
    /// The glam vector as a [`V3`].
    fn v3(v: Self::Vec3) -> V3<Self>;
    /// A [`V3`] as the glam vector.
    fn glam(v: V3<Self>) -> Self::Vec3;
    /// Cube root (`std`'s, correctly signed for negative input).
    fn cbrt(self) -> Self;
    /// Arc cosine of `self` clamped to `[-1, 1]` (radians).
    fn acos_clamped(self) -> Self;
    /// Cosine (radians).
    fn cos(self) -> Self;
    /// `|self|`.
    fn absf(self) -> Self;
}

macro_rules! real {
    ($f:ty) => {
        impl Real for $f {
            #[inline(always)]
            fn v3(v: Self::Vec3) -> V3<Self> {
                V3::new(v.x, v.y, v.z)
            }
            #[inline(always)]
            fn glam(v: V3<Self>) -> Self::Vec3 {
                <Self as Float>::Vec3::new(v.x, v.y, v.z)
            }
            #[inline(always)]
            fn cbrt(self) -> Self {
                <$f>::cbrt(self)
            }
            #[inline(always)]
            fn acos_clamped(self) -> Self {
                <$f>::acos(<$f>::clamp(self, -1.0, 1.0))
            }
            #[inline(always)]
            fn cos(self) -> Self {
                <$f>::cos(self)
            }
            #[inline(always)]
            fn absf(self) -> Self {
                <$f>::abs(self)
            }
        }
    };
}
real!(f32);
real!(f64);

/// A 3-vector of [`Real`]s (points, directions, plane normals).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3<F> {
    /// x.
    pub x: F,
    /// y.
    pub y: F,
    /// z.
    pub z: F,
}

impl<F: Real> V3<F> {
    /// `(x, y, z)`.
    #[inline(always)]
    pub const fn new(x: F, y: F, z: F) -> Self {
        V3 { x, y, z }
    }
    /// Component-wise product.
    #[inline(always)]
    fn times(self, o: Self) -> Self {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
    /// The components rotated: `(y, z, x)`.
    #[inline(always)]
    fn yzx(self) -> Self {
        V3::new(self.y, self.z, self.x)
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> F {
        let p = self.times(o);
        p.x + p.y + p.z
    }
    /// Cross product: `a.yzx·b.zxy − a.zxy·b.yzx`, component-wise.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        let (a, b) = (self.yzx(), o.yzx());
        a.times(b.yzx()) - a.yzx().times(b)
    }
    /// Squared length.
    #[inline(always)]
    pub fn length2(self) -> F {
        self.dot(self)
    }
    /// The unit vector along `self`, or `None` for a zero or non-finite vector.
    #[inline(always)]
    pub fn try_normalize(self) -> Option<Self> {
        let l = self.length2().sqrt();
        (l > F::ZERO && l.is_fin()).then(|| self * (F::ONE / l))
    }
    /// Component-wise minimum.
    #[inline(always)]
    pub fn min(self, o: Self) -> Self {
        V3::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    /// Component-wise maximum.
    #[inline(always)]
    pub fn max(self, o: Self) -> Self {
        V3::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
    /// Largest absolute component.
    #[inline(always)]
    pub fn max_abs(self) -> F {
        self.x.absf().max(self.y.absf()).max(self.z.absf())
    }
    /// Whether every component is finite.
    #[inline(always)]
    pub fn is_finite(self) -> bool {
        self.x.is_fin() && self.y.is_fin() && self.z.is_fin()
    }
    /// Each component rounded from `f64`.
    #[inline(always)]
    pub fn from_d(v: glam::DVec3) -> Self {
        V3::new(F::from_f64(v.x), F::from_f64(v.y), F::from_f64(v.z))
    }
    /// Widened to `f64`.
    #[inline(always)]
    pub fn to_d(self) -> glam::DVec3 {
        glam::DVec3::new(self.x.to_f64(), self.y.to_f64(), self.z.to_f64())
    }
}

/// Component-wise `V3 ∘ V3` operators.
macro_rules! vector_op {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl<F: Real> $tr for V3<F> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                V3::new(self.x $op o.x, self.y $op o.y, self.z $op o.z)
            }
        }
    )*};
}
vector_op!(Add add +, Sub sub -);

impl<F: Real> Mul<F> for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<F: Real> Neg for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}
