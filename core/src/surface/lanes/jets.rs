//! The height with its partial derivatives by `X1` and `X2` over jets, and the local-frame
//! surface derivatives assembled from them: one point (the three vertex terms side by side in
//! four lanes) or four points in four lanes.

use super::Prepared;
use super::curve::EdgeGathered;
use super::height::{
    Chained, EdgeCurves, curve_chained, edge_param, height_at, height_with, line, term_through,
};
use crate::geometry::Shape;
use crate::num::jet::{Jet, seeds};
use crate::num::lane_vec::L3;
use crate::num::lanes::{LaneOps, One};
use crate::num::real::Float;
use crate::num::vec::V3;

/// `∂pS/∂Xk = (Pk − P0) + σ·(dk − d0) + (∂σ/∂Xk)·D` from the height `s` and its partials `ds`
/// at barycentrics `x`.
#[inline(always)]
pub(super) fn assemble<F: Float>(
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

/// The height `σS` and the local-frame surface derivatives `∂pS/∂X1`, `∂pS/∂X2` at
/// barycentrics `x` (with `X0 = 1 − X1 − X2`), from one evaluation of the height over jets: bit for bit the height of [`height_at`] over
/// [`One`] (the jets' value parts are the same operations; their square root differs only for
/// negative arguments, which the height never takes).
///
/// In `f32` and `f64` the three vertex terms of eq. (5) run side by side in the lanes of
/// [`Float::L4`] (one term per lane, over jets: the same operations as three one-point
/// evaluations, summed in the same order), so the result is bit for bit
/// [`terms_in_turn`]'s at about a third of its cost; for other scalars it is that
/// function.
#[inline(always)]
pub(super) fn height_derivatives<F: Float>(
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

/// The height jet `σS`, `∂σS/∂X1`, `∂σS/∂X2` at barycentrics `x`, with the three vertex terms
/// of [`height_at`] in lanes 0–2 of jets over [`Float::L4`] (lane 3 repeats lane 0 and is
/// dropped). The line (`base`, `dir`, `dd`) is shared by the terms: computed once over
/// one-point jets and splatted. Requires `Lane4::POINTS == 4`.
#[inline(always)]
pub(super) fn terms_in_lanes<F: Float>(pr: &Prepared<F>, [x0, x1, x2]: [F; 3]) -> Jet<F> {
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
    let [p1x, p2x, p2y] = pr.vertex_xy;
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
pub(super) fn terms_in_turn<F: Float>(pr: &Prepared<F>, x: [F; 3]) -> Jet<F> {
    let s = height_with(pr, seeds(x.map(One)), &Chained);
    let [One(s1), One(s2)] = s.d;
    Jet {
        v: s.v.0,
        d: [s1, s2],
    }
}

/// [`height_derivatives`] at four barycentric triples: bit for bit four calls of
/// [`height_derivatives`] (so the heights are bit for bit [`heights_x4`]'s).
#[inline(always)]
pub(super) fn height_derivatives_x4<F: Float>(
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

/// The height jets at four barycentric triples over jets of [`Float::L4`], the vertex terms'
/// edge curves from `curves`, and the surface derivatives assembled from them. Requires
/// `Lane4::POINTS == 4`.
#[inline(always)]
pub(super) fn jets_x4<F: Float>(
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
pub(super) fn heights_x4<F: Float>(pr: &Prepared<F>, xs: [[F; 3]; 4]) -> [F; 4] {
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS < 4 {
        return xs.map(|[x0, x1, x2]| height_at(pr, [One(x0), One(x1), One(x2)]).0);
    }
    height_at(pr, columns4(xs)).to_array4()
}

/// Four barycentric triples as three [`Float::L4`] columns (lane `k` holds triple `k`).
#[inline(always)]
pub(super) fn columns4<F: Float>(xs: [[F; 3]; 4]) -> [F::L4; 3] {
    use crate::num::real::Lane4;
    core::array::from_fn(|k| F::L4::from_array4(xs.map(|x| x.get(k).copied().unwrap_or(F::ZERO))))
}
