//! Parity of the GPU kernel with the CPU kernel (f32), on the ray sets of the CPU kernel's own
//! tests (`tests/suite/kernel.rs`): the icosphere and the cube with averaged normals against the
//! analytic sphere, the 8×8 torus against the CPU. Prints what it measures:
//! `cargo test -p smoothtri-gpu --test parity -- --nocapture`.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::accuracy::{F32_SPHERE_HIT, F32_SPHERE_NORMAL};
use smoothtri::mesh::{SharedEdge, close_cracks};
use smoothtri::{Bvh, Hit, LineField, Patch, Ray};
use smoothtri_gpu::{Gpu, GpuScene};
use smoothtri_testkit::random::{Rng, random_ray};
use smoothtri_testkit::scenes::{
    cube, icosphere, sphere_root, teapot, tilted_normal_sphere, torus,
};
use smoothtri_testkit::{Camera, Mesh, build_scene, patches32};
use std::sync::Arc;

/// The budget compared (the GPU's and the demo's default).
const N: usize = 4;
/// Hit/miss must agree on every ray farther than this from a silhouette (scene units).
const SILHOUETTE: f32 = 1e-4;
/// Normals of the same hit must agree to this (difference of unit vectors).
const NORMAL_TOL: f32 = 1e-5;

/// The f32 rounding allowance of a comparison of two `t`: a few ulps of the ray's parameter
/// scale (`|t|` and the origin's distance in units of `|d|`), beyond the two `t_error`s.
fn rounding(ray: &Ray, t: f32) -> f32 {
    16.0 * f32::EPSILON * (t.abs() + ray.origin.length() / ray.dir.length())
}

#[derive(Default, Debug)]
struct Parity {
    rays: usize,
    hits: usize,
    /// max |t_gpu − t_cpu| / (t_error_cpu + rounding)
    ratio_cpu: f32,
    /// max |t_gpu − t_cpu| / (t_error_cpu + t_error_gpu + rounding)
    ratio_both: f32,
    /// hits outside t_error_cpu + rounding
    outside_cpu: usize,
    max_dt: f32,
    max_normal: f32,
    disagreements: usize,
    excused: usize,
    other_patch: usize,
}

