//! Scalar abstraction: one source of math for `f32`, `f64` and dual numbers over them.
//!
//! [`Float`] is a primitive floating-point type (`f32` or `f64`) together with its glam vector
//! type. [`Real`] is anything the surface formulas can be evaluated in: a [`Float`] itself, or a
//! [`Dual`](crate::num::dual::Dual) number over one (which carries an exact derivative along).

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A 3-vector over any [`Real`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3<T> {
    /// x.
    pub x: T,
    /// y.
    pub y: T,
    /// z.
    pub z: T,
}

/// Number of lanes of every `Lane` type.
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
    /// Whether any lane of `m` is set (a branch around work that only such lanes need).
    fn any_set(m: Self::Mask) -> bool;
    /// The same lanes without derivatives: `Self` for plain lanes, the value lanes of a jet.
    /// Data of an evaluation (a patch's vertices, normals, edge coefficients, numeric
    /// constants) enter the formulas as `Plain`, so that a jet multiplies them without the
    /// products of their zero derivatives (which IEEE arithmetic cannot drop: `0·∞` is NaN).
    type Plain: LaneOps<F = Self::F, Mask = Self::Mask>;
    /// `p` as a value of `Self` (zero derivatives).
    fn lift(p: Self::Plain) -> Self;
    /// `self · p`: the value bit for bit `self * Self::lift(p)`'s.
    fn mul_p(self, p: Self::Plain) -> Self;
    /// `self + p` (the value bit for bit `self + Self::lift(p)`'s).
    fn add_p(self, p: Self::Plain) -> Self;
    /// `self − p` (the value bit for bit `self - Self::lift(p)`'s).
    fn sub_p(self, p: Self::Plain) -> Self;
    /// `p − self` (the value bit for bit `Self::lift(p) - self`'s).
    fn rsub_p(self, p: Self::Plain) -> Self;
    /// `p / self` (the value bit for bit `Self::lift(p) / self`'s).
    fn rdiv_p(self, p: Self::Plain) -> Self;
}

/// The [`LaneOps`] items of a type without derivatives: its own `Plain`, the mixed operations
/// its plain arithmetic.
macro_rules! plain_lanes {
    () => {
        type Plain = Self;
        #[inline(always)]
        fn lift(p: Self) -> Self {
            p
        }
        #[inline(always)]
        fn mul_p(self, p: Self) -> Self {
            self * p
        }
        #[inline(always)]
        fn add_p(self, p: Self) -> Self {
            self + p
        }
        #[inline(always)]
        fn sub_p(self, p: Self) -> Self {
            self - p
        }
        #[inline(always)]
        fn rsub_p(self, p: Self) -> Self {
            p - self
        }
        #[inline(always)]
        fn rdiv_p(self, p: Self) -> Self {
            p / self
        }
    };
}
pub(crate) use plain_lanes;

/// An 8-wide vector of the scalar [`LaneOps::F`] (see the module documentation).
///
/// # Panics
/// No method panics.
pub trait Lane: LaneOps<Plain = Self> {
    /// From the eight lane values.
    fn from_array(a: [Self::F; LANES]) -> Self;
    /// The eight lane values.
    fn to_array(self) -> [Self::F; LANES];
    /// Whether any lane of `m` is set.
    fn any(m: Self::Mask) -> bool;
    /// The lanes of `m` as booleans.
    fn mask_array(m: Self::Mask) -> [bool; LANES];
}

/// Up to four points of the scalar [`LaneOps::F`] at once: the seamless shading normal's four
/// exact normals (the hit point and the three edge points) in one height evaluation over jets.
/// `f32` and `f64` carry four points ([`wide::f32x4`], [`wide::f64x4`]); other scalars one
/// (`One`, whose jets the hit normal already instantiates: four evaluations in turn, no extra
/// code to compile).
///
/// # Panics
/// No method panics.
pub trait Lane4: LaneOps<Plain = Self> {
    /// How many of the four values one vector carries: 4, or 1 (the first).
    const POINTS: usize;
    /// From four values (the first [`Lane4::POINTS`] are kept).
    fn from_array4(a: [Self::F; 4]) -> Self;
    /// The four lane values (beyond [`Lane4::POINTS`], copies of the first).
    fn to_array4(self) -> [Self::F; 4];
    /// The lanes of `m` as the bits 0 to 3 (beyond [`Lane4::POINTS`], copies of the first).
    fn bits4(m: Self::Mask) -> u32;
    /// The larger of `self` and `o` per lane, for lanes that are not NaN (one instruction
    /// where the target has it; with a NaN or at `±0` either may be returned).
    fn max_fast(self, o: Self) -> Self;
    /// The smaller of `self` and `o` per lane, as [`Lane4::max_fast`].
    fn min_fast(self, o: Self) -> Self;
}

