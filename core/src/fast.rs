//! `FastF32`: an `f32` whose square root is micromath's fast approximation (feature
//! `micromath`), for targets without a hardware square root.
//!
//! Everything else is plain `f32` arithmetic. Use it as the precision parameter:
//! `Patch::<FastF32>::new(…)`, with glam `Vec3` inputs and outputs wrapped per component.
//!
//! # Accuracy
//! The square root (micromath's estimate and one Newton step) has a relative error of up to
//! [`FASTF32_SQRT_REL`]; a patch built in `FastF32` deviates from the exact patch by up to
//! [`FASTF32_SURFACE`] of the triangle's size and its hits by [`FASTF32_HIT`] of the size (all
//! measured in `tests/fast.rs`), and spheres are no longer reproduced exactly. The kernel's
//! `t_error` still bounds the distance to the `FastF32` surface.
//!
//! [`FASTF32_SQRT_REL`]: crate::accuracy::FASTF32_SQRT_REL
//! [`FASTF32_SURFACE`]: crate::accuracy::FASTF32_SURFACE
//! [`FASTF32_HIT`]: crate::accuracy::FASTF32_HIT

use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::real::{Float, Real};
use crate::vec::V3;

/// An `f32` with micromath's approximate square root.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct FastF32(pub f32);

macro_rules! bin {
    ($tr:ident, $f:ident, $op:tt, $tra:ident, $fa:ident) => {
        impl $tr for FastF32 {
            type Output = FastF32;
            #[inline(always)]
            fn $f(self, o: FastF32) -> FastF32 {
                FastF32(self.0 $op o.0)
            }
        }
        impl $tra for FastF32 {
            #[inline(always)]
            fn $fa(&mut self, o: FastF32) {
                self.0 = self.0 $op o.0;
            }
        }
    };
}
bin!(Add, add, +, AddAssign, add_assign);
bin!(Sub, sub, -, SubAssign, sub_assign);
bin!(Mul, mul, *, MulAssign, mul_assign);
impl Div for FastF32 {
    type Output = FastF32;
    #[inline(always)]
    fn div(self, o: FastF32) -> FastF32 {
        FastF32(self.0 / o.0)
    }
}
impl Neg for FastF32 {
    type Output = FastF32;
    #[inline(always)]
    fn neg(self) -> FastF32 {
        FastF32(-self.0)
    }
}

impl Real for FastF32 {
    type F = FastF32;
    #[inline(always)]
    fn cst(x: FastF32) -> FastF32 {
        x
    }
    #[inline(always)]
    fn re(self) -> FastF32 {
        self
    }
    #[inline(always)]
    fn sqrt0(self) -> FastF32 {
        if self.0 > 0.0 {
            FastF32(crate::math::sqrt_fast_f32(self.0))
        } else {
            FastF32(0.0)
        }
    }
    #[inline(always)]
    fn all_finite(self) -> bool {
        self.0.is_finite()
    }
}

impl Float for FastF32 {
    type Vec3 = glam::Vec3;
    type L8 = crate::lanes::Lanes8<FastF32>;
    const ZERO: FastF32 = FastF32(0.0);
    const ONE: FastF32 = FastF32(1.0);
    const EPSILON: FastF32 = FastF32(f32::EPSILON);
    const MIN_POSITIVE: FastF32 = FastF32(f32::MIN_POSITIVE);
    const MAX: FastF32 = FastF32(f32::MAX);
    const MIN: FastF32 = FastF32(f32::MIN);
    #[inline(always)]
    fn from_f64(x: f64) -> FastF32 {
        FastF32(x as f32)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.0 as f64
    }
    #[inline(always)]
    fn is_fin(self) -> bool {
        self.0.is_finite()
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        self.0.is_nan()
    }
    #[inline(always)]
    fn sqrt(self) -> FastF32 {
        FastF32(crate::math::sqrt_fast_f32(self.0))
    }
    #[inline(always)]
    fn min(self, o: FastF32) -> FastF32 {
        FastF32(self.0.min(o.0))
    }
    #[inline(always)]
    fn max(self, o: FastF32) -> FastF32 {
        FastF32(self.0.max(o.0))
    }
    #[inline(always)]
    fn from_glam(v: glam::Vec3) -> V3<FastF32> {
        V3::new(FastF32(v.x), FastF32(v.y), FastF32(v.z))
    }
    #[inline(always)]
    fn to_glam(v: V3<FastF32>) -> glam::Vec3 {
        glam::Vec3::new(v.x.0, v.y.0, v.z.0)
    }
}