/// Traces `rays` on the CPU (f32 BVH, budget N) and the GPU and compares them; `near_silhouette`
/// says whether a ray is within [`SILHOUETTE`] of one.
fn compare(
    name: &str,
    gpu: &Arc<Gpu>,
    patches: &[Patch],
    rays: &[Ray],
    near_silhouette: &dyn Fn(&Ray) -> bool,
) -> (Parity, Vec<Option<Hit>>) {
    let tree = Tree::new(patches);
    let bvh = tree.bvh(patches);
    let scene = GpuScene::smooth(gpu, &bvh).expect("upload");
    let got = traced(rays, None, |out| {
        scene.closest_hit(rays, 0.0, f32::INFINITY, N, out)
    });
    let mut s = Parity {
        rays: rays.len(),
        ..Parity::default()
    };
    for (ray, g) in rays.iter().zip(&got) {
        let c = bvh.closest_hit(ray, 0.0, f32::INFINITY, N);
        match (g, c) {
            (Some(g), Some(c)) => {
                s.hits += 1;
                let dt = (g.t - c.t).abs();
                let r = rounding(ray, c.t);
                s.max_dt = s.max_dt.max(dt * ray.dir.length());
                s.ratio_cpu = s.ratio_cpu.max(dt / (c.t_error + r));
                s.ratio_both = s.ratio_both.max(dt / (c.t_error + g.t_error + r));
                s.outside_cpu += usize::from(dt > c.t_error + r);
                // The parity statement: within the CPU hit's t_error plus an f32
                // rounding allowance.
                assert!(
                    dt <= c.t_error + r,
                    "{name}: t {} (±{:e}) on the GPU, {} (±{:e}) on the CPU",
                    g.t,
                    g.t_error,
                    c.t,
                    c.t_error
                );
                if g.patch == c.patch {
                    let dn = (g.normal - c.normal).length();
                    s.max_normal = s.max_normal.max(dn);
                    assert!(
                        dn <= NORMAL_TOL,
                        "{name}: normals {} (GPU) and {} (CPU) differ by {dn:e}",
                        g.normal,
                        c.normal
                    );
                    assert_eq!(g.front_face, c.front_face, "{name}: front face");
                    assert!((g.w1 - c.w1).abs() < 1e-3 && (g.w2 - c.w2).abs() < 1e-3);
                } else {
                    // The same point on two patches: only where they meet (an edge).
                    s.other_patch += 1;
                    let (w1, w2) = (c.w1, c.w2);
                    let edge = w1.min(w2).min(1.0 - w1 - w2);
                    assert!(edge < 1e-3, "{name}: patch {} vs {}", g.patch, c.patch);
                }
            }
            (None, None) => {}
            _ => {
                s.disagreements += 1;
                if near_silhouette(ray) {
                    s.excused += 1;
                } else {
                    panic!(
                        "{name}: hit/miss differ away from a silhouette: GPU {g:?}, CPU {c:?}, \
                         ray {ray:?}"
                    );
                }
            }
        }
    }
    eprintln!(
        "{name}: {} rays, {} hits; |t_gpu − t_cpu| max {:.1e} (along the ray), ≤ {:.3} × \
         (CPU t_error + rounding), outside it {}, ≤ {:.3} × (both t_errors + rounding); \
         normals ≤ {:.1e}; hit/miss disagreements {} (all within {SILHOUETTE:e} of a \
         silhouette: {}); other patch at an edge {}",
        s.rays,
        s.hits,
        s.max_dt,
        s.ratio_cpu,
        s.outside_cpu,
        s.ratio_both,
        s.max_normal,
        s.disagreements,
        s.excused,
        s.other_patch
    );
    (s, got)
}

fn sphere_rays(r: f64) -> Vec<(DVec3, DVec3)> {
    let mut rng = Rng(42);
    (0..3000).map(|_| random_ray(&mut rng, 1.3 * r)).collect()
}

/// A mesh that is exactly the sphere of radius `r`: the GPU against the analytic sphere (as
/// `tests/suite/kernel.rs` checks the CPU) and against the CPU.
fn sphere_scene(name: &str, mesh: &Mesh, r: f64) {
    let Some(gpu) = gpu() else { return };
    let patches = patches32(mesh);
    let rays64 = sphere_rays(r);
    let rays: Vec<Ray> = rays64
        .iter()
        .map(|&(o, d)| Ray::new(o.as_vec3(), d.as_vec3()))
        .collect();
    let near = |ray: &Ray| {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        (sphere_root(o, d, r).1 - r).abs() <= f64::from(SILHOUETTE)
    };
    let (s, got) = compare(name, &gpu, &patches, &rays, &near);
    assert_eq!(s.rays, 3000);
    let (mut worst_p, mut worst_n, mut worst_t, mut hits) = (0.0f64, 0.0f64, 0.0f64, 0);
    for (&(o, d), g) in rays64.iter().zip(&got) {
        let (root, closest) = sphere_root(o, d, r);
        let margin = 0.01 * r;
        if closest < r - margin {
            let g = g.unwrap_or_else(|| panic!("{name}: the GPU missed a ray through the sphere"));
            hits += 1;
            let t = root.expect("root");
            let ep = (g.point.as_dvec3().length() - r).abs() / r;
            let en = (g.normal.as_dvec3() - g.point.as_dvec3().normalize()).length();
            let slack = 64.0 * f64::from(f32::EPSILON) * (o.length() / d.length() + t);
            let et = (f64::from(g.t) - t).abs();
            worst_p = worst_p.max(ep);
            worst_n = worst_n.max(en);
            worst_t = worst_t.max(et / (f64::from(g.t_error) + slack));
            assert!(ep <= F32_SPHERE_HIT, "{name}: hit off the sphere by {ep:e}");
            assert!(en <= F32_SPHERE_NORMAL, "{name}: normal off by {en:e}");
            assert!(
                et <= f64::from(g.t_error) + slack,
                "{name}: t {} vs {t}, t_error {}",
                g.t,
                g.t_error
            );
            assert!(g.front_face);
        } else if closest > r + margin {
            assert!(
                g.is_none(),
                "{name}: GPU hit on a ray that misses the sphere"
            );
        }
    }
    eprintln!(
        "{name}: GPU against the analytic sphere: {hits} hits, points ≤ {worst_p:.1e} of the \
         radius, normals ≤ {worst_n:.1e}, |t − t_true| ≤ {worst_t:.3} × (t_error + rounding)"
    );
    assert!(hits > 1000);
}

