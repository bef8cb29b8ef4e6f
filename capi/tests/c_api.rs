//! C programs a user would write (`tests/c/`), compiled with `cc -std=c99 -Wall -Wextra
//! -Werror -pedantic` against the header and the static library and run under valgrind when
//! it is installed (the error test and one scene test; the others run natively).
//! `update_test.c` moves an updatable scene every frame and checks each frame alone. `scene_test.c` prints every mesh, ray and hit; each hit is compared here,
//! bit for bit, with the Rust API's on the same mesh and ray.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

mod common;

use std::path::PathBuf;

use glam::{DVec3, Vec3};
use smoothtri::{BuildOptions, LineField, OwnedScene, Ray, SceneHit, Vertices};

/// The C program `tests/c/{name}.c`, compiled once per run of this file: the tests that run
/// one program share it (compiling it for each, in parallel, would replace the file under a
/// test that is running it).
fn c_program(name: &str) -> PathBuf {
    static BUILT: std::sync::Mutex<Vec<(String, PathBuf)>> = std::sync::Mutex::new(Vec::new());
    let mut built = BUILT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, exe)) = built.iter().find(|(n, _)| n == name) {
        return exe.clone();
    }
    let exe = compile_program(name);
    built.push((name.to_string(), exe.clone()));
    exe
}

fn compile_program(name: &str) -> PathBuf {
    let dir = common::scratch(name);
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/c/{name}.c"));
    let exe = dir.join(name);
    let lib = common::static_lib();
    let mut extra = vec![lib.to_str().unwrap()];
    extra.extend_from_slice(common::NATIVE_LIBS);
    common::compile_c(&[src], &exe, common::Lang::C99, &extra);
    exe
}

#[test]
fn readme_example_is_this_file_and_runs() {
    let src = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c/readme_example.c"),
    )
    .unwrap();
    let readme =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md"))
            .unwrap();
    assert!(
        readme.contains(&format!("```c\n{src}```")),
        "README.md's C example differs from capi/tests/c/readme_example.c"
    );
    let exe = c_program("readme_example");
    let out = common::run(&exe, &[], false);
    // t = 3 − √(1 − 0.3² − 0.2²) on the unit sphere; the normal is radial.
    let t = 3.0 - (1.0f64 - 0.09 - 0.04).sqrt();
    assert!(out.starts_with(&format!("t = {t:.6}")), "{out}");
    assert!(
        out.contains("triangle 0, shading normal (0.300, 0.200, 0.933)"),
        "{out}"
    );
}

#[test]
fn an_animated_scene_updates_every_frame() {
    let exe = c_program("update_test");
    // Natively: under valgrind the debug library's 200 builds and updates take minutes.
    let out = common::run(&exe, &[], false);
    assert!(out.contains("all checks passed"), "{out}");
}

#[test]
fn bad_input_gives_the_documented_status() {
    let exe = c_program("errors_test");
    let out = common::run(&exe, &[], true);
    assert!(out.contains("all checks passed"), "{out}");
}

/// One mesh as the C program printed it.
#[derive(Default)]
struct Mesh {
    positions: Vec<f64>,
    normals: Vec<f64>,
    indices: Vec<[u32; 3]>,
}

fn hex64(s: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(s, 16).unwrap())
}

fn hex32(s: &str) -> f32 {
    f32::from_bits(u32::from_str_radix(s, 16).unwrap())
}

/// The hit fields the C program printed, as bits: t, u, v, ng, ns, t_error.
fn printed(h: &SceneHit<f32>) -> Vec<u64> {
    let v = |v: Vec3| [v.x, v.y, v.z].map(|x| u64::from(x.to_bits()));
    let mut out = vec![h.hit.t, h.hit.w1, h.hit.w2]
        .into_iter()
        .map(|x| u64::from(x.to_bits()))
        .collect::<Vec<_>>();
    out.extend(v(h.hit.normal));
    out.extend(v(h.shading_normal));
    out.push(u64::from(h.hit.t_error.to_bits()));
    out
}

fn printed64(h: &SceneHit<f64>) -> Vec<u64> {
    let v = |v: DVec3| [v.x, v.y, v.z].map(f64::to_bits);
    let mut out = vec![h.hit.t.to_bits(), h.hit.w1.to_bits(), h.hit.w2.to_bits()];
    out.extend(v(h.hit.normal));
    out.extend(v(h.shading_normal));
    out.push(h.hit.t_error.to_bits());
    out
}

