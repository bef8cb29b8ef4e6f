//! The one place that calls `libm` (and, behind the `micromath` feature, `micromath`).
//!
//! Every transcendental operation of the crate goes through here, so the accuracy of the whole
//! crate can be read off this file: square roots are correctly rounded (error ≤ 0.5 ulp), from
//! the hardware's IEEE square root on x86 and `libm` elsewhere.

/// The correctly rounded square roots, one per precision: `wide`'s packed root of the
/// precision's 128-bit lanes (one lane used) on x86 with the named feature, `libm` elsewhere.
macro_rules! sqrt_fns {
    ($($(#[$doc:meta])* $name:ident $f:ty, $packed:ty, $feature:literal, $libm:path;)*) => {
        $(
            $(#[$doc])*
            #[inline(always)]
            pub(crate) fn $name(x: $f) -> $f {
                #[cfg(all(
                    any(target_arch = "x86", target_arch = "x86_64"),
                    target_feature = $feature
                ))]
                {
                    let [r, ..] = <$packed>::splat(x).sqrt().to_array();
                    r
                }
                #[cfg(not(all(
                    any(target_arch = "x86", target_arch = "x86_64"),
                    target_feature = $feature
                )))]
                {
                    $libm(x)
                }
            }
        )*
    };
}

sqrt_fns! {
    /// Correctly rounded `sqrt` of an `f32`. Returns NaN for negative input; callers clamp.
    ///
    /// On x86 with SSE the packed square root of `wide` (one lane used): `libm::sqrtf` is an
    /// inline `sqrtss` in the legacy SSE encoding, which in code built with AVX enabled (`-C
    /// target-feature=+avx2` or `target-cpu=native`) mixes with the VEX-encoded lane code and
    /// paid an SSE/AVX transition on every call (its cost: docs/MEASUREMENTS.md, "Notes moved
    /// from the code"). The compiler encodes `sqrtps` to match the target, and both roundings
    /// are IEEE-exact (the same bits). Elsewhere `libm`.
    sqrt_f32 f32, wide::f32x4, "sse", libm::sqrtf;
    /// Correctly rounded `sqrt` of an `f64`. Returns NaN for negative input; callers clamp.
    /// As [`sqrt_f32`]: `wide`'s packed root on x86 with SSE2, `libm` elsewhere.
    sqrt_f64 f64, wide::f64x2, "sse2", libm::sqrt;
}

/// Fast approximate `sqrt` of an `f32`: micromath's bit-level estimate (relative error up to
/// 5.8e-2, measured) refined by one Newton step (relative error below
/// [`FASTF32_SQRT_REL`](crate::accuracy::FASTF32_SQRT_REL), measured in
/// `tests/fast.rs`). Returns 0 for non-positive input. Used by `FastF32`.
#[cfg(feature = "micromath")]
#[inline(always)]
pub(crate) fn sqrt_fast_f32(x: f32) -> f32 {
    if x <= 0.0 {
        return 0.0;
    }
    let y = micromath::F32Ext::sqrt(x);
    0.5 * (y + x / y)
}