#[test]
fn icosphere_matches_the_sphere_and_the_cpu() {
    sphere_scene("icosphere(1)", &icosphere(1, 2.0), 2.0);
}

#[test]
fn cube_with_averaged_normals_matches_the_sphere_and_the_cpu() {
    sphere_scene("cube", &cube(), 3f64.sqrt());
}

/// Whether the CPU's hit/miss answer changes when the ray's origin moves by [`SILHOUETTE`]
/// sideways (in four directions perpendicular to it): the ray is that close to a silhouette.
fn cpu_near_silhouette(bvh: &smoothtri::Bvh<'_, f32>, ray: &Ray) -> bool {
    let hit = |r: &Ray| bvh.closest_hit(r, 0.0, f32::INFINITY, N).is_some();
    let base = hit(ray);
    let (u, v) = perpendiculars(ray.dir);
    [u, -u, v, -v]
        .iter()
        .any(|&s| hit(&Ray::new(ray.origin + s * SILHOUETTE, ray.dir)) != base)
}

/// Runs `check` with the device, the CPU BVH over the 8×8 torus (the CPU kernel's tests' torus)
/// and 1500 random rays aimed at it from the generator seeded with `seed`; nothing without a
/// device (the skip of [`gpu`]).
fn on_torus(seed: u64, check: impl FnOnce(&Arc<Gpu>, &Bvh<'_, f32>, &[Ray])) {
    let Some(gpu) = gpu() else { return };
    let patches = patches32(&torus(8, 8, 1.0, 0.4));
    let tree = Tree::new(&patches);
    check(&gpu, &tree.bvh(&patches), &random_rays(seed, 1500, 1.4));
}

#[test]
fn torus_matches_the_cpu_kernel() {
    on_torus(5, |gpu, bvh, rays| {
        let near = |ray: &Ray| cpu_near_silhouette(bvh, ray);
        let (s, _) = compare("torus 8x8", gpu, bvh.patches(), rays, &near);
        assert!(s.hits > 900, "{s:?}");
    });
}

/// Shadow rays: the GPU's any-hit answers are the CPU's, away from silhouettes.
#[test]
fn any_hit_matches_the_cpu() {
    on_torus(17, |gpu, bvh, rays| {
        let scene = GpuScene::smooth(gpu, bvh).expect("upload");
        let occluded = traced(rays, false, |out| {
            scene.any_hit(rays, 0.0, f32::INFINITY, N, out)
        });
        let (mut hits, mut excused) = (0, 0);
        for (ray, &g) in rays.iter().zip(&occluded) {
            let c = bvh.any_hit(ray, 0.0, f32::INFINITY, N);
            hits += usize::from(c);
            if g != c {
                assert!(cpu_near_silhouette(bvh, ray), "any hit differs: {ray:?}");
                excused += 1;
            }
        }
        eprintln!(
            "any hit: {hits} of 1500 occluded on the CPU; {excused} differ, all near a silhouette"
        );
        assert!(hits > 900);
    });
}

/// The flat baseline (same traversal, Möller–Trumbore) equals the CPU's flat tracer.
#[test]
fn flat_baseline_matches_the_cpu() {
    on_torus(23, |gpu, bvh, rays| {
        let scene = GpuScene::flat(gpu, bvh).expect("upload");
        let got = traced(rays, None, |out| {
            scene.closest_hit(rays, 0.0, f32::INFINITY, 0, out)
        });
        let (mut hits, mut worst) = (0, 0.0f32);
        for (ray, g) in rays.iter().zip(&got) {
            let c = bvh.closest_with(ray, 0.0, f32::INFINITY, |_, p, a, b| {
                smoothtri::flat_hit(&p.vertices(), None, ray, a, b)
            });
            match (g, c) {
                (Some(g), Some(c)) => {
                    hits += 1;
                    worst = worst.max((g.t - c.t).abs() / c.t);
                    assert!((g.t - c.t).abs() <= 1e-5 * c.t, "{g:?} vs {c:?}");
                    assert!((g.normal - c.normal).length() < 1e-5);
                }
                (None, None) => {}
                _ => {
                    // Only on a triangle's edge (Möller–Trumbore's bary tests in other rounding).
                    let h = g.or(c).expect("one hit");
                    let edge = h.w1.min(h.w2).min(1.0 - h.w1 - h.w2);
                    assert!(edge.abs() < 1e-4, "flat hit/miss differ: {g:?} vs {c:?}");
                }
            }
        }
        eprintln!("flat: {hits} hits, |t_gpu − t_cpu| ≤ {worst:.1e} relative");
        assert!(hits > 900);
    });
}

/// The unit direction of every GPU normal and finite values on grazing rays near a patch's
/// edges (as the CPU's degenerate-ray test).
#[test]
fn grazing_rays_give_finite_answers() {
    let Some(gpu) = gpu() else { return };
    let p = [Vec3::X, Vec3::Y, Vec3::Z];
    let patches = [Patch::new(p, p).expect("patch")];
    let tree = Tree::new(&patches);
    let scene = GpuScene::smooth(&gpu, &tree.bvh(&patches)).expect("upload");
    let mut rng = Rng(3);
    let rays: Vec<Ray> = (0..20000)
        .map(|_| {
            let o = rng.unit().as_vec3() * 3.0;
            let d = (rng.unit() * 0.3 + DVec3::ONE / 3f64.sqrt()).as_vec3() - o;
            Ray::new(o, d)
        })
        .collect();
    let got = traced(&rays, None, |out| {
        scene.closest_hit(&rays, 0.0, f32::INFINITY, 8, out)
    });
    let mut hits = 0;
    for h in got.iter().flatten() {
        hits += 1;
        assert!(h.t.is_finite() && h.point.is_finite() && h.t_error.is_finite());
        assert!((h.normal.length() - 1.0).abs() < 1e-5, "{h:?}");
    }
    assert!(hits > 1000, "{hits}");
}

/// The shader's refinement, rounding, wall-margin and section-Newton constants are the CPU
/// kernel's (one source of truth per figure: the WGSL repeats them, this test keeps them equal).
#[test]
fn shader_constants_match_the_cpu_kernel() {
    use smoothtri::internal::{
        EARLY_STOP, INNER_OF_SPREAD, INNER_OF_STOP, OUTER_OF_INNER, OUTER_OF_SPREAD, OUTER_OF_WIDTH,
    };
    use smoothtri::internal::{ROUNDING_ULPS, WALL_MARGIN_ULPS};
    // The literal a `const {name}: {ty} = …;` of the shader declares.
    let literal = |name: &str, ty: &str| -> &'static str {
        let decl = format!("const {name}: {ty} = ");
        let at = smoothtri_gpu::SHADER
            .find(&decl)
            .unwrap_or_else(|| panic!("{name} not declared in the shader"));
        let rest = &smoothtri_gpu::SHADER[at + decl.len()..];
        let end = rest.find(';').expect("declaration ends");
        rest[..end].trim()
    };
    let value = |name: &str| -> f64 { literal(name, "f32").parse().expect("a number") };
    for (name, cpu) in [
        ("EARLY_STOP", EARLY_STOP),
        ("INNER_OF_SPREAD", INNER_OF_SPREAD),
        ("INNER_OF_STOP", INNER_OF_STOP),
        ("OUTER_OF_SPREAD", OUTER_OF_SPREAD),
        ("OUTER_OF_INNER", OUTER_OF_INNER),
        ("OUTER_OF_WIDTH", OUTER_OF_WIDTH),
        ("ROUNDING_ULPS", ROUNDING_ULPS),
        ("WALL_MARGIN_ULPS", WALL_MARGIN_ULPS),
    ] {
        assert_eq!(value(name), cpu, "{name}");
    }
    let count = |name: &str| -> usize {
        let u32 = literal(name, "u32").strip_suffix('u').expect("a u32");
        u32.parse().expect("a number")
    };
    assert_eq!(count("ESTIMATE_STEPS"), smoothtri::internal::ESTIMATE_STEPS);
    assert_eq!(
        count("SECTION_NEWTON_STEPS"),
        smoothtri::internal::SECTION_NEWTON_STEPS
    );
    let seam = smoothtri::mesh::Seam::<f32>::default();
    assert_eq!(count("TWIST_TERMS"), seam.common[0].len());
    assert_eq!(count("SEAM_VEC4"), smoothtri_gpu::SEAM_VEC4);
    assert_eq!(count("PATCH_VEC4"), smoothtri_gpu::PATCH_VEC4);
}

