//! Nagata patches (T. Nagata, "Simple local interpolation of surfaces using normal vectors",
//! Computer Aided Geometric Design 22, 2005).
//!
//! Each edge `x_0 → x_1` (`d = x_1 − x_0`, unit normals `n_0`, `n_1`) becomes the quadratic
//! `x(t) = x_0 + (d − c) t + c t²` whose tangents are perpendicular to the end normals:
//! `(d − c)·n_0 = 0` and `(d + c)·n_1 = 0`. Of the curvature coefficients `c` that satisfy
//! both, Nagata takes the one of least length (a generalised inverse), which lies in the span of
//! `v = (n_0 + n_1)/2` and `Δv = (n_0 − n_1)/2` (orthogonal to each other). Writing
//! `c = a v + b Δv` and taking the sum and the difference of the two conditions:
//!
//! ```text
//! c = (d·Δv)/(1 − κ) · v + (d·v)/κ · Δv,      κ = Δv·Δv = (1 − n_0·n_1)/2,
//! ```
//!
//! and **`c = 0` (a straight edge) when `κ = 0` or `κ = 1`**: parallel or opposite normals,
//! where the conditions are singular. That is the paper's fallback; in floating point this
//! crate applies it for `κ ≤` [`PARALLEL_TOL`] or `κ ≥ 1 −` [`PARALLEL_TOL`]. Near those
//! limits `c` can grow without bound (a known trait of the scheme: nearly parallel normals
//! on an edge that is not perpendicular to them, as at a crease).
//!
//! The triangular patch is the quadratic whose three boundary curves are the edges' (Nagata's
//! `c_{20} = c_1`, `c_{02} = c_2`, `c_{11} = c_3 − c_1 − c_2` in his parameters): the quadratic
//! Bézier triangle with edge controls `B_ij = (P_i + P_j)/2 − c_ij/2`. Edges depend on their
//! two vertices and normals only, so neighbours meet. The normal is the patch's own
//! ([`QuadPatch::normal`]).

use glam::DVec3;

use crate::quadratic::{PeerError, QuadPatch, checked};
use crate::real::Real;

/// `κ = (1 − n_0·n_1)/2` at or below this (normals within about 2e-6 rad of each other), or at
/// or above `1 −` this, takes the paper's fallback `c = 0`.
pub const PARALLEL_TOL: f64 = 1e-12;

/// Nagata's curvature coefficient `c` of the edge `d = x_1 − x_0` with unit end normals `n0`,
/// `n1` (module docs), in `f64`; 0 for (nearly) parallel or opposite normals.
///
/// # Panics
/// Never.
pub fn curvature_coefficient(d: DVec3, n0: DVec3, n1: DVec3) -> DVec3 {
    let v = (n0 + n1) * 0.5;
    let dv = (n0 - n1) * 0.5;
    let kappa = dv.dot(dv);
    if !(kappa > PARALLEL_TOL && kappa < 1.0 - PARALLEL_TOL) {
        return DVec3::ZERO;
    }
    v * (d.dot(dv) / (1.0 - kappa)) + dv * (d.dot(v) / kappa)
}

/// The Nagata patch of triangle `p` with vertex normals `n` (any positive length), as a
/// [`QuadPatch`].
///
/// Returns [`PeerError::NonFinite`], [`PeerError::ZeroNormal`] or [`PeerError::Degenerate`]
/// (zero area) for bad input.
/// # Panics
/// Never.
pub fn nagata<F: Real>(p: [F::Vec3; 3], n: [F::Vec3; 3]) -> Result<QuadPatch<F>, PeerError> {
    let (p, n) = checked(p.map(F::to_dvec3), n.map(F::to_dvec3))?;
    Ok(QuadPatch::from_control(p, edge_controls(p, n), n))
}

/// The edge controls `[B_01, B_12, B_20]` of the Nagata patch, in `f64`.
pub fn edge_controls(p: [DVec3; 3], n: [DVec3; 3]) -> [DVec3; 3] {
    let b = |i: usize, j: usize| {
        let c = curvature_coefficient(p[j] - p[i], n[i], n[j]);
        (p[i] + p[j]) * 0.5 - c * 0.5
    };
    [b(0, 1), b(1, 2), b(2, 0)]
}
