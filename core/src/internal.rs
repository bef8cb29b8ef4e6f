//! Not part of the API: the constants that the workspace's WGSL port mirrors and its test suite
//! checks against the kernel (each documented where it is defined). Hidden from the docs; they
//! may change in any release.

pub use crate::bvh::MAX_LEAF;
pub use crate::kernel::refine::{
    EARLY_STOP, INNER_OF_SPREAD, INNER_OF_STOP, OUTER_OF_INNER, OUTER_OF_SPREAD, OUTER_OF_WIDTH,
    WORST_SHRINK,
};
pub use crate::kernel::{ROUNDING_ULPS, WALL_MARGIN_ULPS};
pub use crate::mesh::cracks::{CRACK_REACH, CRACK_SAMPLES, MAX_CRACK_REACH};
pub use crate::mesh::seams::{FIT_SAMPLES, TWIST_TERMS};
pub use crate::num::real::LANES;
pub use crate::surface::band::BAND_MIN_NORMAL_COS;
pub use crate::surface::field::SECTION_NEWTON_STEPS;

use crate::num::lanes::{Lane, Two};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::lanes::Prepared;

/// `patch` with an unbounded band (`core/src/surface/band.rs`): the kernel then samples every ray
/// that enters its shell. For tests that compare the cull with no cull.
///
/// # Panics
/// Never.
pub fn without_band<F: crate::Float>(patch: &crate::Patch<F>) -> crate::Patch<F> {
    crate::Patch {
        band: crate::geometry::Band::UNBOUNDED,
        ..*patch
    }
}

/// One patch's kernel precomputation, for timing the kernel's lane call at two widths
/// (`benches/kernel.rs`, "Lane call widths"): eight lanes (one ray's eight samples, the
/// kernel's call) against sixteen (two rays' eight samples each in one call, the width of one
/// AVX-512 register), on the build's target here and per instruction set in `crate::isa`
/// (`probe_f8`, `probe_f16`). Local-frame rays `o + τ·r` (the patch's frame).
#[derive(Clone, Copy, Debug)]
pub struct LaneProbe(Prepared<f32>);

impl LaneProbe {
    /// The probe of `patch`.
    ///
    /// # Panics
    /// Never.
    pub fn new(patch: &crate::Patch<f32>) -> Self {
        LaneProbe(Prepared::new(&patch.shape))
    }

    /// `f` at eight parameters of one ray: the kernel's lane call as the build's target
    /// compiles it ([`Float::L8`], out of line).
    ///
    /// # Panics
    /// Never.
    pub fn f8(&self, o: [f32; 3], r: [f32; 3], taus: [f32; LANES]) -> [f32; LANES] {
        crate::kernel::heights::eight::<f32, <f32 as Float>::L8, false>(&self.0, v3(o), v3(r), taus)
    }

    /// `f` at eight parameters of each of two rays in one call over sixteen lanes (lanes
    /// `0..8` ray 0, `8..16` ray 1): the same values, bit for bit, as two calls of
    /// [`LaneProbe::f8`]; the lane code out of line for the build's target.
    ///
    /// # Panics
    /// Never.
    pub fn f16(
        &self,
        o: [[f32; 3]; 2],
        r: [[f32; 3]; 2],
        taus: [[f32; LANES]; 2],
    ) -> [[f32; LANES]; 2] {
        self.two::<<f32 as Float>::L8>(o, r, taus, false)
    }

    /// [`LaneProbe::f16`] over the two halves of [`Two`]`<L>`, the lane code out of line or
    /// inlined into the caller (the instruction sets' probes in `crate::isa`, over
    /// [`Float::A8`]).
    #[inline(always)]
    pub(crate) fn two<L: Lane<F = f32>>(
        &self,
        o: [[f32; 3]; 2],
        r: [[f32; 3]; 2],
        taus: [[f32; LANES]; 2],
        inline: bool,
    ) -> [[f32; LANES]; 2] {
        let pair = |v: [[f32; 3]; 2], k: usize| {
            let [a, b] = v.map(|v| L::splat(v.get(k).copied().unwrap_or(0.0)));
            Two(a, b)
        };
        let [t0, t1] = taus;
        let t = Two(L::from_array(t0), L::from_array(t1));
        let (o2, r2) = ([0, 1, 2].map(|k| pair(o, k)), [0, 1, 2].map(|k| pair(r, k)));
        let f = if inline {
            self.0.f_inline(o2, r2, t)
        } else {
            self.0.f(o2, r2, t)
        };
        [f.0.to_array(), f.1.to_array()]
    }

    /// [`LaneProbe::f8`] with the lane code inlined into the caller over plain-array lanes
    /// (the instruction sets' probes in `crate::isa`).
    #[inline(always)]
    pub(crate) fn f8_inline(&self, o: [f32; 3], r: [f32; 3], taus: [f32; LANES]) -> [f32; LANES] {
        crate::kernel::heights::eight::<f32, <f32 as Float>::A8, true>(&self.0, v3(o), v3(r), taus)
    }
}

/// `[x, y, z]` as the core's vector.
fn v3([x, y, z]: [f32; 3]) -> V3<f32> {
    V3::new(x, y, z)
}
