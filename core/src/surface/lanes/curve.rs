//! An edge's conjugation curve `c(t)` and its normal `n*(t)` (eq. (3)) over lanes: the
//! points where the vertex terms' lines meet their opposite edges. The edge's data are
//! splatted from one edge (every lane the same edge) or gathered from three (one vertex term
//! per lane).

use super::PreparedEdge;
use crate::num::jet::{Jet, Partials};
use crate::num::lane_vec::{L3, splat_f64};
use crate::num::lanes::LaneOps;
use crate::num::real::Float;
use crate::num::vec::V3;

/// One edge's data ([`PreparedEdge`]) as lanes: splatted from one edge (every lane the same edge:
/// the kernel's `f`, the construction and the builder's four-point jets) or gathered from
/// three ([`EdgeGathered`]: one vertex term per lane, the hit normal's jets).
///
/// One accessor per group of fields, so that the splatting path splats each where it is used.
/// The data are [`LaneOps::Plain`]: constants of the evaluation.
pub(super) trait EdgeLanes<L: LaneOps> {
    /// Start vertex `A`.
    fn a(&self) -> L3<L::Plain>;
    /// Edge vector `e = B − A`.
    fn e(&self) -> L3<L::Plain>;
    /// Direction field at `A`.
    fn da(&self) -> L3<L::Plain>;
    /// `gd = dB − dA`.
    fn gd(&self) -> L3<L::Plain>;
    /// [`PreparedEdge`]'s `curvatures`.
    fn curvatures(&self) -> [L::Plain; 2];
    /// [`PreparedEdge`]'s `g_len2`.
    fn g_len2(&self) -> [L::Plain; 3];
    /// [`PreparedEdge`]'s `e_dot_g`.
    fn e_dot_g(&self) -> [L::Plain; 2];
    /// [`PreparedEdge`]'s `e_len2`.
    fn e_len2(&self) -> L::Plain;
    /// [`PreparedEdge`]'s `m[i]`.
    fn axis_dots(&self, i: usize) -> [L::Plain; 3];
}

impl<L: LaneOps> EdgeLanes<L> for PreparedEdge<L::F> {
    #[inline(always)]
    fn a(&self) -> L3<L::Plain> {
        L3::splat(self.a)
    }
    #[inline(always)]
    fn e(&self) -> L3<L::Plain> {
        L3::splat(self.e)
    }
    #[inline(always)]
    fn da(&self) -> L3<L::Plain> {
        L3::splat(self.da)
    }
    #[inline(always)]
    fn gd(&self) -> L3<L::Plain> {
        L3::splat(self.gd)
    }
    #[inline(always)]
    fn curvatures(&self) -> [L::Plain; 2] {
        self.curvatures.map(L::Plain::splat)
    }
    #[inline(always)]
    fn g_len2(&self) -> [L::Plain; 3] {
        self.g_len2.map(L::Plain::splat)
    }
    #[inline(always)]
    fn e_dot_g(&self) -> [L::Plain; 2] {
        self.e_dot_g.map(L::Plain::splat)
    }
    #[inline(always)]
    fn e_len2(&self) -> L::Plain {
        L::Plain::splat(self.e_len2)
    }
    #[inline(always)]
    fn axis_dots(&self, i: usize) -> [L::Plain; 3] {
        let [m0, m1] = self.axis_dots;
        (if i == 0 { m0 } else { m1 }).map(L::Plain::splat)
    }
}

/// Three edges' data gathered into the lanes of `L` (lane `i` holds edge `edges[i]`; the
/// fourth lane repeats the first): the vertex terms of one point, one per lane.
#[derive(Clone, Copy)]
pub(super) struct EdgeGathered<L> {
    pub(super) a: L3<L>,
    pub(super) e: L3<L>,
    pub(super) da: L3<L>,
    pub(super) gd: L3<L>,
    pub(super) curvatures: [L; 2],
    pub(super) g_len2: [L; 3],
    pub(super) e_dot_g: [L; 2],
    pub(super) e_len2: L,
    pub(super) axis_dots: [[L; 3]; 2],
}

