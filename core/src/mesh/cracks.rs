//! Closing the cracks between neighbouring patches in the kernel (docs/METHOD.md §8, "Cracks").
//!
//! Two patches that share a mesh edge do not always share their edge curve: each triangle's
//! line field `di = ni / (ni·Nf)` depends on its own face normal, so on meshes whose vertex
//! normals do not satisfy `(na·NA)/(nb·NA) = (na·NB)/(nb·NB)` (irregular meshes, the teapot's
//! remedied patches) the two curves part by a gap, and a ray aimed between them would pass
//! through both patches' shells. [`close_cracks`](super::close_cracks) measures that gap once per mesh, for every
//! shared edge, and widens each neighbour's domain across the edge by [`CRACK_REACH`] times
//! the gap, so that the two patches overlap there instead of parting. Beyond its edge a patch
//! continues along its tangent plane at the edge (the plane normal to the interpolated vertex
//! normal there, so the continuation is first order up to the angle between that and the
//! surface normal): a narrow band that meets the neighbour's surface or band. The closest-hit
//! rule of the BVH then keeps the nearer of the two.
//!
//! Meshes whose neighbours share their curves (the torus, spheres, the cube: gaps at the
//! rounding level) get reaches of the order of the rounding, and their patches' surfaces are
//! unchanged everywhere. Nothing changes inside a triangle.

use super::sampling::{EDGE_SAMPLES, Nodes, Side, widest_gap};
use super::topology::EdgePair;
use crate::num::real::Float;
use crate::patch::Patch;

/// How far each neighbour's domain reaches across a shared edge, in multiples of the widest
/// gap measured between the two edge curves (world length `CRACK_REACH · gap`, at most
/// [`MAX_CRACK_REACH`] of the wall's altitude).
///
/// Derivation. In the plane across the edge the two curves end at points `a` and `b`,
/// `gap = |b − a|` apart, and each patch continues beyond its end along its tangent plane
/// there (to within the angle between its surface normal and the interpolated vertex normal;
/// `crate::scalar::height` `beyond_edge`). Two continuations at a dihedral angle `θ` cross once each
/// has run about `gap / sin θ`; when they are nearly parallel, at most `gap` apart, a ray
/// between them must run along both for their overlap `2·reach − gap` while it rises by `gap`,
/// so it passes only if it is within `atan(gap / (2·reach − gap))` of the surface: 8.1° (82°
/// off the normal) for four gaps. The gap is the widest of `CRACK_SAMPLES` = 16 points, not of
/// the whole curve, which the factor also covers. Measured (`tests/suite/watertight.rs`, thousands
/// of rays per mesh aimed between the two curves, up to 80° off both normals): with one gap
/// 1 to 7 rays per mesh still fall through, with two the teapot's f64 rays still do, with four
/// none on any mesh whose reach stays below [`MAX_CRACK_REACH`].
pub const CRACK_REACH: f64 = 4.0;

pub use crate::kernel::MAX_CRACK_REACH;

/// Points per shared edge at which [`close_cracks`](super::close_cracks) measures the gap: the 16 Chebyshev nodes
/// `t_s = (1 − cos((2s + 1)π / 32)) / 2`, 8 of which the seam fit samples too
/// ([`FIT_SAMPLES`](crate::mesh::seams::FIT_SAMPLES)), so that the builder evaluates each
/// neighbour's surface there once for both; two surface evaluations each.
pub const CRACK_SAMPLES: usize = EDGE_SAMPLES;

/// What [`close_cracks`](super::close_cracks) measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CrackReport {
    /// Edges shared by exactly two patches (traversed in opposite directions).
    pub shared_edges: usize,
    /// Of those, the edges whose two curves part (a non-zero gap at some sample).
    pub open_edges: usize,
    /// The widest gap between two neighbours' edge curves (world length, `f64`).
    pub widest_gap: f64,
}

/// The gap of shared edge `pair` ([`edge_gap`]); 0 when an index is out of range.
#[inline]
pub(crate) fn pair_gap<F: Float>(nodes: &Nodes, patches: &[Patch<F>], pair: EdgePair) -> f64 {
    match (patches.get(pair.ta), patches.get(pair.tb)) {
        (Some(pa), Some(pb)) => edge_gap(nodes, pa, pair.ja, pb, pair.jb),
        _ => 0.0,
    }
}

/// Counts shared edge `pair` in `report` and widens both neighbours' walls over it to its
/// `gap`.
pub(crate) fn apply_gap<F: Float>(
    patches: &mut [Patch<F>],
    pair: EdgePair,
    gap: f64,
    report: &mut CrackReport,
) {
    report.shared_edges += 1;
    if !(gap > 0.0) {
        return;
    }
    report.open_edges += 1;
    report.widest_gap = report.widest_gap.max(gap);
    for (t, j) in [(pair.ta, pair.ja), (pair.tb, pair.jb)] {
        if let Some(p) = patches.get_mut(t) {
            widen_wall(p, j, gap);
        }
    }
}

/// The widest distance between the surfaces of `pa` along its edge `ja` (from its vertex `ja`
/// to `ja + 1`) and of `pb` along its edge `jb` (the same edge, traversed the other way) at
/// the [`CRACK_SAMPLES`] nodes, world length; `+∞` when a sample is not finite.
pub(crate) fn edge_gap<F: Float>(
    nodes: &Nodes,
    pa: &Patch<F>,
    ja: usize,
    pb: &Patch<F>,
    jb: usize,
) -> f64 {
    let a = Side::new(pa, ja, false).points(nodes);
    let b = Side::new(pb, jb, true).points(nodes);
    widest_gap(&a, &b)
}

/// Sets the reach of `patch`'s wall over edge `j` (from `Pj` to `Pj+1`, the wall opposite
/// vertex `j + 2`) to `CRACK_REACH · gap` over that wall's altitude; a reach that is not
/// finite (an unbounded gap) is left at 0. The box is fitted by the edge pass once every
/// reach is set ([`Patch::fit_box`]).
fn widen_wall<F: Float>(patch: &mut Patch<F>, j: usize, gap: f64) {
    let [p0, p1, p2] = patch.shape.p;
    let (a, b) = match j % 3 {
        0 => (p0, p1),
        1 => (p1, p2),
        _ => (p2, p0),
    };
    let len = (b - a).length().to_f64();
    // Twice the area: the frame puts P1 on the x axis and P2 in the xy-plane.
    let area2 = (p1.x * p2.y).to_f64();
    let r = F::from_f64((CRACK_REACH * gap * len / area2).min(MAX_CRACK_REACH));
    let mut reach = patch.reach();
    if let Some(slot) = reach.get_mut((j + 2) % 3)
        && r.is_fin()
        && r >= F::ZERO
    {
        *slot = r;
        patch.set_reach(reach);
    }
}
