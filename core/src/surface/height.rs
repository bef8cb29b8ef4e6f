//! The surface height over eight lanes, specialised: the same surface as [`crate::surface::scalar`]
//! (docs/METHOD.md §5), written once over [`LaneOps`] for speed. Patch construction samples the
//! shell's height range with it ([`crate::surface::shell`]); the ray kernel ([`crate::kernel`]) evaluates
//! its function `f(τ) = z(τ) − σS(X(τ))` at eight ray parameters per call ([`f_lanes`]) and the
//! exact normal of a hit over [`Jet`]s ([`derivatives`]; in `f32` and `f64` the three vertex
//! terms of one point side by side in four lanes, bit for bit the terms in turn; each term's edge
//! curve over jets by its edge parameter alone, chained: [`Chained`]).
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
//! size on random patches (the unit test below).

use crate::geometry::Shape;
use crate::num::lanes::{LaneOps, One};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::field::{SECTION_NEWTON_STEPS, Section};

/// One edge's data for the height evaluation, precomputed from the patch (edge `j` runs from
/// `A = Pj` to `B = Pj+1`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgePrep<F> {
    /// Start vertex `A`.
    a: V3<F>,
    /// Edge vector `e = B − A`.
    e: V3<F>,
    /// Direction field at `A` (`z = 1` for parallel sections).
    da: V3<F>,
    /// `gd = dB − dA` (`z = 0` for parallel sections).
    gd: V3<F>,
    /// Curvatures of `S¹` (anchor `A`, axis `nA`) and `S²` (anchor `B`, axis `nB`).
    k: [F; 2],
    /// `|g(t)|² = g0 + t·(g1 + t·g2)`.
    gg: [F; 3],
    /// `e·g(t) = e0 + t·e1`.
    eg: [F; 2],
    /// `|e|²`.
    ee: F,
    /// For each sphere `m = nA, nB`: `[da·m, gd·m, e·m]`.
    m: [[F; 3]; 2],
}

/// A patch's data for the height evaluation: built once per patch test, used by every call.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Prepared<F> {
    /// `P1.x`, `P2.x`, `P2.y` (the other coordinates of the local vertices are zero).
    p: [F; 3],
    /// Unit vertex normals.
    n: [V3<F>; 3],
    /// Direction field at the vertices (`z = 1` for parallel sections).
    d: [V3<F>; 3],
    /// The point-to-section map ([`crate::surface::field`]).
    section: Section<F>,
    /// The edges.
    edges: [EdgePrep<F>; 3],
}

impl<F: Float> Prepared<F> {
    /// The three edges' data (edge `j` runs from `Pj` to `Pj+1`).
    #[inline(always)]
    pub(crate) fn edges(&self) -> &[EdgePrep<F>; 3] {
        &self.edges
    }

    /// The precomputation for `shape` (about 120 flops).
    #[inline(always)]
    pub(crate) fn new(shape: &Shape<F>) -> Self {
        let two = F::from_f64(2.0);
        let edge = |j: usize| {
            let ev = shape.edge(j);
            let e = ev.b - ev.a;
            let gd = ev.db - ev.da;
            EdgePrep {
                a: ev.a,
                e,
                da: ev.da,
                gd,
                k: [ev.k1, ev.k2],
                gg: [ev.da.length2(), two * ev.da.dot(gd), gd.length2()],
                eg: [e.dot(ev.da), e.dot(gd)],
                ee: e.length2(),
                m: [ev.na, ev.nb].map(|m| [ev.da.dot(m), gd.dot(m), e.dot(m)]),
            }
        };
        let [p0, p1, p2] = shape.p;
        let _ = p0;
        Prepared {
            p: [p1.x, p2.x, p2.y],
            n: shape.n,
            d: shape.d,
            section: Section::new(shape),
            edges: [edge(0), edge(1), edge(2)],
        }
    }
}

/// A 3-vector of lanes.
#[derive(Clone, Copy)]
struct L3<L> {
    x: L,
    y: L,
    z: L,
}