impl<L: crate::num::real::Lane4> EdgeGathered<L> {
    /// Edge `edges[i]`'s data in lane `i` (lane 3 repeats lane 0).
    #[inline(always)]
    pub(super) fn new(edges: [&PreparedEdge<L::F>; 3]) -> Self {
        let [a, b, cc] = edges;
        let g = |f: fn(&PreparedEdge<L::F>) -> L::F| L::from_array4([f(a), f(b), f(cc), f(a)]);
        let v = |f: fn(&PreparedEdge<L::F>) -> V3<L::F>| L3 {
            x: L::from_array4([f(a).x, f(b).x, f(cc).x, f(a).x]),
            y: L::from_array4([f(a).y, f(b).y, f(cc).y, f(a).y]),
            z: L::from_array4([f(a).z, f(b).z, f(cc).z, f(a).z]),
        };
        EdgeGathered {
            a: v(|e| e.a),
            e: v(|e| e.e),
            da: v(|e| e.da),
            gd: v(|e| e.gd),
            curvatures: [g(|e| e.curvatures[0]), g(|e| e.curvatures[1])],
            g_len2: [g(|e| e.g_len2[0]), g(|e| e.g_len2[1]), g(|e| e.g_len2[2])],
            e_dot_g: [g(|e| e.e_dot_g[0]), g(|e| e.e_dot_g[1])],
            e_len2: g(|e| e.e_len2),
            axis_dots: [
                [
                    g(|e| e.axis_dots[0][0]),
                    g(|e| e.axis_dots[0][1]),
                    g(|e| e.axis_dots[0][2]),
                ],
                [
                    g(|e| e.axis_dots[1][0]),
                    g(|e| e.axis_dots[1][1]),
                    g(|e| e.axis_dots[1][2]),
                ],
            ],
        }
    }
}

/// The gathered lanes are the jets' data (their [`LaneOps::Plain`]).
impl<L: LaneOps<Plain = L>, D: Partials<L>> EdgeLanes<Jet<L, D>> for EdgeGathered<L> {
    #[inline(always)]
    fn a(&self) -> L3<L> {
        self.a
    }
    #[inline(always)]
    fn e(&self) -> L3<L> {
        self.e
    }
    #[inline(always)]
    fn da(&self) -> L3<L> {
        self.da
    }
    #[inline(always)]
    fn gd(&self) -> L3<L> {
        self.gd
    }
    #[inline(always)]
    fn curvatures(&self) -> [L; 2] {
        self.curvatures
    }
    #[inline(always)]
    fn g_len2(&self) -> [L; 3] {
        self.g_len2
    }
    #[inline(always)]
    fn e_dot_g(&self) -> [L; 2] {
        self.e_dot_g
    }
    #[inline(always)]
    fn e_len2(&self) -> L {
        self.e_len2
    }
    #[inline(always)]
    fn axis_dots(&self, i: usize) -> [L; 3] {
        let [m0, m1] = self.axis_dots;
        if i == 0 { m0 } else { m1 }
    }
}

/// The root nearest 0 of `qa s² + 2 qb s + qc = 0` ([`crate::surface::sphere::nearest_root`]'s
/// cancellation-free form and double-root test, over lanes). `w2 = |w|²`, `g2 = |g|²` and
/// `m2 = |m|²` (the axis may be scaled: `κ` and all three coefficients scale with it) set the
/// noise scales. Returns `(s, q, sq, ok)`: `s = qc/q` where `ok`, else 0.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn root<L: LaneOps>(
    qa: L,
    qb: L,
    qc: L,
    k: L,
    w2: L,
    g2: L,
    m2: L,
) -> (L, L, L, L::Mask) {
    let zero = L::splat(L::F::ZERO);
    let disc = qb * qb - qa * qc;
    let sq = L::select(disc.gt(zero), disc, zero).sqrt();
    let q = L::select(qb.lt(zero), sq - qb, -qb - sq);
    // Double root at s = 0 (the line tangent to the sphere at a point of it): `qc` and `qb`
    // are rounding noise, both below 16 ε of their natural scale.
    let tol = L::F::EPSILON * L::F::from_f64(16.0);
    let tol2 = L::splat(tol * tol);
    let two = splat_f64::<L>(2.0);
    let kk = k * k;
    let c_scale = two * (kk * w2 * w2 + splat_f64::<L>(4.0) * w2 * m2);
    let b_scale = two * (kk * w2 * g2 + g2 * m2);
    let noise = L::and((qc * qc).le(tol2 * c_scale), (qb * qb).le(tol2 * b_scale));
    let s = qc / q;
    let ok = L::and(L::not(noise), L::and(L::not(q.eq(zero)), s.finite()));
    (L::select(ok, s, zero), L::select(ok, q, zero), sq, ok)
}

/// Derivative `s′` of a root of [`root`] from the coefficients' derivatives (forward mode; the
/// square root has derivative 0 where the discriminant is clamped).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn root_derivative<L: LaneOps>(
    s: L,
    q: L,
    sq: L,
    ok: L::Mask,
    [qa, qb, qc]: [L; 3],
    [da, db, dc]: [L; 3],
) -> L {
    let zero = L::splat(L::F::ZERO);
    let two = splat_f64::<L::Plain>(2.0);
    let ddisc = qb.mul_p(two) * db - da * qc - qa * dc;
    let dsq = L::select(sq.gt(zero), ddisc / sq.mul_p(two), zero);
    let dq = L::select(qb.lt(zero), dsq - db, -db - dsq);
    let ds = (dc - s * dq) / q;
    L::select(L::and(ok, ds.finite()), ds, zero)
}