/// Each interior edge of `mesh` once: (triangle, its edge, the neighbour, its edge), edges
/// matched by vertex index.
fn shared_edges(mesh: &Mesh) -> Vec<(usize, usize, usize, usize)> {
    let mut first = std::collections::HashMap::new();
    let mut edges = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            if let Some((ta, ea)) = first.insert((a.min(b), a.max(b)), (t, e)) {
                edges.push((ta, ea, t, e));
            }
        }
    }
    edges
}

/// Rays per shared edge of [`rays_at_edges`].
const RAYS_PER_EDGE: usize = 12;

/// [`RAYS_PER_EDGE`] rays per shared edge, from 2 away, up to 80° off both neighbours' normals, aimed at
/// points of the first neighbour's edge curve (its ends included), or with `midway` at the
/// midpoint between the two neighbours' curves.
fn rays_at_edges(mesh: &Mesh, patches: &[Patch], midway: bool) -> Vec<Ray> {
    let normal = |p: &Patch, e: usize, t: f32| {
        let mut w = [0.0f32; 3];
        w[e] = 1.0 - t;
        w[(e + 1) % 3] = t;
        p.point_normal(w[1], w[2]).1
    };
    let cos_max = 80f64.to_radians().cos() as f32;
    let mut rng = Rng(9);
    let mut rays = Vec::new();
    for (ta, ea, tb, eb) in shared_edges(mesh) {
        for k in 0..RAYS_PER_EDGE {
            let t = if k < 2 { k as f32 } else { rng.f() as f32 };
            let c = patches[ta].edge_point_normal(ea, t).0;
            let target = if midway {
                (c + patches[tb].edge_point_normal(eb, 1.0 - t).0) * 0.5
            } else {
                c
            };
            let (na, nb) = (
                normal(&patches[ta], ea, t),
                normal(&patches[tb], eb, 1.0 - t),
            );
            let u = loop {
                let u = rng.unit().as_vec3();
                if u.dot(na) >= cos_max && u.dot(nb) >= cos_max {
                    break u;
                }
            };
            rays.push(Ray::new(target + u * RAY_DIST, -u));
        }
    }
    rays
}

