//! GPU throughput: closest hits of the primary rays of a 1920×1080 camera, the smooth kernel
//! beside the same compute pipeline tracing flat triangles (same traversal code, Möller–Trumbore
//! instead of the patch test), and beside flat triangles in a pipeline of their own
//! (`FlatScene`: no smooth code, the rows marked "own flat pipeline"; the fair anchor).
//!
//! ```text
//! cargo run --release -p smoothtri-gpu --example bench [-- --width W --height H --iterations N --repeat R --only rays|frames|animated]
//! ```
//!
//! Scenes: the 8×8 torus (smooth) beside the flat 35×35 torus (the coarsest flat grid of equal
//! error, README) and the flat 8×8 torus; the teapot (992 triangles) beside its own flat
//! triangles; a 100 352-triangle wavy torus with generated (angle-weighted) normals beside its
//! own flat triangles; an icosphere with tilted normals on the paper's and on the shared line
//! field (tilted sections). The smooth scenes are built as a renderer builds them (`build_scene`:
//! patches, cracks closed, BVH). Two rates, each the best of `--repeat` runs after a warm-up that compiles
//! the pipelines: over the whole call (ray upload, dispatch, readback: on a discrete GPU this is
//! mostly the PCIe transfers) and over the kernel's own GPU time (timestamp queries, where the
//! adapter has them): the ratio of kernel times is the smooth kernel's cost. On a software adapter (Mesa's
//! lavapipe) the figures say nothing about GPUs: the example says so.
//!
//! A second table times whole frames as `smoothtri view --gpu` renders them
//! (`GpuScene::render_frame`: camera rays, closest hits, the shading normal, a shadow ray per lit
//! hit and the shading, in one compute pass): the smooth torus and teapot with the seamless
//! normal beside the equal-error flat torus and the flat teapot with Phong normals, frames/s
//! and Mrays/s (primary and shadow rays) over the pass and its counters' readback.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use smoothtri::{BuildOptions, LineField, Ray, Vertices};
use smoothtri_gpu::{FlatScene, FrameView, Gpu, GpuFrame, GpuScene, GpuUpdate};
use smoothtri_io::{Mesh, angle_weighted_normals};
use smoothtri_testkit::scenes::{teapot, tilted_normal_sphere, torus};
use smoothtri_testkit::twist::{twist_pose, twisting_torus};
use smoothtri_testkit::{Camera, RayonExecutor, SHADOW_OFFSET_F32, build_scene};

struct Opts {
    width: u32,
    height: u32,
    iterations: usize,
    repeat: usize,
    /// `--only rays|frames|animated`: one table instead of all three.
    only: Option<Table>,
}

/// The bench's tables.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Table {
    Rays,
    Frames,
    Animated,
}

impl Opts {
    fn runs(&self, t: Table) -> bool {
        self.only.is_none_or(|o| o == t)
    }
}

fn opts() -> Result<Opts, String> {
    let mut o = Opts {
        width: 1920,
        height: 1080,
        iterations: smoothtri_gpu::DEFAULT_ITERATIONS,
        repeat: 1,
        only: None,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let v = it.next().ok_or(format!("{a} needs a value"))?;
        if a == "--only" {
            o.only = Some(match v.as_str() {
                "rays" => Table::Rays,
                "frames" => Table::Frames,
                "animated" => Table::Animated,
                _ => return Err(format!("--only {v}: rays, frames or animated")),
            });
            continue;
        }
        let n: usize = v.parse().map_err(|_| format!("{a} {v}: not a number"))?;
        match a.as_str() {
            "--width" => o.width = n as u32,
            "--height" => o.height = n as u32,
            "--iterations" => o.iterations = n,
            "--repeat" => o.repeat = n.max(1),
            _ => return Err(format!("unknown option {a}")),
        }
    }
    Ok(o)
}

/// A torus of `n × n` quads whose minor radius waves (`0.4 + 0.03·sin 7u·sin 5v`), normals
/// generated from the triangles (angle-weighted): a large mesh without analytic normals.
fn wavy_torus(n: usize) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..n {
        for j in 0..n {
            let u = i as f64 / n as f64 * std::f64::consts::TAU;
            let v = j as f64 / n as f64 * std::f64::consts::TAU;
            let r = 0.4 + 0.03 * (7.0 * u).sin() * (5.0 * v).sin();
            let radial = DVec3::new(v.cos() * u.cos(), v.cos() * u.sin(), v.sin());
            m.positions
                .push(DVec3::new(u.cos(), u.sin(), 0.0) + radial * r);
        }
    }
    let id = |i: usize, j: usize| ((i % n) * n + (j % n)) as u32;
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m.normals = angle_weighted_normals(
        &m.positions,
        m.triangles.iter().map(|t| t.map(|i| i as usize)),
    );
    m
}