impl<L: LaneOps> L3<L> {
    #[inline(always)]
    fn splat(v: V3<L::F>) -> Self {
        L3 {
            x: L::splat(v.x),
            y: L::splat(v.y),
            z: L::splat(v.z),
        }
    }
    #[inline(always)]
    fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        L3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        L3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    #[inline(always)]
    fn scale(self, s: L) -> Self {
        L3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    #[inline(always)]
    fn select(m: L::Mask, a: Self, b: Self) -> Self {
        L3 {
            x: L::select(m, a.x, b.x),
            y: L::select(m, a.y, b.y),
            z: L::select(m, a.z, b.z),
        }
    }
    /// `self · o` for data `o` ([`LaneOps::mul_p`]).
    #[inline(always)]
    fn dot_p(self, o: L3<L::Plain>) -> L {
        self.x.mul_p(o.x) + self.y.mul_p(o.y) + self.z.mul_p(o.z)
    }
    /// `self − o` for data `o`.
    #[inline(always)]
    fn sub_p(self, o: L3<L::Plain>) -> Self {
        L3 {
            x: self.x.sub_p(o.x),
            y: self.y.sub_p(o.y),
            z: self.z.sub_p(o.z),
        }
    }
    /// `o + v·s` for data `o` and `v` (the value bit for bit `o + v.scale(s)`'s).
    #[inline(always)]
    fn along(o: L3<L::Plain>, v: L3<L::Plain>, s: L) -> Self {
        L3 {
            x: s.mul_p(v.x).add_p(o.x),
            y: s.mul_p(v.y).add_p(o.y),
            z: s.mul_p(v.z).add_p(o.z),
        }
    }
}

#[inline(always)]
fn c<L: LaneOps>(x: f64) -> L {
    L::splat(L::F::from_f64(x))
}

/// One edge's data ([`EdgePrep`]) as lanes: splatted from one edge (every lane the same edge:
/// [`f_lanes`], the construction and the builder's four-point jets) or gathered from three
/// ([`EdgeGathered`]: one vertex term per lane, [`height_derivatives`]).
///
/// One accessor per group of fields, so that the splatting path splats each where it is used.
/// The data are [`LaneOps::Plain`]: constants of the evaluation.
trait EdgeLanes<L: LaneOps> {
    /// Start vertex `A`.
    fn a(&self) -> L3<L::Plain>;
    /// Edge vector `e = B − A`.
    fn e(&self) -> L3<L::Plain>;
    /// Direction field at `A`.
    fn da(&self) -> L3<L::Plain>;
    /// `gd = dB − dA`.
    fn gd(&self) -> L3<L::Plain>;
    /// [`EdgePrep`]'s `k`.
    fn k(&self) -> [L::Plain; 2];
    /// [`EdgePrep`]'s `gg`.
    fn gg(&self) -> [L::Plain; 3];
    /// [`EdgePrep`]'s `eg`.
    fn eg(&self) -> [L::Plain; 2];
    /// [`EdgePrep`]'s `ee`.
    fn ee(&self) -> L::Plain;
    /// [`EdgePrep`]'s `m[i]`.
    fn m(&self, i: usize) -> [L::Plain; 3];
}

impl<L: LaneOps> EdgeLanes<L> for EdgePrep<L::F> {
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
    fn k(&self) -> [L::Plain; 2] {
        self.k.map(L::Plain::splat)
    }
    #[inline(always)]
    fn gg(&self) -> [L::Plain; 3] {
        self.gg.map(L::Plain::splat)
    }
    #[inline(always)]
    fn eg(&self) -> [L::Plain; 2] {
        self.eg.map(L::Plain::splat)
    }
    #[inline(always)]
    fn ee(&self) -> L::Plain {
        L::Plain::splat(self.ee)
    }
    #[inline(always)]
    fn m(&self, i: usize) -> [L::Plain; 3] {
        let [m0, m1] = self.m;
        (if i == 0 { m0 } else { m1 }).map(L::Plain::splat)
    }
}

/// Three edges' data gathered into the lanes of `L` (lane `i` holds edge `edges[i]`; the
/// fourth lane repeats the first): the vertex terms of one point, one per lane.
#[derive(Clone, Copy)]
struct EdgeGathered<L> {
    a: L3<L>,
    e: L3<L>,
    da: L3<L>,
    gd: L3<L>,
    k: [L; 2],
    gg: [L; 3],
    eg: [L; 2],
    ee: L,
    m: [[L; 3]; 2],
}

impl<L: crate::num::real::Lane4> EdgeGathered<L> {
    #[inline(always)]
    fn new(edges: [&EdgePrep<L::F>; 3]) -> Self {
        let [a, b, cc] = edges;
        let g = |f: fn(&EdgePrep<L::F>) -> L::F| L::from_array4([f(a), f(b), f(cc), f(a)]);
        let v = |f: fn(&EdgePrep<L::F>) -> V3<L::F>| L3 {
            x: L::from_array4([f(a).x, f(b).x, f(cc).x, f(a).x]),
            y: L::from_array4([f(a).y, f(b).y, f(cc).y, f(a).y]),
            z: L::from_array4([f(a).z, f(b).z, f(cc).z, f(a).z]),
        };
        EdgeGathered {
            a: v(|e| e.a),
            e: v(|e| e.e),
            da: v(|e| e.da),
            gd: v(|e| e.gd),
            k: [g(|e| e.k[0]), g(|e| e.k[1])],
            gg: [g(|e| e.gg[0]), g(|e| e.gg[1]), g(|e| e.gg[2])],
            eg: [g(|e| e.eg[0]), g(|e| e.eg[1])],
            ee: g(|e| e.ee),
            m: [
                [g(|e| e.m[0][0]), g(|e| e.m[0][1]), g(|e| e.m[0][2])],
                [g(|e| e.m[1][0]), g(|e| e.m[1][1]), g(|e| e.m[1][2])],
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
    fn k(&self) -> [L; 2] {
        self.k
    }
    #[inline(always)]
    fn gg(&self) -> [L; 3] {
        self.gg
    }
    #[inline(always)]
    fn eg(&self) -> [L; 2] {
        self.eg
    }
    #[inline(always)]
    fn ee(&self) -> L {
        self.ee
    }
    #[inline(always)]
    fn m(&self, i: usize) -> [L; 3] {
        let [m0, m1] = self.m;
        if i == 0 { m0 } else { m1 }
    }
}

/// The root nearest 0 of `qa s² + 2 qb s + qc = 0` ([`crate::surface::sphere::nearest_root`]'s
/// cancellation-free form and double-root test, over lanes). `w2 = |w|²`, `g2 = |g|²` and
/// `m2 = |m|²` (the axis may be scaled: `κ` and all three coefficients scale with it) set the
/// noise scales. Returns `(s, q, sq, ok)`: `s = qc/q` where `ok`, else 0.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn root<L: LaneOps>(qa: L, qb: L, qc: L, k: L, w2: L, g2: L, m2: L) -> (L, L, L, L::Mask) {
    let zero = L::splat(L::F::ZERO);
    let disc = qb * qb - qa * qc;
    let sq = L::select(disc.gt(zero), disc, zero).sqrt();
    let q = L::select(qb.lt(zero), sq - qb, -qb - sq);
    // Double root at s = 0 (the line tangent to the sphere at a point of it): `qc` and `qb`
    // are rounding noise, both below 16 ε of their natural scale.
    let tol = L::F::EPSILON * L::F::from_f64(16.0);
    let tol2 = L::splat(tol * tol);
    let two = c::<L>(2.0);
    let kk = k * k;
    let c_scale = two * (kk * w2 * w2 + c::<L>(4.0) * w2 * m2);
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
fn root_derivative<L: LaneOps>(
    s: L,
    q: L,
    sq: L,
    ok: L::Mask,
    [qa, qb, qc]: [L; 3],
    [da, db, dc]: [L; 3],
) -> L {
    let zero = L::splat(L::F::ZERO);
    let two = c::<L::Plain>(2.0);
    let ddisc = qb.mul_p(two) * db - da * qc - qa * dc;
    let dsq = L::select(sq.gt(zero), ddisc / sq.mul_p(two), zero);
    let dq = L::select(qb.lt(zero), dsq - db, -db - dsq);
    let ds = (dc - s * dq) / q;
    L::select(L::and(ok, ds.finite()), ds, zero)
}

/// An edge's parameters `t` and its polynomials there ([`edge_point_normal`]): `|g|²`, its
/// derivative by `t`, `e·g`, and the constants `e·gd` and `|e|²`.
struct EdgePoly<L: LaneOps> {
    t: L,
    gg: L,
    dgg: L,
    eg: L,
    e1: L::Plain,
    ee: L::Plain,
}

impl<L: LaneOps> EdgePoly<L> {
    /// The root `s` of an edge sphere (curvature `k`, `m = [da·n, gd·n, e·n]` of its axis `n`)
    /// and its derivative by `t`, for the generator offset `w·e` from its anchor (`w = t` from
    /// `A`, `t − 1` from `B`).
    #[inline(always)]
    fn sphere(&self, w: L, k: L::Plain, [m0, m1, m2]: [L::Plain; 3]) -> (L, L) {
        let (one, two) = (c::<L::Plain>(1.0), c::<L::Plain>(2.0));
        let EdgePoly {
            t,
            gg,
            dgg,
            eg,
            e1,
            ee,
        } = *self;
        let w2 = (w * w).mul_p(ee);
        let c = [
            gg.mul_p(k),
            w.mul_p(k) * eg - t.mul_p(m1).add_p(m0),
            w * w.mul_p(k).mul_p(ee).sub_p(two * m2),
        ];
        let dc = [
            dgg.mul_p(k),
            (eg + w.mul_p(e1)).mul_p(k).sub_p(m1),
            w.mul_p(k).mul_p(ee).sub_p(m2).mul_p(two),
        ];
        let (s, q, sq, ok) = root(c[0], c[1], c[2], L::lift(k), w2, gg, L::lift(one));
        (s, root_derivative(s, q, sq, ok, c, dc))
    }
}

/// Conjugation point `c(t)` of an edge and its normal `n*(t)` scaled by `|c′|² > 0`
/// (eq. (3)), at eight edge parameters.
#[inline(always)]
fn edge_point_normal<L: LaneOps>(ep: &impl EdgeLanes<L>, t: L) -> (L3<L>, L3<L>) {
    let one = c::<L::Plain>(1.0);
    let two = c::<L::Plain>(2.0);
    let zero = L::splat(L::F::ZERO);
    let u = t.sub_p(one);
    let e = ep.e();
    let gd = ep.gd();
    // g = da + t·gd (z: 1 exactly for parallel sections, `da.z = 1`, `gd.z = 0`).
    let g = L3::along(ep.da(), gd, t);
    let [g0, g1, g2c] = ep.gg();
    let gg = (t * t.mul_p(g2c).add_p(g1)).add_p(g0);
    let dgg = t.mul_p(two).mul_p(g2c).add_p(g1);
    let [e0, e1] = ep.eg();
    let eg = t.mul_p(e1).add_p(e0);
    let ee = ep.ee();
    let [k1, k2] = ep.k();
    let poly = EdgePoly {
        t,
        gg,
        dgg,
        eg,
        e1,
        ee,
    };
    // S¹: anchor A, w = t·e; S²: anchor B, w = (t − 1)·e.
    let (s1, ds1) = poly.sphere(t, k1, ep.m(0));
    let (s2, ds2) = poly.sphere(u, k2, ep.m(1));
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
pub(crate) fn edge_height<L: LaneOps>(ep: &EdgePrep<L::F>, t: L) -> L {
    edge_point_normal(ep, t).0.z
}

/// The parameter `t = Xb / (Xa + Xb)` on the edge opposite a vertex of the point with the
/// other two barycentrics `xa`, `xb` (½ where they vanish: the vertex itself).
#[inline(always)]
fn edge_param<L: LaneOps>(xa: L, xb: L) -> L {
    let den = xa + xb;
    L::select(den.gt(L::splat(L::F::EPSILON)), xb / den, c::<L>(0.5))
}

/// The term of vertex `i` in eq. (5), `½ (Xi·s¹ + ((1 − Xi)/2)·s²)` for the line `base + s·dir`
/// (`dd = |dir|²`), from the conjugation point `cpt` and its normal `nc` (scaled) on the
/// opposite edge.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn term_through<L: LaneOps>(
    cpt: L3<L>,
    nc: L3<L>,
    pi: L3<L::Plain>,
    ni: L3<L::Plain>,
    xi: L,
    base: L3<L>,
    dir: L3<L>,
    dd: L,
) -> L {
    let zero = L::splat(L::F::ZERO);
    let one = c::<L::Plain>(1.0);
    let two = c::<L::Plain>(2.0);
    // Ŝ¹: anchor Pi, unit axis ni, through c; Ŝ²: anchor c, axis n* (scaled), through Pi.
    let wc = cpt.sub_p(pi);
    let l2 = wc.dot(wc);
    let has = l2.gt(zero);
    let inv = l2.rdiv_p(two);
    let k1 = L::select(has, wc.dot_p(ni) * inv, zero);
    let k2 = L::select(has, -(wc.dot(nc) * inv), zero);
    let w = base.sub_p(pi);
    let w2 = w.dot(w);
    let (s1, _, _, _) = root(
        k1 * dd,
        k1 * w.dot(dir) - dir.dot_p(ni),
        k1 * w2 - w.dot_p(ni).mul_p(two),
        k1,
        w2,
        dd,
        L::lift(one),
    );
    let w = base.sub(cpt);
    let w2 = w.dot(w);
    let (s2, _, _, _) = root(
        k2 * dd,
        k2 * w.dot(dir) - dir.dot(nc),
        k2 * w2 - w.dot(nc).mul_p(two),
        k2,
        w2,
        dd,
        nc.dot(nc),
    );
    xi.mul_p(c(0.5)) * s1 + xi.rsub_p(one).mul_p(c(0.25)) * s2
}

/// The line parameter `λ` of the section through each local point ([`Section::param`] over
/// lanes: `x.z` for parallel sections, else [`SECTION_NEWTON_STEPS`] Newton steps).
#[inline(always)]
fn section_param<L: LaneOps>(sec: &Section<L::F>, x: L3<L>) -> L {
    if sec.parallel {
        return x.z;
    }
    let [k0, k1, k2] = sec.k.map(L3::<L>::splat);
    let [a0, a1, a2] = sec.kd.map(L::splat);
    let (c0, c1, c2, c3) = (
        k0.dot(x),
        k1.dot(x) - a0,
        k2.dot(x) - a1,
        L::splat(L::F::ZERO) - a2,
    );
    let (two, three) = (c::<L>(2.0), c::<L>(3.0));
    let mut l = x.z * L::splat(sec.inv_mean);
    for _ in 0..SECTION_NEWTON_STEPS {
        let g = c0 + l * (c1 + l * (c2 + l * c3));
        let dg = c1 + l * (two * c2 + three * l * c3);
        let next = l - g / dg;
        l = L::select(next.finite(), next, l);
    }
    l
}

/// Barycentrics of local points, projected onto the triangle like
/// [`crate::surface::scalar::project_bary`]: the section through each point (parameter `λ` of
/// [`section_param`], vertices `Pi + λ·di`), negative or non-finite components set to 0,
/// renormalised (the centroid if all vanish).
#[inline(always)]
fn bary<L: LaneOps>(pr: &Prepared<L::F>, x: L3<L>) -> ([L; 3], L) {
    let zero = L::splat(L::F::ZERO);
    let one = c::<L>(1.0);
    let [p1x, p2x, p2y] = pr.p.map(L::splat);
    let [d0, d1, d2] = pr.d;
    let s = section_param(&pr.section, x);
    let ax = |px: L, d: V3<L::F>| px + L::splat(d.x) * s - x.x;
    let ay = |py: L, d: V3<L::F>| py + L::splat(d.y) * s - x.y;
    let (a0x, a0y) = (ax(zero, d0), ay(zero, d0));
    let (a1x, a1y) = (ax(p1x, d1), ay(zero, d1));
    let (a2x, a2y) = (ax(p2x, d2), ay(p2y, d2));
    let n1 = a2x * a0y - a2y * a0x;
    let n2 = a0x * a1y - a0y * a1x;
    let n0 = a1x * a2y - a1y * a2x;
    let area = n0 + n1 + n2;
    let (w1, w2) = (n1 / area, n2 / area);
    let clean = |v: L| L::select(L::and(v.finite(), v.gt(zero)), v, zero);
    let (a, b, cc) = (clean(one - w1 - w2), clean(w1), clean(w2));
    let m = a.max_of(b).max_of(cc);
    let good = L::and(m.gt(zero), m.finite());
    let (a, b, cc) = (a / m, b / m, cc / m);
    let inv = one / (a + b + cc);
    let third = c::<L>(1.0 / 3.0);
    let xp = [
        L::select(good, a * inv, third),
        L::select(good, b * inv, third),
        L::select(good, cc * inv, third),
    ];
    (xp, beyond_edge(pr, [one - w1 - w2, w1, w2], xp, s))
}

/// The height change of the surface's continuation beyond the triangle's edges (the walls
/// moved out by a patch's crack reach, [`crate::mesh::cracks`]): from the projected point `xp` to the
/// point `x` (raw barycentrics, one negative) in the cross-section at height `s`, along the
/// plane normal to the interpolated vertex normal `Σ xp_i n_i`. 0 (exactly) where no raw
/// barycentric is negative, or where the change is not finite.
///
/// So the surface continues across its edges to first order (up to the angle between the
/// interpolated and the surface normal there) instead of as a flat band at the edge's height,
/// and a ray crossing the surface at its edge sees `f` change sign across the wall.
#[inline(always)]
fn beyond_edge<L: LaneOps>(pr: &Prepared<L::F>, x: [L; 3], xp: [L; 3], s: L) -> L {
    let zero = L::splat(L::F::ZERO);
    let [x0, x1, x2] = x;
    let outside = L::or(L::or(x0.lt(zero), x1.lt(zero)), x2.lt(zero));
    // Most calls have every point inside (the walls' margins are a few ulps unless crack
    // closure moved them): the same zeros without the continuation's arithmetic.
    if !L::any_set(outside) {
        return zero;
    }
    let [p1x, p2x, p2y] = pr.p.map(L::splat);
    let [d0, d1, d2] = pr.d;
    let [n0, n1, n2] = pr.n;
    let [q0, q1, q2] = xp;
    let (e0, e1, e2) = (x0 - q0, x1 - q1, x2 - q2);
    let sp = |v: L::F| L::splat(v);
    // The offset o = Σ (x_i − xp_i)(Pi + s·di) within the section of the point (its z is 0
    // for parallel sections).
    let ox = e1 * p1x + e2 * p2x + s * (e0 * sp(d0.x) + e1 * sp(d1.x) + e2 * sp(d2.x));
    let oy = e2 * p2y + s * (e0 * sp(d0.y) + e1 * sp(d1.y) + e2 * sp(d2.y));
    let nx = q0 * sp(n0.x) + q1 * sp(n1.x) + q2 * sp(n2.x);
    let ny = q0 * sp(n0.y) + q1 * sp(n1.y) + q2 * sp(n2.y);
    let nz = q0 * sp(n0.z) + q1 * sp(n1.z) + q2 * sp(n2.z);
    // Along the line field: a step dX moves the surface point by Σ dX_i (Pi + σ·di) + D·dσ
    // (D the unit-height direction at xp), tangent to the plane ⟂ n when
    // dσ = o.z − n·o / n·D (the point's height is o.z above xp's section point).
    let dx = q0 * sp(d0.x) + q1 * sp(d1.x) + q2 * sp(d2.x);
    let dy = q0 * sp(d0.y) + q1 * sp(d1.y) + q2 * sp(d2.y);
    let dh = if pr.section.parallel {
        let nd = nx * dx + ny * dy + nz;
        zero - (nx * ox + ny * oy) / nd
    } else {
        let oz = s * (e0 * sp(d0.z) + e1 * sp(d1.z) + e2 * sp(d2.z));
        let vz = q0 * sp(d0.z) + q1 * sp(d1.z) + q2 * sp(d2.z);
        let nd = (nx * dx + ny * dy) / vz + nz;
        oz - (nx * ox + ny * oy + nz * oz) / nd
    };
    L::select(L::and(outside, dh.finite()), dh, zero)
}

/// Larger of two lanes, NaN-free for the finite, non-negative values [`bary`] compares.
trait MaxOf {
    fn max_of(self, o: Self) -> Self;
}
impl<L: LaneOps> MaxOf for L {
    #[inline(always)]
    fn max_of(self, o: Self) -> Self {
        L::select(self.gt(o), self, o)
    }
}

/// `f(τ) = z − σS(X)` at the local points `o + τ·r` of eight parameters `tau` (one ray: `o`
/// and `r` splatted), with the projected barycentrics `X`.
// Not inlined: one lane call is ~2 000 instructions, so the call costs nothing, and a single
// copy per lane type keeps builds (and the freestanding link proof's LTO) fast.
#[inline(never)]
pub(crate) fn f_lanes<L: LaneOps>(pr: &Prepared<L::F>, o: [L; 3], r: [L; 3], tau: L) -> L {
    let [ox, oy, oz] = o;
    let [rx, ry, rz] = r;
    let x = L3 {
        x: ox + rx * tau,
        y: oy + ry * tau,
        z: oz + rz * tau,
    };
    let (xp, dh) = bary(pr, x);
    x.z - (height_at(pr, xp) + dh)
}

/// Height `σS(X)` at eight barycentric triples (summing to one, inside the triangle).
#[inline(always)]
pub(crate) fn height_at<L: LaneOps>(pr: &Prepared<L::F>, x: [L; 3]) -> L {
    height_with(pr, x, &Curves)
}

/// Where [`height_with`] takes the conjugation points and normals of the vertex terms from.
trait EdgeCurves<L: LaneOps> {
    /// The point and normal of [`edge_point_normal`] on edge `ep` at parameter `t`, for the
    /// term of vertex `i` (`ep` is edge `i + 1`).
    fn point_normal(&self, i: usize, ep: &EdgePrep<L::F>, t: L) -> (L3<L>, L3<L>);
}

/// The edge curves evaluated at every point.
struct Curves;

impl<L: LaneOps> EdgeCurves<L> for Curves {
    #[inline(always)]
    fn point_normal(&self, _: usize, ep: &EdgePrep<L::F>, t: L) -> (L3<L>, L3<L>) {
        edge_point_normal(ep, t)
    }
}

/// The edge curves of jets with two partials (by `X1` and `X2`) evaluated with one: the curve
/// depends on the point only through its edge parameter `t`, so it is evaluated over jets by
/// `t` alone ([`Tangent`]) and its partials taken by the chain rule ([`chained`]): the values
/// bit for bit [`Curves`]' (the same operations), the partials the same within rounding; a
/// product of jets takes four operations instead of seven (the seamless shading normal's four
/// points: 9 658 → 8 101 instructions, docs/MEASUREMENTS.md "Leaner patch tests").
struct Chained;

impl<L: LaneOps<Plain = L>> EdgeCurves<Jet<L>> for Chained {
    #[inline(always)]
    fn point_normal(&self, _: usize, ep: &EdgePrep<L::F>, t: Jet<L>) -> (L3<Jet<L>>, L3<Jet<L>>) {
        curve_chained(ep, t)
    }
}

/// [`Chained`]'s curve on the edge(s) `ep` (one edge splatted, or three gathered into lanes).
#[inline(always)]
fn curve_chained<L: LaneOps<Plain = L>>(
    ep: &impl EdgeLanes<Tangent<L>>,
    t: Jet<L>,
) -> (L3<Jet<L>>, L3<Jet<L>>) {
    let one = L::splat(L::F::ONE);
    let (p, n) = edge_point_normal(ep, Jet { v: t.v, d: [one] });
    (chained(p, t), chained(n, t))
}

/// [`height_at`] with the conjugation points and normals of the vertex terms from `curves`.
#[inline(always)]
fn height_with<L: LaneOps>(
    pr: &Prepared<L::F>,
    [x0, x1, x2]: [L; 3],
    curves: &impl EdgeCurves<L>,
) -> L {
    let zero = L::Plain::splat(L::F::ZERO);
    let [p1x, p2x, p2y] = pr.p.map(L::Plain::splat);
    let (base, dir, dd) = line(pr, [x0, x1, x2]);
    let [e0, e1, e2] = &pr.edges;
    let [n0, n1, n2] = pr.n.map(L3::<L::Plain>::splat);
    let p0 = L3 {
        x: zero,
        y: zero,
        z: zero,
    };
    let p1 = L3 {
        x: p1x,
        y: zero,
        z: zero,
    };
    let p2 = L3 {
        x: p2x,
        y: p2y,
        z: zero,
    };
    let (c0, m0) = curves.point_normal(0, e1, edge_param(x1, x2));
    let s0 = term_through(c0, m0, p0, n0, x0, base, dir, dd);
    let (c1, m1) = curves.point_normal(1, e2, edge_param(x2, x0));
    let s1 = term_through(c1, m1, p1, n1, x1, base, dir, dd);
    let (c2, m2) = curves.point_normal(2, e0, edge_param(x0, x1));
    s0 + s1 + term_through(c2, m2, p2, n2, x2, base, dir, dd)
}

/// The line of the field through barycentrics `X`: its base point `Σ Xi·Pi`, its direction
/// at unit height and the direction's squared length.
#[inline(always)]
fn line<L: LaneOps>(pr: &Prepared<L::F>, [x0, x1, x2]: [L; 3]) -> (L3<L>, L3<L>, L) {
    let zero = L::splat(L::F::ZERO);
    let [p1x, p2x, p2y] = pr.p.map(L::Plain::splat);
    let [d0, d1, d2] = pr.d;
    let sp = |v: L::F| L::Plain::splat(v);
    let base = L3 {
        x: x1.mul_p(p1x) + x2.mul_p(p2x),
        y: x2.mul_p(p2y),
        z: zero,
    };
    let dir = L3 {
        x: x0.mul_p(sp(d0.x)) + x1.mul_p(sp(d1.x)) + x2.mul_p(sp(d2.x)),
        y: x0.mul_p(sp(d0.y)) + x1.mul_p(sp(d1.y)) + x2.mul_p(sp(d2.y)),
        z: x0 + x1 + x2,
    };
    // Unit height (`crate::surface::field::unit_height_dir`): parallel sections have `Vz = Σ Xi`.
    let dir = if pr.section.parallel {
        dir
    } else {
        let one = c::<L::Plain>(1.0);
        let inv = (x0.mul_p(sp(d0.z)) + x1.mul_p(sp(d1.z)) + x2.mul_p(sp(d2.z))).rdiv_p(one);
        L3 {
            x: dir.x * inv,
            y: dir.y * inv,
            z: L::lift(one),
        }
    };
    (base, dir, dir.dot(dir))
}

/// A value with its partial derivatives (forward mode), over a [`LaneOps`] type `L` (one
/// point: [`One`]; eight-lane jets compile to functions too large to keep builds fast), and
/// [`Partials`] `D`: two by default. The height evaluation over it gives `σS` and
/// `∂σS/∂X1`, `∂σS/∂X2` for the exact normal, in one pass (no nested dual numbers: the edge
/// tangents inside are already derivatives written out); with one partial (`[L; 1]`), an
/// edge curve and its derivative by the edge parameter ([`EdgeEnds`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jet<L, D = [L; 2]> {
    /// Value.
    pub v: L,
    /// Partial derivatives.
    pub d: D,
}

/// The partial derivatives of a [`Jet`]: two (`[L; 2]`) or one (`[L; 1]`), each rule written
/// out per count (loops over a const count made the jets' code compile several times slower).
pub(crate) trait Partials<L: LaneOps>: Copy {
    /// All zero.
    fn zero() -> Self;
    /// `a + b` per partial.
    fn add(self, o: Self) -> Self;
    /// `a − b` per partial.
    fn sub(self, o: Self) -> Self;
    /// `−a` per partial.
    fn neg(self) -> Self;
    /// `a·k` per partial.
    fn scale(self, k: L) -> Self;
    /// The product rule `a·ov + sv·b` per partial.
    fn product(self, ov: L, sv: L, o: Self) -> Self;
    /// The quotient rule `(a − v·b) / ov` per partial.
    fn quotient(self, v: L, o: Self, ov: L) -> Self;
    /// The reciprocal rule `−(v·a) / ov` per partial.
    fn reciprocal(self, v: L, ov: L) -> Self;
    /// `a` where `m`, else `b`, per partial.
    fn pick(m: L::Mask, a: Self, b: Self) -> Self;
    /// Whether every partial is finite, per lane.
    fn finite(self) -> L::Mask;
}

impl<L: LaneOps> Partials<L> for [L; 2] {
    #[inline(always)]
    fn zero() -> Self {
        let z = L::splat(L::F::ZERO);
        [z, z]
    }
    #[inline(always)]
    fn add(self, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 + b0, a1 + b1]
    }
    #[inline(always)]
    fn sub(self, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 - b0, a1 - b1]
    }
    #[inline(always)]
    fn neg(self) -> Self {
        let [a0, a1] = self;
        [-a0, -a1]
    }
    #[inline(always)]
    fn scale(self, k: L) -> Self {
        let [a0, a1] = self;
        [a0 * k, a1 * k]
    }
    #[inline(always)]
    fn product(self, ov: L, sv: L, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 * ov + sv * b0, a1 * ov + sv * b1]
    }
    #[inline(always)]
    fn quotient(self, v: L, [b0, b1]: Self, ov: L) -> Self {
        let [a0, a1] = self;
        [(a0 - v * b0) / ov, (a1 - v * b1) / ov]
    }
    #[inline(always)]
    fn reciprocal(self, v: L, ov: L) -> Self {
        let [a0, a1] = self;
        [-(v * a0) / ov, -(v * a1) / ov]
    }
    #[inline(always)]
    fn pick(m: L::Mask, [a0, a1]: Self, [b0, b1]: Self) -> Self {
        [L::select(m, a0, b0), L::select(m, a1, b1)]
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        let [a0, a1] = self;
        L::and(a0.finite(), a1.finite())
    }
}

