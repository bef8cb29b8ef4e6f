//! Properties of the patch construction (docs/METHOD.md §6), f64 and f32, over random inputs,
//! against the named bounds of [`smoothtri::accuracy`]. Each property prints the worst error it
//! measured and its seed: `cargo test --release --test suite patch:: -- --nocapture`
//! (`SMOOTHTRI_CASES=<n>` for more cases than the default 256).

use crate::common::*;
use glam::{DVec3, Vec3};
use smoothtri::accuracy::*;
use smoothtri::{DPatch, Patch, PatchError};

fn to32(v: [DVec3; 3]) -> [Vec3; 3] {
    v.map(|x| x.as_vec3())
}

/// Seeds of the random cases: a fixed sequence (CI runs the same cases every time), 256 by
/// default, `SMOOTHTRI_CASES` for long runs.
fn seeds() -> impl Iterator<Item = u64> {
    let mut rng = Rng(0x5EED_0003);
    (0..env_cases(256)).map(move |_| rng.next_u64())
}

/// Largest of the values seen, with the seed where it was seen.
#[derive(Clone, Copy, Debug, Default)]
struct Worst {
    value: f64,
    seed: u64,
}

impl Worst {
    /// Asserts `value ≤ bound` (the message names the seed, `what`, the value and `unit`), then
    /// records it ([`Worst::see`]).
    fn check(&mut self, value: f64, bound: f64, seed: u64, what: &str, unit: &str) {
        assert!(value <= bound, "seed {seed:#x}: {what} {value:e}{unit}");
        self.see(value, seed);
    }

    /// Records `value` seen at `seed` when it is the largest so far (NaN counts as the largest).
    fn see(&mut self, value: f64, seed: u64) {
        // NaN counts as the worst.
        if value.is_nan() || value > self.value {
            *self = Worst { value, seed };
        }
    }
}

impl std::fmt::Display for Worst {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.2e} (seed {:#x})", self.value, self.seed)
    }
}

/// Vertices exact, edges pass through the conjugation lines, edge normals equal the vertex
/// normals at the ends: f64 within [`F64_INTERPOLATION`] of the size, f32 within
/// [`F32_INTERPOLATION`] of the scale (random triangles, normals ≤ 40°).
#[test]
fn interpolates_vertices_and_edges() {
    let [mut w64, mut w32, mut wn64, mut wn32] = [Worst::default(); 4];
    for seed in seeds() {
        let mut rng = Rng(seed);
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0])
            .length()
            .max((p[2] - p[0]).length())
            .max((p[2] - p[1]).length());
        let scale = p.iter().fold(size, |m, x| m.max(x.abs().max_element()));
        let patch = DPatch::new(p, n).unwrap();
        let p32: Patch = Patch::new(to32(p), to32(n)).unwrap();
        // Relative errors of this case: f64 points, f32 points, f64 normals, f32 normals.
        let (mut e64, mut e32, mut en64, mut en32) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
        for (k, &(w1, w2)) in corners.iter().enumerate() {
            e64 = e64.max((patch.point(w1, w2) - p[k]).length() / size);
            e32 = e32.max((p32.point(w1 as f32, w2 as f32).as_dvec3() - p[k]).length() / scale);
        }
        for edge in 0..3 {
            let (_, n_start) = patch.edge_point_normal(edge, 0.0);
            let (_, n_end) = patch.edge_point_normal(edge, 1.0);
            en64 = en64.max((n_start - n[edge].normalize()).length());
            en64 = en64.max((n_end - n[(edge + 1) % 3].normalize()).length());
            let (_, m_start) = p32.edge_point_normal(edge, 0.0);
            let (_, m_end) = p32.edge_point_normal(edge, 1.0);
            en32 = en32.max((m_start.as_dvec3() - n[edge].normalize()).length());
            en32 = en32.max((m_end.as_dvec3() - n[(edge + 1) % 3].normalize()).length());
            for t in [0.1, 0.37, 0.5, 0.81] {
                // Barycentrics of edge `edge` at parameter t.
                let mut w = [0.0; 3];
                w[edge] = 1.0 - t;
                w[(edge + 1) % 3] = t;
                let (c, _) = patch.edge_point_normal(edge, t);
                e64 = e64.max((patch.point(w[1], w[2]) - c).length() / size);
                let (c32, _) = p32.edge_point_normal(edge, t as f32);
                let x32 = p32.point(w[1] as f32, w[2] as f32);
                e32 = e32.max((x32.as_dvec3() - c32.as_dvec3()).length() / scale);
            }
        }
        w64.check(e64, F64_INTERPOLATION, seed, "f64 points", " of the size");
        w32.check(e32, F32_INTERPOLATION, seed, "f32 points", " of the scale");
        wn64.check(en64, F64_INTERPOLATION, seed, "f64 edge normals", "");
        wn32.check(en32, F32_INTERPOLATION, seed, "f32 edge normals", "");
    }
    eprintln!(
        "interpolation: f64 points {w64}, normals {wn64} (bound {F64_INTERPOLATION:e}); \
         f32 points {w32}, normals {wn32} (bound {F32_INTERPOLATION:e})"
    );
}

