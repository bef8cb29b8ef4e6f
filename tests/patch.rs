//! Properties of the patch construction (docs/METHOD.md §6), f64 and f32, over random inputs.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use proptest::prelude::*;
use smoothtri::{DPatch, Patch, PatchError};

fn to32(v: [DVec3; 3]) -> [Vec3; 3] {
    v.map(|x| x.as_vec3())
}

proptest! {
    // Fixed seed and no failure files: CI runs the same 256 cases every time.
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5EED_0003),
        ..ProptestConfig::default()
    })]

    /// Vertices exact, edges pass through the conjugation lines, edge normals equal the vertex
    /// normals at the ends (f64 ≤ 1e-12 relative, f32 ≤ 1e-5).
    #[test]
    fn interpolates_vertices_and_edges(seed in any::<u64>()) {
        let mut rng = Rng(seed);
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0]).length().max((p[2] - p[0]).length()).max((p[2] - p[1]).length());
        let scale = p.iter().fold(size, |m, x| m.max(x.abs().max_element()));
        let patch = DPatch::new(p, n).unwrap();
        let p32: Patch = Patch::new(to32(p), to32(n)).unwrap();
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
        for (k, &(w1, w2)) in corners.iter().enumerate() {
            assert_vec_close!(patch.point(w1, w2), p[k], 1e-12 * size);
            assert_vec_close!(p32.point(w1 as f32, w2 as f32).as_dvec3(), p[k], 1e-5 * scale);
        }
        for edge in 0..3 {
            let (_, n_start) = patch.edge_point_normal(edge, 0.0);
            let (_, n_end) = patch.edge_point_normal(edge, 1.0);
            assert_vec_close!(n_start, n[edge].normalize(), 1e-12);
            assert_vec_close!(n_end, n[(edge + 1) % 3].normalize(), 1e-12);
            let (_, m_start) = p32.edge_point_normal(edge, 0.0);
            assert_vec_close!(m_start.as_dvec3(), n[edge].normalize(), 1e-5);
            for t in [0.1, 0.37, 0.5, 0.81] {
                // Barycentrics of edge `edge` at parameter t.
                let mut w = [0.0; 3];
                w[edge] = 1.0 - t;
                w[(edge + 1) % 3] = t;
                let (c, _) = patch.edge_point_normal(edge, t);
                assert_vec_close!(patch.point(w[1], w[2]), c, 1e-12 * size, "edge {edge} t {t}");
                let (c32, _) = p32.edge_point_normal(edge, t as f32);
                assert_vec_close!(p32.point(w[1] as f32, w[2] as f32).as_dvec3(), c32.as_dvec3(), 1e-5 * scale);
            }
        }
    }

    /// All normals equal to the face normal reproduce the flat triangle, with the face normal.
    #[test]
    fn flat_normals_give_flat_triangle(seed in any::<u64>()) {
        let mut rng = Rng(seed);
        let size = 10f64.powf(rng.range(-2.0, 1.7));
        let off = DVec3::splat(rng.range(-3.0, 3.0));
        let (p, nf) = well_shaped(&mut rng, size, off);
        let patch = DPatch::new(p, [nf * 2.0, nf, nf * 0.7]).unwrap();
        let size = (p[1] - p[0]).length();
        for (w1, w2) in bary_grid(7) {
            let flat = p[0] * (1.0 - w1 - w2) + p[1] * w1 + p[2] * w2;
            let (x, nrm) = patch.point_normal(w1, w2);
            assert_vec_close!(x, flat, 1e-12 * size.max(p[0].abs().max_element()));
            assert_vec_close!(nrm, nf, 1e-12);
        }
    }

    /// Spheres are reproduced exactly: radius 1e-3…1e3, radial normals; every point on the
    /// sphere (f64 1e-12, f32 2e-6 relative) with a radial normal.
    #[test]
    fn spheres_are_exact(seed in any::<u64>()) {
        let mut rng = Rng(seed);
        let r = 10f64.powf(rng.range(-3.0, 3.0));
        let o = DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)) * r;
        let cap = rng.range(5.0, 35.0);
        let p = sphere_patch(&mut rng, o, r, cap);
        let n = p.map(|x| (x - o) / r);
        let patch = DPatch::new(p, n).unwrap();
        let p32: Patch = Patch::new(to32(p), to32(n)).unwrap();
        let o32 = o.as_vec3().as_dvec3();
        for (w1, w2) in bary_grid(6) {
            let (x, nrm) = patch.point_normal(w1, w2);
            assert_close!((x - o).length(), r, 1e-12 * r);
            assert_vec_close!(nrm, (x - o) / r, 1e-10);
            let (y, m) = p32.point_normal(w1 as f32, w2 as f32);
            let y = y.as_dvec3();
            assert_close!((y - o32).length(), r, 2e-6 * r);
            // f32 normals come from f32 derivatives: up to 2.0e-5 seen over random seeds.
            assert_vec_close!(m.as_dvec3(), (y - o32).normalize(), 5e-5);
        }
    }

    /// Exact derivatives agree with central finite differences of the f64 surface.
    #[test]
    fn derivatives_match_finite_differences(seed in any::<u64>()) {
        let mut rng = Rng(seed);
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0]).length();
        let patch = DPatch::new(p, n).unwrap();
        let (w1, w2) = (rng.range(0.05, 0.6), rng.range(0.05, 0.35));
        let (d1, d2) = patch.derivatives(w1, w2);
        let h = 1e-5;
        let fd1 = (patch.point(w1 + h, w2) - patch.point(w1 - h, w2)) / (2.0 * h);
        let fd2 = (patch.point(w1, w2 + h) - patch.point(w1, w2 - h)) / (2.0 * h);
        assert_vec_close!(d1, fd1, 1e-6 * size);
        assert_vec_close!(d2, fd2, 1e-6 * size);
        // Edge tangent: derivative of the edge curve along t, through the surface normal.
        let (_, nrm) = patch.point_normal(w1, w2);
        assert_close!(nrm.dot(d1), 0.0, 1e-12 * size);
        assert_close!(nrm.dot(d2), 0.0, 1e-12 * size);
    }
}

