//! Phong tessellation (Boubekeur & Alexa, "Phong Tessellation", SIGGRAPH Asia 2008).
//!
//! The point of the flat triangle at barycentrics `w`, `p(w) = Σ w_i P_i`, is projected onto
//! the tangent plane of each vertex, `π_i(p) = p − ((p − P_i)·n_i) n_i`; the projections are
//! interpolated with the same barycentrics, and the result blended with the flat point by the
//! shape factor `α`:
//!
//! ```text
//! p*(w) = (1 − α)·p(w) + α·Σ_i w_i π_i(p(w))
//! ```
//!
//! `α = 3/4` is the paper's recommended value; `α = 1` is the plain projection. Since
//! `p − P_i = Σ_j w_j (P_j − P_i)`, the sum is `p − α Σ_i Σ_j w_i w_j k_ij n_i` with
//! `k_ij = (P_j − P_i)·n_i`: a quadratic Bézier triangle whose vertices are the `P_i` and whose
//! edge controls are
//!
//! ```text
//! B_ij = (P_i + P_j)/2 − (α/2)·(k_ij n_i + k_ji n_j).
//! ```
//!
//! `B_ij` depends on the edge's two vertices and normals only, so neighbours sharing them meet
//! along the edge. The paper shades with the interpolated vertex normals (Phong shading,
//! [`QuadPatch::interpolated_normal`]).

use glam::DVec3;

use crate::quadratic::{PeerError, QuadPatch, checked};
use crate::real::Real;

/// The paper's recommended shape factor.
pub const ALPHA_DEFAULT: f64 = 0.75;

/// The Phong tessellation patch of triangle `p` with vertex normals `n` (any positive length)
/// and shape factor `alpha` (`α`; 0 is the flat triangle), as a [`QuadPatch`].
///
/// Returns [`PeerError::NonFinite`], [`PeerError::ZeroNormal`] or [`PeerError::Degenerate`]
/// (zero area) for bad input.
/// # Panics
/// Never.
pub fn phong_tessellation<F: Real>(
    p: [F::Vec3; 3],
    n: [F::Vec3; 3],
    alpha: f64,
) -> Result<QuadPatch<F>, PeerError> {
    if !alpha.is_finite() {
        return Err(PeerError::NonFinite);
    }
    let (p, n) = checked(p.map(F::to_dvec3), n.map(F::to_dvec3))?;
    Ok(QuadPatch::from_control(p, edge_controls(p, n, alpha), n))
}

/// The edge controls `[B_01, B_12, B_20]` of Phong tessellation (module docs), in `f64`.
pub fn edge_controls(p: [DVec3; 3], n: [DVec3; 3], alpha: f64) -> [DVec3; 3] {
    let b = |i: usize, j: usize| {
        let kij = (p[j] - p[i]).dot(n[i]);
        let kji = (p[i] - p[j]).dot(n[j]);
        (p[i] + p[j]) * 0.5 - (n[i] * kij + n[j] * kji) * (alpha * 0.5)
    };
    [b(0, 1), b(1, 2), b(2, 0)]
}
