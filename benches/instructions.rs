//! Instruction counts (callgrind): the deterministic companion of `benches/kernel.rs`, whose
//! wall-clock timings depend on a shared, noisy machine.
//!
//! `cargo bench --bench instructions` runs each workload of [`CASES`] in a child process under
//! `valgrind --tool=callgrind`, once with `REPS` repetitions and once with none, and prints the
//! difference per unit of work (setup cancels out). Needs `valgrind` on the `PATH`; without it
//! the benchmark says so and exits successfully. One workload by hand:
//! `target/release/deps/instructions-* --case smooth_f32_N8 --reps 3`.

use std::hint::black_box;
use std::process::Command;

use smoothtri::{LineField, Patch, moller_trumbore};
use smoothtri_testkit::scenes::{tilted_normal_sphere, torus};

mod common;
use common::*;

/// `(name, unit of work, units per repetition)`. Per-test cases use the 1024 rays of
/// `kernel.rs` aimed at one torus patch; scene cases the 160×120 camera rays.
const CASES: &[(&str, &str, usize)] = &[
    ("moller_trumbore_f32", "patch test", 1024),
    ("smooth_f32_N0", "patch test", 1024),
    ("smooth_f32_N2", "patch test", 1024),
    ("smooth_f32_N4", "patch test", 1024),
    ("smooth_f32_N8", "patch test", 1024),
    ("smooth_f64_N8", "patch test", 1024),
    ("scene_smooth_8x8_f32_N4", "camera ray", 160 * 120),
    ("scene_smooth_8x8_f32_N8", "camera ray", 160 * 120),
    ("scene_seams_two_steps_8x8_f32_N8", "camera ray", 160 * 120),
    (
        "scene_seams_closest_hit_8x8_f32_N8",
        "camera ray",
        160 * 120,
    ),
    ("scene_wuson_f32_N8", "camera ray", 160 * 120),
    ("scene_tilted_sphere_face_f32_N4", "camera ray", 160 * 120),
    ("scene_tilted_sphere_vertex_f32_N4", "camera ray", 160 * 120),
    ("scene_flat_equal_error_f32", "camera ray", 160 * 120),
    ("bvh_flat_triangles_f32", "camera ray", 160 * 120),
    ("construct_f32", "patch", 128),
    ("build_teapot8_f32", "triangle", 3968),
    ("build_teapot8_seams_f32", "triangle", 3968),
    ("normal_teapot4_f32", "normal", 992 * 10),
    ("seam_shading_teapot4_f32", "normal", 992 * 10),
    ("seam_correct_teapot4_f32", "normal", 992 * 10),
];

/// How many of `rays` `hit` says are hit, over `reps` passes (each ray through `black_box`).
fn count_hits<R>(reps: usize, rays: &[R], mut hit: impl FnMut(&R) -> bool) -> usize {
    let mut hits = 0;
    for _ in 0..reps {
        for r in rays {
            hits += hit(black_box(r)) as usize;
        }
    }
    hits
}

macro_rules! per_patch {
    ($s:expr, $reps:expr, $patch:expr, $rays:expr, $n:literal, $inf:expr) => {
        count_hits($reps, &$rays, |r| {
            $patch.closest_hit(r, 0.0, $inf, $n).is_some()
        })
    };
}

/// The 160×120 camera rays through the BVH of the 8×8 torus, `reps` times.
fn scene_smooth<const N: usize>(reps: usize) -> usize {
    scene_rays::<N>(&Scene::new(&torus(8, 8, 1.0, 0.4)), reps)
}

/// The 160×120 camera rays through the BVH of `scene`, `reps` times.
fn scene_rays<const N: usize>(scene: &Scene, reps: usize) -> usize {
    let bvh = scene.bvh();
    count_hits(reps, &camera_rays(160, 120), |r| {
        bvh.closest_hit(r, 0.0, f32::INFINITY, N).is_some()
    })
}

