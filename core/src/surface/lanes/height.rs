//! The height `σS` of eq. (5) over lanes at barycentric triples, the map of the kernel's ray
//! points to their barycentrics (the section through each point, projected onto the triangle,
//! and the surface's continuation beyond its edges) and the kernel's function `f`.

use super::curve::{EdgeLanes, edge_point_normal, root};
use super::{Prepared, PreparedEdge};
use crate::num::jet::{Jet, Tangent, chained};
use crate::num::lane_vec::{L3, splat_f64};
use crate::num::lanes::LaneOps;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::field::{SECTION_NEWTON_STEPS, Section};

/// The parameter `t = Xb / (Xa + Xb)` on the edge opposite a vertex of the point with the
/// other two barycentrics `xa`, `xb` (½ where they vanish: the vertex itself).
#[inline(always)]
pub(super) fn edge_param<L: LaneOps>(xa: L, xb: L) -> L {
    let den = xa + xb;
    L::select(
        den.gt(L::splat(L::F::EPSILON)),
        xb / den,
        splat_f64::<L>(0.5),
    )
}

/// The term of vertex `i` in eq. (5), `½ (Xi·s¹ + ((1 − Xi)/2)·s²)` for the line `base + s·dir`
/// (`dd = |dir|²`), from the conjugation point `cpt` and its normal `nc` (scaled) on the
/// opposite edge.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn term_through<L: LaneOps>(
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
    let one = splat_f64::<L::Plain>(1.0);
    let two = splat_f64::<L::Plain>(2.0);
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
    xi.mul_p(splat_f64(0.5)) * s1 + xi.rsub_p(one).mul_p(splat_f64(0.25)) * s2
}