/// The f32 path against the f64 path on the same (f32-representable) input: the difference,
/// relative to the larger of the triangle's size and its coordinates, stays below 1e-6 for
/// points and 5e-6 for normals (measured worst values are printed).
#[test]
fn f32_tracks_f64() {
    let mut rng = Rng(99);
    let (mut wp, mut wn) = (0.0f64, 0.0f64);
    for _ in 0..2000 {
        let (p, n) = random_patch(&mut rng, 40.0);
        let (p32, n32) = (to32(p), to32(n));
        let a: Patch = Patch::new(p32, n32).unwrap();
        let b = DPatch::new(p32.map(Vec3::as_dvec3), n32.map(Vec3::as_dvec3)).unwrap();
        let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
        let scale = p.iter().fold(size, |m, x| m.max(x.abs().max_element()));
        for (w1, w2) in [(0.2, 0.3), (0.6, 0.1), (1.0 / 3.0, 1.0 / 3.0), (0.05, 0.9)] {
            let (x, nx) = a.point_normal(w1 as f32, w2 as f32);
            let (y, ny) = b.point_normal(w1 as f32 as f64, w2 as f32 as f64);
            wp = wp.max((x.as_dvec3() - y).length() / scale);
            wn = wn.max((nx.as_dvec3() - ny).length());
        }
    }
    eprintln!(
        "f32 vs f64: worst point difference {wp:.2e} of scale, worst normal difference {wn:.2e}"
    );
    assert!(wp <= 1e-6, "points {wp:e}");
    assert!(wn <= 5e-6, "normals {wn:e}");
}

#[test]
fn every_error_variant_is_reported() {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let up = [DVec3::Z; 3];
    assert_eq!(
        DPatch::new([DVec3::NAN, DVec3::X, DVec3::Y], up),
        Err(PatchError::NonFinite)
    );
    assert_eq!(
        DPatch::new(p, [DVec3::Z, DVec3::new(0.0, f64::INFINITY, 1.0), DVec3::Z]),
        Err(PatchError::NonFinite)
    );
    assert_eq!(
        DPatch::new([DVec3::ZERO, DVec3::X, DVec3::X * 2.0], up),
        Err(PatchError::DegenerateTriangle)
    );
    assert_eq!(
        DPatch::new([DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-9, 0.0)], up),
        Err(PatchError::DegenerateTriangle)
    );
    assert_eq!(
        DPatch::new([DVec3::ZERO; 3], up),
        Err(PatchError::DegenerateTriangle)
    );
    assert_eq!(
        DPatch::new(p, [DVec3::Z, DVec3::ZERO, DVec3::Z]),
        Err(PatchError::ZeroNormal { vertex: 1 })
    );
    assert_eq!(
        DPatch::new(p, [DVec3::Z, DVec3::Z, DVec3::splat(1e-300)]),
        Err(PatchError::ZeroNormal { vertex: 2 })
    );
    assert_eq!(
        DPatch::new(p, [-DVec3::Z, DVec3::Z, DVec3::Z]),
        Err(PatchError::BackFacingNormal { vertex: 0 })
    );
    // Exactly perpendicular, and within the tolerance of it.
    assert_eq!(
        DPatch::new(p, [DVec3::Z, DVec3::X, DVec3::Z]),
        Err(PatchError::BackFacingNormal { vertex: 1 })
    );
    assert_eq!(
        DPatch::new(p, [DVec3::Z, DVec3::Z, DVec3::new(1.0, 0.0, 5e-4)]),
        Err(PatchError::BackFacingNormal { vertex: 2 })
    );
    // Clockwise triangle with upward normals is back-facing.
    assert_eq!(
        DPatch::new([DVec3::ZERO, DVec3::Y, DVec3::X], up),
        Err(PatchError::BackFacingNormal { vertex: 0 })
    );
    // Strongly diverging normals flip the shell.
    let out = [
        DVec3::new(-1.0, -1.0, 0.05),
        DVec3::new(1.0, 0.0, 0.05),
        DVec3::new(0.0, 1.0, 0.05),
    ];
    assert_eq!(DPatch::new(p, out), Err(PatchError::InvalidShell));
    // f32 overflow.
    let big = [Vec3::ZERO, Vec3::X * 3e38, Vec3::Y * 3e38];
    assert_eq!(
        Patch::<f32>::new(big, [Vec3::Z; 3]),
        Err(PatchError::OutOfRange)
    );
    // Every error has a readable message.
    for e in [
        PatchError::NonFinite,
        PatchError::DegenerateTriangle,
        PatchError::ZeroNormal { vertex: 1 },
        PatchError::BackFacingNormal { vertex: 2 },
        PatchError::InvalidShell,
        PatchError::OutOfRange,
    ] {
        assert!(e.to_string().len() > 10);
    }
}

#[test]
fn patch_memory_is_documented() {
    assert_eq!(std::mem::size_of::<Patch<f32>>(), 216);
    assert_eq!(std::mem::size_of::<Patch<f64>>(), 432);
}
