//! Seamless shading normals (`smoothtri::seam`, docs/METHOD.md "Seamless shading normals"): the
//! jump of the shading normal across shared edges, spheres, vertices, the normal error against
//! the true torus, and `fit_seams`'s errors and non-manifold cases.
//! `cargo test --release --test suite seam:: -- --nocapture` prints the measured values.

use crate::common::pins::*;
use crate::common::*;
use glam::DVec3;
use smoothtri::Patch;
use smoothtri::accuracy::*;
use smoothtri::internal::{FIT_SAMPLES, TWIST_TERMS};
use smoothtri::mesh::{MeshError, Seam, SharedEdge, fit_seams};
use smoothtri_testkit::{Mesh, scenes};

/// The patches of `mesh` (every triangle accepted, some perhaps with clamped normals:
/// [`Patch::new_or_tilted`]) and their fitted seams, with the number of shared edges fitted.
fn build<F: Float>(mesh: &Mesh) -> (Vec<Patch<F>>, Vec<Seam<F>>, usize) {
    let patches: Vec<Patch<F>> = (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            Patch::<F>::new_or_tilted(p.map(F::from_dvec3), n.map(F::from_dvec3)).unwrap()
        })
        .collect();
    let mut scratch = vec![SharedEdge::default(); 3 * patches.len()];
    let mut seams = vec![Seam::default(); patches.len()];
    let fitted = fit_seams(
        &patches,
        &mesh.triangles,
        mesh.positions.len(),
        &mut scratch,
        &mut seams,
    )
    .unwrap();
    (patches, seams, fitted)
}

/// Barycentrics `(w1, w2)` of the point at `t` on edge `e` (from vertex `e` to `e + 1`).
fn edge_bary(e: usize, t: f64) -> (f64, f64) {
    let mut w = [0.0; 3];
    w[e % 3] = 1.0 - t;
    w[(e + 1) % 3] = t;
    (w[1], w[2])
}

fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// Samples per edge of the jump measurement (`t = (k + ½)/JUMP_SAMPLES`, between the fit's
/// samples as well as on them).
const JUMP_SAMPLES: usize = 50;

/// Whether the patch folds over (docs: issue 12 item 3): somewhere on a barycentric grid the
/// derivatives' cross product points away from the face normal or the interpolated vertex
/// normal. The geometric normal swings by tens of degrees along such a patch's edges.
fn folded<F: Float>(p: &Patch<F>) -> bool {
    let nf = F::to_dvec3(p.face_normal());
    let ns = p.normals().map(F::to_dvec3);
    bary_grid(24).iter().any(|&(w1, w2)| {
        let (d1, d2) = p.derivatives(F::from_f64(w1), F::from_f64(w2));
        let c = F::to_dvec3(d1).cross(F::to_dvec3(d2));
        let ph = ns[0] * (1.0 - w1 - w2) + ns[1] * w1 + ns[2] * w2;
        c.dot(nf) <= 0.0 || c.dot(ph) <= 0.0
    })
}

/// The interior edges whose jumps are measured: every shared edge, clamped and folded patches
/// included, and with `shared_curves` only those whose two edge curves coincide (to 1e-12 of
/// the edge's length, `f64`).
fn measured_edges(mesh: &Mesh, shared_curves: bool) -> Vec<(usize, usize, usize, usize)> {
    let (patches, _, _) = build::<f64>(mesh);
    let parted = |ta: usize, ea: usize, tb: usize, eb: usize| {
        let (pa, pb) = (&patches[ta], &patches[tb]);
        let len = pa
            .edge_point_normal(ea, 0.0)
            .0
            .distance(pa.edge_point_normal(ea, 1.0).0);
        (0..=8).any(|k| {
            let t = k as f64 / 8.0;
            let a = pa.edge_point_normal(ea, t).0;
            a.distance(pb.edge_point_normal(eb, 1.0 - t).0) > 1e-12 * len
        })
    };
    interior_edges(mesh)
        .into_iter()
        .filter(|&(ta, ea, tb, eb)| !(shared_curves && parted(ta, ea, tb, eb)))
        .collect()
}

