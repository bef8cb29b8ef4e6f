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

/// Fast approximate `sqrt` of an `f32` (micromath, relative error about 5e-2 before refinement).
///
/// One Newton step is applied to the micromath estimate, which brings the relative error to
/// about 1e-3 while staying division-light; see [`crate::FastF32`].
#[cfg(feature = "micromath")]
#[inline(always)]
pub(crate) fn sqrt_fast_f32(x: f32) -> f32 {
    use micromath::F32Ext;
    if x <= 0.0 {
        return 0.0;
    }
    let y = F32Ext::sqrt(x);
    0.5 * (y + x / y)
}
