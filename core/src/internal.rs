//! Not part of the API: the constants that the workspace's WGSL port mirrors and its test suite
//! checks against the kernel (each documented where it is defined). Hidden from the docs; they
//! may change in any release.

pub use crate::bvh::MAX_LEAF;
pub use crate::kernel::budget::EXTENT_EDGES;
pub use crate::kernel::refine::{
    EARLY_STOP, ESTIMATE_STEPS, INNER_OF_SPREAD, INNER_OF_STOP, OUTER_OF_INNER, OUTER_OF_SPREAD,
    OUTER_OF_WIDTH, WORST_SHRINK,
};
pub use crate::kernel::study::{Search, predictor_error, search_study};
pub use crate::kernel::{ROUNDING_ULPS, WALL_MARGIN_ULPS};
pub use crate::mesh::cracks::{CRACK_REACH, CRACK_SAMPLES, MAX_CRACK_REACH};
pub use crate::mesh::sampling::FIT_NODES;
pub use crate::mesh::seams::{FIT_SAMPLES, FREE_END_TOL, TWIST_TERMS};
pub use crate::num::real::LANES;
pub use crate::surface::band::BAND_MIN_NORMAL_COS;
pub use crate::surface::field::SECTION_NEWTON_STEPS;
pub use crate::surface::shell::{EDGE_T, MARGIN_ABS, MARGIN_REL, SAMPLES as SHELL_SAMPLES};

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

/// The edge parameters `t_s = (1 − cos((2s + 1)π / (2·CRACK_SAMPLES))) / 2` at which crack
/// closure measures the gap and the seam fit samples (its [`FIT_NODES`] of them), as the CPU's
/// builder computes them (`f64`, `libm::cos`): for a port of the update, so that it samples the
/// same points.
///
/// # Panics
/// Never.
pub fn crack_nodes() -> [f64; CRACK_SAMPLES] {
    crate::mesh::sampling::Nodes::new().all()
}

/// The seam fit's least-squares map from the [`FIT_SAMPLES`] tilt samples of an edge (at the
/// nodes [`FIT_NODES`]) to its [`TWIST_TERMS`] coefficients, `c = P·y`, as the CPU's fit
/// computes it once per build (`f64`): for a port of the fit.
///
/// # Panics
/// Never.
pub fn seam_fit_matrix() -> [[f64; FIT_SAMPLES]; TWIST_TERMS] {
    crate::mesh::seams::FitMatrix::new().rows()
}
