//! The surface in lanes: the same surface as [`crate::surface::scalar`] (docs/METHOD.md §5),
//! written once over [`LaneOps`] for speed, evaluated at four or eight points per call from a
//! [`Prepared`] patch.
//!
//! The prepared patch is the one entry point. Patch construction samples the shell's height
//! range with it ([`Prepared::heights`], [`Prepared::edge_heights`]); the ray kernel
//! evaluates its function `f(τ) = z(τ) − σS(X(τ))` at eight ray parameters per call
//! ([`Prepared::f`]) and the exact normal of a hit ([`Prepared::derivatives`]); the seamless
//! shading normal takes four points' derivatives at once ([`Prepared::derivatives_x4`]), and
//! the builder's shared edges their heights and derivatives with the edge curves at the
//! edge's ends evaluated once ([`Prepared::on_edge`]).
//!
//! One file per idea:
//! - [`curve`]: an edge's conjugation curve and its normal `n*` over lanes, one edge splatted
//!   or three gathered into lanes;
//! - [`height`]: the height `σS` of eq. (5) at barycentrics, the point-to-barycentrics map of
//!   the kernel's ray points and `f`;
//! - [`jets`]: the height with its partial derivatives over [`Jet`](crate::num::jet::Jet)s,
//!   the surface derivatives assembled from them (one point, or four points in four lanes);
//! - [`on_edge`]: the builder's specialisation for points on one edge of the triangle.
//!
//! Differences from the generic evaluation (which stays the reference and serves the public
//! evaluation API):
//! - eight points per call, in the lanes of [`Float::L8`], with selects instead of branches;
//! - per-patch precomputation ([`Prepared`], built once per patch test or construction): the
//!   generator line of an edge is linear in its parameter `t` (`p(t) − anchor = t·e` or
//!   `(t − 1)·e`, `g(t) = da + t·gd`), so the three coefficients of each edge sphere's quadratic
//!   `qa s² + 2 qb s + qc` are polynomials in `t` of degree ≤ 2 whose coefficients are dot
//!   products of patch data, computed once;
//! - no dual numbers: the edge tangent `c′(t)` that the edge normal `n*` needs (eq. (3)) is the
//!   forward derivative of the two edge-sphere roots, `s′ = (qc′ − s·q′)/q`, the arithmetic the
//!   dual numbers perform, with the polynomials' exact derivatives;
//! - the exact zeros of the local frame are used (`P0 = 0`, `P1.y = P1.z = P2.z = 0`,
//!   `di.z = 1`, so `g.z = 1`), and the normal `n*` is left unnormalised where the formulas are
//!   homogeneous in it (the curvature through a point and all three coefficients of the line
//!   quadratic scale with the axis, so the root does not change).
//!
//! # Accuracy
//! Equal to [`crate::surface::scalar`]'s height within rounding: within
//! `KERNEL_HEIGHT_VS_SURFACE` (`core/src/accuracy.rs`) of the triangle's
//! size on random patches (`tests.rs` here); the four-lane and one-point jets bit for bit
//! each other.

mod curve;
mod height;
mod jets;
mod on_edge;
#[cfg(test)]
mod tests;

use crate::geometry::Shape;
use crate::num::lanes::LaneOps;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::field::Section;

pub(crate) use on_edge::OnEdge;

/// One edge's data for the height evaluation, precomputed from the patch (edge `j` runs from
/// `A = Pj` to `B = Pj+1`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedEdge<F> {
    /// Start vertex `A`.
    pub(super) a: V3<F>,
    /// Edge vector `e = B − A`.
    pub(super) e: V3<F>,
    /// Direction field at `A` (`z = 1` for parallel sections).
    pub(super) da: V3<F>,
    /// `gd = dB − dA` (`z = 0` for parallel sections).
    pub(super) gd: V3<F>,
    /// Curvatures of `S¹` (anchor `A`, axis `nA`) and `S²` (anchor `B`, axis `nB`).
    pub(super) curvatures: [F; 2],
    /// `|g(t)|² = g0 + t·(g1 + t·g2)`.
    pub(super) g_len2: [F; 3],
    /// `e·g(t) = e0 + t·e1`.
    pub(super) e_dot_g: [F; 2],
    /// `|e|²`.
    pub(super) e_len2: F,
    /// For each sphere `m = nA, nB`: `[da·m, gd·m, e·m]`.
    pub(super) axis_dots: [[F; 3]; 2],
}

/// A patch's data for the height evaluation: built once per patch test, used by every call.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Prepared<F> {
    /// `P1.x`, `P2.x`, `P2.y` (the other coordinates of the local vertices are zero).
    pub(super) vertex_xy: [F; 3],
    /// Unit vertex normals.
    pub(super) n: [V3<F>; 3],
    /// Direction field at the vertices (`z = 1` for parallel sections).
    pub(super) d: [V3<F>; 3],
    /// The point-to-section map ([`crate::surface::field`]).
    pub(super) section: Section<F>,
    /// The edges.
    pub(super) edges: [PreparedEdge<F>; 3],
}

