//! The two neighbours' surfaces along a shared edge, sampled once at [`EDGE_SAMPLES`] nodes
//! for both crack closure (the widest gap between the two surfaces' edges, at all of them)
//! and the seam fit (their geometric normals, at the [`FIT_NODES`] among them).

use super::topology::edge_bary;
use crate::geometry::{Frame, Shape};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::surface::lanes::{OnEdge, Prepared};
use crate::surface::scalar;

/// Samples per shared edge, at the Chebyshev nodes `t_s = (1 − cos((2s + 1)π / (2·16))) / 2`
/// ([`Nodes`]): [`CRACK_SAMPLES`](super::cracks::CRACK_SAMPLES).
pub(crate) const EDGE_SAMPLES: usize = 16;
const _: () = assert!(EDGE_SAMPLES.is_multiple_of(2));

/// The nodes at which the seam fit takes the geometric normals
/// ([`FIT_SAMPLES`](super::seams::FIT_SAMPLES) of them): every other node, the odd ones in the
/// first half and the even ones in the second, so that the set is symmetric
/// (`FIT_NODES[i] + FIT_NODES[7 − i] = 15`: the second side, which runs the edge backwards,
/// samples the same points) and holds the two nodes nearest the middle.
pub const FIT_NODES: [usize; 8] = [1, 3, 5, 7, 8, 10, 12, 14];

/// The other nodes, where only the points are needed (the gap).
const POINT_NODES: [usize; 8] = [0, 2, 4, 6, 9, 11, 13, 15];
// Checked at compile time (an index out of range fails the build, never a run): the fit's
// nodes are symmetric and increasing, and the two sets split the nodes.
#[allow(clippy::indexing_slicing)]
const _: () = {
    let mut seen = [false; EDGE_SAMPLES];
    let mut i = 0;
    while i < 8 {
        assert!(FIT_NODES[i] + FIT_NODES[7 - i] == EDGE_SAMPLES - 1);
        assert!(i == 0 || FIT_NODES[i - 1] < FIT_NODES[i]);
        assert!(!seen[FIT_NODES[i]] && !seen[POINT_NODES[i]] && FIT_NODES[i] != POINT_NODES[i]);
        seen[FIT_NODES[i]] = true;
        seen[POINT_NODES[i]] = true;
        i += 1;
    }
};

/// The edge parameters of the samples ([`EDGE_SAMPLES`] Chebyshev nodes, crowded toward the
/// vertices; symmetric: `1 − t_s = t_{15−s}` to rounding).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nodes {
    t: [f64; EDGE_SAMPLES],
}

impl Nodes {
    /// The nodes (sixteen cosines, once per build).
    pub(crate) fn new() -> Self {
        Nodes {
            t: core::array::from_fn(|s| {
                let a = (2 * s + 1) as f64 * core::f64::consts::PI / (2 * EDGE_SAMPLES) as f64;
                0.5 * (1.0 - libm::cos(a))
            }),
        }
    }

    /// All the nodes, in order.
    pub(crate) fn all(&self) -> [f64; EDGE_SAMPLES] {
        self.t
    }

    /// Node `s` (0.5 out of range).
    #[inline(always)]
    pub(crate) fn t(&self, s: usize) -> f64 {
        self.t.get(s).copied().unwrap_or(0.5)
    }

    /// The fit's sample `i`: node [`FIT_NODES`]`[i]` (0.5 out of range).
    #[inline(always)]
    pub(crate) fn fit_t(&self, i: usize) -> f64 {
        self.t(FIT_NODES.get(i).copied().unwrap_or(usize::MAX))
    }
}

/// One neighbour of a shared edge: its frame and shape widened to `f64` (for the world points
/// and the fit), its own shape and height precomputation in the scene's precision `F` (for the
/// surface evaluations, as the kernel evaluates it), and which of its edges is shared (run
/// backwards by the second side, so that both sides' samples `s` are the same points of the
/// edge).
pub(crate) struct Side<F: Float> {
    pub(crate) frame: Frame<f64>,
    pub(crate) shape: Shape<f64>,
    own: Shape<F>,
    prepared: Prepared<F>,
    pub(crate) edge: usize,
    backwards: bool,
}

/// Nodes per surface evaluation (four lanes of [`Float::L4`]).
const CHUNK: usize = 4;
const _: () = assert!(EDGE_SAMPLES.is_multiple_of(CHUNK));

impl<F: Float> Side<F> {
    /// Edge `edge` of `patch`, forwards (the first side) or `backwards` (the second).
    pub(crate) fn new(patch: &Patch<F>, edge: usize, backwards: bool) -> Self {
        let (frame, shape) = patch.widened();
        Side {
            prepared: Prepared::new(&patch.shape),
            own: patch.shape,
            frame,
            shape,
            edge,
            backwards,
        }
    }

    /// This side's own edge parameter of node `t`.
    #[inline(always)]
    pub(crate) fn own_t(&self, t: f64) -> f64 {
        if self.backwards { 1.0 - t } else { t }
    }

    /// The barycentrics of nodes `group`, in `f64` and rounded to `F`.
    #[inline(always)]
    fn chunk(&self, nodes: &Nodes, group: &[usize]) -> ([[f64; 3]; CHUNK], [[F; 3]; CHUNK]) {
        let xs: [[f64; 3]; CHUNK] = core::array::from_fn(|i| {
            self.bary(nodes.t(group.get(i).copied().unwrap_or(usize::MAX)))
        });
        (xs, xs.map(|x| x.map(F::from_f64)))
    }