/// All normals equal to the face normal reproduce the flat triangle, with the face normal
/// (within [`F64_FLAT_TRIANGLE`]).
#[test]
fn flat_normals_give_flat_triangle() {
    let (mut wp, mut wn) = (Worst::default(), Worst::default());
    for seed in seeds() {
        let mut rng = Rng(seed);
        let size = 10f64.powf(rng.range(-2.0, 1.7));
        let off = DVec3::splat(rng.range(-3.0, 3.0));
        let (p, nf) = well_shaped(&mut rng, size, off);
        let patch = DPatch::new(p, [nf * 2.0, nf, nf * 0.7]).unwrap();
        let scale = (p[1] - p[0]).length().max(p[0].abs().max_element());
        let (mut ep, mut en) = (0.0f64, 0.0f64);
        for (w1, w2) in bary_grid(7) {
            let flat = p[0] * (1.0 - w1 - w2) + p[1] * w1 + p[2] * w2;
            let (x, nrm) = patch.point_normal(w1, w2);
            ep = ep.max((x - flat).length() / scale);
            en = en.max((nrm - nf).length());
        }
        wp.check(ep, F64_FLAT_TRIANGLE, seed, "points", " of the scale");
        wn.check(en, F64_FLAT_TRIANGLE, seed, "normals", "");
    }
    eprintln!("flat normals: points {wp}, normals {wn} (bound {F64_FLAT_TRIANGLE:e})");
}

/// Spheres are reproduced exactly: radius 1e-3…1e3, radial normals; every point on the sphere
/// ([`F64_SPHERE_POINT`], [`F32_SPHERE_POINT`] of the radius) with a radial normal
/// ([`F64_SPHERE_NORMAL`], [`F32_SPHERE_NORMAL`]).
#[test]
fn spheres_are_exact() {
    let [mut wp64, mut wp32, mut wn64, mut wn32] = [Worst::default(); 4];
    for seed in seeds() {
        let mut rng = Rng(seed);
        let r = 10f64.powf(rng.range(-3.0, 3.0));
        let o = DVec3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        ) * r;
        let cap = rng.range(5.0, 35.0);
        let p = sphere_patch(&mut rng, o, r, cap);
        let n = p.map(|x| (x - o) / r);
        let patch = DPatch::new(p, n).unwrap();
        let p32: Patch = Patch::new(to32(p), to32(n)).unwrap();
        let o32 = o.as_vec3().as_dvec3();
        let (mut ep64, mut ep32, mut en64, mut en32) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (w1, w2) in bary_grid(6) {
            let (x, nrm) = patch.point_normal(w1, w2);
            ep64 = ep64.max(((x - o).length() - r).abs() / r);
            en64 = en64.max((nrm - (x - o) / r).length());
            let (y, m) = p32.point_normal(w1 as f32, w2 as f32);
            let y = y.as_dvec3();
            ep32 = ep32.max(((y - o32).length() - r).abs() / r);
            en32 = en32.max((m.as_dvec3() - (y - o32).normalize()).length());
        }
        wp64.check(ep64, F64_SPHERE_POINT, seed, "f64 points", "");
        wp32.check(ep32, F32_SPHERE_POINT, seed, "f32 points", "");
        wn64.check(en64, F64_SPHERE_NORMAL, seed, "f64 normals", "");
        wn32.check(en32, F32_SPHERE_NORMAL, seed, "f32 normals", "");
    }
    eprintln!(
        "spheres: f64 points {wp64}, normals {wn64}; f32 points {wp32}, normals {wn32} (of the radius)"
    );
}