/// Jumps across the interior edges of [`measured_edges`], degrees: (shading max, shading mean
/// of the per-edge max, geometric max, geometric mean).
fn jumps<F: Float>(
    mesh: &Mesh,
    patches: &[Patch<F>],
    seams: &[Seam<F>],
    shared_curves: bool,
) -> (f64, f64, f64, f64) {
    let edges = measured_edges(mesh, shared_curves);
    assert!(!edges.is_empty());
    let (mut smax, mut ssum, mut gmax, mut gsum) = (0.0f64, 0.0, 0.0f64, 0.0);
    for &(ta, ea, tb, eb) in &edges {
        let (mut se, mut ge) = (0.0f64, 0.0f64);
        for k in 0..JUMP_SAMPLES {
            let t = (k as f64 + 0.5) / JUMP_SAMPLES as f64;
            let (a1, a2) = edge_bary(ea, t);
            let (b1, b2) = edge_bary(eb, 1.0 - t);
            let (a1, a2, b1, b2) = (
                F::from_f64(a1),
                F::from_f64(a2),
                F::from_f64(b1),
                F::from_f64(b2),
            );
            let sa = F::to_dvec3(seams[ta].shading_normal(&patches[ta], a1, a2));
            let sb = F::to_dvec3(seams[tb].shading_normal(&patches[tb], b1, b2));
            let ga = F::to_dvec3(patches[ta].point_normal(a1, a2).1);
            let gb = F::to_dvec3(patches[tb].point_normal(b1, b2).1);
            se = se.max(angle_deg(sa, sb));
            ge = ge.max(angle_deg(ga, gb));
        }
        smax = smax.max(se);
        gmax = gmax.max(ge);
        ssum += se;
        gsum += ge;
    }
    let n = edges.len() as f64;
    (smax, ssum / n, gmax, gsum / n)
}

#[test]
fn sizes_and_constants() {
    // Two tilt fits of three edges, and the three edges' free-end flags (padded to the scalar).
    assert_eq!(
        std::mem::size_of::<Seam<f32>>(),
        3 * 2 * TWIST_TERMS * 4 + 4
    );
    assert_eq!(
        std::mem::size_of::<Seam<f64>>(),
        3 * 2 * TWIST_TERMS * 8 + 8
    );
    assert_eq!(std::mem::size_of::<Seam<f32>>(), 148);
    // The patch (at most issue 63's 320 bytes with its predictor) and its seam: issue 24's 400
    // bytes per triangle (f32) held until the predictor's 52 bytes.
    assert!(std::mem::size_of::<Seam<f32>>() + std::mem::size_of::<Patch<f32>>() <= 320 + 148);
    const { assert!(FIT_SAMPLES > TWIST_TERMS && TWIST_TERMS >= 6) };
}

/// The shading normal is continuous across every shared edge of the torus, the teapot and the
/// cube (whose neighbours share their edge curves), in both precisions; the geometric normal
/// is not.
#[test]
fn shading_normal_is_continuous_across_shared_edges() {
    let meshes = [
        ("torus 8x8", scenes::torus(8, 8, 1.0, 0.4)),
        ("cube", scenes::cube()),
        ("icosphere 2", scenes::icosphere(2, 1.0)),
    ];
    for (name, mesh) in &meshes {
        let n_edges = interior_edges(mesh).len();
        let (patches, seams, fitted) = build::<f64>(mesh);
        assert_eq!(fitted, n_edges, "{name}: every interior edge fitted");
        let (smax, smean, gmax, gmean) = jumps(mesh, &patches, &seams, false);
        let (patches, seams, _) = build::<f32>(mesh);
        let (smax32, smean32, _, _) = jumps(mesh, &patches, &seams, false);
        eprintln!(
            "{name}: {n_edges} shared edges; jump of the shading normal max {smax:.5}° mean \
             {smean:.5}° (f32: {smax32:.5}° / {smean32:.5}°), geometric max {gmax:.4}° mean \
             {gmean:.4}°"
        );
        assert!(smax <= SEAM_JUMP_DEG, "{name}: f64 {smax}°");
        assert!(smax32 <= SEAM_JUMP_DEG, "{name}: f32 {smax32}°");
    }
}

