//! The builder's specialisation of the lane formulas for points on one edge of the
//! triangle: two of the three vertex terms meet their opposite edges at the same parameter (0
//! or 1) at every point of the edge, so their edge curves are evaluated once per edge, with
//! their derivatives by the edge parameter, and chained onto each point's jets.

use super::curve::{EdgeGathered, edge_point_normal};
use super::height::{EdgeCurves, curve_chained, height_with};
use super::jets::{columns4, height_derivatives_x4, heights_x4, jets_x4};
use super::{Prepared, PreparedEdge};
use crate::geometry::Shape;
use crate::num::jet::{Jet, Tangent, chained};
use crate::num::lane_vec::L3;
use crate::num::lanes::{LaneOps, One};
use crate::num::real::Float;
use crate::num::vec::V3;

/// The conjugation points and normals of the two vertex terms whose edge parameter is the
/// same at every point of a triangle's edge `edge` (from `Pj` to `Pj+1`; the opposite
/// barycentric `Xj+2` is 0): vertex `Pj`'s term meets its opposite edge `j + 1` at `t = 0`
/// and vertex `Pj+1`'s meets edge `j + 2` at `t = 1`. Each with its derivative by `t`, so
/// that [`OnEdge::height_derivatives_x4`] takes the jets of both by the chain rule instead of
/// evaluating the edge curves again at every point.
#[derive(Clone, Copy)]
pub(super) struct EdgeEnds<F: Float> {
    pub(super) edge: usize,
    /// `[vertex j's term, vertex j + 1's]`.
    pub(super) ends: [CurveAt<F>; 2],
}

/// A conjugation point and its normal with their derivatives by the edge parameter
/// (one-point jets).
pub(super) type CurveAt<F> = (L3<Tangent<One<F>>>, L3<Tangent<One<F>>>);

impl<F: Float> EdgeEnds<F> {
    /// The two end terms of `pr`'s edge `edge` (taken modulo 3): in `f32` and `f64` both in
    /// one evaluation over four lanes (lanes 0 and 1), for other scalars in turn; the same
    /// operations either way.
    #[inline(always)]
    pub(super) fn new(pr: &Prepared<F>, edge: usize) -> Self {
        use crate::num::real::Lane4;
        let edge = edge % 3;
        let [e0, e1, e2] = &pr.edges;
        let pick = |e: usize| match e % 3 {
            0 => e0,
            1 => e1,
            _ => e2,
        };
        // Vertex `Pj`'s term meets edge `j + 1` at t = 0, `Pj+1`'s meets edge `j + 2` at 1.
        let (first, second) = (pick(edge + 1), pick(edge + 2));
        let (zero, one) = (F::ZERO, F::ONE);
        let ends = if <F::L4 as Lane4>::POINTS < 4 {
            let at = |ep: &PreparedEdge<F>, t: F| {
                edge_point_normal(
                    ep,
                    Jet {
                        v: One(t),
                        d: [One(one)],
                    },
                )
            };
            [at(first, zero), at(second, one)]
        } else {
            let sp = <F::L4 as LaneOps>::splat;
            let t = Jet {
                v: F::L4::from_array4([zero, one, zero, zero]),
                d: [sp(one)],
            };
            let (p, n) = edge_point_normal(&EdgeGathered::new([first, second, first]), t);
            [0, 1].map(|k| (lane_of(p, k), lane_of(n, k)))
        };
        EdgeEnds { edge, ends }
    }
}

/// Lane `k` of jets over [`Float::L4`].
#[inline(always)]
pub(super) fn lane_of<F: Float>(v: L3<Tangent<F::L4>>, k: usize) -> L3<Tangent<One<F>>> {
    use crate::num::real::Lane4;
    let one = |q: Tangent<F::L4>| {
        let at = |l: F::L4| One(l.to_array4().get(k).copied().unwrap_or(F::ZERO));
        let [d] = q.d;
        Jet {
            v: at(q.v),
            d: [at(d)],
        }
    };
    L3 {
        x: one(v.x),
        y: one(v.y),
        z: one(v.z),
    }
}

