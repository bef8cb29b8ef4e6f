//! The primitive floats' impls of [`Real`] and [`Float`]: `f32` and `f64` with their glam
//! vectors, `wide` lanes and array lanes. In a file of their own, above both the traits
//! (`num/real.rs`) and the array lane types (`num/lanes.rs`), so that neither imports the other
//! back.

use crate::num::lanes::{F32x4, F32x8, F64x4, F64x8};
use crate::num::math::{sqrt_f32, sqrt_f64};
use crate::num::real::{Float, Real, V3};

macro_rules! impl_float {
    ($($f:ty, $v:ty, $l:ty, $l4:ty, $a:ty, $a4:ty, $sqrt:path;)*) => {$(
        impl Real for $f {
            type F = $f;
            #[inline(always)]
            fn cst(x: $f) -> $f {
                x
            }
            #[inline(always)]
            fn re(self) -> $f {
                self
            }
            #[inline(always)]
            fn sqrt0(self) -> $f {
                if self > 0.0 { $sqrt(self) } else { 0.0 }
            }
            #[inline(always)]
            fn all_finite(self) -> bool {
                self.is_finite()
            }
        }
        impl Float for $f {
            type Vec3 = $v;
            type L8 = $l;
            type L4 = $l4;
            type A8 = $a;
            type A4 = $a4;
            const ZERO: $f = 0.0;
            const ONE: $f = 1.0;
            const EPSILON: $f = <$f>::EPSILON;
            const MIN_POSITIVE: $f = <$f>::MIN_POSITIVE;
            const MAX: $f = <$f>::MAX;
            const MIN: $f = <$f>::MIN;
            #[inline(always)]
            fn from_f64(x: f64) -> $f {
                x as $f
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn is_fin(self) -> bool {
                self.is_finite()
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                <$f>::is_nan(self)
            }
            #[inline(always)]
            fn sqrt(self) -> $f {
                $sqrt(self)
            }
            #[inline(always)]
            fn min(self, o: $f) -> $f {
                <$f>::min(self, o)
            }
            #[inline(always)]
            fn max(self, o: $f) -> $f {
                <$f>::max(self, o)
            }
            #[inline(always)]
            fn from_glam(v: $v) -> V3<$f> {
                V3 {
                    x: v.x,
                    y: v.y,
                    z: v.z,
                }
            }
            #[inline(always)]
            fn to_glam(v: V3<$f>) -> $v {
                <$v>::new(v.x, v.y, v.z)
            }
        }
    )*};
}

impl_float! {
    f32, glam::Vec3, wide::f32x8, wide::f32x4, F32x8, F32x4, sqrt_f32;
    f64, glam::DVec3, wide::f64x8, wide::f64x4, F64x8, F64x4, sqrt_f64;
}