/// The teapot: coarse (the built-in 4×4 per Bézier patch, 992 triangles) and finer (8×8,
/// 3968). Its neighbours' edge curves part on many edges (cracks up to 5.6e-4 of the
/// diagonal); on the coarse one the geometric normal swings by up to 27° along some edges,
/// some patches fold over and some have clamped normals (their vertex normals differ from
/// their neighbours'). Every shared edge is measured, those included: within
/// [`SEAM_JUMP_DEG`], because the correction takes each side's exact normal on the edge and the
/// common normal both build alike.
#[test]
fn teapot_jumps() {
    let coarse = scenes::teapot(4);
    let (patches, _, _) = build::<f64>(&coarse);
    let clamped = patches
        .iter()
        .filter(|p| p.normal_clamp().is_some())
        .count();
    let folds = patches.iter().filter(|p| folded(*p)).count();
    eprintln!("teapot 4x4: {clamped} clamped patches, {folds} folded");
    assert!(
        clamped > 0 && folds > 0,
        "the hard cases are in the measurement"
    );
    for (name, mesh, shared) in [
        ("teapot 4x4", coarse, false),
        ("teapot 8x8", scenes::teapot(8), false),
        ("teapot 8x8, shared curves", scenes::teapot(8), true),
    ] {
        assert_jumps(name, &mesh, shared, SEAM_JUMP_DEG);
    }
}

/// Measures the jumps of [`jumps`] in `f64` and `f32`, prints them, and asserts that both are
/// within `bound` and far below the geometric normal's.
fn assert_jumps(name: &str, mesh: &Mesh, shared: bool, bound: f64) {
    let (patches, seams, _) = build::<f64>(mesh);
    let (smax, smean, gmax, gmean) = jumps(mesh, &patches, &seams, shared);
    let (p32, s32, _) = build::<f32>(mesh);
    let (smax32, _, _, _) = jumps(mesh, &p32, &s32, shared);
    eprintln!(
        "{name}: jump of the shading normal max {smax:.5}° mean {smean:.5}° (f32 max \
         {smax32:.5}°), geometric max {gmax:.3}° mean {gmean:.3}°"
    );
    assert!(
        smax <= bound && smax32 <= bound,
        "{name}: {smax}°, {smax32}°"
    );
    assert!(smax * 20.0 < gmax, "{name}");
}

/// On the irregular mesh the two neighbours' edge curves part; the common normal's frame is
/// built from the edge's shared data, so the jump is the fits' residual as on shared curves.
#[test]
fn irregular_mesh_jump() {
    let mesh = irregular();
    let (patches, seams, fitted) = build::<f64>(&mesh);
    assert_eq!(fitted, interior_edges(&mesh).len());
    let (smax, smean, gmax, gmean) = jumps(&mesh, &patches, &seams, false);
    eprintln!(
        "irregular icosphere 3 ({} triangles): jump of the shading normal max {smax:.4}° mean \
         {smean:.5}°, geometric max {gmax:.3}° mean {gmean:.3}°",
        mesh.triangles.len()
    );
    assert!(smax <= SEAM_JUMP_DEG, "{smax}°");
    assert!(smax * 50.0 < gmax, "{smax}° against {gmax}°");
}

