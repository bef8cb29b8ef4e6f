//! The one place that calls `libm` (and, behind the `micromath` feature, `micromath`).
//!
//! Every transcendental operation of the crate goes through here, so the accuracy of the whole
//! crate can be read off this file: `libm` square roots are correctly rounded (error ≤ 0.5 ulp).

/// Correctly rounded `sqrt` of an `f32` (libm). Returns NaN for negative input; callers clamp.
#[inline(always)]
pub(crate) fn sqrt_f32(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// Correctly rounded `sqrt` of an `f64` (libm). Returns NaN for negative input; callers clamp.
#[inline(always)]
pub(crate) fn sqrt_f64(x: f64) -> f64 {
    libm::sqrt(x)
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
