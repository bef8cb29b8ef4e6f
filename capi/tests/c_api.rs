//! C programs a user would write (`tests/c/`), compiled with `cc -std=c99 -Wall -Wextra
//! -Werror -pedantic` against the header and the static library, each run twice: under
//! valgrind's memcheck (the README example, the error test and one scene test; the others
//! natively, valgrind being too slow for them) and compiled with AddressSanitizer and
//! UndefinedBehaviorSanitizer; both runs must succeed and print the same. A missing valgrind
//! or sanitizer runtime skips its run, unless `SMOOTHTRI_REQUIRE_VALGRIND` or
//! `SMOOTHTRI_REQUIRE_SANITIZERS` is set (CI sets both): then it fails.
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
use smoothtri::{BuildOptions, BuildReport, Float, LineField, OwnedScene, Ray, SceneHit, Vertices};

/// The C program `tests/c/{name}.c`, compiled once per run of this file for each build (plain
/// for native and valgrind runs, with the sanitizers): the tests that run one program share it
/// (compiling it for each, in parallel, would replace the file under a test that is running it).
fn c_program(name: &str, mode: common::Mode) -> PathBuf {
    static BUILT: std::sync::Mutex<Vec<(String, bool, PathBuf)>> =
        std::sync::Mutex::new(Vec::new());
    let sanitized = mode == common::Mode::Sanitizers;
    let mut built = BUILT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, _, exe)) = built.iter().find(|(n, s, _)| n == name && *s == sanitized) {
        return exe.clone();
    }
    let exe = common::build_program(&format!("c/{name}.c"), mode, &[]);
    built.push((name.to_string(), sanitized, exe.clone()));
    exe
}

/// Runs `tests/c/{name}.c` in every mode ([`common::modes`]: under valgrind when `memcheck`,
/// else natively, and built with AddressSanitizer and UndefinedBehaviorSanitizer); every run
/// must succeed and print the same. Returns what they printed.
fn run_c(name: &str, args: &[&str], memcheck: bool) -> String {
    let mut first: Option<String> = None;
    for mode in common::modes(memcheck) {
        let out = common::run_in(mode, &c_program(name, mode), args);
        match &first {
            None => first = Some(out),
            Some(f) => assert_eq!(*f, out, "{name} printed otherwise in {mode:?}"),
        }
    }
    first.unwrap()
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
    let out = run_c("readme_example", &[], true);
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
    // Natively and with the sanitizers: under valgrind its 200 builds and updates take minutes.
    let out = run_c("update_test", &[], false);
    assert!(out.contains("all checks passed"), "{out}");
}

#[test]
fn bad_input_gives_the_documented_status() {
    let out = run_c("errors_test", &[], true);
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

/// The scene of `indices` over packed `positions` and `normals` (x, y, z each), built with
/// `options` as the C program built it, and its build report.
fn build_packed<F: Float>(
    positions: &[F],
    normals: &[F],
    indices: &[[u32; 3]],
    mut options: BuildOptions,
) -> (OwnedScene<F>, BuildReport) {
    let s = OwnedScene::<F>::build(
        Vertices::packed(positions),
        Vertices::packed(normals),
        indices,
        &mut options,
    )
    .unwrap();
    let report = *s.scene().report();
    (s, report)
}

fn check_scene_test(flags: u32, iterations: u32, rays: usize, memcheck: bool) {
    let args = [flags, iterations, rays as u32].map(|x| x.to_string());
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run_c("scene_test", &args, memcheck);
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
                    let (s, r) = build_packed(&p, &n, &mesh.indices, options);
                    (scene32, scene64) = (Some(s), None);
                    r
                } else {
                    let (s, r) =
                        build_packed(&mesh.positions, &mesh.normals, &mesh.indices, options);
                    (scene32, scene64) = (None, Some(s));
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
    s.scene().closest_hit(r, 0.0, f32::INFINITY, n as usize)
}

fn closest64(s: &OwnedScene<f64>, r: &Ray<f64>, n: u32) -> Option<SceneHit<f64>> {
    s.scene().closest_hit(r, 0.0, f64::INFINITY, n as usize)
}

#[test]
fn st_get_isa_names_the_kernels_smoothtri_isa_an_environment_override_chooses() {
    // `SMOOTHTRI_ISA`, when set (CI sets each instruction set the machine has), names the
    // kernels the queries run; unset, the widest the CPU has.
    let want = smoothtri_isa::Kernels::from_env().expect("SMOOTHTRI_ISA names a supported set");
    // SAFETY: `st_get_isa` returns a static, NUL-terminated string.
    let got = unsafe { std::ffi::CStr::from_ptr(smoothtri_capi::st_get_isa()) };
    assert_eq!(got, want.isa().c_name());
    assert_eq!(smoothtri_isa::kernels(), want);
}

/// One test per list of `check_scene_test` cases (`flags, iterations, rays, memcheck`): the C
/// program's hits equal the Rust API's for each.
macro_rules! scene_tests {
    ($($(#[doc = $doc:literal])* $name:ident: [$($case:expr),+ $(,)?];)+) => {$(
        $(#[doc = $doc])*
        #[test]
        fn $name() {
            for (flags, iterations, rays, memcheck) in [$($case),+] {
                check_scene_test(flags, iterations, rays, memcheck);
            }
        }
    )+};
}

scene_tests! {
    c_hits_equal_the_rust_api_with_seams: [(1, 8, 8, true), (1, 8, 192, false)];
    c_hits_equal_the_rust_api_without_seams_on_the_shared_field: [(2, 16, 192, false)];
    c_hits_equal_the_rust_api_bracketing_only: [(0, 0, 192, false)];
    /// Budgets the C API took no instantiation of before `N` was a run-time value, and the
    /// largest.
    c_hits_equal_the_rust_api_at_any_budget: [(1, 3, 64, false), (0, 64, 64, false)];
}

/// The memory tools fail a run on the errors they exist for (so the runs above prove
/// something): a program that leaks a block, and one that reads past a heap block, each fail
/// under valgrind (`--error-exitcode`, definite leaks counted as errors) and with the
/// sanitizers; a clean program passes both.
#[test]
fn valgrind_and_the_sanitizers_fail_a_leak_and_an_overflow() {
    let dir = common::scratch("memory-tools");
    // `keep` is volatile so the compiler keeps every allocation; the overflow's index comes
    // from `argc` (1) so no warning sees it at compile time.
    let cases = [
        (
            "clean",
            "keep = malloc(16); keep[15] = 1; free((void *)keep);",
            true,
        ),
        ("leak", "keep = malloc(16); keep[0] = 1; keep = 0;", false),
        (
            "overflow",
            "keep = malloc(16); keep[15 + argc] = 1; free((void *)keep);",
            false,
        ),
    ];
    for (name, body, clean) in cases {
        let src = dir.join(format!("{name}.c"));
        std::fs::write(
            &src,
            format!(
                "#include <stdlib.h>\nstatic char *volatile keep;\nint main(int argc, char \
                 **argv) {{ (void)argc; (void)argv; {body} return 0; }}\n"
            ),
        )
        .unwrap();
        for mode in common::modes(true) {
            if mode == common::Mode::Native {
                continue;
            }
            let exe = dir.join(format!("{name}-{mode:?}"));
            common::compile_for(
                mode,
                std::slice::from_ref(&src),
                &exe,
                common::Lang::C99,
                &[],
            );
            let result = common::try_run_in(mode, &exe, &[]);
            assert_eq!(result.is_ok(), clean, "{name} in {mode:?}: {result:?}");
        }
    }
}
