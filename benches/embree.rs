//! smoothtri beside Embree on the same camera rays, one thread:
//! `cargo bench --features embree --bench embree` (needs Embree 3: `apt-get install
//! libembree-dev` on Debian and Ubuntu).
//!
//! The rays are those of `smoothtri render`'s default image: the built-in 8×8 torus (R = 1,
//! r = 0.4, 128 triangles) framed by `Camera::for_mesh` from the default view (azimuth 30°,
//! elevation 35°), 640×480 pixel-centre rays in f32. smoothtri traces its patches (f32, N = 4
//! refinement steps, closest hit through its BVH, hit normal included); Embree traces
//! the flat n×n torus of the same generator (n = 35 by default, the coarsest flat grid whose
//! error matches smoothtri's, `SMOOTHTRI_EMBREE_N` to change it) with `rtcIntersect1`, and
//! interpolates the Phong normal from the hit's barycentrics inside the timed loop. The table
//! reports the median of several timed passes after a warm-up pass, the memory, the maximum
//! and mean distance of the hit points to the true torus, and the hit count. A second Embree
//! row traces the flat grid of equal maximum error found at run time when it differs from n.
//!
//! A second table comes from a C program (`benches/embree/plugin_bench.c`, compiled here
//! against `capi/include` and the C API's static library): the same mesh and rays traced
//! by smoothtri's own BVH through the C API (`st_intersect1`), by Embree's BVH over the smooth
//! patches through the plug-in (`smoothtri_embree.h`), and by Embree over the mesh's own flat
//! triangles, in one process, interleaved rounds: the 8×8 torus and, when Debian's
//! `assimp-testmodels` is installed, a real scanned mesh with vertex normals (`WusonOBJ.obj`,
//! 3.7k triangles), each framed by the camera, N = 8.
//!
//! Between the two, smoothtri's BVH traces the flat n×n torus beside Embree;
//! `SMOOTHTRI_EMBREE_FLAT_ONLY=1` runs that table alone.
//!
//! smoothtri's kernel runs on the widest instruction set the CPU has (`smoothtri-isa`, also in
//! the C library); `SMOOTHTRI_ISA=sse2|avx2|avx512` picks one, for one row per instruction set.

use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use glam::{DVec3, Vec3};
use smoothtri::{LineField, Ray};
use smoothtri_io::load;
use smoothtri_isa::Dispatch;
use smoothtri_testkit::scenes::{builtin, torus, torus_distance};
use smoothtri_testkit::{Camera, Mesh, assimp_models, build_scene};

mod common;
#[path = "embree/ffi.rs"]
mod ffi;

use common::{FlatBvh, cpu_name, flat_torus_matching};
use ffi::embree_hit;

/// `smoothtri render`'s defaults: image size, view (azimuth, elevation), iterations.
const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
const VIEW: (f64, f64) = (30.0, 35.0);
/// Refinement steps: f32 hits reach the f32 rounding of the surface from N = 3 (README,
/// precision versus iterations); 4 leaves a margin.
const N_ITER: usize = 4;
/// Torus radii of the built-in scene.
const BIG_R: f64 = 1.0;
const SMALL_R: f64 = 0.4;

/// One row of the table.
struct Row {
    what: String,
    prims: usize,
    mrays: f64,
    kib: f64,
    max_dist: f64,
    mean_dist: f64,
    hits: usize,
    /// What the memory column counts.
    memory_note: String,
}