/// How far [`rays_at_edges`] start from their targets.
const RAY_DIST: f32 = 2.0;

/// The indices of the `rays` that pass more than 1 % of their length beyond their target on
/// the GPU.
fn fell_through(gpu: &Arc<Gpu>, patches: &[Patch], rays: &[Ray]) -> Vec<usize> {
    let tree = Tree::new(patches);
    let scene = GpuScene::smooth(gpu, &tree.bvh(patches)).expect("upload");
    let got = traced(rays, None, |out| {
        scene.closest_hit(rays, 0.0, f32::INFINITY, N, out)
    });
    (0..got.len())
        .filter(|&i| got[i].is_none_or(|h| h.t > RAY_DIST * 1.01))
        .collect()
}

/// Watertightness on the GPU (docs/METHOD.md §8, "Shared edges"; the CPU's
/// `tests/suite/watertight.rs`): rays aimed from outside at points of shared edge curves (vertices
/// included), up to 80° off both neighbours' normals, all hit there (or in front), none passes
/// through, on meshes whose neighbours share their curves.
#[test]
fn rays_at_shared_edges_never_fall_through() {
    let Some(gpu) = gpu() else { return };
    for (name, mesh) in [
        ("torus 8x8", torus(8, 8, 1.0, 0.4)),
        ("icosphere(2)", icosphere(2, 1.0)),
    ] {
        let patches = patches32(&mesh);
        let rays = rays_at_edges(&mesh, &patches, false);
        let through = fell_through(&gpu, &patches, &rays).len();
        eprintln!("{name}: {through} of {} rays fell through", rays.len());
        assert_eq!(through, 0, "{name}");
    }
}