fn check_scene_test(flags: u32, iterations: u32, rays: usize, memcheck: bool) {
    let exe = c_program("scene_test");
    let args = [flags, iterations, rays as u32].map(|x| x.to_string());
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = common::run(&exe, &args, memcheck);
    let options = BuildOptions {
        seams: flags & 1 != 0,
        field: if flags & 2 != 0 {
            LineField::Vertex
        } else {
            LineField::Face
        },
        ..BuildOptions::default()
    };
    let mut mesh = Mesh::default();
    let mut scene32: Option<OwnedScene<f32>> = None;
    let mut scene64: Option<OwnedScene<f64>> = None;
    let mut ray32: Option<Ray<f32>> = None;
    let mut ray64: Option<Ray<f64>> = None;
    let (mut compared, mut hits) = (0, 0);
    for line in out.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w[0] {
            "mesh" => mesh = Mesh::default(),
            "v" => {
                let x: Vec<f64> = w[1..7].iter().map(|s| hex64(s)).collect();
                mesh.positions.extend_from_slice(&x[..3]);
                mesh.normals.extend_from_slice(&x[3..]);
            }
            "f" => mesh
                .indices
                .push([w[1], w[2], w[3]].map(|s| s.parse().unwrap())),
            "build" => {
                let (patches, rejected, remedied, seams): (usize, usize, usize, usize) = (
                    w[3].parse().unwrap(),
                    w[4].parse().unwrap(),
                    w[5].parse().unwrap(),
                    w[6].parse().unwrap(),
                );
                let report = if w[2] == "f32" {
                    // The C program rounded its double buffer to float; so does this.
                    let p: Vec<f32> = mesh.positions.iter().map(|&x| x as f32).collect();
                    let n: Vec<f32> = mesh.normals.iter().map(|&x| x as f32).collect();
                    let s = OwnedScene::<f32>::build(
                        Vertices::packed(&p),
                        Vertices::packed(&n),
                        &mesh.indices,
                        &mut { options },
                    )
                    .unwrap();
                    let r = *s.scene().report();
                    scene32 = Some(s);
                    scene64 = None;
                    r
                } else {
                    let s = OwnedScene::<f64>::build(
                        Vertices::packed(&mesh.positions),
                        Vertices::packed(&mesh.normals),
                        &mesh.indices,
                        &mut { options },
                    )
                    .unwrap();
                    let r = *s.scene().report();
                    scene64 = Some(s);
                    scene32 = None;
                    r
                };
                assert_eq!(
                    (patches, rejected, remedied, seams),
                    (
                        report.patches,
                        report.triangles - report.patches,
                        report.remedied,
                        report.seam_edges.unwrap_or(0)
                    ),
                    "{line}"
                );
            }
            "r" if scene32.is_some() => {
                let x: Vec<f32> = w[1..7].iter().map(|s| hex32(s)).collect();
                ray32 = Some(Ray::new(
                    Vec3::new(x[0], x[1], x[2]),
                    Vec3::new(x[3], x[4], x[5]),
                ));
            }
            "r" => {
                let x: Vec<f64> = w[1..7].iter().map(|s| hex64(s)).collect();
                ray64 = Some(Ray::new(
                    DVec3::new(x[0], x[1], x[2]),
                    DVec3::new(x[3], x[4], x[5]),
                ));
            }
            "hit" | "miss" => {
                let c_hit: Option<(u32, Vec<u64>)> = (w[0] == "hit").then(|| {
                    (
                        w[1].parse().unwrap(),
                        w[2..]
                            .iter()
                            .map(|s| u64::from_str_radix(s, 16).unwrap())
                            .collect(),
                    )
                });
                let rust_hit = if let Some(s) = &scene32 {
                    closest32(s, ray32.as_ref().unwrap(), iterations)
                        .map(|h| (h.triangle, printed(&h)))
                } else {
                    let s = scene64.as_ref().unwrap();
                    closest64(s, ray64.as_ref().unwrap(), iterations)
                        .map(|h| (h.triangle, printed64(&h)))
                };
                assert_eq!(c_hit, rust_hit, "C and Rust differ after line `{line}`");
                compared += 1;
                hits += usize::from(c_hit.is_some());
            }
            _ => panic!("unexpected line `{line}`"),
        }
    }
    // Two meshes, two precisions; most rays hit.
    assert_eq!(compared, 4 * rays);
    assert!(hits > compared / 2, "{hits} hits of {compared}");
}

fn closest32(s: &OwnedScene<f32>, r: &Ray<f32>, n: u32) -> Option<SceneHit<f32>> {
    let s = s.scene();
    match n {
        0 => s.closest_hit::<0>(r, 0.0, f32::INFINITY),
        8 => s.closest_hit::<8>(r, 0.0, f32::INFINITY),
        16 => s.closest_hit::<16>(r, 0.0, f32::INFINITY),
        _ => unimplemented!(),
    }
}

fn closest64(s: &OwnedScene<f64>, r: &Ray<f64>, n: u32) -> Option<SceneHit<f64>> {
    let s = s.scene();
    match n {
        0 => s.closest_hit::<0>(r, 0.0, f64::INFINITY),
        8 => s.closest_hit::<8>(r, 0.0, f64::INFINITY),
        16 => s.closest_hit::<16>(r, 0.0, f64::INFINITY),
        _ => unimplemented!(),
    }
}

#[test]
fn c_hits_equal_the_rust_api_with_seams() {
    check_scene_test(1, 8, 8, true);
    check_scene_test(1, 8, 192, false);
}

#[test]
fn c_hits_equal_the_rust_api_without_seams_on_the_shared_field() {
    check_scene_test(2, 16, 192, false);
}

#[test]
fn c_hits_equal_the_rust_api_bracketing_only() {
    check_scene_test(0, 0, 192, false);
}
