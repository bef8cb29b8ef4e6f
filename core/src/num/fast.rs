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

use crate::num::real::{Float, LANES, Lane, LaneOps, Real, sealed::Sealed};
use crate::num::vec::V3;

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

impl Sealed for FastF32 {}

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
            FastF32(crate::num::math::sqrt_fast_f32(self.0))
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
    type L8 = Lanes8<FastF32>;
    type L4 = crate::num::lanes::One<FastF32>;
    type A8 = Lanes8<FastF32>;
    type A4 = crate::num::lanes::One<FastF32>;
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
        FastF32(crate::num::math::sqrt_fast_f32(self.0))
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

/// The portable lane type: eight scalars in an array, each operation a loop the compiler may
/// vectorise (used for scalars without a `wide` type, such as `FastF32`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lanes8<F>(pub [F; LANES]);

#[inline(always)]
fn zip<F: Copy>(a: [F; LANES], b: [F; LANES], f: impl Fn(F, F) -> F) -> [F; LANES] {
    let mut out = a;
    for (o, y) in out.iter_mut().zip(b) {
        *o = f(*o, y);
    }
    out
}

#[inline(always)]
fn cmp<F: Copy>(a: [F; LANES], b: [F; LANES], f: impl Fn(F, F) -> bool) -> [bool; LANES] {
    let mut out = [false; LANES];
    for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
        *o = f(x, y);
    }
    out
}

macro_rules! lanes8_op {
    ($tr:ident, $m:ident, $op:tt) => {
        impl<F: Float> $tr for Lanes8<F> {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: Self) -> Self {
                Lanes8(zip(self.0, o.0, |x, y| x $op y))
            }
        }
    };
}
lanes8_op!(Add, add, +);
lanes8_op!(Sub, sub, -);
lanes8_op!(Mul, mul, *);
lanes8_op!(Div, div, /);

impl<F: Float> Neg for Lanes8<F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Lanes8(self.0.map(|x| -x))
    }
}

impl<F: Float> Lane for Lanes8<F> {
    #[inline(always)]
    fn from_array(a: [F; LANES]) -> Self {
        Lanes8(a)
    }
    #[inline(always)]
    fn to_array(self) -> [F; LANES] {
        self.0
    }
    #[inline(always)]
    fn any(m: [bool; LANES]) -> bool {
        m.iter().any(|&x| x)
    }
    #[inline(always)]
    fn mask_array(m: [bool; LANES]) -> [bool; LANES] {
        m
    }
}

impl<F: Float> LaneOps for Lanes8<F> {
    type F = F;
    type Mask = [bool; LANES];
    crate::num::real::plain_lanes!();
    #[inline(always)]
    fn splat(x: F) -> Self {
        Lanes8([x; LANES])
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Lanes8(self.0.map(Float::sqrt))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Lanes8(self.0.map(|x| if x < F::ZERO { -x } else { x }))
    }
    #[inline(always)]
    fn lt(self, o: Self) -> [bool; LANES] {
        cmp(self.0, o.0, |x, y| x < y)
    }
    #[inline(always)]
    fn le(self, o: Self) -> [bool; LANES] {
        cmp(self.0, o.0, |x, y| x <= y)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> [bool; LANES] {
        cmp(self.0, o.0, |x, y| x > y)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> [bool; LANES] {
        cmp(self.0, o.0, |x, y| x == y)
    }
    #[inline(always)]
    fn finite(self) -> [bool; LANES] {
        self.0.map(Float::is_fin)
    }
    #[inline(always)]
    fn select(m: [bool; LANES], a: Self, b: Self) -> Self {
        let mut out = b.0;
        for ((o, x), c) in out.iter_mut().zip(a.0).zip(m) {
            if c {
                *o = x;
            }
        }
        Lanes8(out)
    }
    #[inline(always)]
    fn and(a: [bool; LANES], b: [bool; LANES]) -> [bool; LANES] {
        let mut out = a;
        for (o, y) in out.iter_mut().zip(b) {
            *o = *o && y;
        }
        out
    }
    #[inline(always)]
    fn or(a: [bool; LANES], b: [bool; LANES]) -> [bool; LANES] {
        let mut out = a;
        for (o, y) in out.iter_mut().zip(b) {
            *o = *o || y;
        }
        out
    }
    #[inline(always)]
    fn not(a: [bool; LANES]) -> [bool; LANES] {
        a.map(|x| !x)
    }
    #[inline(always)]
    fn any_set(m: [bool; LANES]) -> bool {
        m.iter().any(|&x| x)
    }
}