/// Median seconds of `reps` timed calls of `f` after one warm-up call.
fn median_secs(reps: usize, mut f: impl FnMut() -> usize) -> f64 {
    black_box(f());
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            black_box(f());
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// Max and mean distance of `points` to the true torus.
fn distances(points: &[DVec3]) -> (f64, f64) {
    let d: Vec<f64> = points
        .iter()
        .map(|&p| torus_distance(p, BIG_R, SMALL_R))
        .collect();
    let max = d.iter().copied().fold(0.0, f64::max);
    (max, d.iter().sum::<f64>() / d.len().max(1) as f64)
}

fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn smoothtri_row(mesh: &Mesh, rays: &[Ray], reps: usize) -> Row {
    let owned = build_scene::<f32>(mesh, LineField::Face, false).expect("the torus builds");
    let scene = owned.scene();
    let report = scene.report();
    assert_eq!(
        report.patches, report.triangles,
        "no torus triangle is rejected"
    );
    let bvh = scene.bvh();
    let trace = || {
        let mut hits = 0;
        for r in rays {
            if let Some(h) = bvh.closest_hit_isa(r, 0.0, f32::MAX, N_ITER) {
                black_box(h.normal);
                hits += 1;
            }
        }
        hits
    };
    let secs = median_secs(reps, trace);
    let points: Vec<DVec3> = rays
        .iter()
        .filter_map(|r| bvh.closest_hit_isa(r, 0.0, f32::MAX, N_ITER))
        .map(|h| h.point.as_dvec3())
        .collect();
    let (max_dist, mean_dist) = distances(&points);
    let bytes = size_of_val(scene.patches()) + bvh.memory_bytes();
    Row {
        what: format!("smoothtri 8×8 torus patches, f32, N = {N_ITER}"),
        prims: scene.patches().len(),
        mrays: rays.len() as f64 / secs / 1e6,
        kib: bytes as f64 / 1024.0,
        max_dist,
        mean_dist,
        hits: points.len(),
        memory_note: format!(
            "smoothtri: the patches ({} B) + the BVH's nodes and order ({} B)",
            size_of_val(scene.patches()),
            bvh.memory_bytes()
        ),
    }
}

/// smoothtri's BVH over the flat `n`×`n` torus, as an Embree user geometry would use it
/// (`common::FlatBvh`): the BVH built over the flat triangles' boxes, each leaf running
/// Möller–Trumbore on the triangles of an array indexed by the patch index
/// (`Bvh::closest_with`), and the Phong normal interpolated once, for the closest hit, as the
/// Embree row does.
/// Returns the row and Embree's rate on the same triangles and rays, timed in interleaved
/// rounds (this machine's speed drifts between passes).
fn our_flat_row(n: usize, rays: &[Ray], reps: usize) -> (Row, f64) {
    let mesh = torus(n, n, BIG_R, SMALL_R);
    let flat = FlatBvh::new(&mesh);
    let bvh = flat.bvh();
    let tris = &flat.triangles;
    let normals: Vec<[Vec3; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| mesh.normals[i as usize].as_vec3()))
        .collect();
    let hit = |r: &Ray| {
        let h = flat.closest_hit(&bvh, r)?;
        let [n0, n1, n2] = normals[h.patch as usize];
        let n = (n0 * (1.0 - h.w1 - h.w2) + n1 * h.w1 + n2 * h.w2).normalize();
        Some(smoothtri::Hit {
            normal: n,
            point: r.origin + r.dir * h.t,
            ..h
        })
    };
    let ours = || {
        let mut hits = 0;
        for r in rays {
            if let Some(h) = hit(r) {
                black_box(h.normal);
                hits += 1;
            }
        }
        hits
    };
    // Embree on the same triangles (the vertices as the generator gives them).
    let vertex_normals: Vec<Vec3> = mesh.normals.iter().map(|p| p.as_vec3()).collect();
    let device = ffi::Device::new(c"threads=1");
    let escene = ffi::Scene::of_mesh(&device, &mesh);
    let mut ctx = ffi::RTCIntersectContext::new();
    let mut theirs = || {
        let mut hits = 0;
        for r in rays {
            let h = embree_hit(&escene, &mut ctx, &mesh.triangles, &vertex_normals, r);
            if let Some((t, nrm)) = h {
                black_box((t, nrm));
                hits += 1;
            }
        }
        hits
    };
    let (mut a, mut b) = (Vec::new(), Vec::new());
    black_box((ours(), theirs()));
    for _ in 0..reps {
        a.push(median_secs(1, ours));
        b.push(median_secs(1, &mut theirs));
    }
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (secs, embree_secs) = (a[a.len() / 2], b[b.len() / 2]);
    let points: Vec<DVec3> = rays
        .iter()
        .filter_map(|r| hit(r).map(|h| h.point.as_dvec3()))
        .collect();
    let (max_dist, mean_dist) = distances(&points);
    let row = Row {
        what: format!(
            "smoothtri's BVH, flat {n}×{n}, Phong normals, Bvh::closest_with + moller_trumbore"
        ),
        prims: tris.len(),
        mrays: rays.len() as f64 / secs / 1e6,
        kib: (size_of_val(tris.as_slice()) + size_of_val(normals.as_slice()) + bvh.memory_bytes())
            as f64
            / 1024.0,
        max_dist,
        mean_dist,
        hits: points.len(),
        memory_note: format!(
            "smoothtri's BVH over the flat {n}×{n} triangles: the triangles ({} B) and their \
             vertex normals ({} B) + the BVH's nodes and order ({} B)",
            size_of_val(tris.as_slice()),
            size_of_val(normals.as_slice()),
            bvh.memory_bytes()
        ),
    };
    (row, rays.len() as f64 / embree_secs / 1e6)
}

