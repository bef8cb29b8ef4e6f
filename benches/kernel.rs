//! Benchmarks of the smooth kernel, patch construction and BVH scenes, each measured side by
//! side with the flat-triangle baseline in the same run, and of the whole scene build of the
//! largest mesh at hand (`bench_build`).
//!
//! `cargo bench --bench kernel` runs the criterion groups and then prints a summary table of
//! ratios measured by interleaved timing (A, B, A, B, … so machine noise hits both alike).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};

mod common;
use common::*;
use smoothtri::max_height_evals;
use smoothtri::{DEFAULT_SAMPLES, Patch, moller_trumbore};
use smoothtri_testkit::scenes::torus;

/// How many of `rays` hit the triangle `tri` (Möller–Trumbore, in `[0, inf]`).
macro_rules! mt_hits {
    ($tri:expr, $rays:expr, $inf:expr) => {
        $rays
            .iter()
            .filter(|r| moller_trumbore(&$tri, r, 0.0, $inf).is_some())
            .count()
    };
}

/// How many of `rays` hit `patch` (closest hit in `[0, inf]`, `n` refinement steps).
macro_rules! smooth_hits {
    ($patch:expr, $rays:expr, $inf:expr, $n:literal) => {
        $rays
            .iter()
            .filter(|r| $patch.closest_hit(r, 0.0, $inf, $n).is_some())
            .count()
    };
}

fn bench_kernel(c: &mut Criterion) {
    let s = setup();
    let mut g = c.benchmark_group("per_ray_patch_test_1024_rays");
    g.bench_function("moller_trumbore_f32", |b| {
        b.iter(|| mt_hits!(s.tri32, s.rays32, f32::INFINITY))
    });
    g.bench_function("moller_trumbore_f64", |b| {
        b.iter(|| mt_hits!(s.tri64, s.rays64, f64::INFINITY))
    });
    macro_rules! smooth_benches {
        ($($n:literal),*) => {$(
            g.bench_function(concat!("smooth_f32_N", $n), |b| {
                b.iter(|| smooth_hits!(s.p32, black_box(&s.rays32), f32::INFINITY, $n))
            });
            g.bench_function(concat!("smooth_f64_N", $n), |b| {
                b.iter(|| smooth_hits!(s.p64, black_box(&s.rays64), f64::INFINITY, $n))
            });
        )*};
    }
    smooth_benches!(0, 2, 4, 8, 16);
    g.finish();

    let mesh = torus(8, 8, 1.0, 0.4);
    let tris = triangles32(&mesh);
    let mut g = c.benchmark_group("patch_construction_128_patches");
    g.bench_function("f32", |b| {
        b.iter(|| {
            tris.iter()
                .filter(|(p, n)| Patch::<f32>::new(*p, *n).is_ok())
                .count()
        })
    });
    g.finish();
}

fn bench_scene(c: &mut Criterion) {
    let smooth = Scene::new(&torus(8, 8, 1.0, 0.4));
    let (n, _) = flat_torus_matching(7.4e-3);
    let flat = Scene::new(&torus(n, n, 1.0, 0.4));
    let rays = camera_rays(160, 120);
    let mut g = c.benchmark_group("scene_torus_19200_camera_rays");
    g.bench_function("smooth_8x8_f32_N8", |b| {
        let bvh = smooth.bvh();
        b.iter(|| {
            rays.iter()
                .filter(|r| bvh.closest_hit(r, 0.0, f32::INFINITY, 8).is_some())
                .count()
        })
    });
    g.bench_function(format!("flat_{n}x{n}_equal_error_f32"), |b| {
        let bvh = flat.bvh();
        b.iter(|| rays.iter().filter(|r| hits_flat(&bvh, r)).count())
    });
    g.finish();
}

/// Interleaved timing of `a` and `b` (ABAB…, `rounds` each); returns mean seconds per call.
fn interleaved(
    mut a: impl FnMut() -> usize,
    mut b: impl FnMut() -> usize,
    rounds: usize,
) -> (f64, f64) {
    let (mut ta, mut tb) = (Duration::ZERO, Duration::ZERO);
    let mut sink = 0usize;
    for _ in 0..rounds {
        let t = Instant::now();
        sink += black_box(a());
        ta += t.elapsed();
        let t = Instant::now();
        sink += black_box(b());
        tb += t.elapsed();
    }
    black_box(sink);
    (
        ta.as_secs_f64() / rounds as f64,
        tb.as_secs_f64() / rounds as f64,
    )
}