/// Exact derivatives agree with central finite differences of the f64 surface, and the edge
/// curves are tangent to the surface: the central difference of the edge curve `c(t)` equals
/// the surface's derivative along the edge and is perpendicular to both the edge curve's normal
/// `n*(t)` and the surface normal there (all within [`DERIVATIVES_VS_CENTRAL_DIFFERENCES`] of
/// the size).
#[test]
fn derivatives_match_finite_differences() {
    let (mut wd, mut wt, mut wnt) = (Worst::default(), Worst::default(), Worst::default());
    let h = 1e-5;
    for seed in seeds() {
        let mut rng = Rng(seed);
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0]).length();
        let patch = DPatch::new(p, n).unwrap();
        let (w1, w2) = (rng.range(0.05, 0.6), rng.range(0.05, 0.35));
        let (d1, d2) = patch.derivatives(w1, w2);
        let fd1 = (patch.point(w1 + h, w2) - patch.point(w1 - h, w2)) / (2.0 * h);
        let fd2 = (patch.point(w1, w2 + h) - patch.point(w1, w2 - h)) / (2.0 * h);
        let ed = (d1 - fd1).length().max((d2 - fd2).length()) / size;
        assert!(
            ed <= DERIVATIVES_VS_CENTRAL_DIFFERENCES,
            "seed {seed:#x}: derivatives {d1} {d2} vs {fd1} {fd2}: {ed:e} of the size"
        );
        wd.see(ed, seed);
        // Edge tangents: the edge curve's central difference against the surface's exact
        // derivative along the edge (barycentrics (1 − t, t) on the edge's two vertices).
        let edge = (rng.f() * 3.0) as usize % 3;
        let t = rng.range(0.1, 0.9);
        let mut w = [0.0; 3];
        w[edge] = 1.0 - t;
        w[(edge + 1) % 3] = t;
        let tangent_fd = (patch.edge_point_normal(edge, t + h).0
            - patch.edge_point_normal(edge, t - h).0)
            / (2.0 * h);
        let (e1, e2) = patch.derivatives(w[1], w[2]);
        // d/dt of (w1, w2) along edge 0, 1, 2: (1, 0), (−1, 1), (0, −1).
        let along = match edge {
            0 => e1,
            1 => e2 - e1,
            _ => -e2,
        };
        let et = (along - tangent_fd).length() / size;
        let (_, edge_normal) = patch.edge_point_normal(edge, t);
        let (_, surface_normal) = patch.point_normal(w[1], w[2]);
        let ent = edge_normal
            .dot(tangent_fd)
            .abs()
            .max(surface_normal.dot(tangent_fd).abs())
            / size;
        assert!(
            et <= DERIVATIVES_VS_CENTRAL_DIFFERENCES,
            "seed {seed:#x}: edge {edge} t {t}: surface derivative {along} vs edge tangent {tangent_fd}: {et:e}"
        );
        assert!(
            ent <= DERIVATIVES_VS_CENTRAL_DIFFERENCES,
            "seed {seed:#x}: edge {edge} t {t}: tangent {tangent_fd} not perpendicular to the \
             edge normal {edge_normal} or the surface normal {surface_normal}: {ent:e}"
        );
        wt.see(et, seed);
        wnt.see(ent, seed);
    }
    eprintln!(
        "derivatives vs central differences: {wd}; edge tangent vs surface derivative {wt}; \
         normals · edge tangent {wnt} (of the size, bound {DERIVATIVES_VS_CENTRAL_DIFFERENCES:e})"
    );
}

/// The f32 path against the f64 path on the same (f32-representable) input: points within
/// [`F32_VS_F64_POINT`] of the larger of the triangle's size and its coordinates, normals within
/// [`F32_VS_F64_NORMAL`].
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
        "f32 vs f64: worst point difference {wp:.2e} of scale (bound {F32_VS_F64_POINT:e}), \
         worst normal difference {wn:.2e} (bound {F32_VS_F64_NORMAL:e})"
    );
    assert!(wp <= F32_VS_F64_POINT, "points {wp:e}");
    assert!(wn <= F32_VS_F64_NORMAL, "normals {wn:e}");
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
    // Every error has its own readable message, naming the vertex where there is one.
    let messages = [
        PatchError::NonFinite,
        PatchError::DegenerateTriangle,
        PatchError::ZeroNormal { vertex: 1 },
        PatchError::BackFacingNormal { vertex: 2 },
        PatchError::InvalidShell,
        PatchError::OutOfRange,
    ]
    .map(|e| e.to_string());
    for (i, m) in messages.iter().enumerate() {
        assert!(m.len() > 10, "{m:?}");
        assert!(!messages[..i].contains(m), "{m:?} repeated");
    }
    assert!(messages[2].contains("vertex 1") && messages[3].contains("vertex 2"));
}

#[test]
fn patch_memory_is_documented() {
    assert_eq!(std::mem::size_of::<Patch<f32>>(), 304);
    assert_eq!(std::mem::size_of::<Patch<f64>>(), 608);
    // Issue 63's ceiling for the patch with its predictor.
    const { assert!(std::mem::size_of::<Patch<f32>>() <= 320) };
}