/// Throughput of closest hits of `rays` on `scene`, the best of `repeat` runs.
struct Rate {
    /// Mrays/s over the whole call: ray upload, dispatch and readback.
    call: f64,
    /// Mrays/s over the GPU's own execution time of the kernel (timestamp queries), when the
    /// adapter has them.
    kernel: Option<f64>,
    hits: usize,
}

fn rate(
    scene: &GpuScene,
    n: usize,
    rays: &[Ray],
    repeat: usize,
) -> Result<Rate, smoothtri_gpu::GpuError> {
    let mut hits = vec![None; rays.len()];
    scene.closest_hit(
        rays.get(..256).unwrap_or(rays),
        0.0,
        f32::MAX,
        n,
        &mut hits[..rays.len().min(256)],
    )?;
    let (call, kernel) = best_of(repeat, rays.len(), || {
        scene.closest_hit_timed(rays, 0.0, f32::MAX, n, &mut hits)
    })?;
    let hits = hits.iter().flatten().count();
    Ok(Rate { call, kernel, hits })
}

/// [`rate`] for the flat triangles' own pipeline ([`FlatScene`]), after one whole warm-up pass
/// (its dispatches are short: a cold clock would dominate).
fn rate_own(
    scene: &FlatScene,
    rays: &[Ray],
    repeat: usize,
) -> Result<Rate, smoothtri_gpu::GpuError> {
    let mut hits = vec![None; rays.len()];
    scene.closest_hit(rays, 0.0, f32::MAX, &mut hits)?;
    let (call, kernel) = best_of(repeat.max(3), rays.len(), || {
        scene.closest_hit_timed(rays, 0.0, f32::MAX, &mut hits)
    })?;
    let hits = hits.iter().flatten().count();
    Ok(Rate { call, kernel, hits })
}

/// The best of `repeat` calls of `call` (which returns the kernel's GPU time, if timed), as
/// Mrays/s for `rays` rays: over the whole call and over the kernel's time.
fn best_of(
    repeat: usize,
    rays: usize,
    mut call: impl FnMut() -> Result<Option<f64>, smoothtri_gpu::GpuError>,
) -> Result<(f64, Option<f64>), smoothtri_gpu::GpuError> {
    let mut best = f64::INFINITY;
    let mut best_kernel: Option<f64> = None;
    for _ in 0..repeat {
        let t = Instant::now();
        let kernel = call()?;
        best = best.min(t.elapsed().as_secs_f64());
        if let Some(k) = kernel {
            best_kernel = Some(best_kernel.map_or(k, |b| b.min(k)));
        }
    }
    let m = rays as f64 / 1e6;
    Ok((m / best, best_kernel.map(|k| m / k)))
}

/// How many times faster `flat` traces than `smooth`: by the kernels' GPU time where both have
/// it, else by the whole calls.
fn speedup(smooth: &Rate, flat: &Rate) -> String {
    match (smooth.kernel, flat.kernel) {
        (Some(sk), Some(fk)) => format!("{:.1}×", fk / sk),
        _ => format!("{:.1}× (whole call)", flat.call / smooth.call),
    }
}

/// `12.345` or `—` where the adapter has no timestamp queries.
fn opt(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| format!("{v:.1}"))
}

/// A smooth scene and the flat scenes it is compared with.
type Case = (&'static str, Mesh, LineField, Vec<(&'static str, Mesh)>);

