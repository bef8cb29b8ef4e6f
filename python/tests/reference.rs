//! The Rust side of the Python package's tests: writes what the Rust API answers on the
//! built-in scenes, as `.npy` files the Python tests (`python/tests/test_reference.py`)
//! compare with, bit for bit.
//!
//! For each built-in scene (`smoothtri_testkit::scenes::builtin`): the mesh, random rays, and
//! for each precision, line field and seam choice of [`CONFIGS`] at each budget of
//! [`BUDGETS`] the core's `Scene::closest_hit` and `Scene::any_hit` (budget `n`); random surface
//! points through `Patch::point_normal` and `Seam::correct`; the build report. And the demo's
//! precision study on the torus (`smoothtri_demo::commands::precision::sweep`) with its
//! camera rays.
//!
//! The files go to `$SMOOTHTRI_PY_REFERENCE` when set, else to `python-reference/` in Cargo's
//! temporary folder for tests (`CARGO_TARGET_TMPDIR`, under the build folder); `done` is
//! written last.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use smoothtri::{BuildOptions, Float, LineField, OwnedScene, Ray};
use smoothtri_testkit::scenes::{SCENE_NAMES, builtin};
use smoothtri_testkit::{Camera, Mesh, RayonExecutor, Rng};

/// The budgets of the hit references.
const BUDGETS: [usize; 3] = [0, 4, 8];
/// Rays per scene.
const RAYS: usize = 500;
/// Surface points per scene.
const POINTS: usize = 300;
/// `(precision, field, seams)`.
const CONFIGS: [(&str, &str, bool); 4] = [
    ("f32", "face", true),
    ("f64", "face", true),
    ("f32", "vertex", false),
    ("f64", "vertex", true),
];
/// The precision study's camera.
const STUDY_SIZE: (u32, u32) = (48, 36);

fn out_dir() -> PathBuf {
    match std::env::var_os("SMOOTHTRI_PY_REFERENCE") {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_TARGET_TMPDIR")).join("python-reference"),
    }
}

/// One field of a structured `.npy` record: name, numpy type string, components, bytes.
struct Field {
    name: &'static str,
    descr: &'static str,
    count: usize,
}

impl Field {
    const fn new(name: &'static str, descr: &'static str, count: usize) -> Self {
        Field { name, descr, count }
    }
}

/// An `.npy` file (version 1.0): the header of `descr` and `shape` (as numpy writes them in
/// it), then the bytes `data`.
fn write_npy(path: &Path, descr: &str, shape: &str, data: &[u8]) {
    let mut header = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': {shape}, }}");
    // Magic (6) + version (2) + length (2) + header + '\n', padded to a multiple of 64.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    std::fs::write(path, bytes).unwrap();
}

/// A structured array as `.npy`: `rows` records of `fields`, the bytes of each record in
/// `data`.
fn write_records(path: &Path, fields: &[Field], rows: usize, data: &[u8]) {
    let mut descr = String::from("[");
    for f in fields {
        if f.count == 1 {
            let _ = write!(descr, "('{}', '{}'), ", f.name, f.descr);
        } else {
            let _ = write!(descr, "('{}', '{}', ({},)), ", f.name, f.descr, f.count);
        }
    }
    descr.push(']');
    write_npy(path, &descr, &format!("({rows},)"), data);
}

/// A plain `(rows, cols)` array as `.npy`.
fn write_matrix<T: Copy>(
    path: &Path,
    descr: &'static str,
    cols: usize,
    values: &[T],
    bytes: fn(T) -> Vec<u8>,
) {
    let rows = values.len() / cols;
    let data: Vec<u8> = values.iter().flat_map(|&v| bytes(v)).collect();
    write_npy(
        path,
        &format!("'{descr}'"),
        &format!("({rows}, {cols})"),
        &data,
    );
}

fn f64s(v: f64) -> Vec<u8> {
    v.to_le_bytes().to_vec()
}

