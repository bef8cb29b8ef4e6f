//! Eight evaluations at once: the lane type the kernel evaluates its height function over.
//!
//! [`Lane`] is an 8-wide vector of one precision with the few operations the kernel needs
//! (arithmetic, square root, comparisons into masks, selects). Every precision names its lane
//! type through [`Float::L8`]: `f32` uses [`wide::f32x8`] and `f64` [`wide::f64x8`] (from the
//! `wide` crate with default features off: no_std; AVX/AVX2 when the target enables them, two
//! SSE2 or NEON halves otherwise, a scalar fallback elsewhere), and other scalars (`FastF32`) the
//! portable `Lanes8` array (`num/fast.rs`). The kernel's arithmetic is written once, over [`Lane`], with
//! selects instead of branches, so one call costs about as much as one scalar evaluation on
//! AVX2 (docs/METHOD.md §8).
//!
//! How an embedding renderer gets the wide instructions: compile with the target's features,
//! e.g. `RUSTFLAGS="-C target-cpu=native"` or `-C target-feature=+avx2,+fma` on x86-64 (NEON is
//! on by default on aarch64). Without them the code is still correct, using SSE2 halves.

pub(crate) use crate::num::real::{Float, LANES, Lane, Lane4, LaneOps};

macro_rules! impl_wide_ops {
    ($l:ty, $f:ty) => {
        impl LaneOps for $l {
            type F = $f;
            type Mask = $l;
            crate::num::real::plain_lanes!();
            #[inline(always)]
            fn splat(x: $f) -> Self {
                <$l>::splat(x)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$l>::sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$l>::abs(self)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Self {
                self.simd_lt(o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> Self {
                self.simd_le(o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Self {
                self.simd_gt(o)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> Self {
                self.simd_eq(o)
            }
            #[inline(always)]
            fn finite(self) -> Self {
                <$l>::is_finite(self)
            }
            #[inline(always)]
            fn select(m: Self, a: Self, b: Self) -> Self {
                m.select(a, b)
            }
            #[inline(always)]
            fn and(a: Self, b: Self) -> Self {
                a & b
            }
            #[inline(always)]
            fn or(a: Self, b: Self) -> Self {
                a | b
            }
            #[inline(always)]
            fn not(a: Self) -> Self {
                !a
            }
            #[inline(always)]
            fn any_set(m: Self) -> bool {
                m.any()
            }
        }
    };
}

macro_rules! impl_wide {
    ($l:ty, $f:ty) => {
        impl Lane for $l {
            #[inline(always)]
            fn from_array(a: [$f; LANES]) -> Self {
                <$l>::new(a)
            }
            #[inline(always)]
            fn to_array(self) -> [$f; LANES] {
                <$l>::to_array(self)
            }
            #[inline(always)]
            fn any(m: Self) -> bool {
                m.any()
            }
            #[inline(always)]
            fn mask_array(m: Self) -> [bool; LANES] {
                let bits = m.to_bitmask();
                core::array::from_fn(|i| bits & (1 << i) != 0)
            }
        }
        impl_wide_ops!($l, $f);
    };
}

impl_wide!(wide::f32x8, f32);
impl_wide!(wide::f64x8, f64);
macro_rules! impl_wide4 {
    ($l:ty, $f:ty) => {
        impl Lane4 for $l {
            const POINTS: usize = 4;
            #[inline(always)]
            fn from_array4(a: [$f; 4]) -> Self {
                <$l>::new(a)
            }
            #[inline(always)]
            fn to_array4(self) -> [$f; 4] {
                <$l>::to_array(self)
            }
            #[inline(always)]
            fn bits4(m: Self) -> u32 {
                m.to_bitmask() as u32
            }
            #[inline(always)]
            fn max_fast(self, o: Self) -> Self {
                self.fast_max(o)
            }
            #[inline(always)]
            fn min_fast(self, o: Self) -> Self {
                self.fast_min(o)
            }
        }
        impl_wide_ops!($l, $f);
    };
}

// Four lanes: the seamless shading normal's jets (one SSE2 or NEON register in `f32`).
impl_wide4!(wide::f32x4, f32);
impl_wide4!(wide::f64x4, f64);
// Two `f64` lanes (one SSE2 or NEON register): the builder's height jets, small enough to
// compile quickly where eight-lane jets are not.
impl_wide_ops!(wide::f64x2, f64);

/// One scalar as a lane type (`Mask = bool`): the one-point evaluations over the lane code
/// (the hit normal's jets, `crate::surface::lanes::Prepared::derivatives`), the same arithmetic as the
/// scalar with branches for selects.
#[derive(Clone, Copy, Debug)]
pub struct One<F>(pub(crate) F);

impl<F: Float> core::ops::Add for One<F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        One(self.0 + o.0)
    }
}
impl<F: Float> core::ops::Sub for One<F> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        One(self.0 - o.0)
    }
}
impl<F: Float> core::ops::Mul for One<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        One(self.0 * o.0)
    }
}
impl<F: Float> core::ops::Div for One<F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        One(self.0 / o.0)
    }
}
impl<F: Float> core::ops::Neg for One<F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        One(-self.0)
    }
}

impl<F: Float> Lane4 for One<F> {
    const POINTS: usize = 1;
    #[inline(always)]
    fn from_array4([a, ..]: [F; 4]) -> Self {
        One(a)
    }
    #[inline(always)]
    fn to_array4(self) -> [F; 4] {
        [self.0; 4]
    }
    #[inline(always)]
    fn bits4(m: bool) -> u32 {
        if m { 0b1111 } else { 0 }
    }
    #[inline(always)]
    fn max_fast(self, o: Self) -> Self {
        if self.0 > o.0 { self } else { o }
    }
    #[inline(always)]
    fn min_fast(self, o: Self) -> Self {
        if self.0 < o.0 { self } else { o }
    }
}

impl<F: Float> LaneOps for One<F> {
    type F = F;
    type Mask = bool;
    crate::num::real::plain_lanes!();
    #[inline(always)]
    fn splat(x: F) -> Self {
        One(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        One(Float::sqrt(self.0))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        if self.0 < F::ZERO { -self } else { self }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self.0 < o.0
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self.0 <= o.0
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self.0 > o.0
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self.0 == o.0
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.0.is_fin()
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a && b
    }
    #[inline(always)]
    fn or(a: bool, b: bool) -> bool {
        a || b
    }
    #[inline(always)]
    fn not(a: bool) -> bool {
        !a
    }
    #[inline(always)]
    fn any_set(m: bool) -> bool {
        m
    }
}