/// Our BVH on Embree's task (the same flat triangles, the same rays): the table.
fn flat_table(n: usize, rays: &[Ray], embree_reps: usize) {
    let (ours_flat, embree_same) = our_flat_row(n, rays, embree_reps);
    println!(
        "\n## smoothtri's BVH on flat triangles beside Embree's (the flat {n}×{n} torus, the same \
         rays, one thread, median of {embree_reps} interleaved rounds)\n\n| what | Mrays/s | \
         ÷ Embree |\n|---|---|---|"
    );
    println!(
        "| {} | {:.3} | {:.2}× |",
        ours_flat.what,
        ours_flat.mrays,
        embree_same / ours_flat.mrays
    );
    println!("| Embree flat {n}×{n}, Phong normals, rtcIntersect1 | {embree_same:.3} | 1.00× |");
}

/// The Embree row of the flat `n`×`n` torus; `equal` marks the grid of equal max error.
fn embree_row(n: usize, equal: bool, rays: &[Ray], reps: usize) -> Row {
    let mesh = torus(n, n, BIG_R, SMALL_R);
    let normals: Vec<Vec3> = mesh.normals.iter().map(|p| p.as_vec3()).collect();
    let indices = mesh.triangles.clone();
    let device = ffi::Device::new(c"threads=1");
    let scene = ffi::Scene::of_mesh(&device, &mesh);
    let (net, peak) = (device.net_bytes(), device.peak_bytes());
    let mut ctx = ffi::RTCIntersectContext::new();
    let secs = median_secs(reps, || {
        let mut hits = 0;
        for r in rays {
            if let Some((t, nrm)) = embree_hit(&scene, &mut ctx, &indices, &normals, r) {
                black_box((t, nrm));
                hits += 1;
            }
        }
        hits
    });
    let points: Vec<DVec3> = rays
        .iter()
        .filter_map(|r| {
            embree_hit(&scene, &mut ctx, &indices, &normals, r)
                .map(|(t, _)| (r.origin + r.dir * t).as_dvec3())
        })
        .collect();
    let (max_dist, mean_dist) = distances(&points);
    // The monitor counts Embree's own copies of the vertex and index buffers and its BVH; the
    // normals live in the application's array.
    let bytes = net.max(0) as usize + size_of_val(normals.as_slice());
    let memory_note = format!(
        "Embree {n}×{n}: the net bytes Embree's memory monitor reports after `rtcCommitScene` \
         ({net} B: its vertex and index buffers, {} B, and the BVH; the peak during the build \
         was {peak} B) + the vertex normals ({} B)",
        // Embree's vertex buffer: one `[f32; 3]` per vertex.
        mesh.positions.len() * size_of::<[f32; 3]>() + size_of_val(indices.as_slice()),
        size_of_val(normals.as_slice())
    );
    Row {
        what: format!(
            "Embree flat {n}×{n}{}, Phong normals, rtcIntersect1",
            if equal { " (equal max error)" } else { "" }
        ),
        prims: indices.len(),
        mrays: rays.len() as f64 / secs / 1e6,
        kib: bytes as f64 / 1024.0,
        max_dist,
        mean_dist,
        hits: points.len(),
        memory_note,
    }
}

/// The C API's static library that cargo built for this bench (`deps/libsmoothtri_capi-*.a`
/// beside the bench binary; the newest when several builds left one).
fn capi_static_lib() -> PathBuf {
    let exe = std::env::current_exe().expect("the bench's path");
    let deps = exe.parent().expect("the deps folder");
    std::fs::read_dir(deps)
        .expect("the deps folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            name.starts_with("libsmoothtri_capi") && name.ends_with(".a")
        })
        .max_by_key(|p| p.metadata().and_then(|m| m.modified()).ok())
        .expect("cargo built the C API's static library (dev-dependency smoothtri-capi)")
}

/// Compiles `benches/embree/plugin_bench.c` (optimised, as a renderer would) against the C API.
fn plugin_program() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugin_bench");
    let status = Command::new("cc")
        .args([
            "-std=c99",
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-I",
        ])
        .arg(root.join("capi/include"))
        .arg(root.join("benches/embree/plugin_bench.c"))
        .arg("-o")
        .arg(&exe)
        .arg(capi_static_lib())
        .args([
            "-lembree3",
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
        ])
        .status()
        .expect("cc runs");
    assert!(status.success(), "plugin_bench.c did not compile");
    exe
}

/// The C program's three rows for `mesh` and `rays`: (what, Mrays/s, hits).
fn plugin_rows(exe: &Path, mesh: &Mesh, rays: &[Ray], rounds: u32) -> Vec<(String, f64, u64)> {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugin_bench.bin");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).expect("input file"));
    let head = [
        mesh.positions.len() as u32,
        mesh.triangles.len() as u32,
        rays.len() as u32,
        rounds,
        8,
    ];
    let mut put = |x: &[u8]| f.write_all(x).expect("write");
    head.iter().for_each(|x| put(&x.to_le_bytes()));
    for v in mesh.positions.iter().chain(&mesh.normals) {
        v.as_vec3()
            .to_array()
            .iter()
            .for_each(|x| put(&x.to_le_bytes()));
    }
    mesh.triangles
        .iter()
        .flatten()
        .for_each(|x| put(&x.to_le_bytes()));
    for r in rays {
        r.origin
            .to_array()
            .iter()
            .chain(&r.dir.to_array())
            .for_each(|x| put(&x.to_le_bytes()));
    }
    drop(f);
    let out = Command::new(exe)
        .arg(&path)
        .output()
        .expect("plugin_bench runs");
    assert!(
        out.status.success(),
        "plugin_bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_prefix("row "))
        .map(|l| {
            let f: Vec<&str> = l.split('|').collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap_or(0.0),
                f[2].parse().unwrap_or(0),
            )
        })
        .collect()
}