/// Prints the README's tables: ratios measured side by side, plus absolute numbers.
fn summary() {
    let s = setup();
    let nr = s.rays32.len() as f64;
    println!(
        "\n## Summary ({}; interleaved timing, {} rays per batch)\n",
        cpu_name(),
        s.rays32.len()
    );
    println!("| kernel | f32 ns/test | f32 × MT | f64 ns/test | f64 × MT |");
    println!("|---|---|---|---|---|");
    let mt32 = || mt_hits!(s.tri32, s.rays32, f32::INFINITY);
    let mt64 = || mt_hits!(s.tri64, s.rays64, f64::INFINITY);
    macro_rules! row {
        ($n:literal) => {{
            let (m32, k32) = interleaved(
                mt32,
                || smooth_hits!(s.p32, s.rays32, f32::INFINITY, $n),
                200,
            );
            let (m64, k64) = interleaved(
                mt64,
                || smooth_hits!(s.p64, s.rays64, f64::INFINITY, $n),
                200,
            );
            println!(
                "| smooth N = {} | {:.1} | {:.1} | {:.1} | {:.1} |",
                $n,
                k32 / nr * 1e9,
                k32 / m32,
                k64 / nr * 1e9,
                k64 / m64
            );
            if $n == 0 {
                println!(
                    "| Möller–Trumbore | {:.1} | 1 | {:.1} | 1 |",
                    m32 / nr * 1e9,
                    m64 / nr * 1e9
                );
            }
        }};
    }
    row!(0);
    row!(2);
    row!(4);
    row!(8);
    row!(16);
    #[cfg(feature = "micromath")]
    {
        use smoothtri::{FastF32, Ray};
        let (p, n) = torus(8, 8, 1.0, 0.4).triangle(21);
        let fast = Patch::<FastF32>::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap();
        let zero = FastF32(0.0);
        let inf = FastF32(f32::INFINITY);
        let fast_rays: Vec<Ray<FastF32>> =
            s.rays32.iter().map(|r| Ray::new(r.origin, r.dir)).collect();
        println!("| FastF32 (micromath sqrt), f32 columns: | | | | |");
        macro_rules! frow {
            ($n:literal) => {{
                let (m32, k32) = interleaved(
                    mt32,
                    || {
                        fast_rays
                            .iter()
                            .filter(|r| fast.closest_hit(r, zero, inf, $n).is_some())
                            .count()
                    },
                    200,
                );
                println!(
                    "| FastF32 N = {} | {:.1} | {:.1} | | |",
                    $n,
                    k32 / nr * 1e9,
                    k32 / m32
                );
            }};
        }
        frow!(0);
        frow!(8);
    }

    // Work per patch test (deterministic): mean lane calls over the rays that reach
    // bracketing (eight height evaluations per call; the estimate step of four counts half),
    // against the bound max_height_evals(K, N) / 8.
    println!("\n| N | f32 mean lane calls | f64 mean lane calls | bound (no early stop) |");
    println!("|---|---|---|---|");
    macro_rules! calls {
        ($n:literal) => {{
            let mean = |evals: Vec<u32>| {
                let searched: Vec<u32> = evals.into_iter().filter(|&e| e > 0).collect();
                searched.iter().map(|&e| f64::from(e) / 8.0).sum::<f64>() / searched.len() as f64
            };
            let e32 = s
                .rays32
                .iter()
                .map(|r| {
                    s.p32
                        .closest_hit_stats::<DEFAULT_SAMPLES>(r, 0.0, f32::INFINITY, $n)
                        .1
                        .height_evals
                })
                .collect();
            let e64 = s
                .rays64
                .iter()
                .map(|r| {
                    s.p64
                        .closest_hit_stats::<DEFAULT_SAMPLES>(r, 0.0, f64::INFINITY, $n)
                        .1
                        .height_evals
                })
                .collect();
            println!(
                "| {} | {:.2} | {:.2} | {} |",
                $n,
                mean(e32),
                mean(e64),
                max_height_evals(DEFAULT_SAMPLES, $n) as f64 / 8.0
            );
        }};
    }
    calls!(0);
    calls!(2);
    calls!(4);
    calls!(8);
    calls!(16);

    let mesh = torus(8, 8, 1.0, 0.4);
    let tris = triangles32(&mesh);
    let t = Instant::now();
    let mut built = 0usize;
    while t.elapsed() < Duration::from_millis(500) {
        built += tris
            .iter()
            .filter(|(p, n)| black_box(Patch::<f32>::new(*p, *n)).is_ok())
            .count();
    }
    let rate = built as f64 / t.elapsed().as_secs_f64();
    println!(
        "\nPatch construction (f32, shell bounds included): {:.2} M patches/s on one core",
        rate / 1e6
    );

    let smooth = Scene::new(&mesh);
    let (n, err) = flat_torus_matching(7.4e-3);
    let flat = Scene::new(&torus(n, n, 1.0, 0.4));
    let rays = camera_rays(160, 120);
    let (bs, bf) = (smooth.bvh(), flat.bvh());
    let (ts, tf) = interleaved(
        || {
            rays.iter()
                .filter(|r| bs.closest_hit(r, 0.0, f32::INFINITY, 8).is_some())
                .count()
        },
        || rays.iter().filter(|r| hits_flat(&bf, r)).count(),
        10,
    );
    let mem = |sc: &Scene| std::mem::size_of_val(sc.patches()) + sc.bvh().memory_bytes();
    println!(
        "\n| scene (160×120 camera rays, closest hit) | triangles | max error to torus | Mrays/s | memory |"
    );
    println!("|---|---|---|---|---|");
    println!(
        "| smooth torus 8×8, f32, N = 8 | {} | 7.3e-3 | {:.2} | {} KiB |",
        smooth.patches().len(),
        rays.len() as f64 / ts / 1e6,
        mem(&smooth) / 1024
    );
    println!(
        "| flat torus {n}×{n} (equal error) | {} | {:.1e} | {:.2} | {} KiB |",
        flat.patches().len(),
        err,
        rays.len() as f64 / tf / 1e6,
        mem(&flat) / 1024
    );
}

