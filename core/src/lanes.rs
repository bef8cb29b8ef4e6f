//! Eight evaluations at once: the lane type the kernel evaluates its height function over.
//!
//! [`Lane`] is an 8-wide vector of one precision with the few operations the kernel needs
//! (arithmetic, square root, comparisons into masks, selects). Every precision names its lane
//! type through [`Float::L8`]: `f32` uses [`wide::f32x8`] and `f64` [`wide::f64x8`] (from the
//! `wide` crate with default features off: no_std; AVX/AVX2 when the target enables them, two
//! SSE2 or NEON halves otherwise, a scalar fallback elsewhere), and other scalars (`FastF32`) the
//! portable [`Lanes8`] array. The kernel's arithmetic is written once, over [`Lane`], with
//! selects instead of branches, so one call costs about as much as one scalar evaluation on
//! AVX2 (docs/METHOD.md §8).
//!
//! How an embedding renderer gets the wide instructions: compile with the target's features,
//! e.g. `RUSTFLAGS="-C target-cpu=native"` or `-C target-feature=+avx2,+fma` on x86-64 (NEON is
//! on by default on aarch64). Without them the code is still correct, using SSE2 halves.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::real::Float;

/// Number of lanes of every [`Lane`] type.
pub const LANES: usize = 8;

/// The arithmetic the kernel's height evaluation is written over: lanes of a scalar (or, for
/// the exact normal, a scalar with its derivatives), with comparisons into masks and selects
/// instead of branches.
///
/// Comparisons are IEEE (false for NaN operands); masks combine with [`LaneOps::and`],
/// [`LaneOps::or`], [`LaneOps::not`] and choose values with [`LaneOps::select`].
///
/// # Panics
/// No method panics.
pub trait LaneOps:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The scalar.
    type F: Float;
    /// A per-lane boolean.
    type Mask: Copy;
    /// Every lane `x`.
    fn splat(x: Self::F) -> Self;
    /// Square root per lane (correctly rounded; NaN for negative lanes).
    fn sqrt(self) -> Self;
    /// Absolute value per lane.
    fn abs(self) -> Self;
    /// `self < o` per lane.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self <= o` per lane.
    fn le(self, o: Self) -> Self::Mask;
    /// `self > o` per lane.
    fn gt(self, o: Self) -> Self::Mask;
    /// `self == o` per lane.
    fn eq(self, o: Self) -> Self::Mask;
    /// Finite (not NaN, not infinite) per lane.
    fn finite(self) -> Self::Mask;
    /// Per lane: `a` where `m`, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Lane-wise and.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lane-wise or.
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lane-wise not.
    fn not(a: Self::Mask) -> Self::Mask;
}

/// An 8-wide vector of the scalar [`LaneOps::F`] (see the module documentation).
///
/// # Panics
/// No method panics.
pub trait Lane: LaneOps {
    /// From the eight lane values.
    fn from_array(a: [Self::F; LANES]) -> Self;
    /// The eight lane values.
    fn to_array(self) -> [Self::F; LANES];
    /// Whether any lane of `m` is set.
    fn any(m: Self::Mask) -> bool;
    /// The lanes of `m` as booleans.
    fn mask_array(m: Self::Mask) -> [bool; LANES];
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
        impl LaneOps for $l {
            type F = $f;
            type Mask = $l;
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
        }
    };
}

impl_wide!(wide::f32x8, f32);
impl_wide!(wide::f64x8, f64);

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
}