/// The teapot, whose neighbours' edge curves part (by up to 1.4e-2 of the diagonal): rays aimed
/// midway between the two curves fall through the WGSL kernel as built; once `close_cracks`
/// has set the patches' reach (docs/METHOD.md §8, "Cracks") the GPU lets exactly the rays
/// through that the CPU does, at least fifty times fewer, and each of them at an edge whose
/// gap exceeds what `MAX_CRACK_REACH` bridges (a reach at the cap: edges of patches whose
/// normals the remedy clamped hard).
#[test]
fn rays_into_cracks_once_closed() {
    let Some(gpu) = gpu() else { return };
    let mesh = teapot(4);
    let mut patches: Vec<Patch> = (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            Patch::new_or_tilted(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).expect("patch")
        })
        .collect();
    let rays = rays_at_edges(&mesh, &patches, true);
    let before = fell_through(&gpu, &patches, &rays).len();
    let mut scratch = vec![SharedEdge::default(); 3 * patches.len()];
    close_cracks(
        &mut patches,
        &mesh.triangles,
        mesh.positions.len(),
        &mut scratch,
    )
    .expect("close cracks");
    let after = fell_through(&gpu, &patches, &rays);
    let tree = Tree::new(&patches);
    let bvh = tree.bvh(&patches);
    let cpu: Vec<usize> = (0..rays.len())
        .filter(|&i| {
            bvh.closest_hit(&rays[i], 0.0, f32::INFINITY, N)
                .is_none_or(|h| h.t > RAY_DIST * 1.01)
        })
        .collect();
    eprintln!(
        "teapot: {before} of {} rays into the cracks fell through as built, {} once closed \
         (CPU: {})",
        rays.len(),
        after.len(),
        cpu.len()
    );
    assert_eq!(after, cpu, "GPU and CPU disagree");
    assert!(after.len() * 50 < before, "{} of {before}", after.len());
    let edges = shared_edges(&mesh);
    let cap = smoothtri::internal::MAX_CRACK_REACH as f32;
    for &i in &after {
        let (ta, ea, tb, eb) = edges[i / RAYS_PER_EDGE];
        let wall = |t: usize, e: usize| patches[t].data().reach[(e + 2) % 3];
        assert!(
            wall(ta, ea) >= cap || wall(tb, eb) >= cap,
            "ray {i} fell through at an edge whose reach is below the cap"
        );
    }
}

