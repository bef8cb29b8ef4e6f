//! Benchmarks of the smooth kernel, patch construction and BVH scenes, each measured side by
//! side with the flat-triangle baseline in the same run.
//!
//! `cargo bench --bench kernel` runs the criterion groups and then prints a summary table of
//! ratios measured by interleaved timing (A, B, A, B, … so machine noise hits both alike).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};
use glam::{DVec3, Vec3};
use smoothtri::{Bvh, BvhNode, DPatch, DRay, Patch, Ray, flat_hit, moller_trumbore};
use smoothtri_demo::scenes::{Mesh, torus, torus_distance};

/// Deterministic SplitMix64.
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The triangles and vertex normals of `m`, rounded to f32.
fn triangles32(m: &Mesh) -> Vec<([Vec3; 3], [Vec3; 3])> {
    (0..m.triangles.len())
        .map(|t| {
            let (p, n) = m.triangle(t);
            (p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()))
        })
        .collect()
}

fn patches32(m: &Mesh) -> Vec<Patch> {
    triangles32(m)
        .into_iter()
        .map(|(p, n)| Patch::new(p, n).unwrap())
        .collect()
}

/// Rays aimed at random points of patch `k`'s triangle from random directions above it:
/// every ray hits the patch's box, most hit the patch (the per-test cost of a real traversal).
fn rays_at_patch(p: &DPatch, n: usize) -> Vec<DRay> {
    let mut rng = Rng(7);
    let v = p.vertices();
    let nf = p.face_normal();
    (0..n)
        .map(|_| {
            let (a, b) = (rng.f(), rng.f());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            let target = v[0] * (1.0 - a - b) + v[1] * a + v[2] * b;
            let dir =
                (nf + DVec3::new(rng.f() - 0.5, rng.f() - 0.5, rng.f() - 0.5) * 1.2).normalize();
            DRay::new(target + dir * 2.0, -dir)
        })
        .collect()
}

struct Setup {
    p64: DPatch,
    p32: Patch,
    tri32: [Vec3; 3],
    tri64: [DVec3; 3],
    rays64: Vec<DRay>,
    rays32: Vec<Ray>,
}

fn setup() -> Setup {
    let mesh = torus(8, 8, 1.0, 0.4);
    let (p, n) = mesh.triangle(21);
    let p64 = DPatch::new(p, n).unwrap();
    let p32 = Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap();
    let rays64 = rays_at_patch(&p64, 1024);
    let rays32 = rays64
        .iter()
        .map(|r| Ray::new(r.origin.as_vec3(), r.dir.as_vec3()))
        .collect();
    Setup {
        p64,
        p32,
        tri32: p.map(|x| x.as_vec3()),
        tri64: p,
        rays64,
        rays32,
    }
}

macro_rules! smooth32 {
    ($s:expr, $n:literal) => {
        |rays: &[Ray]| {
            rays.iter()
                .filter(|r| $s.p32.intersect::<$n>(r, 0.0, f32::INFINITY).is_some())
                .count()
        }
    };
}
macro_rules! smooth64 {
    ($s:expr, $n:literal) => {
        |rays: &[DRay]| {
            rays.iter()
                .filter(|r| $s.p64.intersect::<$n>(r, 0.0, f64::INFINITY).is_some())
                .count()
        }
    };
}

