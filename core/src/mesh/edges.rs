//! The shared-edge pass: for every edge two patches share, the gap between their edge curves
//! (crack closure) and, with seams, both sides' fits of the common normal, from one evaluation
//! of the two neighbours' surfaces. The builder, an update, [`close_cracks`] and [`fit_seams`]
//! all run this one pass.
//!
//! Each edge's result is a pure function of its two patches: the pass computes them block by
//! block into the caller's [`EdgeWork`] on the executor's threads, then applies them in edge
//! order on the calling thread, so the result does not depend on the executor.

use super::cracks::{CrackReport, apply_gap, pair_gap};
use super::parallel::EdgeWork;
use super::seams::{FitMatrix, Seam, apply_fit, gap_and_fit};
use super::topology::{EdgePair, MeshError, SharedEdge, edge_pair, pair_shared_edges};
#[cfg(doc)]
use super::{
    cracks::{CRACK_REACH, MAX_CRACK_REACH},
    seams::{FIT_SAMPLES, TWIST_TERMS},
};
use crate::exec::Executor;
use crate::num::real::Float;
use crate::patch::Patch;

/// What the pass computes per edge, and where its results go.
pub(crate) struct EdgeSink<'s, F: Float> {
    /// The patches, widened where `close` (their reach over each shared edge).
    pub(crate) patches: Patches<'s, F>,
    /// With seams: where both sides' fits go (one [`Seam`] per patch, reset first).
    pub(crate) seams: Option<&'s mut [Seam<F>]>,
    /// What crack closure measured.
    pub(crate) cracks: CrackReport,
    /// Shared edges whose seams were fitted.
    pub(crate) fitted: usize,
}

/// The patches of an edge pass: widened (crack closure) or only read (the seam fit alone).
pub(crate) enum Patches<'s, F: Float> {
    /// Measured and widened.
    Close(&'s mut [Patch<F>]),
    /// Only read.
    Read(&'s [Patch<F>]),
}

impl<F: Float> Patches<'_, F> {
    fn view(&self) -> &[Patch<F>] {
        match self {
            Patches::Close(p) => p,
            Patches::Read(p) => p,
        }
    }
}

/// Runs the pass over the shared edges `pairs` (as [`pair_shared_edges`] left them) in blocks
/// of `work.len()` edges (at least one) on `executor`, calling `progress(done, total)` after
/// each block. Edges with a placeholder on either side ([`Patch::rejected`]) are not shared
/// edges: nothing is measured or fitted there. Reaches are reset to 0 first (where `close`),
/// seams to zeros; each widened patch's box is fitted once, after the last block, on
/// `executor`.
///
/// [`pair_shared_edges`]: super::topology::pair_shared_edges
pub(crate) fn edge_pass<F: Float>(
    sink: &mut EdgeSink<'_, F>,
    pairs: &[SharedEdge],
    work: &mut [EdgeWork<F>],
    executor: &impl Executor,
    mut progress: impl FnMut(usize, usize),
) {
    // Reaches are set edge by edge below and each patch's box fitted once at the end.
    if let Patches::Close(p) = &mut sink.patches {
        for patch in p.iter_mut() {
            patch.set_reach([F::ZERO; 3]);
        }
    }
    if let Some(seams) = sink.seams.as_deref_mut() {
        for s in seams.iter_mut() {
            *s = Seam::default();
        }
    }
    let with_seams = sink.seams.is_some();
    let fit = FitMatrix::new();
    let n = pairs.len();
    let mut one = [EdgeWork::default()];
    let work = if work.is_empty() { &mut one[..] } else { work };
    let step = work.len();
    let mut start = 0usize;
    while start < n {
        let len = step.min(n - start);
        let Some(block) = work.get_mut(..len) else {
            break;
        };
        let view = sink.patches.view();
        executor.run_chunks(block, 64, &|first, chunk| {
            for (k, w) in chunk.iter_mut().enumerate() {
                // A negative gap marks an edge that is not shared by two patches.
                let Some(e) = shared(view, pairs, start + first + k) else {
                    (w.gap, w.fit) = (-1.0, None);
                    continue;
                };
                (w.gap, w.fit) = if with_seams {
                    gap_and_fit(&fit, view, e)
                } else {
                    (pair_gap(&fit.nodes, view, e), None)
                };
            }
        });
        for (k, w) in block.iter().enumerate() {
            let Some(e) = edge_pair(pairs, start + k) else {
                continue;
            };
            if w.gap < 0.0 {
                continue;
            }
            if let Patches::Close(p) = &mut sink.patches {
                apply_gap(p, e, w.gap, &mut sink.cracks);
            } else {
                sink.cracks.shared_edges += 1;
            }
            if let Some(seams) = sink.seams.as_deref_mut() {
                sink.fitted += usize::from(apply_fit(seams, e, w.fit));
            }
        }
        start += len;
        progress(start, n);
    }
    // Each box once, from its three final reaches (a pure function of the patch: any order).
    if let Patches::Close(p) = &mut sink.patches {
        executor.run_chunks(p, 256, &|_, chunk| {
            for patch in chunk.iter_mut() {
                patch.fit_box();
            }
        });
    }
}

/// Shared edge `k` of `pairs` when both of its patches are patches (not placeholders).
#[inline]
fn shared<F: Float>(patches: &[Patch<F>], pairs: &[SharedEdge], k: usize) -> Option<EdgePair> {
    let e = edge_pair(pairs, k)?;
    let real = |t: usize| patches.get(t).is_some_and(|p| p.rejected().is_none());
    (real(e.ta) && real(e.tb)).then_some(e)
}