/// An end's point or normal (one point) in every lane of `L`.
#[inline(always)]
pub(super) fn splat_end<F: Float, L: LaneOps<F = F>>(q: L3<Tangent<One<F>>>) -> L3<Tangent<L>> {
    let one = |q: Tangent<One<F>>| {
        let [One(dt)] = q.d;
        Jet {
            v: L::splat(q.v.0),
            d: [L::splat(dt)],
        }
    };
    L3 {
        x: one(q.x),
        y: one(q.y),
        z: one(q.z),
    }
}

impl<F: Float> EdgeCurves<Jet<F::L4>> for EdgeEnds<F> {
    #[inline(always)]
    fn point_normal(
        &self,
        i: usize,
        ep: &PreparedEdge<F>,
        t: Jet<F::L4>,
    ) -> (L3<Jet<F::L4>>, L3<Jet<F::L4>>) {
        let [first, second] = self.ends;
        let end = |(p, n): CurveAt<F>| (chained(splat_end(p), t), chained(splat_end(n), t));
        if i == self.edge {
            end(first)
        } else if i == (self.edge + 1) % 3 {
            end(second)
        } else {
            // The shared edge's own curve, by its parameter alone (one partial), chained.
            curve_chained(ep, t)
        }
    }
}

/// [`EdgeEnds`]' values alone, for the plain heights on the edge ([`OnEdge::heights_x4`]).
pub(super) struct EndValues<'a, F: Float>(&'a EdgeEnds<F>);

/// The end terms' points and normals splatted from their values.
impl<F: Float> EdgeCurves<F::L4> for EndValues<'_, F> {
    #[inline(always)]
    fn point_normal(&self, i: usize, ep: &PreparedEdge<F>, t: F::L4) -> (L3<F::L4>, L3<F::L4>) {
        let EndValues(ends) = self;
        let [first, second] = ends.ends;
        let value = |q: L3<Tangent<One<F>>>| L3::<F::L4>::splat(V3::new(q.x.v.0, q.y.v.0, q.z.v.0));
        if i == ends.edge {
            (value(first.0), value(first.1))
        } else if i == (ends.edge + 1) % 3 {
            (value(second.0), value(second.1))
        } else {
            edge_point_normal(ep, t)
        }
    }
}

/// The evaluations at points of one edge of the triangle ([`Prepared::on_edge`]): the
/// builder's shared-edge samples, strictly inside the edge (the opposite barycentric exactly 0,
/// the other two above `ε`), with the two end terms' edge curves taken once from
/// [`EdgeEnds`] (their parameters are exactly 0 and 1 there). For other scalars than `f32`
/// and `f64`, the general evaluations.
#[derive(Clone, Copy)]
pub(crate) struct OnEdge<'a, F: Float> {
    prepared: &'a Prepared<F>,
    ends: EdgeEnds<F>,
}

impl<'a, F: Float> OnEdge<'a, F> {
    /// The evaluations on `pr`'s edge `edge` (taken modulo 3).
    #[inline(always)]
    pub(super) fn new(pr: &'a Prepared<F>, edge: usize) -> Self {
        OnEdge {
            prepared: pr,
            ends: EdgeEnds::new(pr, edge),
        }
    }

    /// The heights `σS` at four points of the edge: bit for bit [`heights_x4`]'s.
    #[inline(always)]
    pub(crate) fn heights_x4(&self, xs: [[F; 3]; 4]) -> [F; 4] {
        use crate::num::real::Lane4;
        if <F::L4 as Lane4>::POINTS < 4 {
            return heights_x4(self.prepared, xs);
        }
        height_with(self.prepared, columns4(xs), &EndValues(&self.ends)).to_array4()
    }

    /// The heights and the local-frame surface derivatives at four points of the edge of
    /// `shape` (this patch's): the heights bit for bit [`heights_x4`]'s, the derivatives
    /// [`height_derivatives_x4`]'s within rounding (the two end terms' jets by the chain rule
    /// from [`EdgeEnds`]; the third term's edge curve, as everywhere, by its edge parameter
    /// alone).
    #[inline(always)]
    pub(crate) fn height_derivatives_x4(
        &self,
        shape: &Shape<F>,
        xs: [[F; 3]; 4],
    ) -> [(F, [V3<F>; 2]); 4] {
        use crate::num::real::Lane4;
        if <F::L4 as Lane4>::POINTS < 4 {
            return height_derivatives_x4(shape, self.prepared, xs);
        }
        jets_x4(shape, self.prepared, xs, &self.ends)
    }
}