impl<L: LaneOps> Partials<L> for [L; 1] {
    #[inline(always)]
    fn zero() -> Self {
        [L::splat(L::F::ZERO)]
    }
    #[inline(always)]
    fn add(self, [b]: Self) -> Self {
        let [a] = self;
        [a + b]
    }
    #[inline(always)]
    fn sub(self, [b]: Self) -> Self {
        let [a] = self;
        [a - b]
    }
    #[inline(always)]
    fn neg(self) -> Self {
        let [a] = self;
        [-a]
    }
    #[inline(always)]
    fn scale(self, k: L) -> Self {
        let [a] = self;
        [a * k]
    }
    #[inline(always)]
    fn product(self, ov: L, sv: L, [b]: Self) -> Self {
        let [a] = self;
        [a * ov + sv * b]
    }
    #[inline(always)]
    fn quotient(self, v: L, [b]: Self, ov: L) -> Self {
        let [a] = self;
        [(a - v * b) / ov]
    }
    #[inline(always)]
    fn reciprocal(self, v: L, ov: L) -> Self {
        let [a] = self;
        [-(v * a) / ov]
    }
    #[inline(always)]
    fn pick(m: L::Mask, [a]: Self, [b]: Self) -> Self {
        [L::select(m, a, b)]
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        let [a] = self;
        a.finite()
    }
}