/// Camera rays framing `mesh` from `render`'s default view.
fn camera_rays(mesh: &Mesh) -> Vec<Ray> {
    Camera::for_mesh(mesh, VIEW.0, VIEW.1, WIDTH, HEIGHT).rays_f32()
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` does not: skip its debug-build run.
    if !std::env::args().any(|a| a == "--bench") {
        eprintln!("run with `cargo bench --features embree --bench embree`");
        return;
    }
    let mesh = builtin("torus").expect("the built-in torus");
    let rays = camera_rays(&mesh);
    let smooth_reps = env_usize("SMOOTHTRI_EMBREE_REPS", 5).max(1);
    let n = env_usize("SMOOTHTRI_EMBREE_N", 35).max(3);

    let embree_reps = 4 * smooth_reps + 1;
    if std::env::var_os("SMOOTHTRI_EMBREE_FLAT_ONLY").is_some() {
        flat_table(n, &rays, embree_reps);
        return;
    }

    let smooth = smoothtri_row(&mesh, &rays, smooth_reps);
    // The coarsest flat grid whose triangles stay within smoothtri's max distance (sampled on
    // each triangle): 35 for the kernel of the issue.
    let (n_eq, flat_err) = flat_torus_matching(smooth.max_dist);
    let mut rows = vec![smooth, embree_row(n, n == n_eq, &rays, embree_reps)];
    if n_eq != n {
        rows.push(embree_row(n_eq, true, &rays, embree_reps));
    }

    println!(
        "\n## smoothtri vs Embree 3 ({}; smoothtri's kernel: {}; one thread, {} camera rays \
         {WIDTH}×{HEIGHT}, median of {smooth_reps} passes for smoothtri, {embree_reps} for \
         Embree)\n",
        cpu_name(),
        smoothtri_isa::kernels().isa(),
        rays.len(),
    );
    println!("| what | triangles/patches | Mrays/s | memory KiB | max dist | mean dist | hits |");
    println!("|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {:.3} | {:.1} | {:.2e} | {:.2e} | {} |",
            r.what, r.prims, r.mrays, r.kib, r.max_dist, r.mean_dist, r.hits
        );
    }
    println!(
        "\nEqual max error: the flat {n_eq}×{n_eq} grid is the coarsest within smoothtri's max \
         distance ({flat_err:.2e} sampled over its triangles).\n\nMemory:"
    );
    for r in &rows {
        println!("- {}", r.memory_note);
    }
    let s = &rows[0];
    for r in &rows[1..] {
        println!(
            "\n{} ÷ smoothtri: {:.1}× the ray rate, {:.1}× the memory, {:.2}× the max distance",
            r.what,
            r.mrays / s.mrays,
            r.kib / s.kib,
            r.max_dist / s.max_dist
        );
    }
    flat_table(n, &rays, embree_reps);

    // The plug-in table: the same mesh three ways, from C.
    let exe = plugin_program();
    let mut meshes = vec![("torus 8×8 (128 triangles)".to_string(), mesh.clone())];
    if let Ok(Some(dir)) = assimp_models() {
        let path = dir.join("OBJ/WusonOBJ.obj");
        if let Ok(loaded) = load(&path.to_string_lossy()) {
            let t = loaded.mesh.triangles.len();
            meshes.push((format!("WusonOBJ.obj ({t} triangles)"), loaded.mesh));
        }
    }
    println!(
        "\n## The C API and the Embree plug-in ({}; one thread, {WIDTH}×{HEIGHT} camera rays \
         framing each mesh, f32, N = 8, median of {embree_reps} interleaved rounds)\n",
        cpu_name()
    );
    println!("| mesh | what | Mrays/s | hits | ÷ Embree flat |");
    println!("|---|---|---|---|---|");
    for (name, m) in &meshes {
        let rows = plugin_rows(&exe, m, &camera_rays(m), embree_reps as u32);
        let flat = rows.last().map_or(1.0, |r| r.1);
        for (what, mrays, hits) in &rows {
            println!(
                "| {name} | {what} | {mrays:.3} | {hits} | {:.1}× |",
                flat / mrays
            );
        }
    }
}
