//! The two neighbours' surfaces along a shared edge, sampled once at [`EDGE_SAMPLES`] nodes
//! for both crack closure (the widest gap between the two surfaces' edges) and the seam fit
//! (their geometric normals there).

use super::topology::edge_bary;
use crate::geometry::{Frame, Shape};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::surface::height::{self, Prepared};
use crate::surface::scalar;

/// Samples per shared edge, at the Chebyshev nodes `t_s = (1 − cos((2s + 1)π / (2·16))) / 2`
/// ([`Nodes`]); both [`CRACK_SAMPLES`](super::cracks::CRACK_SAMPLES) and
/// [`FIT_SAMPLES`](super::seams::FIT_SAMPLES).
pub(crate) const EDGE_SAMPLES: usize = 16;
const _: () = assert!(EDGE_SAMPLES.is_multiple_of(2));

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

    /// Node `s` (0.5 out of range).
    #[inline(always)]
    pub(crate) fn t(&self, s: usize) -> f64 {
        self.t.get(s).copied().unwrap_or(0.5)
    }
}

/// One neighbour of a shared edge, widened to `f64`: its frame, shape and height
/// precomputation, and which of its edges is shared (run backwards by the second side, so that
/// both sides' samples `s` are the same points of the edge).
pub(crate) struct Side {
    pub(crate) frame: Frame<f64>,
    pub(crate) shape: Shape<f64>,
    prepared: Prepared<f64>,
    pub(crate) edge: usize,
    backwards: bool,
}

impl Side {
    /// Edge `edge` of `patch`, forwards (the first side) or `backwards` (the second).
    pub(crate) fn new<F: Float>(patch: &Patch<F>, edge: usize, backwards: bool) -> Self {
        let (frame, shape) = patch.widened();
        Side {
            prepared: Prepared::new(&shape),
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

    /// World surface points at the nodes.
    pub(crate) fn points(&self, nodes: &Nodes) -> [V3<f64>; EDGE_SAMPLES] {
        let mut out = [V3::zero(); EDGE_SAMPLES];
        for (k, o) in out.chunks_exact_mut(2).enumerate() {
            let xs = [self.bary(nodes.t(2 * k)), self.bary(nodes.t(2 * k + 1))];
            for ((o, x), h) in o.iter_mut().zip(xs).zip(heights(&self.prepared, xs)) {
                *o = self.world(x, h);
            }
        }
        out
    }

    /// World surface points (bit for bit [`Side::points`]) and local-frame unit geometric
    /// normals at the nodes (one height evaluation over jets each, as the kernel's hit normal).
    pub(crate) fn points_normals(
        &self,
        nodes: &Nodes,
    ) -> ([V3<f64>; EDGE_SAMPLES], [V3<f64>; EDGE_SAMPLES]) {
        let mut pts = [V3::zero(); EDGE_SAMPLES];
        let mut nrm = [V3::zero(); EDGE_SAMPLES];
        for (k, (p, n)) in pts
            .chunks_exact_mut(2)
            .zip(nrm.chunks_exact_mut(2))
            .enumerate()
        {
            let xs = [self.bary(nodes.t(2 * k)), self.bary(nodes.t(2 * k + 1))];
            let hn = heights_normals(&self.shape, &self.prepared, xs);
            for (((p, n), x), (h, normal)) in p.iter_mut().zip(n).zip(xs).zip(hn) {
                *p = self.world(x, h);
                *n = normal;
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

/// The heights at two barycentric triples (the kernel's height over two `f64` lanes: the same
/// operations as one point's, lane by lane). Not inlined and not generic: one copy in the
/// crate, called in a loop.
#[inline(never)]
fn heights(pr: &Prepared<f64>, xs: [[f64; 3]; 2]) -> [f64; 2] {
    let [a, b] = xs;
    let lane = |k: usize| {
        wide::f64x2::new([
            a.get(k).copied().unwrap_or(0.0),
            b.get(k).copied().unwrap_or(0.0),
        ])
    };
    height::height_at(pr, [lane(0), lane(1), lane(2)]).to_array()
}

/// The heights (bit for bit [`heights`]') and the local-frame unit geometric normals at
/// two barycentric triples (height jets over two lanes). Not inlined and not generic, as
/// [`heights`].
#[inline(never)]
fn heights_normals(
    shape: &Shape<f64>,
    pr: &Prepared<f64>,
    xs: [[f64; 3]; 2],
) -> [(f64, V3<f64>); 2] {
    let [a, b] = height::height_derivatives_x2(shape, pr, xs);
    let [xa, xb] = xs;
    let normal = |x: [f64; 3], [d1, d2]: [V3<f64>; 2]| scalar::normal_local(shape, x, d1, d2);
    [(a.0, normal(xa, a.1)), (b.0, normal(xb, b.1))]
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