/// Runs one workload `reps` times; returns something derived from the results so nothing is
/// optimised away.
fn run_case(name: &str, reps: usize) -> usize {
    let s = setup();
    match name {
        "moller_trumbore_f32" => count_hits(reps, &s.rays32, |r| {
            moller_trumbore(&s.tri32, r, 0.0, f32::INFINITY).is_some()
        }),
        "smooth_f32_N0" => per_patch!(s, reps, s.p32, s.rays32, 0, f32::INFINITY),
        "smooth_f32_N2" => per_patch!(s, reps, s.p32, s.rays32, 2, f32::INFINITY),
        "smooth_f32_N4" => per_patch!(s, reps, s.p32, s.rays32, 4, f32::INFINITY),
        "smooth_f32_N8" => per_patch!(s, reps, s.p32, s.rays32, 8, f32::INFINITY),
        "smooth_f64_N8" => per_patch!(s, reps, s.p64, s.rays64, 8, f64::INFINITY),
        "scene_smooth_8x8_f32_N4" => scene_smooth::<4>(reps),
        "scene_smooth_8x8_f32_N8" => scene_smooth::<8>(reps),
        "scene_tilted_sphere_face_f32_N4" => scene_rays::<4>(
            &Scene::new_on(&tilted_normal_sphere(), LineField::Face),
            reps,
        ),
        "scene_tilted_sphere_vertex_f32_N4" => scene_rays::<4>(
            &Scene::new_on(&tilted_normal_sphere(), LineField::Vertex),
            reps,
        ),
        "scene_wuson_f32_N8" => {
            // Issue 25's same-mesh workload: the scanned WusonOBJ (3 732 triangles, vertex
            // normals; Debian's assimp-testmodels) as the C API's `st_intersect1` traces it
            // (`Scene::closest_hit`, no seams, the hit normal included), camera rays framing it
            // as the `embree` bench's, 160×120 of them.
            let dir = smoothtri_testkit::assimp_models()
                .ok()
                .flatten()
                .expect("assimp-testmodels installed");
            let path = dir.join("OBJ/WusonOBJ.obj");
            let mesh = smoothtri_io::load(&path.to_string_lossy())
                .expect("WusonOBJ loads")
                .mesh;
            let built = smoothtri_testkit::build_scene::<f32>(&mesh, LineField::Face, false)
                .expect("WusonOBJ builds");
            let scene = built.scene();
            let rays = smoothtri_testkit::Camera::for_mesh(&mesh, 30.0, 35.0, 160, 120).rays_f32();
            count_hits(reps, &rays, |r| {
                scene.closest_hit(r, 0.0, f32::INFINITY, 8).is_some()
            })
        }
        "scene_seams_two_steps_8x8_f32_N8" | "scene_seams_closest_hit_8x8_f32_N8" => {
            // The torus with seams: a closest hit with its seamless shading normal, as
            // `Bvh::closest_hit` then `Scene::scene_hit` (two steps: the hit's normal, then
            // `Seam::correct`) or as `Scene::closest_hit` (both normals in one evaluation).
            let built = smoothtri_testkit::build_scene::<f32>(
                &torus(8, 8, 1.0, 0.4),
                LineField::Face,
                true,
            )
            .expect("the torus builds");
            let scene = built.scene();
            let bvh = scene.bvh();
            let rays = camera_rays(160, 120);
            let fused = name.contains("closest_hit");
            let mut acc = 0.0f32;
            for _ in 0..reps {
                for r in &rays {
                    let h = if fused {
                        scene.closest_hit(black_box(r), 0.0, f32::INFINITY, 8)
                    } else {
                        bvh.closest_hit(black_box(r), 0.0, f32::INFINITY, 8)
                            .map(|h| scene.scene_hit(h))
                    };
                    acc += h.map_or(0.0, |h| h.shading_normal.x);
                }
            }
            acc as usize
        }
        "scene_flat_equal_error_f32" => {
            let (n, _) = flat_torus_matching(7.4e-3);
            let scene = Scene::new(&torus(n, n, 1.0, 0.4));
            let bvh = scene.bvh();
            count_hits(reps, &camera_rays(160, 120), |r| hits_flat(&bvh, r))
        }
        "bvh_flat_triangles_f32" => {
            // Our BVH on Embree's task (the `embree` bench's row): the flat 35×35 torus, boxes
            // of the flat triangles, Möller–Trumbore in the leaves.
            let (n, _) = flat_torus_matching(7.4e-3);
            let flat = FlatBvh::new(&torus(n, n, 1.0, 0.4));
            let bvh = flat.bvh();
            count_hits(reps, &camera_rays(160, 120), |r| {
                flat.closest_hit(&bvh, r).is_some()
            })
        }
        "construct_f32" => {
            let tris = triangles32(&torus(8, 8, 1.0, 0.4));
            let mut ok = 0;
            for _ in 0..reps {
                for (p, n) in &tris {
                    ok += Patch::<f32>::new(black_box(*p), black_box(*n)).is_ok() as usize;
                }
            }
            ok
        }
        "build_teapot8_f32" | "build_teapot8_seams_f32" => {
            use smoothtri::{BuildOptions, OwnedScene, Vertices};
            let m = smoothtri_testkit::scenes::teapot(8);
            let flat =
                |v: &[glam::DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
            let (p, n) = (flat(&m.positions), flat(&m.normals));
            let options = BuildOptions {
                seams: name.contains("seams"),
                ..BuildOptions::default()
            };
            let mut patches = 0;
            for _ in 0..reps {
                let s = OwnedScene::<f32>::build(
                    Vertices::packed(black_box(&p)),
                    Vertices::packed(&n),
                    &m.triangles,
                    &mut { options },
                );
                patches += s.map(|s| s.scene().report().patches).unwrap_or(0);
            }
            patches
        }
        "normal_teapot4_f32" | "seam_shading_teapot4_f32" | "seam_correct_teapot4_f32" => {
            // The geometric normal against the seamless shading normal at ten interior points of
            // each patch of the built-in teapot (f32, seams fitted).
            use smoothtri::{BuildOptions, OwnedScene, Vertices};
            let m = smoothtri_testkit::scenes::teapot(4);
            let flat =
                |v: &[glam::DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
            let (p, n) = (flat(&m.positions), flat(&m.normals));
            let options = BuildOptions {
                seams: true,
                ..BuildOptions::default()
            };
            let Ok(owned) = OwnedScene::<f32>::build(
                Vertices::packed(&p),
                Vertices::packed(&n),
                &m.triangles,
                &mut { options },
            ) else {
                return 0;
            };
            let scene = owned.scene();
            let seamless = name.starts_with("seam_shading");
            let correct = name.starts_with("seam_correct");
            let points: [(f32, f32); 10] = [
                (0.1, 0.1),
                (0.2, 0.5),
                (0.6, 0.2),
                (0.33, 0.33),
                (0.05, 0.45),
                (0.45, 0.05),
                (0.7, 0.1),
                (0.1, 0.7),
                (0.25, 0.25),
                (0.4, 0.4),
            ];
            // `Seam::correct` (what `Scene::shading_normal` does with a hit) is given the
            // geometric normals, computed once here (setup, which the count subtracts).
            let geometric: Vec<glam::Vec3> = scene
                .patches()
                .iter()
                .flat_map(|p| points.map(|(w1, w2)| p.point_normal(w1, w2).1))
                .collect();
            let mut acc = 0.0f32;
            for _ in 0..reps {
                let mut ng = geometric.iter();
                for (patch, seam) in scene.patches().iter().zip(scene.seams()) {
                    for &(w1, w2) in &points {
                        let g = ng.next().copied().unwrap_or(glam::Vec3::Z);
                        let v = if correct {
                            seam.correct(patch, black_box(w1), w2, g)
                        } else if seamless {
                            seam.shading_normal(patch, black_box(w1), w2)
                        } else {
                            patch.point_normal(black_box(w1), w2).1
                        };
                        acc += v.x;
                    }
                }
            }
            acc as usize
        }
        _ => {
            eprintln!("unknown case {name}");
            std::process::exit(2);
        }
    }
}

/// Instructions executed by `exe --case name --reps reps` under callgrind.
fn count(exe: &str, name: &str, reps: usize) -> Option<u64> {
    let out = Command::new("valgrind")
        .args([
            "--tool=callgrind",
            "--callgrind-out-file=/dev/null",
            exe,
            "--case",
            name,
            "--reps",
            &reps.to_string(),
        ])
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stderr);
    let line = text.lines().find(|l| l.contains("Collected :"))?;
    line.rsplit(':').next()?.trim().parse().ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |key: &str| {
        args.iter()
            .position(|a| a == key)
            .and_then(|i| args.get(i + 1))
    };
    if let Some(name) = arg("--case") {
        let reps = arg("--reps").and_then(|r| r.parse().ok()).unwrap_or(1);
        println!("{}", black_box(run_case(name, reps)));
        return;
    }
    let exe = args.first().cloned().unwrap_or_default();
    if Command::new("valgrind").arg("--version").output().is_err() {
        println!("valgrind not found: instruction counts skipped (install valgrind to run them)");
        return;
    }
    println!(
        "\n## Instruction counts (callgrind; {}, release build)\n",
        cpu_name()
    );
    println!("| workload | unit | instructions per unit | × Möller–Trumbore |");
    println!("|---|---|---|---|");
    let mut mt = None;
    for &(name, unit, units) in CASES {
        let reps = if unit == "camera ray" { 1 } else { 4 };
        let per = match (count(&exe, name, reps), count(&exe, name, 0)) {
            (Some(a), Some(b)) => a.saturating_sub(b) as f64 / (reps * units) as f64,
            _ => {
                println!("| {name} | {unit} | (callgrind failed) | |");
                continue;
            }
        };
        if name == "moller_trumbore_f32" {
            mt = Some(per);
        }
        let ratio = match (unit, mt) {
            ("patch test", Some(m)) if m > 0.0 => format!("{:.0}", per / m),
            _ => String::new(),
        };
        println!("| {name} | {unit} | {per:.0} | {ratio} |");
    }
}
