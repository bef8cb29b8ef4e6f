//! The lane formulas against the generic scalar surface and against each other.

use super::height::*;
use super::jets::*;
use super::*;
use crate::num::jet::Jet;
use crate::num::lane_vec::L3;
use crate::num::lanes::{LANES, One};
use crate::patch::Patch;
use crate::surface::field::LineField;
use crate::surface::scalar;
use crate::testing::{Rng, random_patches_on};

/// Calls `f` with each of `count` random `f64` patches (seed `seed`) on each line field, with
/// its size and its prepared lanes; returns how many patches it saw.
fn on_random_patches(
    seed: u64,
    count: usize,
    mut f: impl FnMut(&Patch<f64>, f64, &Prepared<f64>),
) -> usize {
    let mut tested = 0;
    for field in [LineField::Face, LineField::Vertex] {
        for (patch, size) in random_patches_on(seed, count, field) {
            tested += 1;
            f(&patch, size, &Prepared::new(&patch.shape));
        }
    }
    tested
}

#[test]
fn equals_the_generic_height_within_rounding() {
    let mut worst = 0.0f64;
    let tested = on_random_patches(7, 400, |patch, size, pr| {
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
            let h = height_at(pr, [lane(0), lane(1), lane(2)]).to_array();
            for (x, a) in chunk.iter().zip(h) {
                let b = scalar::height(&patch.shape, *x);
                worst = worst.max((a - b).abs() / size);
            }
        }
    });
    assert!(tested > 600, "{tested}");
    assert!(
        worst < crate::accuracy::KERNEL_HEIGHT_VS_SURFACE,
        "worst {worst:e}"
    );
}

#[test]
fn jet_derivatives_equal_the_dual_number_derivatives() {
    let mut worst = 0.0f64;
    let tested = on_random_patches(11, 300, |patch, size, pr| {
        for i in 0..=8 {
            for j in 0..=(8 - i) {
                let (w1, w2) = (i as f64 / 8.0, j as f64 / 8.0);
                let x = [1.0 - w1 - w2, w1, w2];
                let [a1, a2] = pr.derivatives(&patch.shape, x);
                let [_, b1, b2] = scalar::point_derivs_local(&patch.shape, x);
                let d = (a1 - b1).length().max((a2 - b2).length());
                worst = worst.max(d / size);
            }
        }
    });
    assert!(tested > 400, "{tested}");
    // Same derivatives of the same surface, different rounding (exact either way).
    assert!(worst < 1e-9, "worst {worst:e}");
}

/// The four-lane jets ([`Prepared::derivatives_x4`], the seamless shading normal's;
/// [`height_derivatives_x4`], the builder's edge samples) and the four-lane heights
/// ([`heights_x4`]) equal four one-point evaluations ([`Prepared::derivatives`], the kernel's hit
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
            let lanes = pr.derivatives_x4(shape, four);
            let jets = height_derivatives_x4(shape, &pr, four);
            let heights = heights_x4(&pr, four);
            let rows = four.iter().zip(lanes).zip(jets).zip(heights);
            for (((x, got), (jet_h, jet_d)), h) in rows.take(chunk.len()) {
                let want = pr.derivatives(shape, *x);
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
/// ([`OnEdge::height_derivatives_x4`], the builder's edge samples) against the jets over
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
            let on = pr.on_edge(edge);
            for k in 0..4 {
                let xs: [[F; 3]; 4] = core::array::from_fn(|i| {
                    let t = 0.0025 + (0.995 * (4 * k + i) as f64) / 15.0;
                    crate::mesh::topology::edge_bary(edge, t).map(F::from_f64)
                });
                let got = on.height_derivatives_x4(shape, xs);
                let want = height_derivatives_x4(shape, &pr, xs);
                let plain = on.heights_x4(xs);
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
            let (n, area) = sec.bary_numerators(shape, q);
            for (nk, xk) in n.into_iter().zip(x) {
                worst_x = worst_x.max((nk / area - xk).abs());
            }
        }
    }
    assert!(tested > 300, "{tested}");
    assert!(worst_l < 1e-12, "λ: {worst_l:e} of the size");
    assert!(worst_x < 1e-12, "X: {worst_x:e}");
}