/// Spheres: the correction vanishes and the shading normal stays radial (icosphere and the
/// cube with averaged normals, which the method makes a sphere of radius √3).
#[test]
fn sphere_shading_normals_stay_radial() {
    for (name, mesh) in [
        ("icosphere 2", scenes::icosphere(2, 1.0)),
        ("cube", scenes::cube()),
    ] {
        let grid = bary_grid(12);
        let worst = |radial: &dyn Fn(&(f64, f64), usize) -> f64| {
            (0..mesh.triangles.len())
                .flat_map(|t| grid.iter().map(move |g| (t, g)))
                .map(|(t, g)| radial(g, t))
                .fold(0.0f64, f64::max)
        };
        let (p64, s64, _) = build::<f64>(&mesh);
        let e64 = worst(&|&(w1, w2), t| {
            let x = p64[t].point(w1, w2);
            (s64[t].shading_normal(&p64[t], w1, w2) - x.normalize()).length()
        });
        let (p32, s32, _) = build::<f32>(&mesh);
        let e32 = worst(&|&(w1, w2), t| {
            let (w1, w2) = (w1 as f32, w2 as f32);
            let x = p32[t].point(w1, w2).as_dvec3();
            (s32[t].shading_normal(&p32[t], w1, w2).as_dvec3() - x.normalize()).length()
        });
        eprintln!("{name}: shading normal radial to {e64:.2e} (f64), {e32:.2e} (f32)");
        assert!(e64 <= F64_SPHERE_NORMAL, "{name}: {e64:e}");
        assert!(e32 <= F32_SPHERE_NORMAL, "{name}: {e32:e}");
    }
}

/// At the vertices the shading normal is the vertex normal; with a zero seam it is the
/// geometric normal bit for bit; `correct` agrees with `shading_normal`; unit length.
#[test]
fn vertices_zero_seams_and_correct() {
    let mesh = irregular();
    let (patches, seams, _) = build::<f64>(&mesh);
    let grid = bary_grid(6);
    let eps = f64::EPSILON;
    for (patch, seam) in patches.iter().zip(&seams) {
        assert!(!seam.is_zero());
        let n = patch.normals();
        for (k, (w1, w2)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
            assert_vec_close!(seam.shading_normal(patch, w1, w2), n[k], F64_INTERPOLATION);
        }
        for &(w1, w2) in &grid {
            let g = patch.point_normal(w1, w2).1;
            assert_eq!(Seam::default().shading_normal(patch, w1, w2), g);
            let s = seam.shading_normal(patch, w1, w2);
            assert_close!(s.length(), 1.0, UNIT_LENGTH_ULPS * eps);
            assert_vec_close!(seam.correct(patch, w1, w2, g), s, 1e-14);
        }
    }
    let (patches, seams, _) = build::<f32>(&mesh);
    for (patch, seam) in patches.iter().zip(&seams) {
        let n = patch.normals();
        for (k, (w1, w2)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
            let s = seam.shading_normal(patch, w1, w2).as_dvec3();
            assert_vec_close!(s, n[k].as_dvec3(), F32_INTERPOLATION);
        }
        for &(w1, w2) in &grid {
            let (w1, w2) = (w1 as f32, w2 as f32);
            let s = seam.shading_normal(patch, w1, w2).as_dvec3();
            assert_close!(s.length(), 1.0, UNIT_LENGTH_ULPS * f32::EPSILON as f64);
        }
    }
}

/// The true torus normal (major radius 1 about z, minor 0.4) at the nearest torus point.
fn torus_normal(x: DVec3) -> DVec3 {
    let c = DVec3::new(x.x, x.y, 0.0).normalize();
    (x - c).normalize()
}

/// (max, 99th percentile, mean) of a list of angles.
fn stats(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let p99 = v[((n as f64 * 0.99) as usize).min(n - 1)];
    (v[n - 1], p99, v.iter().sum::<f64>() / n as f64)
}