impl<F: Float> Prepared<F> {
    /// The precomputation for `shape` (about 120 flops).
    #[inline(always)]
    pub(crate) fn new(shape: &Shape<F>) -> Self {
        let two = F::from_f64(2.0);
        let edge = |j: usize| {
            let ev = shape.edge(j);
            let e = ev.b - ev.a;
            let gd = ev.db - ev.da;
            PreparedEdge {
                a: ev.a,
                e,
                da: ev.da,
                gd,
                curvatures: [ev.k1, ev.k2],
                g_len2: [ev.da.length2(), two * ev.da.dot(gd), gd.length2()],
                e_dot_g: [e.dot(ev.da), e.dot(gd)],
                e_len2: e.length2(),
                axis_dots: [ev.na, ev.nb].map(|m| [ev.da.dot(m), gd.dot(m), e.dot(m)]),
            }
        };
        let [p0, p1, p2] = shape.p;
        let _ = p0;
        Prepared {
            vertex_xy: [p1.x, p2.x, p2.y],
            n: shape.n,
            d: shape.d,
            section: Section::new(shape),
            edges: [edge(0), edge(1), edge(2)],
        }
    }

    /// `f(τ) = z − σS(X)` at the local points `o + τ·r` of the lanes' ray parameters `tau`
    /// (one ray: `o` and `r` splatted), with `X` the points' barycentrics projected onto the
    /// triangle and the surface continued beyond its edges (docs/METHOD.md §8). Not inlined:
    /// one copy per lane type.
    #[inline(always)]
    pub(crate) fn f<L: LaneOps<F = F>>(&self, o: [L; 3], r: [L; 3], tau: L) -> L {
        height::f_lanes(self, o, r, tau)
    }

    /// [`Prepared::f`] inlined into the caller, so that the lane code is compiled with the
    /// caller's target features (`crate::isa`'s out-of-line lane calls).
    #[inline(always)]
    pub(crate) fn f_inline<L: LaneOps<F = F>>(&self, o: [L; 3], r: [L; 3], tau: L) -> L {
        height::f_inline(self, o, r, tau)
    }

    /// The local ray points `o + τ·r` of the lanes: their height, their projected barycentrics
    /// and the height change of the surface's continuation beyond the edges there, where
    /// [`Prepared::f`] evaluates the height and what it adds to it (the predictor's `f̃` uses
    /// the same, [`crate::surface::predictor`]).
    #[inline(always)]
    pub(crate) fn ray_bary<L: LaneOps<F = F>>(
        &self,
        o: [L; 3],
        r: [L; 3],
        tau: L,
    ) -> (L, [L; 3], L) {
        height::ray_bary(self, o, r, tau)
    }

    /// The height `σS(X)` at the lanes' barycentric triples (summing to one, inside the
    /// triangle).
    #[inline(always)]
    pub(crate) fn heights<L: LaneOps<F = F>>(&self, x: [L; 3]) -> L {
        height::height_at(self, x)
    }

    /// The height `c(t).z` of edge `edge`'s conjugation curve over the triangle's plane (edge
    /// `j` runs from `Pj` to `Pj+1`; `edge` taken modulo 3) at the lanes' edge parameters `t`:
    /// the `z` of [`crate::surface::edge::edge_point`]'s point within rounding.
    #[inline(always)]
    pub(crate) fn edge_heights<L: LaneOps<F = F>>(&self, edge: usize, t: L) -> L {
        let [e0, e1, e2] = &self.edges;
        let ep = match edge % 3 {
            0 => e0,
            1 => e1,
            _ => e2,
        };
        curve::edge_height(ep, t)
    }

    /// The local-frame surface derivatives `∂pS/∂X1`, `∂pS/∂X2` at barycentrics `x` (with
    /// `X0 = 1 − X1 − X2`) of this patch's `shape`, from one evaluation of the height over
    /// jets: the kernel's hit normal.
    #[inline(always)]
    pub(crate) fn derivatives(&self, shape: &Shape<F>, x: [F; 3]) -> [V3<F>; 2] {
        jets::height_derivatives(shape, self, x).1
    }

    /// [`Prepared::derivatives`] at four barycentric triples: bit for bit four calls of it (in
    /// `f32` and `f64` one evaluation over four lanes). Lanes whose input is not finite
    /// return non-finite derivatives and leave the others alone.
    #[inline(always)]
    pub(crate) fn derivatives_x4(&self, shape: &Shape<F>, xs: [[F; 3]; 4]) -> [[V3<F>; 2]; 4] {
        jets::height_derivatives_x4(shape, self, xs).map(|(_, d)| d)
    }

    /// The map of local points to their cross-sections, as prepared for this patch.
    #[inline(always)]
    pub(crate) fn section(&self) -> &Section<F> {
        &self.section
    }

    /// The evaluations at points of the triangle's edge `edge` (from `Pj` to `Pj+1`, taken
    /// modulo 3), with the two edge curves whose parameter is fixed there evaluated once.
    #[inline(always)]
    pub(crate) fn on_edge(&self, edge: usize) -> OnEdge<'_, F> {
        OnEdge::new(self, edge)
    }
}