impl<L: LaneOps, D: Partials<L>> core::ops::Add for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Jet {
            v: self.v + o.v,
            d: self.d.add(o.d),
        }
    }
}
impl<L: LaneOps, D: Partials<L>> core::ops::Sub for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Jet {
            v: self.v - o.v,
            d: self.d.sub(o.d),
        }
    }
}
impl<L: LaneOps, D: Partials<L>> core::ops::Mul for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Jet {
            v: self.v * o.v,
            d: self.d.product(o.v, self.v, o.d),
        }
    }
}
impl<L: LaneOps, D: Partials<L>> core::ops::Div for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Jet {
            v,
            d: self.d.quotient(v, o.d, o.v),
        }
    }
}
impl<L: LaneOps, D: Partials<L>> core::ops::Neg for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Jet {
            v: -self.v,
            d: self.d.neg(),
        }
    }
}

impl<L: LaneOps, D: Partials<L>> Jet<L, D> {
    /// `v` with zero derivatives.
    #[inline(always)]
    fn constant(v: L) -> Self {
        Jet { v, d: D::zero() }
    }

    /// Each part `a` where `m`, else `b`'s.
    #[inline(always)]
    fn pick(m: L::Mask, a: Self, b: Self) -> Self {
        Jet {
            v: L::select(m, a.v, b.v),
            d: D::pick(m, a.d, b.d),
        }
    }
}