fn vecs(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Random rays at the mesh: from points on a sphere of twice the mesh's bounding radius
/// towards random points of its bounding box grown by half (many hits, misses, grazes).
fn rays(mesh: &Mesh, rng: &mut Rng) -> Vec<(DVec3, DVec3)> {
    let (lo, hi) = mesh.bounds();
    let c = (lo + hi) * 0.5;
    let r = (hi - lo).length() * 0.5;
    let (lo, hi) = (c + (lo - c) * 1.5, c + (hi - c) * 1.5);
    (0..RAYS)
        .map(|_| {
            let o = c + rng.unit() * (2.0 * r);
            let target = DVec3::new(
                rng.range(lo.x, hi.x),
                rng.range(lo.y, hi.y),
                rng.range(lo.z, hi.z),
            );
            // Directions of assorted lengths: t is in units of the direction.
            (o, (target - o) * rng.range(0.25, 4.0))
        })
        .collect()
}

/// The element bytes of a float in `F`.
trait Bytes: Float {
    const DESCR: &'static str;
    fn bytes(self) -> Vec<u8>;
    fn arr(v: Self::Vec3) -> [Self; 3];
}
impl Bytes for f32 {
    const DESCR: &'static str = "<f4";
    fn bytes(self) -> Vec<u8> {
        self.to_le_bytes().to_vec()
    }
    fn arr(v: glam::Vec3) -> [f32; 3] {
        v.to_array()
    }
}
impl Bytes for f64 {
    const DESCR: &'static str = "<f8";
    fn bytes(self) -> Vec<u8> {
        self.to_le_bytes().to_vec()
    }
    fn arr(v: DVec3) -> [f64; 3] {
        v.to_array()
    }
}

fn vec_bytes<F: Bytes>(v: F::Vec3) -> Vec<u8> {
    F::arr(v).iter().flat_map(|x| x.bytes()).collect()
}

/// The hits of `rays` at budget `N` through the core's scene, and whether each is occluded.
fn hits<F: Bytes, const N: usize>(scene: &OwnedScene<F>, rays: &[(DVec3, DVec3)], path: &Path) {
    let s = scene.scene();
    let fields = [
        Field::new("hit", "|b1", 1),
        Field::new("t", F::DESCR, 1),
        Field::new("t_error", F::DESCR, 1),
        Field::new("point", F::DESCR, 3),
        Field::new("normal", F::DESCR, 3),
        Field::new("shading_normal", F::DESCR, 3),
        Field::new("triangle", "<i8", 1),
        Field::new("barycentric", F::DESCR, 2),
        Field::new("occluded", "|b1", 1),
    ];
    let mut data = Vec::new();
    for &(o, d) in rays {
        let ray = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
        let inf = F::from_f64(f64::INFINITY);
        let h = s.closest_hit(&ray, F::ZERO, inf, N);
        let occluded = s.any_hit(&ray, F::ZERO, inf, N);
        data.push(u8::from(h.is_some()));
        match h {
            Some(h) => {
                data.extend(h.hit.t.bytes());
                data.extend(h.hit.t_error.bytes());
                data.extend(vec_bytes::<F>(h.hit.point));
                data.extend(vec_bytes::<F>(h.hit.normal));
                data.extend(vec_bytes::<F>(h.shading_normal));
                data.extend(i64::from(h.triangle).to_le_bytes());
                data.extend(h.hit.w1.bytes());
                data.extend(h.hit.w2.bytes());
            }
            None => {
                let z = F::ZERO.bytes();
                data.extend(F::from_f64(f64::INFINITY).bytes());
                for _ in 0..10 {
                    data.extend(&z);
                }
                data.extend((-1i64).to_le_bytes());
                data.extend(&z);
                data.extend(&z);
            }
        }
        data.push(u8::from(occluded));
    }
    write_records(path, &fields, rays.len(), &data);
}

/// Random surface points of accepted triangles, and the core's point, normal and shading
/// normal there.
fn surface<F: Bytes>(scene: &OwnedScene<F>, rng: &mut Rng, path: &Path) {
    let s = scene.scene();
    let fields = [
        Field::new("triangle", "<i8", 1),
        Field::new("w", "<f8", 2),
        Field::new("point", F::DESCR, 3),
        Field::new("normal", F::DESCR, 3),
        Field::new("shading_normal", F::DESCR, 3),
    ];
    let ids = s.triangle_ids();
    let mut data = Vec::new();
    for _ in 0..POINTS {
        let p = (rng.f() * ids.len() as f64) as usize % ids.len();
        let (w1, w2) = (rng.f(), rng.f());
        // Some points outside the triangle (w1 + w2 > 1): the evaluation projects them.
        let (w1, w2) = if rng.f() < 0.8 && w1 + w2 > 1.0 {
            (1.0 - w1, 1.0 - w2)
        } else {
            (w1, w2)
        };
        let patch = &s.patches()[p];
        let (a, b) = (F::from_f64(w1), F::from_f64(w2));
        let (x, n) = patch.point_normal(a, b);
        let sn = match s.seams().get(p) {
            Some(seam) => seam.correct(patch, a, b, n),
            None => n,
        };
        data.extend(i64::from(ids[p]).to_le_bytes());
        data.extend(w1.to_le_bytes());
        data.extend(w2.to_le_bytes());
        data.extend(vec_bytes::<F>(x));
        data.extend(vec_bytes::<F>(n));
        data.extend(vec_bytes::<F>(sn));
    }
    write_records(path, &fields, POINTS, &data);
}

/// The report's counts, `key=value` per line.
fn report<F: Float>(scene: &OwnedScene<F>, path: &Path) {
    let s = scene.scene();
    let r = s.report();
    let mut t = String::new();
    let _ = writeln!(t, "triangles={}", r.triangles);
    let _ = writeln!(t, "patches={}", r.patches);
    let _ = writeln!(t, "remedied={}", r.remedied);
    let _ = writeln!(t, "shared_edges={}", r.cracks.shared_edges);
    let _ = writeln!(t, "open_edges={}", r.cracks.open_edges);
    let _ = writeln!(t, "widest_gap={:?}", r.cracks.widest_gap);
    let _ = writeln!(t, "bvh_nodes={}", r.bvh_nodes);
    let _ = writeln!(t, "memory_bytes={}", s.memory_bytes());
    std::fs::write(path, t).unwrap();
}

#[allow(clippy::too_many_arguments)]
fn config<F: Bytes>(
    mesh: &Mesh,
    name: &str,
    tag: &str,
    field: LineField,
    seams: bool,
    rays: &[(DVec3, DVec3)],
    dir: &Path,
    seed: u64,
) {
    let mut options = BuildOptions {
        field,
        seams,
        ..BuildOptions::default()
    }
    .with_executor(RayonExecutor);
    let scene: OwnedScene<F> = mesh.build_scene(&mut options).unwrap();
    hits::<F, 0>(&scene, rays, &dir.join(format!("{name}-{tag}-N0.npy")));
    hits::<F, 4>(&scene, rays, &dir.join(format!("{name}-{tag}-N4.npy")));
    hits::<F, 8>(&scene, rays, &dir.join(format!("{name}-{tag}-N8.npy")));
    surface(
        &scene,
        &mut Rng(seed),
        &dir.join(format!("{name}-{tag}-eval.npy")),
    );
    report(&scene, &dir.join(format!("{name}-{tag}-report.txt")));
}

#[test]
fn write_reference() {
    assert_eq!(
        BUDGETS,
        [0, 4, 8],
        "the budgets are spelled out in `config`"
    );
    let dir = out_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let _ = std::fs::remove_file(dir.join("done"));
    let mut rng = Rng(0x5EED_0050);
    for name in SCENE_NAMES {
        let mesh = builtin(name).unwrap();
        let u32s = |v: u32| v.to_le_bytes().to_vec();
        write_matrix(
            &dir.join(format!("{name}-vertices.npy")),
            "<f8",
            3,
            &vecs(&mesh.positions),
            f64s,
        );
        write_matrix(
            &dir.join(format!("{name}-normals.npy")),
            "<f8",
            3,
            &vecs(&mesh.normals),
            f64s,
        );
        let faces: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        write_matrix(
            &dir.join(format!("{name}-faces.npy")),
            "<u4",
            3,
            &faces,
            u32s,
        );
        let rays = rays(&mesh, &mut rng);
        let o: Vec<DVec3> = rays.iter().map(|r| r.0).collect();
        let d: Vec<DVec3> = rays.iter().map(|r| r.1).collect();
        write_matrix(
            &dir.join(format!("{name}-origins.npy")),
            "<f8",
            3,
            &vecs(&o),
            f64s,
        );
        write_matrix(
            &dir.join(format!("{name}-directions.npy")),
            "<f8",
            3,
            &vecs(&d),
            f64s,
        );
        for (k, (precision, field, seams)) in CONFIGS.into_iter().enumerate() {
            let tag = format!(
                "{precision}-{field}-{}",
                if seams { "seams" } else { "noseams" }
            );
            let f = if field == "vertex" {
                LineField::Vertex
            } else {
                LineField::Face
            };
            let seed = 0xE7A1 + k as u64;
            match precision {
                "f32" => config::<f32>(&mesh, name, &tag, f, seams, &rays, &dir, seed),
                _ => config::<f64>(&mesh, name, &tag, f, seams, &rays, &dir, seed),
            }
        }
    }
    // The demo's precision study on the torus, with its camera rays.
    let mesh = builtin("torus").unwrap();
    let (w, h) = STUDY_SIZE;
    let cam = Camera::for_mesh(&mesh, 30.0, 35.0, w, h);
    let (mut o, mut d) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let (a, b) = cam.pixel_ray(x, y);
            o.push(a);
            d.push(b);
        }
    }
    write_matrix(&dir.join("study-origins.npy"), "<f8", 3, &vecs(&o), f64s);
    write_matrix(&dir.join("study-directions.npy"), "<f8", 3, &vecs(&d), f64s);
    let study = smoothtri_demo::commands::precision::sweep(&mesh, &cam).unwrap();
    std::fs::write(dir.join("study.csv"), study.csv()).unwrap();
    std::fs::write(dir.join("study.txt"), study.table()).unwrap();
    std::fs::write(dir.join("done"), format!("{}\n", dir.display())).unwrap();
}