pub(crate) mod sealed {
    /// Seals [`Real`](super::Real): each impl stands beside its type.
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A number the patch formulas can be evaluated in: `f32`, `f64`, or a dual number over them.
///
/// Comparisons (`<`, `>`, …) compare the value part only. This trait is sealed.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + sealed::Sealed
{
    /// The primitive float under this number (`f32` or `f64`).
    type F: Float;
    /// Lifts a primitive constant (derivative zero).
    fn cst(x: Self::F) -> Self;
    /// The value part.
    fn re(self) -> Self::F;
    /// Square root of `max(self, 0)`; its derivative is taken as zero where the value is zero,
    /// so the result is never NaN for finite input.
    fn sqrt0(self) -> Self;
    /// `true` when the value and every derivative part are finite.
    fn all_finite(self) -> bool;

    /// `0`.
    #[inline(always)]
    fn zero() -> Self {
        Self::cst(Self::F::ZERO)
    }
    /// `1`.
    #[inline(always)]
    fn one() -> Self {
        Self::cst(Self::F::ONE)
    }
    /// Lifts an `f64` literal (rounded to the primitive precision).
    #[inline(always)]
    fn lit(x: f64) -> Self {
        Self::cst(Self::F::from_f64(x))
    }
    /// `max(self, 0)` with a zero derivative where clamped.
    #[inline(always)]
    fn max0(self) -> Self {
        if self.re() > Self::F::ZERO {
            self
        } else {
            Self::zero()
        }
    }
    /// `|self|`.
    #[inline(always)]
    fn abs(self) -> Self {
        if self.re() < Self::F::ZERO {
            -self
        } else {
            self
        }
    }
    /// `+1` for a value ≥ 0 (including +0 and −0), `−1` otherwise.
    #[inline(always)]
    fn sign1(self) -> Self::F {
        if self.re() < Self::F::ZERO {
            -Self::F::ONE
        } else {
            Self::F::ONE
        }
    }
}

/// A primitive float (`f32` or `f64`) with its glam vector type. This trait is sealed.
pub trait Float: Real<F = Self> + Copy + Default + PartialEq + Send + Sync {
    /// The glam 3-vector over this float (`glam::Vec3` or `glam::DVec3`).
    type Vec3: Copy + Debug + PartialEq + Send + Sync;
    /// The 8-lane vector of this float that the kernel evaluates over (internal).
    #[doc(hidden)]
    type L8: Lane<F = Self>;
    /// The 4-lane vector of this float (internal).
    #[doc(hidden)]
    type L4: Lane4<F = Self>;
    /// Eight lanes as a plain array, vectorised by the target features of the function the
    /// lane code is inlined into (internal: the kernels per instruction set of
    /// [`isa`](crate::isa)).
    #[doc(hidden)]
    type A8: Lane<F = Self>;
    /// Four lanes as a plain array, as [`Float::A8`] (internal).
    #[doc(hidden)]
    type A4: Lane4<F = Self>;
    /// `0.0`.
    const ZERO: Self;
    /// `1.0`.
    const ONE: Self;
    /// Machine epsilon (`f32::EPSILON` or `f64::EPSILON`).
    const EPSILON: Self;
    /// Smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// Largest finite number.
    const MAX: Self;
    /// The most negative finite value (`−MAX`).
    const MIN: Self;
    /// Rounds an `f64` to this precision.
    fn from_f64(x: f64) -> Self;
    /// Widens to `f64` (exact).
    fn to_f64(self) -> f64;
    /// `true` when finite (neither NaN nor infinite).
    fn is_fin(self) -> bool;
    /// `true` when NaN.
    fn is_nan(self) -> bool;
    /// Square root (correctly rounded, libm); NaN for negative input.
    fn sqrt(self) -> Self;
    /// Converts from the glam vector.
    #[doc(hidden)]
    fn from_glam(v: Self::Vec3) -> V3<Self>;
    /// Converts to the glam vector.
    #[doc(hidden)]
    fn to_glam(v: V3<Self>) -> Self::Vec3;
    /// Rounds an `f64` vector to this precision (each component once; exact for `f64`).
    ///
    /// # Panics
    /// Never.
    #[inline]
    fn from_dvec3(v: glam::DVec3) -> Self::Vec3 {
        Self::to_glam(V3 {
            x: Self::from_f64(v.x),
            y: Self::from_f64(v.y),
            z: Self::from_f64(v.z),
        })
    }
    /// Widens a vector of this precision to `f64` (exact).
    ///
    /// # Panics
    /// Never.
    #[inline]
    fn to_dvec3(v: Self::Vec3) -> glam::DVec3 {
        let w = Self::from_glam(v);
        glam::DVec3::new(w.x.to_f64(), w.y.to_f64(), w.z.to_f64())
    }
    /// The three components `[x, y, z]` of a vector of this precision (exact).
    ///
    /// # Panics
    /// Never.
    #[inline]
    fn to_array3(v: Self::Vec3) -> [Self; 3] {
        let w = Self::from_glam(v);
        [w.x, w.y, w.z]
    }
    /// The vector of three components `[x, y, z]` (exact).
    ///
    /// # Panics
    /// Never.
    #[inline]
    fn from_array3(a: [Self; 3]) -> Self::Vec3 {
        let [x, y, z] = a;
        Self::to_glam(V3 { x, y, z })
    }
    /// The smaller of two numbers (the other one if one is NaN).
    fn min(self, o: Self) -> Self;
    /// The larger of two numbers (the other one if one is NaN).
    fn max(self, o: Self) -> Self;
}