/// An edge's parameters `t` and its polynomials there ([`edge_point_normal`]): `|g|²`, its
/// derivative by `t`, `e·g`, and the constants `e·gd` and `|e|²`.
pub(super) struct EdgePoly<L: LaneOps> {
    pub(super) t: L,
    pub(super) g_len2: L,
    pub(super) dg_len2: L,
    pub(super) e_dot_g: L,
    pub(super) e_dot_gd: L::Plain,
    pub(super) e_len2: L::Plain,
}

impl<L: LaneOps> EdgePoly<L> {
    /// The root `s` of an edge sphere (curvature `k`, `m = [da·n, gd·n, e·n]` of its axis `n`)
    /// and its derivative by `t`, for the generator offset `w·e` from its anchor (`w = t` from
    /// `A`, `t − 1` from `B`).
    #[inline(always)]
    fn sphere(&self, w: L, k: L::Plain, [m0, m1, m2]: [L::Plain; 3]) -> (L, L) {
        let (one, two) = (splat_f64::<L::Plain>(1.0), splat_f64::<L::Plain>(2.0));
        let EdgePoly {
            t,
            g_len2,
            dg_len2,
            e_dot_g,
            e_dot_gd,
            e_len2,
        } = *self;
        let w2 = (w * w).mul_p(e_len2);
        let c = [
            g_len2.mul_p(k),
            w.mul_p(k) * e_dot_g - t.mul_p(m1).add_p(m0),
            w * w.mul_p(k).mul_p(e_len2).sub_p(two * m2),
        ];
        let dc = [
            dg_len2.mul_p(k),
            (e_dot_g + w.mul_p(e_dot_gd)).mul_p(k).sub_p(m1),
            w.mul_p(k).mul_p(e_len2).sub_p(m2).mul_p(two),
        ];
        let (s, q, sq, ok) = root(c[0], c[1], c[2], L::lift(k), w2, g_len2, L::lift(one));
        (s, root_derivative(s, q, sq, ok, c, dc))
    }
}

/// Conjugation point `c(t)` of an edge and its normal `n*(t)` scaled by `|c′|² > 0`
/// (eq. (3)), at eight edge parameters.
#[inline(always)]
pub(super) fn edge_point_normal<L: LaneOps>(ep: &impl EdgeLanes<L>, t: L) -> (L3<L>, L3<L>) {
    let one = splat_f64::<L::Plain>(1.0);
    let two = splat_f64::<L::Plain>(2.0);
    let zero = L::splat(L::F::ZERO);
    let u = t.sub_p(one);
    let e = ep.e();
    let gd = ep.gd();
    // g = da + t·gd (z: 1 exactly for parallel sections, `da.z = 1`, `gd.z = 0`).
    let g = L3::along(ep.da(), gd, t);
    let [g0, g1, g2c] = ep.g_len2();
    let g_len2 = (t * t.mul_p(g2c).add_p(g1)).add_p(g0);
    let dg_len2 = t.mul_p(two).mul_p(g2c).add_p(g1);
    let [e0, e1] = ep.e_dot_g();
    let e_dot_g = t.mul_p(e1).add_p(e0);
    let e_len2 = ep.e_len2();
    let [k1, k2] = ep.curvatures();
    let poly = EdgePoly {
        t,
        g_len2,
        dg_len2,
        e_dot_g,
        e_dot_gd: e1,
        e_len2,
    };
    // S¹: anchor A, w = t·e; S²: anchor B, w = (t − 1)·e.
    let (s1, ds1) = poly.sphere(t, k1, ep.axis_dots(0));
    let (s2, ds2) = poly.sphere(u, k2, ep.axis_dots(1));
    let s = t * s2 - u * s1;
    let ds = t * ds2 - u * ds1 + (s2 - s1);
    let cpt = L3::along(ep.a(), e, t).add(g.scale(s));
    // c′ = e + g′·s + g·s′.
    let tan = L3::along(e, gd, s).add(g.scale(ds));
    let tt = tan.dot(tan);
    let n = g.scale(tt).sub(tan.scale(tan.dot(g)));
    // Where the tangent vanishes or is parallel to g (never for an accepted patch): g.
    let good = L::and(tt.gt(zero), n.dot(n).gt(zero));
    (cpt, L3::select(good, n, g))
}

/// Height of edge `ep`'s conjugation line over the triangle's plane, `c(t).z`, at eight edge
/// parameters: the `z` of [`crate::surface::edge::edge_point`]'s point within rounding (the normal of
/// [`edge_point_normal`] is not needed, and is optimised away).
#[inline(always)]
pub(super) fn edge_height<L: LaneOps>(ep: &PreparedEdge<L::F>, t: L) -> L {
    edge_point_normal(ep, t).0.z
}