    /// World surface points at the nodes: the heights evaluated in `F` (four nodes per
    /// evaluation, [`heights`]), placed in `f64` over the `f64` barycentrics, so that
    /// two sides differ only by their surfaces' heights and the frames' rounding.
    pub(crate) fn points(&self, nodes: &Nodes) -> [V3<f64>; EDGE_SAMPLES] {
        let mut out = [V3::zero(); EDGE_SAMPLES];
        let ends = self.prepared.on_edge(self.edge);
        for (k, o) in out.chunks_exact_mut(CHUNK).enumerate() {
            let group: [usize; CHUNK] = core::array::from_fn(|i| CHUNK * k + i);
            let (xs, xf) = self.chunk(nodes, &group);
            let hs = heights(&ends, xf);
            for ((o, x), h) in o.iter_mut().zip(xs).zip(hs) {
                *o = self.world(x, h.to_f64());
            }
        }
        out
    }

    /// The world surface points at the nodes `group` (four), into `out` (indexed by node).
    #[inline(always)]
    fn points_at(
        &self,
        nodes: &Nodes,
        ends: &OnEdge<'_, F>,
        group: &[usize],
        out: &mut [V3<f64>; EDGE_SAMPLES],
    ) {
        let (xs, xf) = self.chunk(nodes, group);
        let hs = heights(ends, xf);
        for ((&s, x), h) in group.iter().zip(xs).zip(hs) {
            if let Some(o) = out.get_mut(s) {
                *o = self.world(x, h.to_f64());
            }
        }
    }

    /// World surface points at all nodes (bit for bit [`Side::points`]) and local-frame unit
    /// geometric normals at the [`FIT_NODES`] (there the heights' jets in `F`, four nodes per
    /// evaluation, the edge curves at the edge's ends evaluated once per side:
    /// [`heights_derivatives`]; the normal from the widened derivatives; elsewhere the heights
    /// alone).
    pub(crate) fn points_normals(
        &self,
        nodes: &Nodes,
    ) -> ([V3<f64>; EDGE_SAMPLES], [V3<f64>; FIT_NODES.len()]) {
        let mut pts = [V3::zero(); EDGE_SAMPLES];
        let mut nrm = [V3::zero(); FIT_NODES.len()];
        // The edge curves at the shared edge's ends, once for all nodes.
        let ends = self.prepared.on_edge(self.edge);
        for group in POINT_NODES.chunks_exact(CHUNK) {
            self.points_at(nodes, &ends, group, &mut pts);
        }
        for (group, n) in FIT_NODES
            .chunks_exact(CHUNK)
            .zip(nrm.chunks_exact_mut(CHUNK))
        {
            let (xs, xf) = self.chunk(nodes, group);
            let hd = heights_derivatives(&self.own, &ends, xf);
            for (((&s, n), x), (h, [d1, d2])) in group.iter().zip(n).zip(xs).zip(hd) {
                if let Some(p) = pts.get_mut(s) {
                    *p = self.world(x, h.to_f64());
                }
                *n = scalar::normal_local(&self.shape, x, widen(d1), widen(d2));
            }
        }
        (pts, nrm)
    }

    /// Barycentrics of node `t`.
    #[inline(always)]
    fn bary(&self, t: f64) -> [f64; 3] {
        edge_bary(self.edge, self.own_t(t))
    }

    /// The world point of barycentrics `x` at height `h`.
    #[inline(always)]
    fn world(&self, x: [f64; 3], h: f64) -> V3<f64> {
        self.frame
            .local_to_world(scalar::point_from_height(&self.shape, x, h))
    }
}

/// `v` in `f64`.
#[inline(always)]
fn widen<F: Float>(v: V3<F>) -> V3<f64> {
    V3::new(v.x.to_f64(), v.y.to_f64(), v.z.to_f64())
}

/// The heights at four points of the shared edge ([`OnEdge::heights_x4`]: bit for bit the
/// general evaluation's, the edge curves at the edge's ends evaluated once per side). Not
/// inlined: one copy per precision, called in a loop.
#[inline(never)]
fn heights<F: Float>(on: &OnEdge<'_, F>, xs: [[F; 3]; CHUNK]) -> [F; CHUNK] {
    on.heights_x4(xs)
}

/// The heights (bit for bit [`heights`]') and the local-frame surface derivatives at four
/// points of the shared edge of `shape` ([`OnEdge::height_derivatives_x4`], jets over four
/// lanes). Not inlined, as [`heights`].
#[inline(never)]
fn heights_derivatives<F: Float>(
    shape: &Shape<F>,
    on: &OnEdge<'_, F>,
    xs: [[F; 3]; CHUNK],
) -> [(F, [V3<F>; 2]); CHUNK] {
    on.height_derivatives_x4(shape, xs)
}

/// The widest distance between corresponding samples, `+∞` when one is not finite.
pub(crate) fn widest_gap(a: &[V3<f64>; EDGE_SAMPLES], b: &[V3<f64>; EDGE_SAMPLES]) -> f64 {
    let mut widest = 0.0f64;
    for (a, b) in a.iter().zip(b.iter()) {
        let d = (*a - *b).length();
        if !d.is_finite() {
            return f64::INFINITY;
        }
        widest = widest.max(d);
    }
    widest
}