/// Measures, for every edge shared by two patches, the gap between the two neighbours' edge
/// curves at `CRACK_SAMPLES` = 16 points (heights evaluated in `F` as the kernel evaluates
/// them, world points placed in `f64`), and sets each neighbour's reach across that edge to
/// [`CRACK_REACH`] times the widest gap (over the wall's altitude, in barycentric units, at
/// most [`MAX_CRACK_REACH`]); the patches' bounding boxes grow to match. Reaches of boundary edges, non-manifold edges and lone triangles are reset to 0, so
/// calling it again gives the same patches.
///
/// `patches[i]` must be the patch of triangle `triangles[i]` (vertex indices in the patch's
/// vertex order, `< vertex_count`); `scratch` holds at least `3 × triangles.len()` entries
/// (contents on return unspecified). Edges are matched by vertex index as in
/// [`fit_seams`]. Call it after building the patches and before
/// building the [`Bvh`](crate::bvh::Bvh) (which reads their boxes).
///
/// Returns the [`CrackReport`], or a [`MeshError`] when the lengths differ, the scratch is
/// too small, or an index is out of range or repeated within a triangle (the patches are
/// then unchanged).
///
/// Work: `2·CRACK_SAMPLES` surface-point evaluations per shared edge (the kernel's height)
/// and one heapsort of the
/// edges (`O(n log n)`, in place, no allocation). The kernel's work per ray is unchanged.
///
/// # Accuracy
/// A crossing found in a patch's reach lies on the band that continues the patch beyond its
/// edge, within the hit's `t_error` of it; the band extends at most `CRACK_REACH · gap` (and
/// at most [`MAX_CRACK_REACH`] of the altitude) from the edge curve, and within the patch's
/// height range. The reported normal there is the edge's (barycentrics are projected).
/// # Panics
/// Never.
pub fn close_cracks<F: Float>(
    patches: &mut [Patch<F>],
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &mut [SharedEdge],
) -> Result<CrackReport, MeshError> {
    if triangles.len() != patches.len() {
        return Err(MeshError::PatchCount {
            patches: patches.len(),
            triangles: triangles.len(),
        });
    }
    let n = pair_shared_edges(triangles, vertex_count, scratch)?;
    let pairs = scratch.get(..n).unwrap_or(&[]);
    let mut sink = EdgeSink {
        patches: Patches::Close(patches),
        seams: None,
        cracks: CrackReport::default(),
        fitted: 0,
    };
    edge_pass(&mut sink, pairs, &mut [], &(), |_, _| {});
    Ok(sink.cracks)
}

/// Fits the [`Seam`]s of a mesh's patches: for every edge shared by exactly two triangles that
/// traverse it in opposite directions, the common normal's two tilts for both sides (least
/// squares on [`FIT_SAMPLES`] points, [`TWIST_TERMS`] terms; the surface sampled in `F` as
/// the kernel evaluates it, the fit in `f64`), or, where the two sides' vertex normals differ
/// at an end, each side's copy of the other's ([`Seam::free`]). Non-manifold edges are not joined: three or more sheets meeting at an
/// edge (a fin, a T-junction) have no common normal.
///
/// `patches[i]` must be the patch of triangle `triangles[i]` (vertex indices in the patch's
/// vertex order, `< vertex_count`); `seams` receives one [`Seam`] per patch (overwritten);
/// `scratch` holds at least `3 × triangles.len()` entries (its contents on return are
/// unspecified). Edges are matched by their vertex indices, so vertices that should be smooth
/// across an edge must share the index (a split vertex makes a boundary). Boundary edges,
/// edges of more than two triangles, edges traversed twice in the same direction, edges whose
/// endpoints do not coincide in the two patches (beyond `√ε` of the edge's length), edges where
/// the common normal is within about 0.06° of perpendicular to the interpolated vertex normals
/// and edges whose fit is not finite get zeros: no correction.
///
/// Returns the number of shared edges fitted, or a [`MeshError`] when the lengths differ, the
/// scratch is too small, or an index is out of range or repeated within a triangle.
///
/// Work: `2·FIT_SAMPLES` normal evaluations per shared edge (height evaluations over
/// value-and-derivative jets, as the kernel's hit normal, with the two edge curves that meet
/// the shared edge's ends evaluated once per side) and one
/// heapsort of the edges
/// (`O(n log n)`, in place, no allocation).
///
/// # Accuracy
/// Both sides' fits agree to rounding, so the jump of [`Seam::shading_normal`] across every
/// fitted edge is at rounding level: see [`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG).
/// # Panics
/// Never.
pub fn fit_seams<F: Float>(
    patches: &[Patch<F>],
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &mut [SharedEdge],
    seams: &mut [Seam<F>],
) -> Result<usize, MeshError> {
    let n = patches.len();
    if triangles.len() != n || seams.len() != n {
        return Err(MeshError::LengthMismatch {
            patches: n,
            triangles: triangles.len(),
            seams: seams.len(),
        });
    }
    let m = pair_shared_edges(triangles, vertex_count, scratch)?;
    let pairs = scratch.get(..m).unwrap_or(&[]);
    let mut sink = EdgeSink {
        patches: Patches::Read(patches),
        seams: Some(seams),
        cracks: CrackReport::default(),
        fitted: 0,
    };
    edge_pass(&mut sink, pairs, &mut [], &(), |_, _| {});
    Ok(sink.fitted)
}
