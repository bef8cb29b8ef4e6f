//! The two neighbours' surfaces along a shared edge, sampled once at [`EDGE_SAMPLES`] nodes
//! for both crack closure (the widest gap between the two surfaces' edges) and the seam fit
//! (their geometric normals there).

use super::topology::edge_bary;
use crate::geometry::{Frame, Shape};
use crate::num::lanes::One;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::surface::height::{self, Prepared};
use crate::surface::scalar;

/// Samples per shared edge, at the Chebyshev nodes `t_s = (1 − cos((2s + 1)π / (2·16))) / 2`
/// ([`Nodes`]); both [`CRACK_SAMPLES`](super::cracks::CRACK_SAMPLES) and
/// [`FIT_SAMPLES`](super::seams::FIT_SAMPLES).
pub(crate) const EDGE_SAMPLES: usize = 16;

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
        for (s, o) in out.iter_mut().enumerate() {
            let x = self.bary(nodes.t(s));
            *o = self.world(x, height_of(&self.prepared, x));
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
        for (s, (p, n)) in pts.iter_mut().zip(nrm.iter_mut()).enumerate() {
            let x = self.bary(nodes.t(s));
            let (h, normal) = height_normal(&self.shape, &self.prepared, x);
            *p = self.world(x, h);
            *n = normal;
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

/// The height at barycentrics `x` (the kernel's height, one point). Not inlined and not
/// generic: one copy in the crate, called in a loop.
#[inline(never)]
fn height_of(pr: &Prepared<f64>, x: [f64; 3]) -> f64 {
    let [x0, x1, x2] = x;
    height::height_at(pr, [One(x0), One(x1), One(x2)]).0
}

/// The height (bit for bit [`height_of`]'s) and the local-frame unit geometric normal at
/// barycentrics `x` (height jets). Not inlined and not generic, as [`height_of`].
#[inline(never)]
fn height_normal(shape: &Shape<f64>, pr: &Prepared<f64>, x: [f64; 3]) -> (f64, V3<f64>) {
    let (h, [d1, d2]) = height::height_derivatives(shape, pr, x);
    (h, scalar::normal_local(shape, x, d1, d2))
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