impl<L: LaneOps<Plain = L>, D: Partials<L>> LaneOps for Jet<L, D> {
    type F = L::F;
    type Mask = L::Mask;
    type Plain = L;
    #[inline(always)]
    fn lift(p: L) -> Self {
        Jet::constant(p)
    }
    #[inline(always)]
    fn mul_p(self, p: L) -> Self {
        Jet {
            v: self.v * p,
            d: self.d.scale(p),
        }
    }
    #[inline(always)]
    fn add_p(self, p: L) -> Self {
        Jet {
            v: self.v + p,
            d: self.d,
        }
    }
    #[inline(always)]
    fn sub_p(self, p: L) -> Self {
        Jet {
            v: self.v - p,
            d: self.d,
        }
    }
    #[inline(always)]
    fn rsub_p(self, p: L) -> Self {
        Jet {
            v: p - self.v,
            d: self.d.neg(),
        }
    }
    #[inline(always)]
    fn rdiv_p(self, p: L) -> Self {
        let v = p / self.v;
        Jet {
            v,
            d: self.d.reciprocal(v, self.v),
        }
    }
    #[inline(always)]
    fn splat(x: L::F) -> Self {
        Jet::constant(L::splat(x))
    }
    /// The square root; its derivative is 0 where the value is not positive (as the dual
    /// numbers' `sqrt0`: the kernel only takes roots of clamped discriminants).
    #[inline(always)]
    fn sqrt(self) -> Self {
        let z = L::splat(L::F::ZERO);
        let pos = self.v.gt(z);
        let r = L::select(pos, self.v, L::splat(L::F::ONE)).sqrt();
        let k = L::splat(L::F::ONE) / (r + r);
        let root = Jet {
            v: r,
            d: self.d.scale(k),
        };
        Self::pick(pos, root, Jet::constant(z))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Self::pick(self.v.lt(L::splat(L::F::ZERO)), -self, self)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> L::Mask {
        self.v.lt(o.v)
    }
    #[inline(always)]
    fn le(self, o: Self) -> L::Mask {
        self.v.le(o.v)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> L::Mask {
        self.v.gt(o.v)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> L::Mask {
        self.v.eq(o.v)
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        L::and(self.v.finite(), self.d.finite())
    }
    #[inline(always)]
    fn select(m: L::Mask, a: Self, b: Self) -> Self {
        Self::pick(m, a, b)
    }
    #[inline(always)]
    fn and(a: L::Mask, b: L::Mask) -> L::Mask {
        L::and(a, b)
    }
    #[inline(always)]
    fn or(a: L::Mask, b: L::Mask) -> L::Mask {
        L::or(a, b)
    }
    #[inline(always)]
    fn not(a: L::Mask) -> L::Mask {
        L::not(a)
    }
    #[inline(always)]
    fn any_set(m: L::Mask) -> bool {
        L::any_set(m)
    }
}

/// `∂pS/∂Xk = (Pk − P0) + σ·(dk − d0) + (∂σ/∂Xk)·D` from the height `s` and its partials `ds`
/// at barycentrics `x`.
#[inline(always)]
fn assemble<F: Float>(
    shape: &Shape<F>,
    parallel: bool,
    [x0, x1, x2]: [F; 3],
    s: F,
    [s1, s2]: [F; 2],
) -> [V3<F>; 2] {
    let [p0, p1, p2] = shape.p;
    let [d0, d1, d2] = shape.d;
    let dir = d0 * x0 + d1 * x1 + d2 * x2;
    if parallel {
        return [
            p1 - p0 + (d1 - d0) * s + dir * s1,
            p2 - p0 + (d2 - d0) * s + dir * s2,
        ];
    }
    // D = V / Vz: ∂D/∂Xk = ((dk − d0) − D·(dk.z − d0.z)) / Vz.
    let inv = F::ONE / dir.z;
    let dir = dir * inv;
    let dd = |dk: V3<F>| (dk - d0 - dir * (dk.z - d0.z)) * inv;
    [
        p1 - p0 + dd(d1) * s + dir * s1,
        p2 - p0 + dd(d2) * s + dir * s2,
    ]
}

/// Local-frame surface derivatives `∂pS/∂X1`, `∂pS/∂X2` at barycentrics `x` (with
/// `X0 = 1 − X1 − X2`), from one evaluation of the height over [`Jet`]s of one point.
#[inline(always)]
pub(crate) fn derivatives<F: Float>(shape: &Shape<F>, pr: &Prepared<F>, x: [F; 3]) -> [V3<F>; 2] {
    height_derivatives(shape, pr, x).1
}

/// [`derivatives`] with the height `σS` itself: bit for bit the height of [`height_at`] over
/// [`One`] (the jets' value parts are the same operations; their square root differs only for
/// negative arguments, which the height never takes).
///
/// In `f32` and `f64` the three vertex terms of eq. (5) run side by side in the lanes of
/// [`Float::L4`] (one term per lane, over jets: the same operations as three one-point
/// evaluations, summed in the same order), so the result is bit for bit
/// [`terms_in_turn`]'s at about a third of its cost; for other scalars it is that
/// function.
#[inline(always)]
pub(crate) fn height_derivatives<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    x: [F; 3],
) -> (F, [V3<F>; 2]) {
    use crate::num::real::Lane4;
    let s = if <F::L4 as Lane4>::POINTS < 4 {
        terms_in_turn(pr, x)
    } else {
        terms_in_lanes(pr, x)
    };
    (s.v, assemble(shape, pr.section.parallel, x, s.v, s.d))
}

/// The seeds of the jets of barycentrics `x` (`X0 = 1 − X1 − X2`): value and the partials by
/// `X1` and `X2`.
#[inline(always)]
fn seeds<L: LaneOps>([x0, x1, x2]: [L; 3]) -> [Jet<L>; 3] {
    let (one, zero) = (L::splat(L::F::ONE), L::splat(L::F::ZERO));
    let mone = zero - one;
    [
        Jet {
            v: x0,
            d: [mone, mone],
        },
        Jet {
            v: x1,
            d: [one, zero],
        },
        Jet {
            v: x2,
            d: [zero, one],
        },
    ]
}

/// The height jet `σS`, `∂σS/∂X1`, `∂σS/∂X2` at barycentrics `x`, with the three vertex terms
/// of [`height_at`] in lanes 0–2 of jets over [`Float::L4`] (lane 3 repeats lane 0 and is
/// dropped). The line (`base`, `dir`, `dd`) is shared by the terms: computed once over
/// one-point jets and splatted. Requires `Lane4::POINTS == 4`.
#[inline(always)]
fn terms_in_lanes<F: Float>(pr: &Prepared<F>, [x0, x1, x2]: [F; 3]) -> Jet<F> {
    use crate::num::real::Lane4;
    let xs = seeds([x0, x1, x2].map(One));
    let (base, dir, dd) = line(pr, xs);
    let wide = |j: Jet<One<F>>| {
        let [One(a), One(b)] = j.d;
        Jet {
            v: F::L4::splat(j.v.0),
            d: [F::L4::splat(a), F::L4::splat(b)],
        }
    };
    let wide3 = |v: L3<Jet<One<F>>>| L3 {
        x: wide(v.x),
        y: wide(v.y),
        z: wide(v.z),
    };
    let (base, dir, dd) = (wide3(base), wide3(dir), wide(dd));
    // Lane i holds vertex term i: its own barycentric, then the next two (as `height_at`).
    let lanes = |f: fn(&Jet<One<F>>) -> F, [i, j, k]: [usize; 3]| {
        let get = |n: usize| xs.get(n).map(f).unwrap_or(F::ZERO);
        F::L4::from_array4([get(i), get(j), get(k), get(i)])
    };
    let perm = |order: [usize; 3]| Jet {
        v: lanes(|q| q.v.0, order),
        d: [lanes(|q| q.d[0].0, order), lanes(|q| q.d[1].0, order)],
    };
    let (xi, xa, xb) = (perm([0, 1, 2]), perm([1, 2, 0]), perm([2, 0, 1]));
    let zero = F::ZERO;
    let [p1x, p2x, p2y] = pr.p;
    let four = |a: F, b: F, cc: F| F::L4::from_array4([a, b, cc, a]);
    let pi = L3 {
        x: four(zero, p1x, p2x),
        y: four(zero, zero, p2y),
        z: four(zero, zero, zero),
    };
    let [n0, n1, n2] = pr.n;
    let ni = L3 {
        x: four(n0.x, n1.x, n2.x),
        y: four(n0.y, n1.y, n2.y),
        z: four(n0.z, n1.z, n2.z),
    };
    let [e0, e1, e2] = &pr.edges;
    let edges = EdgeGathered::new([e1, e2, e0]);
    let (cpt, nc) = curve_chained(&edges, edge_param(xa, xb));
    let t = term_through(cpt, nc, pi, ni, xi, base, dir, dd);
    let sum = |l: F::L4| {
        let [a, b, cc, _] = l.to_array4();
        a + b + cc
    };
    let [d1, d2] = t.d;
    Jet {
        v: sum(t.v),
        d: [sum(d1), sum(d2)],
    }
}

/// The height jet of [`terms_in_lanes`] over one-point jets, the three vertex terms in turn
/// ([`height_at`]): the reference the lane version is tested against, and the path for scalars
/// without four-lane vectors.
#[inline(always)]
fn terms_in_turn<F: Float>(pr: &Prepared<F>, x: [F; 3]) -> Jet<F> {
    let s = height_with(pr, seeds(x.map(One)), &Chained);
    let [One(s1), One(s2)] = s.d;
    Jet {
        v: s.v.0,
        d: [s1, s2],
    }
}

/// [`derivatives`] at four barycentric triples, over jets of [`Float::L4`]: in `f32` and `f64`
/// one evaluation over four lanes (one SSE2 or NEON register in `f32`), the same operations
/// lane by lane, so bit for bit four calls of [`derivatives`] (IEEE arithmetic and square roots
/// per lane; the selects pick what the branches would); for other scalars four one-point
/// evaluations in turn. Lanes whose input is not finite return non-finite derivatives and
/// leave the others alone.
#[inline(always)]
pub(crate) fn derivatives_x4<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    xs: [[F; 3]; 4],
) -> [[V3<F>; 2]; 4] {
    height_derivatives_x4(shape, pr, xs).map(|(_, d)| d)
}

/// [`derivatives_x4`] with the heights `σS` themselves: bit for bit four calls of
/// [`height_derivatives`] (so the heights are bit for bit [`heights_x4`]'s).
#[inline(always)]
pub(crate) fn height_derivatives_x4<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    xs: [[F; 3]; 4],
) -> [(F, [V3<F>; 2]); 4] {
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS < 4 {
        return xs.map(|x| height_derivatives(shape, pr, x));
    }
    jets_x4(shape, pr, xs, &Chained)
}