/// The shading normal is closer to the true torus normal than the geometric one (8×8 torus,
/// 325 samples per triangle, 41 600 in all).
#[test]
fn torus_normal_error_improves() {
    let mesh = scenes::torus(8, 8, 1.0, 0.4);
    let (patches, seams, _) = build::<f64>(&mesh);
    let grid = bary_grid(24);
    let (mut geo, mut shade) = (Vec::new(), Vec::new());
    for (patch, seam) in patches.iter().zip(&seams) {
        for &(w1, w2) in &grid {
            let (x, g) = patch.point_normal(w1, w2);
            let truth = torus_normal(x);
            geo.push(angle_deg(g, truth));
            shade.push(angle_deg(seam.shading_normal(patch, w1, w2), truth));
        }
    }
    let (gmax, gp99, gmean) = stats(geo);
    let (smax, sp99, smean) = stats(shade);
    eprintln!(
        "torus 8x8 normal error against the true torus: geometric max {gmax:.3}° p99 \
         {gp99:.3}° mean {gmean:.3}°; shading max {smax:.3}° p99 {sp99:.3}° mean {smean:.3}°"
    );
    assert_close!(gmax, TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG, 0.01);
    assert_close!(gp99, TORUS_8X8_GEOMETRIC_NORMAL_P99_DEG, 0.01);
    assert_close!(smax, TORUS_8X8_SEAMLESS_NORMAL_MAX_DEG, 0.01);
    assert_close!(sp99, TORUS_8X8_SEAMLESS_NORMAL_P99_DEG, 0.01);
    assert!(smean < gmean);
}

