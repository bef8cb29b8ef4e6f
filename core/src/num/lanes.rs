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

use crate::num::math::{sqrt_f32, sqrt_f64};
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

/// `f` of each pair of entries of `a` and `b`, in order: the array lanes' and masks' `zip`.
#[inline(always)]
fn zip_arrays<T: Copy, const W: usize>(mut a: [T; W], b: [T; W], f: impl Fn(T, T) -> T) -> [T; W] {
    for (x, y) in a.iter_mut().zip(b) {
        *x = f(*x, y);
    }
    a
}

/// Lane types as plain arrays of `W` values, every operation a loop over the lanes with the
/// scalar's own IEEE operation: the compiler turns each loop into vector instructions of the
/// width that the *enclosing function* may use (the target's features, or those of a
/// `#[target_feature]` entry point that the lane code is inlined into: two SSE2 or NEON
/// registers or one AVX register for eight `f32`), and every lane's value is the scalar
/// operation's, bit for bit, whatever the width. Masks are lanes of the same width with all bits
/// set or clear.
macro_rules! array_lanes {
    ($name:ident, $mask:ident, $f:ty, $u:ty, $w:literal, $align:literal, $sqrt:path, $doc:literal) => {
        #[doc = $doc]
        ///
        /// # Panics
        /// No method panics.
        #[derive(Clone, Copy, Debug)]
        #[repr(C, align($align))]
        pub struct $name(pub(crate) [$f; $w]);

        /// The per-lane booleans of
        #[doc = concat!("[`", stringify!($name), "`]")]
        /// : all bits set (true) or clear (false).
        #[derive(Clone, Copy, Debug)]
        #[repr(C, align($align))]
        pub struct $mask(pub(crate) [$u; $w]);

        impl $name {
            /// `f` of each lane.
            #[inline(always)]
            fn map(self, f: impl Fn($f) -> $f) -> Self {
                let mut out = self.0;
                for x in out.iter_mut() {
                    *x = f(*x);
                }
                $name(out)
            }
            /// `f` of each pair of lanes.
            #[inline(always)]
            fn zip(self, o: Self, f: impl Fn($f, $f) -> $f) -> Self {
                $name(zip_arrays(self.0, o.0, f))
            }
            /// The mask of `f` of each pair of lanes.
            #[inline(always)]
            fn cmp(self, o: Self, f: impl Fn($f, $f) -> bool) -> $mask {
                let mut out = [0 as $u; $w];
                for ((m, x), y) in out.iter_mut().zip(self.0).zip(o.0) {
                    *m = (0 as $u).wrapping_sub(f(x, y) as $u);
                }
                $mask(out)
            }
        }

        impl $mask {
            /// `f` of each pair of lanes.
            #[inline(always)]
            fn zip(self, o: Self, f: impl Fn($u, $u) -> $u) -> Self {
                $mask(zip_arrays(self.0, o.0, f))
            }
            /// The lanes' bits, or-ed together: non-zero when any lane is set.
            #[inline(always)]
            fn or_all(self) -> $u {
                self.0.iter().fold(0, |a, &b| a | b)
            }
        }

        impl core::ops::Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                self.zip(o, |x, y| x + y)
            }
        }
        impl core::ops::Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                self.zip(o, |x, y| x - y)
            }
        }
        impl core::ops::Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                self.zip(o, |x, y| x * y)
            }
        }
        impl core::ops::Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                self.zip(o, |x, y| x / y)
            }
        }
        impl core::ops::Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.map(|x| -x)
            }
        }

        impl LaneOps for $name {
            type F = $f;
            type Mask = $mask;
            crate::num::real::plain_lanes!();
            #[inline(always)]
            fn splat(x: $f) -> Self {
                $name([x; $w])
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                self.map($sqrt)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                self.map(<$f>::abs)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $mask {
                self.cmp(o, |x, y| x < y)
            }
            #[inline(always)]
            fn le(self, o: Self) -> $mask {
                self.cmp(o, |x, y| x <= y)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> $mask {
                self.cmp(o, |x, y| x > y)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $mask {
                self.cmp(o, |x, y| x == y)
            }
            #[inline(always)]
            fn finite(self) -> $mask {
                // `x·0 = 0` exactly for finite `x` (NaN for NaN and ±∞): `is_finite` as one
                // multiply and compare per register. Written with `is_finite` (`|x| < ∞`), the
                // compiler merges it with a neighbouring comparison of the same lanes
                // (`x > 0`) into one test of the float's class, which AVX2 has no instruction
                // for, and tests each lane's bits in scalar code.
                self.cmp(self, |x, _| x * (0.0 as $f) == 0.0 as $f)
            }
            #[inline(always)]
            fn select(m: $mask, a: Self, b: Self) -> Self {
                let mut out = a.0;
                for ((x, y), m) in out.iter_mut().zip(b.0).zip(m.0) {
                    *x = <$f>::from_bits((x.to_bits() & m) | (y.to_bits() & !m));
                }
                $name(out)
            }
            #[inline(always)]
            fn and(a: $mask, b: $mask) -> $mask {
                a.zip(b, |x, y| x & y)
            }
            #[inline(always)]
            fn or(a: $mask, b: $mask) -> $mask {
                a.zip(b, |x, y| x | y)
            }
            #[inline(always)]
            fn not(a: $mask) -> $mask {
                a.zip(a, |x, _| !x)
            }
            #[inline(always)]
            fn any_set(m: $mask) -> bool {
                m.or_all() != 0
            }
        }
    };
}

/// [`array_lanes`] with the [`Lane`] items of an eight-lane type.
macro_rules! array_lane8 {
    ($name:ident, $f:ty) => {
        impl Lane for $name {
            #[inline(always)]
            fn from_array(a: [$f; LANES]) -> Self {
                $name(a)
            }
            #[inline(always)]
            fn to_array(self) -> [$f; LANES] {
                self.0
            }
            #[inline(always)]
            fn any(m: Self::Mask) -> bool {
                Self::any_set(m)
            }
            #[inline(always)]
            fn mask_array(m: Self::Mask) -> [bool; LANES] {
                m.0.map(|x| x != 0)
            }
        }
    };
}

/// [`array_lanes`] with the [`Lane4`] items of a four-lane type.
macro_rules! array_lane4 {
    ($name:ident, $f:ty) => {
        impl Lane4 for $name {
            const POINTS: usize = 4;
            #[inline(always)]
            fn from_array4(a: [$f; 4]) -> Self {
                $name(a)
            }
            #[inline(always)]
            fn to_array4(self) -> [$f; 4] {
                self.0
            }
            #[inline(always)]
            fn bits4(m: Self::Mask) -> u32 {
                let mut bits = 0u32;
                for (i, &b) in m.0.iter().enumerate() {
                    bits |= u32::from(b != 0) << i;
                }
                bits
            }
            #[inline(always)]
            fn max_fast(self, o: Self) -> Self {
                self.zip(o, |x, y| if x > y { x } else { y })
            }
            #[inline(always)]
            fn min_fast(self, o: Self) -> Self {
                self.zip(o, |x, y| if x < y { x } else { y })
            }
        }
    };
}

/// The array lane types, one row each: type, mask, scalar, mask bits, lanes, alignment, square
/// root, the lane-count trait's impl, doc.
macro_rules! lane_types {
    ($($name:ident $mask:ident $f:ty, $u:ty, $w:literal, $align:literal, $sqrt:path, $shape:ident,
       $doc:literal;)*) => {
        $(
            array_lanes!($name, $mask, $f, $u, $w, $align, $sqrt, $doc);
            $shape!($name, $f);
        )*
    };
}

lane_types! {
    F32x8 M32x8 f32, u32, 8, 32, sqrt_f32, array_lane8,
        "Eight `f32` lanes: the kernel's height evaluations ([`Float::L8`] of `f32`).";
    F64x8 M64x8 f64, u64, 8, 64, sqrt_f64, array_lane8,
        "Eight `f64` lanes ([`Float::L8`] of `f64`).";
    F32x4 M32x4 f32, u32, 4, 16, sqrt_f32, array_lane4,
        "Four `f32` lanes: the estimate step, the BVH's slab test of four children, the seamless \
         shading normal's four points ([`Float::L4`] of `f32`).";
    F64x4 M64x4 f64, u64, 4, 32, sqrt_f64, array_lane4,
        "Four `f64` lanes ([`Float::L4`] of `f64`).";
}

/// One scalar as a lane type (`Mask = bool`): the one-point evaluations over the lane code
/// (the hit normal's jets, `crate::surface::lanes::Prepared::derivatives`), the same arithmetic as the
/// scalar with branches for selects.
#[derive(Clone, Copy, Debug)]
pub struct One<F>(pub(crate) F);

/// `One`'s arithmetic: the scalar's, operator by operator.
macro_rules! one_binops {
    ($($tr:ident $m:ident $op:tt),*) => {
        $(
            impl<F: Float> core::ops::$tr for One<F> {
                type Output = Self;
                #[inline(always)]
                fn $m(self, o: Self) -> Self {
                    One(self.0 $op o.0)
                }
            }
        )*
    };
}
one_binops!(Add add +, Sub sub -, Mul mul *, Div div /);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain-array lanes' `finite` is `is_finite` in every lane, on the values where a
    /// float's class changes (zeros, subnormals, the largest finite, infinities, NaNs of both
    /// signs), and `and(gt(0), finite)` (the projection's test, which the compiler could merge
    /// into one class test) keeps exactly the positive finite lanes. (It fails when `finite`
    /// lets an infinity or a NaN through, or drops a finite lane.)
    #[test]
    fn array_lanes_finite_is_is_finite() {
        let f32s = [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
            1.5,
            -2.5,
            1e-30,
            3e38,
        ];
        for chunk in f32s.chunks_exact(8) {
            let mut a = [0.0f32; 8];
            a.copy_from_slice(chunk);
            let l = F32x8(a);
            let pos = F32x8::and(l.gt(F32x8::splat(0.0)), l.finite());
            for ((&x, &m), &p) in a.iter().zip(l.finite().0.iter()).zip(pos.0.iter()) {
                assert_eq!(m != 0, x.is_finite(), "{x:?}");
                assert_eq!(p != 0, x.is_finite() && x > 0.0, "{x:?}");
            }
        }
        for chunk in f32s.chunks_exact(4) {
            let mut a = [0.0f32; 4];
            a.copy_from_slice(chunk);
            for (&x, &m) in a.iter().zip(F32x4(a).finite().0.iter()) {
                assert_eq!(m != 0, x.is_finite(), "{x:?}");
            }
        }
        let f64s = f32s.map(|x| {
            if x.is_nan() {
                f64::from_bits(0x7ff8_0000_0000_0001)
                    * if x.is_sign_negative() { -1.0 } else { 1.0 }
            } else if x == f32::MAX {
                f64::MAX
            } else if x == f32::from_bits(1) {
                f64::from_bits(1)
            } else {
                f64::from(x)
            }
        });
        for chunk in f64s.chunks_exact(8) {
            let mut a = [0.0f64; 8];
            a.copy_from_slice(chunk);
            for (&x, &m) in a.iter().zip(F64x8(a).finite().0.iter()) {
                assert_eq!(m != 0, x.is_finite(), "{x:?}");
            }
        }
        for chunk in f64s.chunks_exact(4) {
            let mut a = [0.0f64; 4];
            a.copy_from_slice(chunk);
            for (&x, &m) in a.iter().zip(F64x4(a).finite().0.iter()) {
                assert_eq!(m != 0, x.is_finite(), "{x:?}");
            }
        }
    }
}