/// The conjugation points and normals of the two vertex terms whose edge parameter is the
/// same at every point of a triangle's edge `edge` (from `Pj` to `Pj+1`; the opposite
/// barycentric `Xj+2` is 0): vertex `Pj`'s term meets its opposite edge `j + 1` at `t = 0`
/// and vertex `Pj+1`'s meets edge `j + 2` at `t = 1`. Each with its derivative by `t`, so
/// that [`height_derivatives_on_edge_x4`] takes the jets of both by the chain rule instead of
/// evaluating the edge curves again at every point.
#[derive(Clone, Copy)]
pub(crate) struct EdgeEnds<F: Float> {
    edge: usize,
    /// `[vertex j's term, vertex j + 1's]`.
    ends: [CurveAt<F>; 2],
}

/// A jet with one partial: by an edge parameter.
type Tangent<L> = Jet<L, [L; 1]>;

/// A conjugation point and its normal with their derivatives by the edge parameter
/// (one-point jets).
type CurveAt<F> = (L3<Tangent<One<F>>>, L3<Tangent<One<F>>>);

impl<F: Float> EdgeEnds<F> {
    /// The two end terms of `pr`'s edge `edge` (taken modulo 3): in `f32` and `f64` both in
    /// one evaluation over four lanes (lanes 0 and 1), for other scalars in turn; the same
    /// operations either way.
    #[inline(always)]
    pub(crate) fn new(pr: &Prepared<F>, edge: usize) -> Self {
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
            let at = |ep: &EdgePrep<F>, t: F| {
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
fn lane_of<F: Float>(v: L3<Tangent<F::L4>>, k: usize) -> L3<Tangent<One<F>>> {
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

/// The jets of a point or normal `q` given with its derivative by the edge parameter, at
/// points whose edge-parameter jets are `t`: `∂q/∂Xk = (dq/dt)·(∂t/∂Xk)`.
#[inline(always)]
fn chained<L: LaneOps>(q: L3<Tangent<L>>, t: Jet<L>) -> L3<Jet<L>> {
    let [t1, t2] = t.d;
    let one = |q: Tangent<L>| {
        let [dt] = q.d;
        Jet {
            v: q.v,
            d: [dt * t1, dt * t2],
        }
    };
    L3 {
        x: one(q.x),
        y: one(q.y),
        z: one(q.z),
    }
}

/// An end's point or normal (one point) in every lane of `L`.
#[inline(always)]
fn splat_end<F: Float, L: LaneOps<F = F>>(q: L3<Tangent<One<F>>>) -> L3<Tangent<L>> {
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
        ep: &EdgePrep<F>,
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

/// [`EdgeEnds`]' values alone, for the plain heights on the edge ([`heights_on_edge_x4`]).
struct EndValues<'a, F: Float>(&'a EdgeEnds<F>);

/// The end terms' points and normals splatted from their values.
impl<F: Float> EdgeCurves<F::L4> for EndValues<'_, F> {
    #[inline(always)]
    fn point_normal(&self, i: usize, ep: &EdgePrep<F>, t: F::L4) -> (L3<F::L4>, L3<F::L4>) {
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

/// [`heights_x4`] at four points of the edge of `ends` (as
/// [`height_derivatives_on_edge_x4`]'s points), bit for bit, the two end terms' edge curves
/// taken from [`EdgeEnds`] (their parameters are exactly 0 and 1 there). For other scalars
/// than `f32` and `f64`, [`heights_x4`] itself.
#[inline(always)]
pub(crate) fn heights_on_edge_x4<F: Float>(
    pr: &Prepared<F>,
    ends: &EdgeEnds<F>,
    xs: [[F; 3]; 4],
) -> [F; 4] {
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS < 4 {
        return heights_x4(pr, xs);
    }
    height_with(pr, columns4(xs), &EndValues(ends)).to_array4()
}

/// [`height_derivatives_x4`] at four points of the edge of `ends` (the opposite barycentric
/// exactly 0, the other two above `ε`: points strictly inside the edge, as the builder's
/// edge samples): the heights bit for bit [`heights_x4`]'s, the derivatives the same within
/// rounding (the two end terms' jets by the chain rule from [`EdgeEnds`]; the third term's
/// edge curve, as everywhere, [`Chained`]). For other scalars than `f32` and `f64`,
/// [`height_derivatives_x4`] itself.
#[inline(always)]
pub(crate) fn height_derivatives_on_edge_x4<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    ends: &EdgeEnds<F>,
    xs: [[F; 3]; 4],
) -> [(F, [V3<F>; 2]); 4] {
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS < 4 {
        return height_derivatives_x4(shape, pr, xs);
    }
    jets_x4(shape, pr, xs, ends)
}

/// The height jets at four barycentric triples over jets of [`Float::L4`], the vertex terms'
/// edge curves from `curves`, and the surface derivatives assembled from them. Requires
/// `Lane4::POINTS == 4`.
#[inline(always)]
fn jets_x4<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    xs: [[F; 3]; 4],
    curves: &impl EdgeCurves<Jet<F::L4>>,
) -> [(F, [V3<F>; 2]); 4] {
    use crate::num::real::Lane4;
    let [x0, x1, x2] = columns4(xs);
    let sp = <F::L4 as LaneOps>::splat;
    let (one, zero) = (F::ONE, F::ZERO);
    let j = |v: F::L4, a: F, b: F| Jet {
        v,
        d: [sp(a), sp(b)],
    };
    let s = height_with(
        pr,
        [j(x0, -one, -one), j(x1, one, zero), j(x2, zero, one)],
        curves,
    );
    let [s1, s2] = s.d;
    let (v, s1, s2) = (s.v.to_array4(), s1.to_array4(), s2.to_array4());
    let par = pr.section.parallel;
    let mut out = [(F::ZERO, [V3::zero(); 2]); 4];
    for ((((o, x), v), a), b) in out.iter_mut().zip(xs).zip(v).zip(s1).zip(s2) {
        *o = (v, assemble(shape, par, x, v, [a, b]));
    }
    out
}

/// The heights `σS` at four barycentric triples, over [`Float::L4`] (as
/// [`height_derivatives_x4`]: bit for bit four one-point evaluations of [`height_at`]).
#[inline(always)]
pub(crate) fn heights_x4<F: Float>(pr: &Prepared<F>, xs: [[F; 3]; 4]) -> [F; 4] {
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS < 4 {
        return xs.map(|[x0, x1, x2]| height_at(pr, [One(x0), One(x1), One(x2)]).0);
    }
    height_at(pr, columns4(xs)).to_array4()
}

/// Four barycentric triples as three [`Float::L4`] columns (lane `k` holds triple `k`).
#[inline(always)]
fn columns4<F: Float>(xs: [[F; 3]; 4]) -> [F::L4; 3] {
    use crate::num::real::Lane4;
    core::array::from_fn(|k| F::L4::from_array4(xs.map(|x| x.get(k).copied().unwrap_or(F::ZERO))))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::num::lanes::LANES;
    use crate::patch::Patch;
    use crate::surface::field::LineField;
    use crate::surface::scalar;
    use glam::DVec3;

    /// SplitMix64, for reproducible random patches without extra dependencies.
    pub(crate) struct Rng(pub(crate) u64);
    impl Rng {
        pub(crate) fn unit(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(crate) fn vec(&mut self) -> DVec3 {
            DVec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - DVec3::ONE
        }
    }

    /// The accepted patches among `count` random triangles (size ~3, normals up to ~30° from
    /// the face), with their longest edge from `P0`.
    pub(crate) fn random_patches(
        seed: u64,
        count: usize,
    ) -> impl Iterator<Item = (Patch<f64>, f64)> {
        random_patches_on(seed, count, LineField::Face)
    }

    /// [`random_patches`] on the line field `field`.
    pub(crate) fn random_patches_on(
        seed: u64,
        count: usize,
        field: LineField,
    ) -> impl Iterator<Item = (Patch<f64>, f64)> {
        let mut rng = Rng(seed);
        (0..count).filter_map(move |_| {
            let p = [rng.vec() * 3.0, rng.vec() * 3.0, rng.vec() * 3.0];
            let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let n = [0, 1, 2].map(|_| (nf + rng.vec() * 0.6).normalize_or_zero());
            let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
            Patch::<f64>::with_field(p, n, field)
                .ok()
                .map(|patch| (patch, size))
        })
    }

    #[test]
    fn equals_the_generic_height_within_rounding() {
        let mut worst = 0.0f64;
        let mut tested = 0;
        let fields = [LineField::Face, LineField::Vertex];
        for (patch, size) in fields
            .into_iter()
            .flat_map(|f| random_patches_on(7, 400, f))
        {
            tested += 1;
            let pr = Prepared::new(&patch.shape);
            let mut xs = [[0.0; 3]; 66];
            let grid = (0..=10).flat_map(|i| (0..=(10 - i)).map(move |j| (i, j)));
            for (slot, (i, j)) in xs.iter_mut().zip(grid) {
                let (w1, w2) = (i as f64 / 10.0, j as f64 / 10.0);
                *slot = [1.0 - w1 - w2, w1, w2];
            }
            for chunk in xs.chunks(LANES) {
                let lane = |c: usize| {
                    wide::f64x8::new(core::array::from_fn(|i| {
                        let x = chunk.get(i).or(chunk.first()).copied().unwrap_or_default();
                        x.get(c).copied().unwrap_or_default()
                    }))
                };
                let h = height_at(&pr, [lane(0), lane(1), lane(2)]).to_array();
                for (x, a) in chunk.iter().zip(h) {
                    let b = scalar::height(&patch.shape, *x);
                    worst = worst.max((a - b).abs() / size);
                }
            }
        }
        assert!(tested > 600, "{tested}");
        assert!(
            worst < crate::accuracy::KERNEL_HEIGHT_VS_SURFACE,
            "worst {worst:e}"
        );
    }

    #[test]
    fn jet_derivatives_equal_the_dual_number_derivatives() {
        let mut worst = 0.0f64;
        let mut tested = 0;
        let fields = [LineField::Face, LineField::Vertex];
        for (patch, size) in fields
            .into_iter()
            .flat_map(|f| random_patches_on(11, 300, f))
        {
            tested += 1;
            let pr = Prepared::new(&patch.shape);
            for i in 0..=8 {
                for j in 0..=(8 - i) {
                    let (w1, w2) = (i as f64 / 8.0, j as f64 / 8.0);
                    let x = [1.0 - w1 - w2, w1, w2];
                    let [a1, a2] = derivatives(&patch.shape, &pr, x);
                    let [_, b1, b2] = scalar::point_derivs_local(&patch.shape, x);
                    let d = (a1 - b1).length().max((a2 - b2).length());
                    worst = worst.max(d / size);
                }
            }
        }
        assert!(tested > 400, "{tested}");
        // Same derivatives of the same surface, different rounding (exact either way).
        assert!(worst < 1e-9, "worst {worst:e}");
    }

    /// The four-lane jets ([`derivatives_x4`], the seamless shading normal's;
    /// [`height_derivatives_x4`], the builder's edge samples) and the four-lane heights
    /// ([`heights_x4`]) equal four one-point evaluations ([`derivatives`], the kernel's hit
    /// normal; [`height_at`] over [`One`]) bit for bit, in `f64`
    /// and `f32`, on both line fields, at grid points, on the edges and at the vertices; a lane
    /// whose input is not finite leaves the other lanes alone.
    #[test]
    fn four_lane_jets_equal_one_point_jets_bit_for_bit() {
        fn check<F: Float>(patch: &Patch<F>) -> usize {
            let shape = &patch.shape;
            let pr = Prepared::new(shape);
            let c = F::from_f64;
            let mut xs = [[F::ZERO; 3]; 45];
            let grid = (0..=8).flat_map(|i| (0..=(8 - i)).map(move |j| (i, j)));
            for (slot, (i, j)) in xs.iter_mut().zip(grid) {
                let (w1, w2) = (c(i as f64 / 8.0), c(j as f64 / 8.0));
                *slot = [F::ONE - w1 - w2, w1, w2];
            }
            let mut same = 0;
            for chunk in xs.chunks(3) {
                // The fourth lane is not finite (as an edge point at the opposite vertex).
                let nan = c(f64::NAN);
                let four: [[F; 3]; 4] =
                    core::array::from_fn(|k| chunk.get(k).copied().unwrap_or([nan; 3]));
                let lanes = derivatives_x4(shape, &pr, four);
                let jets = height_derivatives_x4(shape, &pr, four);
                let heights = heights_x4(&pr, four);
                let rows = four.iter().zip(lanes).zip(jets).zip(heights);
                for (((x, got), (jet_h, jet_d)), h) in rows.take(chunk.len()) {
                    let want = derivatives(shape, &pr, *x);
                    let bits = |d: [V3<F>; 2]| d.map(|v| [v.x, v.y, v.z].map(F::to_f64));
                    let (g, w) = (bits(got), bits(want));
                    for (a, b) in g.iter().flatten().zip(w.iter().flatten()) {
                        assert_eq!(a.to_bits(), b.to_bits(), "{x:?}");
                    }
                    assert_eq!(bits(jet_d), w, "{x:?}");
                    let [x0, x1, x2] = *x;
                    let one = height_at(&pr, [One(x0), One(x1), One(x2)]).0.to_f64();
                    let want_h = height_derivatives(shape, &pr, *x).0.to_f64();
                    assert_eq!(one.to_bits(), want_h.to_bits(), "{x:?}");
                    assert_eq!(h.to_f64().to_bits(), one.to_bits(), "{x:?}");
                    assert_eq!(jet_h.to_f64().to_bits(), one.to_bits(), "{x:?}");
                    same += 1;
                }
            }
            same
        }
        let mut tested = 0;
        for field in [LineField::Face, LineField::Vertex] {
            for (patch, _) in random_patches_on(13, 200, field) {
                tested += check(&patch);
                let (v, n) = (patch.vertices(), patch.normals());
                if let Ok(p32) =
                    Patch::<f32>::with_field(v.map(|p| p.as_vec3()), n.map(|p| p.as_vec3()), field)
                {
                    tested += check(&p32);
                }
            }
        }
        assert!(tested > 45 * 500, "{tested}");
    }

    /// The jets at points of an edge with the end terms by the chain rule
    /// ([`height_derivatives_on_edge_x4`], the builder's edge samples) against the jets over
    /// the whole evaluation ([`height_derivatives_x4`]), on all three edges, both line fields,
    /// `f64` and `f32`: the heights bit for bit, the derivatives within rounding of the
    /// triangle's size (they differ only in the order of the derivative's products).
    #[test]
    fn on_edge_jets_equal_the_full_jets() {
        fn check<F: Float>(patch: &Patch<F>, size: f64, worst: &mut f64) -> usize {
            let shape = &patch.shape;
            let pr = Prepared::new(shape);
            let mut n = 0;
            for edge in 0..3 {
                let ends = EdgeEnds::new(&pr, edge);
                for k in 0..4 {
                    let xs: [[F; 3]; 4] = core::array::from_fn(|i| {
                        let t = 0.0025 + (0.995 * (4 * k + i) as f64) / 15.0;
                        crate::mesh::topology::edge_bary(edge, t).map(F::from_f64)
                    });
                    let got = height_derivatives_on_edge_x4(shape, &pr, &ends, xs);
                    let want = height_derivatives_x4(shape, &pr, xs);
                    let plain = heights_on_edge_x4(&pr, &ends, xs);
                    for (a, b) in plain.into_iter().zip(heights_x4(&pr, xs)) {
                        assert_eq!(a.to_f64().to_bits(), b.to_f64().to_bits());
                    }
                    for ((gh, gd), (wh, wd)) in got.into_iter().zip(want) {
                        assert_eq!(gh.to_f64().to_bits(), wh.to_f64().to_bits());
                        for (a, b) in gd.iter().zip(wd.iter()) {
                            let d = *a - *b;
                            let d = [d.x, d.y, d.z].map(|v| v.to_f64().abs());
                            *worst = worst.max(d.into_iter().fold(0.0, f64::max) / size);
                        }
                        n += 1;
                    }
                }
            }
            n
        }
        let (mut w64, mut w32, mut tested) = (0.0f64, 0.0f64, 0);
        for field in [LineField::Face, LineField::Vertex] {
            for (patch, size) in random_patches_on(17, 200, field) {
                tested += check(&patch, size, &mut w64);
                let (v, n) = (patch.vertices(), patch.normals());
                if let Ok(p32) =
                    Patch::<f32>::with_field(v.map(|p| p.as_vec3()), n.map(|p| p.as_vec3()), field)
                {
                    tested += check(&p32, size, &mut w32);
                }
            }
        }
        assert!(tested > 48 * 500, "{tested}");
        assert!(w64 < 1e-13, "f64 {w64:e}");
        assert!(w32 < 1e-5, "f32 {w32:e}");
    }

    /// The one-point jets with the three vertex terms in lanes ([`terms_in_lanes`], the
    /// kernel's hit normal) equal the one-point jets with the terms in turn
    /// ([`terms_in_turn`]) bit for bit, in `f64` and `f32`, on both line fields, at
    /// grid points, on the edges, at the vertices and at random points.
    #[test]
    fn terms_in_lanes_equal_terms_in_turn_bit_for_bit() {
        fn check<F: Float>(patch: &Patch<F>, rng: &mut Rng) -> usize {
            let pr = Prepared::new(&patch.shape);
            let c = F::from_f64;
            let grid = (0..=8).flat_map(|i| (0..=(8 - i)).map(move |j| (i as f64, j as f64)));
            let random = (0..20).map(|_| (rng.unit() * 8.0, rng.unit() * 8.0));
            let mut same = 0;
            for (i, j) in grid.chain(random) {
                let (w1, w2) = (c(i / 8.0), c(j / 8.0));
                let x = [F::ONE - w1 - w2, w1, w2];
                let bits = |j: Jet<F>| [j.v, j.d[0], j.d[1]].map(|q| q.to_f64().to_bits());
                let (lanes, turn) = (terms_in_lanes(&pr, x), terms_in_turn(&pr, x));
                assert_eq!(bits(lanes), bits(turn), "{x:?}");
                same += 1;
            }
            same
        }
        let (mut tested, mut rng) = (0, Rng(5));
        for field in [LineField::Face, LineField::Vertex] {
            for (patch, _) in random_patches_on(17, 200, field) {
                tested += check(&patch, &mut rng);
                let (v, n) = (patch.vertices(), patch.normals());
                if let Ok(p32) =
                    Patch::<f32>::with_field(v.map(|p| p.as_vec3()), n.map(|p| p.as_vec3()), field)
                {
                    tested += check(&p32, &mut rng);
                }
            }
        }
        assert!(tested > 65 * 500, "{tested}");
    }

    /// A point built on the line of barycentrics `X` at parameter `λ` (inside the shell and up
    /// to a tenth of the triangle beyond its edges) is mapped back to that `λ` and `X`, by the
    /// scalar [`Section::param`] and by the lanes, on patches whose sections are tilted.
    #[test]
    fn section_param_recovers_the_line() {
        let (mut worst_l, mut worst_x, mut tested) = (0.0f64, 0.0f64, 0);
        let mut rng = Rng(3);
        for (patch, size) in random_patches_on(13, 400, LineField::Vertex) {
            let shape = &patch.shape;
            if crate::surface::field::parallel(shape) {
                continue;
            }
            tested += 1;
            let sec = Section::new(shape);
            let [lo, hi] = crate::surface::shell::lambda_range(shape, patch.sigma);
            let mut pts = [(V3::zero(), 0.0, [0.0; 3]); LANES];
            for slot in pts.iter_mut() {
                let (w1, w2) = (rng.unit() * 1.2 - 0.1, rng.unit() * 1.2 - 0.1);
                let (w1, w2) = if w1 + w2 > 1.1 {
                    (1.0 - w1, 1.0 - w2)
                } else {
                    (w1, w2)
                };
                let x = [1.0 - w1 - w2, w1, w2];
                let l = lo + (hi - lo) * rng.unit();
                let mut q = V3::zero();
                for ((p, d), w) in shape.p.iter().zip(shape.d.iter()).zip(x) {
                    q = q + (*p + *d * l) * w;
                }
                *slot = (q, l, x);
            }
            let lane = |c: usize| {
                wide::f64x8::new(core::array::from_fn(|i| {
                    let q = pts.get(i).map(|p| p.0).unwrap_or(V3::zero());
                    [q.x, q.y, q.z].get(c).copied().unwrap_or_default()
                }))
            };
            let lanes = section_param(
                &sec,
                L3 {
                    x: lane(0),
                    y: lane(1),
                    z: lane(2),
                },
            )
            .to_array();
            for ((q, l, x), ll) in pts.into_iter().zip(lanes) {
                let got = sec.param(q);
                worst_l = worst_l
                    .max((got - l).abs() / size)
                    .max((ll - l).abs() / size);
                let (n, area) = crate::kernel::clip::bary_numerators(shape, &sec, q);
                for (nk, xk) in n.into_iter().zip(x) {
                    worst_x = worst_x.max((nk / area - xk).abs());
                }
            }
        }
        assert!(tested > 300, "{tested}");
        assert!(worst_l < 1e-12, "λ: {worst_l:e} of the size");
        assert!(worst_x < 1e-12, "X: {worst_x:e}");
    }
}