/// The shared line field (`LineField::Vertex`, docs/METHOD.md §2 "Line fields"): patches whose
/// sections are tilted (the shader's Newton steps for a point's section, the ruled walls) match
/// the CPU kernel on random rays, and rays aimed at their shared edge curves never fall
/// through, with no crack closure.
#[test]
fn shared_line_field_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let mesh = tilted_normal_sphere();
    let patches: Vec<Patch> = (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            let (p, n) = (p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()));
            Patch::with_field(p, n, LineField::Vertex).expect("patch")
        })
        .collect();
    let tilted = patches
        .iter()
        .filter(|p| p.data().d.iter().any(|d| d[2] != 1.0))
        .count();
    assert!(tilted * 2 > patches.len(), "{tilted} tilted");
    let rays = random_rays(17, 1500, 1.1);
    let tree = Tree::new(&patches);
    let bvh = tree.bvh(&patches);
    let near = |ray: &Ray| cpu_near_silhouette(&bvh, ray);
    let (s, _) = compare(
        "tilted-normal icosphere, shared field",
        &gpu,
        &patches,
        &rays,
        &near,
    );
    assert!(s.hits > 900, "{s:?}");
    let at = rays_at_edges(&mesh, &patches, false);
    let through = fell_through(&gpu, &patches, &at).len();
    eprintln!(
        "shared field: {through} of {} rays at shared edges fell through",
        at.len()
    );
    assert_eq!(through, 0);
}

/// Camera rays framing `mesh` (`w × h`, from the demo's camera).
fn camera_rays(mesh: &Mesh, w: u32, h: u32) -> Vec<Ray> {
    Camera::for_mesh(mesh, 30.0, 35.0, w, h).rays_f32()
}

/// The seamless normal in WGSL (`Shading::Seamless`) against the CPU's `Scene::shading_normal`
/// of the same hit, on the torus and the teapot (clamped and folded patches included), and the
/// Phong normal of the flat triangles against the interpolated vertex normals. The corrections
/// must matter (differ from the geometric normal) for the comparison to mean anything.
#[test]
fn shading_normals_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    for (name, mesh) in [("torus", torus(8, 8, 1.0, 0.4)), ("teapot", teapot(4))] {
        let scene = build_scene::<f32>(&mesh, LineField::Face, true).expect("scene");
        let core = scene.scene();
        let rays = camera_rays(&mesh, 120, 90);
        let got = traced(&rays, None, |out| {
            GpuScene::smooth_seamless(&gpu, core.bvh(), core.seams())
                .expect("upload")
                .closest_shaded(&rays, 0.0, f32::INFINITY, N, out)
        });
        let (mut hits, mut corrected, mut worst) = (0, 0, 0.0f32);
        for (hit, shading) in got.iter().flatten() {
            let cpu = core.shading_normal(hit);
            let d = (*shading - cpu).length();
            assert!(
                d <= NORMAL_TOL,
                "{name}: seamless normal {shading} vs CPU {cpu} ({d}) at {hit:?}"
            );
            worst = worst.max(d);
            hits += 1;
            corrected += usize::from((cpu - hit.normal).length() > 1e-3);
        }
        eprintln!(
            "{name}: {hits} hits, {corrected} with a seam correction over 1e-3, GPU vs CPU \
             seamless normal at most {worst:.2e}"
        );
        assert!(hits > rays.len() / 10 && corrected > hits / 10, "{name}");

        let flat = traced(&rays, None, |out| {
            GpuScene::phong(&gpu, core.bvh())
                .expect("upload")
                .closest_shaded(&rays, 0.0, f32::INFINITY, 0, out)
        });
        let mut interpolated = 0;
        for (hit, shading) in flat.iter().flatten() {
            let [n0, n1, n2] = core.patches()[hit.patch as usize].normals();
            let cpu = (n0 * (1.0 - hit.w1 - hit.w2) + n1 * hit.w1 + n2 * hit.w2)
                .try_normalize()
                .unwrap_or(hit.normal);
            assert!(
                (*shading - cpu).length() <= NORMAL_TOL,
                "{name}: Phong normal {shading} vs {cpu}"
            );
            interpolated += usize::from((cpu - hit.normal).length() > 1e-3);
        }
        assert!(
            interpolated > hits / 2,
            "{name}: Phong normals are not interpolated"
        );
    }
}