/// The line parameter `λ` of the section through each local point ([`Section::param`] over
/// lanes: `x.z` for parallel sections, else [`SECTION_NEWTON_STEPS`] Newton steps).
#[inline(always)]
pub(super) fn section_param<L: LaneOps>(sec: &Section<L::F>, x: L3<L>) -> L {
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
    let (two, three) = (splat_f64::<L>(2.0), splat_f64::<L>(3.0));
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
pub(super) fn bary<L: LaneOps>(pr: &Prepared<L::F>, x: L3<L>) -> ([L; 3], L) {
    let zero = L::splat(L::F::ZERO);
    let one = splat_f64::<L>(1.0);
    let [p1x, p2x, p2y] = pr.vertex_xy.map(L::splat);
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
    let third = splat_f64::<L>(1.0 / 3.0);
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
pub(super) fn beyond_edge<L: LaneOps>(pr: &Prepared<L::F>, x: [L; 3], xp: [L; 3], s: L) -> L {
    let zero = L::splat(L::F::ZERO);
    let [x0, x1, x2] = x;
    let outside = L::or(L::or(x0.lt(zero), x1.lt(zero)), x2.lt(zero));
    // Most calls have every point inside (the walls' margins are a few ulps unless crack
    // closure moved them): the same zeros without the continuation's arithmetic.
    if !L::any_set(outside) {
        return zero;
    }
    let [p1x, p2x, p2y] = pr.vertex_xy.map(L::splat);
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
pub(super) trait MaxOf {
    fn max_of(self, o: Self) -> Self;
}

impl<L: LaneOps> MaxOf for L {
    #[inline(always)]
    fn max_of(self, o: Self) -> Self {
        L::select(self.gt(o), self, o)
    }
}

/// `f(τ) = z − σS(X)` at the local points `o + τ·r` of eight parameters `tau` (one ray: `o`
/// and `r` splatted), with the projected barycentrics `X`: [`f_inline`] out of line.
// Not inlined: one lane call is long beside the cost of a call, and a single copy per lane
// type keeps builds (and the freestanding link proof's LTO) fast.
#[inline(never)]
pub(super) fn f_lanes<L: LaneOps>(pr: &Prepared<L::F>, o: [L; 3], r: [L; 3], tau: L) -> L {
    f_inline(pr, o, r, tau)
}

/// [`f_lanes`] inlined into its caller: the lane code compiled with the caller's target
/// features (the kernels per instruction set, `crate::isa`, call it from their own
/// out-of-line functions).
#[inline(always)]
pub(super) fn f_inline<L: LaneOps>(pr: &Prepared<L::F>, o: [L; 3], r: [L; 3], tau: L) -> L {
    let (z, xp, dh) = ray_bary(pr, o, r, tau);
    z - (height_at(pr, xp) + dh)
}

/// The local ray points `o + τ·r` of the lanes: their height `z`, their projected barycentrics
/// and the height change of the continuation beyond the edges there ([`bary`]): what `f`
/// evaluates the height at and adds to it.
#[inline(always)]
pub(super) fn ray_bary<L: LaneOps>(
    pr: &Prepared<L::F>,
    o: [L; 3],
    r: [L; 3],
    tau: L,
) -> (L, [L; 3], L) {
    let [ox, oy, oz] = o;
    let [rx, ry, rz] = r;
    let x = L3 {
        x: ox + rx * tau,
        y: oy + ry * tau,
        z: oz + rz * tau,
    };
    let (xp, dh) = bary(pr, x);
    (x.z, xp, dh)
}

/// Height `σS(X)` at eight barycentric triples (summing to one, inside the triangle).
#[inline(always)]
pub(super) fn height_at<L: LaneOps>(pr: &Prepared<L::F>, x: [L; 3]) -> L {
    height_with(pr, x, &Curves)
}

/// Where [`height_with`] takes the conjugation points and normals of the vertex terms from.
pub(super) trait EdgeCurves<L: LaneOps> {
    /// The point and normal of [`edge_point_normal`] on edge `ep` at parameter `t`, for the
    /// term of vertex `i` (`ep` is edge `i + 1`).
    fn point_normal(&self, i: usize, ep: &PreparedEdge<L::F>, t: L) -> (L3<L>, L3<L>);
}

/// The edge curves evaluated at every point.
pub(super) struct Curves;

impl<L: LaneOps> EdgeCurves<L> for Curves {
    #[inline(always)]
    fn point_normal(&self, _: usize, ep: &PreparedEdge<L::F>, t: L) -> (L3<L>, L3<L>) {
        edge_point_normal(ep, t)
    }
}

/// The edge curves of jets with two partials (by `X1` and `X2`) evaluated with one: the curve
/// depends on the point only through its edge parameter `t`, so it is evaluated over jets by
/// `t` alone ([`Tangent`]) and its partials taken by the chain rule ([`chained`]): the values
/// bit for bit [`Curves`]' (the same operations), the partials the same within rounding; a
/// product of jets takes four operations instead of seven.
pub(super) struct Chained;

impl<L: LaneOps<Plain = L>> EdgeCurves<Jet<L>> for Chained {
    #[inline(always)]
    fn point_normal(
        &self,
        _: usize,
        ep: &PreparedEdge<L::F>,
        t: Jet<L>,
    ) -> (L3<Jet<L>>, L3<Jet<L>>) {
        curve_chained(ep, t)
    }
}

/// [`Chained`]'s curve on the edge(s) `ep` (one edge splatted, or three gathered into lanes).
#[inline(always)]
pub(super) fn curve_chained<L: LaneOps<Plain = L>>(
    ep: &impl EdgeLanes<Tangent<L>>,
    t: Jet<L>,
) -> (L3<Jet<L>>, L3<Jet<L>>) {
    let one = L::splat(L::F::ONE);
    let (p, n) = edge_point_normal(ep, Jet { v: t.v, d: [one] });
    (chained(p, t), chained(n, t))
}

/// [`height_at`] with the conjugation points and normals of the vertex terms from `curves`.
#[inline(always)]
pub(super) fn height_with<L: LaneOps>(
    pr: &Prepared<L::F>,
    [x0, x1, x2]: [L; 3],
    curves: &impl EdgeCurves<L>,
) -> L {
    let zero = L::Plain::splat(L::F::ZERO);
    let [p1x, p2x, p2y] = pr.vertex_xy.map(L::Plain::splat);
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
pub(super) fn line<L: LaneOps>(pr: &Prepared<L::F>, [x0, x1, x2]: [L; 3]) -> (L3<L>, L3<L>, L) {
    let zero = L::splat(L::F::ZERO);
    let [p1x, p2x, p2y] = pr.vertex_xy.map(L::Plain::splat);
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
        let one = splat_f64::<L::Plain>(1.0);
        let inv = (x0.mul_p(sp(d0.z)) + x1.mul_p(sp(d1.z)) + x2.mul_p(sp(d2.z))).rdiv_p(one);
        L3 {
            x: dir.x * inv,
            y: dir.y * inv,
            z: L::lift(one),
        }
    };
    (base, dir, dir.dot(dir))
}