fn bench_kernel(c: &mut Criterion) {
    let s = setup();
    let mut g = c.benchmark_group("per_ray_patch_test_1024_rays");
    g.bench_function("moller_trumbore_f32", |b| {
        b.iter(|| {
            s.rays32
                .iter()
                .filter(|r| moller_trumbore(&s.tri32, r, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    g.bench_function("moller_trumbore_f64", |b| {
        b.iter(|| {
            s.rays64
                .iter()
                .filter(|r| moller_trumbore(&s.tri64, r, 0.0, f64::INFINITY).is_some())
                .count()
        })
    });
    macro_rules! smooth_benches {
        ($($n:literal),*) => {$(
            g.bench_function(concat!("smooth_f32_N", $n), |b| {
                b.iter(|| smooth32!(s, $n)(black_box(&s.rays32)))
            });
            g.bench_function(concat!("smooth_f64_N", $n), |b| {
                b.iter(|| smooth64!(s, $n)(black_box(&s.rays64)))
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

/// Smallest flat torus grid whose maximum distance to the true torus is at most `target`.
fn flat_torus_matching(target: f64) -> (usize, f64) {
    for n in 8..200 {
        let m = torus(n, n, 1.0, 0.4);
        let mut worst = 0.0f64;
        for t in 0..m.triangles.len() {
            let (p, _) = m.triangle(t);
            for i in 0..=8 {
                for j in 0..=(8 - i) {
                    let (a, b) = (i as f64 / 8.0, j as f64 / 8.0);
                    let x = p[0] * (1.0 - a - b) + p[1] * a + p[2] * b;
                    worst = worst.max(torus_distance(x, 1.0, 0.4));
                }
            }
        }
        if worst <= target {
            return (n, worst);
        }
    }
    (200, f64::NAN)
}

struct Scene {
    patches: Vec<Patch>,
    nodes: Vec<BvhNode<f32>>,
    order: Vec<u32>,
}
impl Scene {
    fn new(m: &Mesh) -> Self {
        let patches = patches32(m);
        let mut nodes = vec![BvhNode::default(); Bvh::<f32>::nodes_needed(patches.len())];
        let mut order = vec![0u32; patches.len()];
        let used = Bvh::build(&patches, &mut nodes, &mut order)
            .unwrap()
            .node_count();
        nodes.truncate(used);
        Scene {
            patches,
            nodes,
            order,
        }
    }
    fn bvh(&self) -> Bvh<'_, f32> {
        Bvh::from_parts(&self.patches, &self.nodes, &self.order)
    }
}

fn camera_rays(w: usize, h: usize) -> Vec<Ray> {
    let eye = Vec3::new(0.0, -3.2, 2.2);
    let fwd = (-eye).normalize();
    let right = fwd.cross(Vec3::Z).normalize();
    let up = right.cross(fwd);
    let mut rays = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let u = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
            let v = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
            rays.push(Ray::new(eye, fwd + right * u * 0.55 + up * v * 0.42));
        }
    }
    rays
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
                .filter(|r| matches!(bvh.closest_hit::<8>(r, 0.0, f32::INFINITY), Ok(Some(_))))
                .count()
        })
    });
    g.bench_function(format!("flat_{n}x{n}_equal_error_f32"), |b| {
        let bvh = flat.bvh();
        b.iter(|| {
            rays.iter()
                .filter(|r| {
                    matches!(
                        bvh.closest_with(r, 0.0, f32::INFINITY, |p, a, t| flat_hit(
                            &p.vertices(),
                            None,
                            r,
                            a,
                            t
                        )),
                        Ok(Some(_))
                    )
                })
                .count()
        })
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

fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into())
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
    let mt32 = || {
        s.rays32
            .iter()
            .filter(|r| moller_trumbore(&s.tri32, r, 0.0, f32::INFINITY).is_some())
            .count()
    };
    let mt64 = || {
        s.rays64
            .iter()
            .filter(|r| moller_trumbore(&s.tri64, r, 0.0, f64::INFINITY).is_some())
            .count()
    };
    macro_rules! row {
        ($n:literal) => {{
            let (m32, k32) = interleaved(mt32, || smooth32!(s, $n)(&s.rays32), 200);
            let (m64, k64) = interleaved(mt64, || smooth64!(s, $n)(&s.rays64), 200);
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
        use smoothtri::FastF32;
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
                            .filter(|r| fast.intersect::<$n>(r, zero, inf).is_some())
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
                .filter(|r| matches!(bs.closest_hit::<8>(r, 0.0, f32::INFINITY), Ok(Some(_))))
                .count()
        },
        || {
            rays.iter()
                .filter(|r| {
                    matches!(
                        bf.closest_with(r, 0.0, f32::INFINITY, |p, a, t| flat_hit(
                            &p.vertices(),
                            None,
                            r,
                            a,
                            t
                        )),
                        Ok(Some(_))
                    )
                })
                .count()
        },
        10,
    );
    let mem =
        |sc: &Scene| sc.patches.len() * std::mem::size_of::<Patch>() + sc.bvh().memory_bytes();
    println!(
        "\n| scene (160×120 camera rays, closest hit) | triangles | max error to torus | Mrays/s | memory |"
    );
    println!("|---|---|---|---|---|");
    println!(
        "| smooth torus 8×8, f32, N = 8 | {} | 7.3e-3 | {:.2} | {} KiB |",
        smooth.patches.len(),
        rays.len() as f64 / ts / 1e6,
        mem(&smooth) / 1024
    );
    println!(
        "| flat torus {n}×{n} (equal error) | {} | {:.1e} | {:.2} | {} KiB |",
        flat.patches.len(),
        err,
        rays.len() as f64 / tf / 1e6,
        mem(&flat) / 1024
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = bench_kernel, bench_scene
}

fn main() {
    let quick = std::env::args().any(|a| a == "--summary-only");
    if !quick {
        benches();
        Criterion::default().configure_from_args().final_summary();
    }
    summary();
}