fn tri_mesh(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Mesh {
    // Normals: a dome over the xy plane, so that every patch is curved.
    let normals = positions
        .iter()
        .map(|p| (DVec3::Z * 2.0 + DVec3::new(p.x, p.y, 0.0)).normalize())
        .collect();
    Mesh {
        positions,
        normals,
        triangles,
    }
}

fn fit64(
    mesh: &Mesh,
    patches: &[Patch<f64>],
    vertex_count: usize,
    scratch: usize,
    seams: usize,
) -> Result<(usize, Vec<Seam<f64>>), MeshError> {
    let mut s = vec![SharedEdge::default(); scratch];
    let mut out = vec![Seam::default(); seams];
    fit_seams(patches, &mesh.triangles, vertex_count, &mut s, &mut out).map(|n| (n, out))
}

/// Errors: lengths, scratch, indices. Non-manifold, boundary and same-direction edges get no
/// correction; lone triangles none at all.
#[test]
fn fit_errors_and_non_manifold_edges() {
    let p = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.1),
        DVec3::new(-1.0, 0.5, 0.1),
    ];
    // Two triangles sharing edge 1–2 in opposite directions.
    let pair = tri_mesh(p.clone(), vec![[0, 1, 2], [1, 3, 2]]);
    let (patches, _, _) = build::<f64>(&pair);
    let nv = pair.positions.len();
    let (n, seams) = fit64(&pair, &patches, nv, 6, 2).unwrap();
    assert_eq!(n, 1);
    assert!(!seams[0].is_zero() && !seams[1].is_zero());
    // Only the shared edge (edge 1 of the first triangle, edge 2 of the second) is corrected.
    assert_eq!(seams[0].common[0], [0.0; TWIST_TERMS]);
    assert_eq!(seams[0].common[2], [0.0; TWIST_TERMS]);
    assert_ne!(seams[0].common[1], seams[0].common_along[1]);
    assert_eq!(seams[1].common_along[0], [0.0; TWIST_TERMS]);
    assert_ne!(seams[1].common[2], [0.0; TWIST_TERMS]);
    // A larger scratch is fine.
    assert_eq!(fit64(&pair, &patches, nv, 100, 2).unwrap().0, 1);
    // Errors.
    assert_eq!(
        fit64(&pair, &patches, nv, 6, 3).unwrap_err(),
        MeshError::LengthMismatch {
            patches: 2,
            triangles: 2,
            seams: 3
        }
    );
    assert_eq!(
        fit64(&pair, &patches[..1], nv, 6, 1).unwrap_err(),
        MeshError::LengthMismatch {
            patches: 1,
            triangles: 2,
            seams: 1
        }
    );
    assert_eq!(
        fit64(&pair, &patches, nv, 5, 2).unwrap_err(),
        MeshError::ScratchTooSmall { needed: 6 }
    );
    assert_eq!(
        fit64(&pair, &patches, 3, 6, 2).unwrap_err(),
        MeshError::BadIndex { triangle: 1 }
    );
    let repeated = Mesh {
        triangles: vec![[0, 1, 2], [1, 1, 2]],
        ..pair.clone()
    };
    let e = fit64(&repeated, &patches, nv, 6, 2).unwrap_err();
    assert_eq!(e, MeshError::BadIndex { triangle: 1 });
    assert!(e.to_string().contains("triangle 1"));
    // The same edge traversed twice in the same direction (inconsistent winding): no
    // correction. The index buffer says so; the patches are the pair's.
    let same_dir = Mesh {
        triangles: vec![[0, 1, 2], [2, 1, 3]],
        ..pair.clone()
    };
    let (n, seams) = fit64(&same_dir, &patches, nv, 6, 2).unwrap();
    assert_eq!(n, 0);
    assert!(seams.iter().all(Seam::is_zero));
    // Indices that say "shared" where the patches' vertices differ (the second patch's
    // vertices are 1, 3, 2): no correction.
    let wrong = Mesh {
        triangles: vec![[0, 1, 2], [3, 2, 1]],
        ..pair.clone()
    };
    assert_eq!(fit64(&wrong, &patches, nv, 6, 2).unwrap().0, 0);
    // Non-manifold: three triangles on edge 1–2; and a lone triangle.
    let fan = tri_mesh(p.clone(), vec![[0, 1, 2], [1, 3, 2], [2, 1, 4]]);
    let (patches, seams, n) = build::<f64>(&fan);
    assert_eq!(n, 0);
    assert!(seams.iter().all(Seam::is_zero));
    let g = patches[0].point_normal(0.3, 0.3).1;
    assert_eq!(seams[0].shading_normal(&patches[0], 0.3, 0.3), g);
    let lone = tri_mesh(p, vec![[0, 1, 2]]);
    let (_, seams, n) = build::<f64>(&lone);
    assert_eq!(n, 0);
    assert!(seams[0].is_zero());
    // Boundary edges of an open mesh (the torus without its last row of quads): those stay
    // zero, the rest is fitted.
    let mut open = scenes::torus(8, 8, 1.0, 0.4);
    open.triangles.truncate(open.triangles.len() - 16);
    let (patches, seams, n) = build::<f64>(&open);
    assert_eq!(n, interior_edges(&open).len());
    assert_eq!(n, 3 * open.triangles.len() / 2 - 8);
    let (smax, _, _, _) = jumps(&open, &patches, &seams, false);
    assert!(smax <= SEAM_JUMP_DEG);
    // Empty input.
    let empty = Mesh::default();
    assert_eq!(fit64(&empty, &[], 0, 0, 0).unwrap().0, 0);
}

/// The stress meshes of `tests/suite/stress_meshes.rs`, whose neighbours' curves part (boxes and
/// cylinders with averaged normals, an icosphere with noisy normals): the shading normal's jump
/// is within [`SEAM_JUMP_DEG`] on every shared edge, as where curves are shared (the boxes'
/// corner patches have clamped normals).
#[test]
fn stress_mesh_jumps() {
    for (name, mesh) in [
        (
            "box 1x2x4, averaged normals",
            box_mesh(1.0, 2.0, 4.0).to_mesh(),
        ),
        ("cylinder, 8 sides", cylinder(8).to_mesh()),
        (
            "icosphere(2), normals tilted ≤ 20°",
            noisy_sphere(&mut Rng(7), 20.0).to_mesh(),
        ),
    ] {
        assert_jumps(name, &mesh, false, SEAM_JUMP_DEG);
    }
}