fn main() -> Result<(), String> {
    let o = opts()?;
    let gpu: Arc<Gpu> = Gpu::new().map_err(|e| e.to_string())?;
    println!("adapter: {}", gpu.adapter_name());
    if gpu.is_software() {
        println!(
            "NOTE: software Vulkan (a CPU implementation): these figures are a correctness run, \
             not GPU timings"
        );
    }
    if o.runs(Table::Rays) {
        rays(&gpu, &o)?;
    }
    if o.runs(Table::Frames) {
        frames(&gpu, &o).map_err(|e| e.to_string())?;
    }
    if o.runs(Table::Animated) {
        animated(&gpu, &o).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The ray table's scenes.
fn ray_cases() -> Vec<Case> {
    vec![
        (
            "torus 8×8",
            torus(8, 8, 1.0, 0.4),
            LineField::Face,
            vec![
                ("flat torus 35×35 (equal error)", torus(35, 35, 1.0, 0.4)),
                ("flat torus 8×8 (same mesh)", torus(8, 8, 1.0, 0.4)),
            ],
        ),
        (
            "teapot",
            teapot(4),
            LineField::Face,
            vec![("flat teapot (same mesh)", teapot(4))],
        ),
        (
            "wavy torus, generated normals",
            wavy_torus(224),
            LineField::Face,
            vec![("flat (same mesh)", wavy_torus(224))],
        ),
        (
            "icosphere(3), normals tilted ≤ 20°, paper's field",
            tilted_normal_sphere(),
            LineField::Face,
            vec![("flat (same mesh)", tilted_normal_sphere())],
        ),
        (
            "icosphere(3), normals tilted ≤ 20°, shared field",
            tilted_normal_sphere(),
            LineField::Vertex,
            vec![("flat (same mesh)", tilted_normal_sphere())],
        ),
    ]
}

/// The ray table: closest hits of the camera's primary rays, each smooth scene beside its flat
/// baselines.
fn rays(gpu: &Arc<Gpu>, o: &Opts) -> Result<(), String> {
    println!(
        "camera {}x{}, closest hit of every primary ray, smooth N = {}, best of {} runs; \
         Mrays/s over the whole call (upload, dispatch, readback) and over the kernel's GPU time \
         alone (timestamp queries)",
        o.width, o.height, o.iterations, o.repeat
    );
    println!(
        "| scene | smooth triangles | smooth Mrays/s call / kernel | flat baseline | flat triangles | flat Mrays/s call / kernel | smooth / flat kernel time |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, mesh, field, flats) in ray_cases() {
        let rays: Vec<Ray> = Camera::for_mesh(&mesh, 30.0, 35.0, o.width, o.height).rays_f32();
        // As a renderer builds it: patches, cracks closed, BVH (`build_scene`).
        let owned = build_scene::<f32>(&mesh, field, false).map_err(|e| e.to_string())?;
        let b = owned.scene();
        let smooth = GpuScene::smooth(gpu, b.bvh()).map_err(|e| e.to_string())?;
        let s = rate(&smooth, o.iterations, &rays, o.repeat).map_err(|e| e.to_string())?;
        for (flat_name, flat_mesh) in flats {
            let flat_owned = build_scene::<f32>(&flat_mesh, LineField::Face, false)
                .map_err(|e| e.to_string())?;
            let fb = flat_owned.scene();
            let flat = GpuScene::flat(gpu, fb.bvh()).map_err(|e| e.to_string())?;
            let f = rate(&flat, 0, &rays, o.repeat).map_err(|e| e.to_string())?;
            let ratio = speedup(&s, &f);
            println!(
                "| {name} ({} hits) | {} | {:.1} / {} | {flat_name} ({} hits) | {} | {:.1} / {} | {ratio} |",
                s.hits,
                b.patches().len(),
                s.call,
                opt(s.kernel),
                f.hits,
                fb.patches().len(),
                f.call,
                opt(f.kernel),
            );
            // The fair baseline: flat triangles in a pipeline of their own (no smooth code).
            let tris: Vec<[glam::Vec3; 3]> = (0..flat_mesh.triangles.len())
                .map(|t| flat_mesh.triangle(t).0.map(|p| p.as_vec3()))
                .collect();
            let own = FlatScene::new(gpu, &tris).map_err(|e| e.to_string())?;
            let g = rate_own(&own, &rays, o.repeat).map_err(|e| e.to_string())?;
            let ratio = speedup(&s, &g);
            println!(
                "| {name} | | | {flat_name}, own flat pipeline ({} hits) | {} | {:.1} / {} | {ratio} |",
                g.hits,
                tris.len(),
                g.call,
                opt(g.kernel),
            );
        }
    }
    Ok(())
}

/// The frame table: `render_frame` at the camera of the first table, best of `--repeat` frames
/// after one that compiles the pipeline.
fn frames(gpu: &Arc<Gpu>, o: &Opts) -> Result<(), Box<dyn std::error::Error>> {
    println!();
    println!(
        "whole frames (view --gpu), {}x{}: camera rays, closest hit, shading normal, shadow ray, \
         shading; best of {} frames",
        o.width, o.height, o.repeat
    );
    println!("| scene | shading | N | ms / frame | frames/s | Mrays/s (primary + shadow) |");
    println!("|---|---|---|---|---|---|");
    let cases = [
        ("torus 8×8", torus(8, 8, 1.0, 0.4), true),
        (
            "flat torus 35×35 (equal error)",
            torus(35, 35, 1.0, 0.4),
            false,
        ),
        ("teapot", teapot(4), true),
        ("flat teapot (same mesh)", teapot(4), false),
    ];
    for (name, mesh, smooth) in cases {
        let owned = build_scene::<f32>(&mesh, LineField::Face, smooth)?;
        let b = owned.scene();
        let (bvh, seams) = (b.bvh(), b.seams());
        let (scene, shading, n) = if smooth {
            (
                GpuScene::smooth_seamless(gpu, bvh, seams)?,
                "seamless",
                o.iterations,
            )
        } else {
            (GpuScene::phong(gpu, bvh)?, "Phong", 0)
        };
        let view = frame_view(&mesh, o);
        let mut frame = GpuFrame::new(gpu, o.width, o.height)?;
        let mut best = scene.render_frame(n, &view, &mut frame)?;
        for _ in 0..o.repeat {
            let s = scene.render_frame(n, &view, &mut frame)?;
            if s.seconds < best.seconds {
                best = s;
            }
        }
        println!(
            "| {name} | {shading} | {n} | {:.2} | {:.1} | {:.1} |",
            best.seconds * 1e3,
            1.0 / best.seconds,
            best.rays as f64 / best.seconds / 1e6
        );
    }
    Ok(())
}

/// The twisting torus's grid side in the animated table: 2·224² = 100 352 triangles.
const TWIST_SIDE: usize = 224;
/// Frames timed in the animated table (a twentieth of a period apart), after one untimed.
const TWIST_FRAMES: usize = 12;

/// The animated table: the 100k twisting torus (`smoothtri_testkit::twist`) with seams, each
/// frame posed, updated on the CPU (`OwnedScene::update` on rayon's pool, every core), moved
/// into the GPU scene in place (`GpuScene::update`: records packed and written, no allocation)
/// and rendered as `view --gpu --animate` renders it (1080p with shadows). Medians over
/// [`TWIST_FRAMES`] frames; then the same on the device ([`device_update`]).
fn animated(gpu: &Arc<Gpu>, o: &Opts) -> Result<(), Box<dyn std::error::Error>> {
    let mut mesh = twisting_torus(TWIST_SIDE, 0.0);
    let flat = |v: &[DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
    let mut options = BuildOptions {
        field: LineField::Face,
        seams: true,
        observer: (),
        executor: RayonExecutor,
    };
    let mut cpu = mesh.build_scene::<f32, _, _>(&mut options)?;
    let s = cpu.scene();
    let mut scene = GpuScene::smooth_seamless(gpu, s.bvh(), s.seams())?;
    let view = frame_view(&mesh, o);
    let mut frame = GpuFrame::new(gpu, o.width, o.height)?;
    scene.render_frame(o.iterations, &view, &mut frame)?;
    let mut times: [Vec<f64>; 5] = Default::default();
    let mut refits = 0;
    for k in 0..=TWIST_FRAMES {
        let t = 0.05 * k as f64;
        let t0 = Instant::now();
        twist_pose(TWIST_SIDE, t, &mut mesh.positions, &mut mesh.normals);
        let (p, n) = (flat(&mesh.positions), flat(&mesh.normals));
        let t1 = Instant::now();
        let report = *cpu.update(Vertices::packed(&p), Vertices::packed(&n), &mut options)?;
        let t2 = Instant::now();
        let s = cpu.scene();
        scene.update(s.bvh(), Some(s.seams()))?;
        let t3 = Instant::now();
        let stats = scene.render_frame(o.iterations, &view, &mut frame)?;
        let t4 = Instant::now();
        if k == 0 {
            continue;
        }
        refits += usize::from(report.bvh_refitted);
        for (v, x) in times.iter_mut().zip([
            (t1 - t0).as_secs_f64(),
            (t2 - t1).as_secs_f64(),
            (t3 - t2).as_secs_f64(),
            stats.seconds,
            (t4 - t0).as_secs_f64(),
        ]) {
            v.push(x * 1e3);
        }
    }
    println!();
    println!(
        "animated (view --gpu --animate): the twisting torus, {} triangles, seams, {}x{}, N = {}; \
         CPU update on {} rayon threads, then GpuScene::update in place (4 buffer writes, \
         {:.1} MB, no dispatch); median of {} frames, {} refitted",
        mesh.triangles.len(),
        o.width,
        o.height,
        o.iterations,
        rayon::current_num_threads(),
        scene.memory_bytes() as f64 / 1e6,
        TWIST_FRAMES,
        refits
    );
    println!(
        "| pose (not the renderer's) ms | CPU update ms | GpuScene::update ms | frame ms | \
         whole frame ms | frames/s |"
    );
    println!("|---|---|---|---|---|---|");
    let [a, b, c, d, e] = &mut times;
    let whole = median(e);
    println!(
        "| {:.1} | {:.1} | {:.1} | {:.2} | {:.1} | {:.1} |",
        median(a),
        median(b),
        median(c),
        median(d),
        whole,
        1e3 / whole
    );
    device_update(gpu, o)
}

/// The animated table's second part: the same twisting torus, without and with seams,
/// updated on the device ([`GpuUpdate`]: patches, crack closure, the seam fits, boxes and the
/// tree's refit as compute passes from the vertex buffers) and rendered. The pose is made on
/// the CPU and written into the vertex buffers (a renderer's skinning pass would write them on
/// the device).
fn device_update(gpu: &Arc<Gpu>, o: &Opts) -> Result<(), Box<dyn std::error::Error>> {
    println!();
    println!(
        "animated, updated on the device (GpuUpdate): the twisting torus, {}x{}, N = {}; median \
         of {} frames",
        o.width, o.height, o.iterations, TWIST_FRAMES,
    );
    println!("| seams | update | write vertices ms | GpuUpdate::run ms | frame ms |");
    println!("|---|---|---|---|---|");
    for seams in [false, true] {
        device_update_row(gpu, o, seams)?;
    }
    Ok(())
}

/// One row of [`device_update`]'s table: the twisting torus without or with `seams`.
fn device_update_row(
    gpu: &Arc<Gpu>,
    o: &Opts,
    seams: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut mesh = twisting_torus(TWIST_SIDE, 0.0);
    let cpu = build_scene::<f32>(&mesh, LineField::Face, seams)?;
    let s = cpu.scene();
    let scene = if seams {
        GpuScene::smooth_seamless(gpu, s.bvh(), s.seams())?
    } else {
        GpuScene::smooth(gpu, s.bvh())?
    };
    let up = GpuUpdate::new(
        &scene,
        &s,
        &mesh.triangles,
        mesh.positions.len(),
        LineField::Face,
    )?;
    let view = frame_view(&mesh, o);
    let mut frame = GpuFrame::new(gpu, o.width, o.height)?;
    let mut times: [Vec<f64>; 3] = Default::default();
    for k in 0..=TWIST_FRAMES {
        twist_pose(
            TWIST_SIDE,
            0.05 * k as f64,
            &mut mesh.positions,
            &mut mesh.normals,
        );
        let t0 = Instant::now();
        up.write_vertices(&f32s(&mesh.positions), &f32s(&mesh.normals))?;
        let t1 = Instant::now();
        up.run(&scene)?;
        let t2 = Instant::now();
        let stats = scene.render_frame(o.iterations, &view, &mut frame)?;
        if k == 0 {
            continue;
        }
        for (v, x) in times.iter_mut().zip([
            (t1 - t0).as_secs_f64(),
            (t2 - t1).as_secs_f64(),
            stats.seconds,
        ]) {
            v.push(x * 1e3);
        }
    }
    let [a, b, c] = &mut times;
    println!(
        "| {} | {up:?} | {:.1} | {:.1} | {:.2} |",
        if seams { "yes" } else { "no" },
        median(a),
        median(b),
        median(c)
    );
    Ok(())
}

/// The view of `smoothtri view --gpu` framing `mesh` (the demo's `gpu::frame_view`): its
/// camera at the table's size, its light and the CPU renderer's f32 shadow offset.
fn frame_view(mesh: &Mesh, o: &Opts) -> FrameView {
    let cam = Camera::for_mesh(mesh, 30.0, 35.0, o.width, o.height);
    let basis = [cam.forward, cam.right, cam.up];
    let eps = mesh.diagonal() * SHADOW_OFFSET_F32;
    FrameView::pinhole(cam.eye, basis, cam.tan_half, cam.light_dir(), eps)
}

/// The coordinates of `v` in `f32`, three per point.
fn f32s(v: &[DVec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.as_vec3().to_array()).collect()
}

/// The median of `v` (sorted in place; the upper one of an even count).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