/// The constants the update's passes (`gpu/src/update/`) repeat from the CPU's builder, equal to
/// the CPU's: a change on either side fails here.
#[test]
fn update_shader_constants_match_the_cpu_builder() {
    use smoothtri::internal::{
        BAND_MIN_NORMAL_COS, CRACK_REACH, CRACK_SAMPLES, EDGE_T, EXTENT_EDGES, MARGIN_ABS,
        MARGIN_REL, MAX_CRACK_REACH, SHELL_SAMPLES,
    };
    let source = smoothtri_gpu::UPDATE_SHADER;
    let declared = |decl: &str| -> &str {
        let at = source
            .find(decl)
            .unwrap_or_else(|| panic!("{decl} not declared in the update shader"));
        let rest = &source[at + decl.len()..];
        rest[..rest.find(';').expect("declaration ends")].trim()
    };
    let f32_of = |name: &str| -> f32 {
        declared(&format!("const {name}: f32 = "))
            .parse()
            .expect("a number")
    };
    for (name, cpu) in [
        ("MIN_NORMAL_COS", smoothtri::MIN_NORMAL_COS),
        ("MARGIN_REL", MARGIN_REL),
        ("MARGIN_ABS", MARGIN_ABS),
        ("EXTENT_EDGES", EXTENT_EDGES),
        ("MAX_CRACK_REACH", MAX_CRACK_REACH),
        ("BAND_MIN_NORMAL_COS", BAND_MIN_NORMAL_COS),
        ("CRACK_REACH", CRACK_REACH),
    ] {
        assert_eq!(f32_of(name), cpu as f32, "{name}");
    }
    assert_eq!(f32_of("DEGENERATE_RATIO"), f32::EPSILON.sqrt());
    assert_eq!(f32_of("MIN_POSITIVE"), f32::MIN_POSITIVE);
    assert_eq!(f32_of("F32_MAX"), f32::MAX);
    let u32_of = |name: &str| -> usize {
        declared(&format!("const {name}: u32 = "))
            .trim_end_matches('u')
            .parse()
            .expect("a number")
    };
    assert_eq!(u32_of("CRACK_SAMPLES"), CRACK_SAMPLES);
    assert_eq!(u32_of("FIT_SAMPLES"), smoothtri::internal::FIT_SAMPLES);
    assert_eq!(
        f32_of("FREE_END_TOL"),
        smoothtri::internal::FREE_END_TOL as f32
    );
    let fit_nodes: Vec<usize> = declared("const FIT_NODES = array<u32, 8>(")
        .trim_end_matches(')')
        .split(',')
        .map(|x| x.trim().trim_end_matches('u').parse().expect("a number"))
        .collect();
    assert_eq!(fit_nodes, smoothtri::internal::FIT_NODES);
    assert_eq!(u32_of("SHELL_SAMPLES"), SHELL_SAMPLES);
    let edge_t: Vec<f32> = declared("const EDGE_T = array<f32, 5>(")
        .trim_end_matches(')')
        .split(',')
        .map(|x| x.trim().parse().expect("a number"))
        .collect();
    assert_eq!(edge_t, EDGE_T.map(|t| t as f32));
}