/// The largest mesh at hand: the 121k-triangle CAD model of Debian's `assimp-testmodels`
/// when installed, else the generated 8×8 teapot (3 968 triangles).
fn largest_mesh() -> (String, smoothtri_testkit::Mesh) {
    let cad = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    match smoothtri_io::load(cad) {
        Ok(l) => ("2CylinderEngine.glb".into(), l.mesh),
        Err(_) => ("teapot 8x8".into(), smoothtri_testkit::scenes::teapot(8)),
    }
}

/// The whole scene build (patches, shared edges, BVH) of [`largest_mesh`] in `f32`: with and
/// without seams, on one thread and on rayon's pool (issue 24: triangles per second per core).
fn bench_build(c: &mut Criterion) {
    use smoothtri::{BuildOptions, LineField, OwnedScene, Vertices};
    let (name, m) = largest_mesh();
    let flat = |v: &[glam::DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
    let (p, n) = (flat(&m.positions), flat(&m.normals));
    let mut g = c.benchmark_group(format!("build_{}_triangles", m.triangles.len()));
    g.sample_size(10);
    for seams in [false, true] {
        let options = BuildOptions {
            field: LineField::Face,
            seams,
            ..BuildOptions::default()
        };
        let label = if seams { "seams" } else { "no_seams" };
        let build = |threads: bool| {
            let (pv, nv) = (Vertices::packed(&p), Vertices::packed(&n));
            let s = if threads {
                let mut pool = options.with_executor(smoothtri_testkit::RayonExecutor);
                OwnedScene::<f32>::build(pv, nv, &m.triangles, &mut pool)
            } else {
                OwnedScene::<f32>::build(pv, nv, &m.triangles, &mut { options })
            };
            s.map(|s| s.scene().report().patches).unwrap_or(0)
        };
        g.bench_function(format!("{name}_{label}_one_thread"), |b| {
            b.iter(|| build(false))
        });
        g.bench_function(format!("{name}_{label}_rayon"), |b| b.iter(|| build(true)));
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = bench_kernel, bench_scene, bench_build
}

fn main() {
    let quick = std::env::args().any(|a| a == "--summary-only");
    if !quick {
        benches();
        Criterion::default().configure_from_args().final_summary();
    }
    summary();
}
