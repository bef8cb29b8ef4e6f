//! A built scene is immutable and its queries are thread-safe: four threads tracing the same
//! `const st_scene*` at once get, ray for ray, what one thread gets. Through the C functions
//! themselves (the rlib), as a C program would call them; and from C with POSIX threads
//! (`tests/c/threads_test.c`), the one allowed pattern of concurrent use around an update:
//! threads trace, are joined, the scene is updated with no tracer running, and the threads
//! trace again, each frame equal to a fresh build of its pose (under valgrind and with the
//! sanitizers, as `tests/c_api.rs` runs its programs).
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

mod common;

use smoothtri_capi::*;

/// A 16×8 torus (R = 1, r = 0.4), packed positions and normals.
fn torus() -> (Vec<f32>, Vec<f32>, Vec<u32>) {
    let (nu, nv) = (16u32, 8u32);
    let (mut p, mut n, mut idx) = (vec![], vec![], vec![]);
    for i in 0..nu {
        for j in 0..nv {
            let u = std::f32::consts::TAU * i as f32 / nu as f32;
            let w = std::f32::consts::TAU * j as f32 / nv as f32;
            n.extend([w.cos() * u.cos(), w.cos() * u.sin(), w.sin()]);
            p.extend([
                (1.0 + 0.4 * w.cos()) * u.cos(),
                (1.0 + 0.4 * w.cos()) * u.sin(),
                0.4 * w.sin(),
            ]);
        }
    }
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (i * nv + j, ((i + 1) % nu) * nv + j);
            let (c, d) = (((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv);
            idx.extend([a, b, c, a, c, d]);
        }
    }
    (p, n, idx)
}

fn ray(k: usize) -> st_rayhit {
    let a = k as f32 * 0.37;
    let mut rh = st_rayhit::default();
    rh.ray.org_x = 3.0 * a.cos();
    rh.ray.org_y = 3.0 * a.sin();
    rh.ray.org_z = 1.0 + 0.5 * (k as f32 * 0.11).sin();
    rh.ray.dir_x = -rh.ray.org_x + 0.3 * (k as f32 * 0.7).sin();
    rh.ray.dir_y = -rh.ray.org_y;
    rh.ray.dir_z = -rh.ray.org_z;
    rh.ray.tfar = f32::INFINITY;
    rh
}

#[test]
fn queries_from_many_threads_equal_one_thread() {
    let (p, n, idx) = torus();
    let (vc, tc) = (p.len() / 3, idx.len() / 3);
    let mut bytes = 0usize;
    // SAFETY: `bytes` is writable.
    let status = unsafe { st_scene_required_bytes(vc, tc, ST_BUILD_SEAMS, &mut bytes) };
    assert_eq!(status, ST_OK);
    let mut memory = vec![0u8; bytes];
    let mut scene: *mut st_scene = std::ptr::null_mut();
    // SAFETY: the buffers hold `vc` packed vertices and `tc` triangles; `memory` holds `bytes`.
    let status = unsafe {
        st_scene_build(
            memory.as_mut_ptr().cast(),
            bytes,
            p.as_ptr(),
            0,
            n.as_ptr(),
            0,
            vc,
            idx.as_ptr(),
            tc,
            ST_BUILD_SEAMS,
            8,
            &mut scene,
        )
    };
    assert_eq!(status, ST_OK);
    // The scene's address, shared by the threads as C would share a `const st_scene*`.
    let shared = scene as usize;
    let trace = |k: usize| {
        let mut rh = ray(k);
        // SAFETY: the scene lives in `memory`, which outlives the threads; `rh` is exclusive.
        unsafe { st_intersect1(shared as *const st_scene, &mut rh) };
        rh
    };
    let alone: Vec<st_rayhit> = (0..2000).map(trace).collect();
    assert!(
        alone
            .iter()
            .filter(|h| h.hit.prim_id != ST_INVALID_ID)
            .count()
            > 500
    );
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..4)
            .map(|w| {
                s.spawn(move || {
                    (w..2000)
                        .step_by(4)
                        .map(|k| (k, trace(k)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for worker in workers {
            for (k, rh) in worker.join().unwrap() {
                assert_eq!(rh, alone[k], "ray {k}");
            }
        }
    });
    drop(memory);
}

/// `tests/c/threads_test.c` under valgrind and with the sanitizers (each when available, see
/// `common::modes`): four POSIX threads trace one updatable scene at once, are joined, the
/// scene is updated (a small wobble that refits the tree, then a scramble that rebuilds it),
/// and they trace again; every thread's answers equal one thread's byte for byte, and each
/// frame equals a fresh build of its pose (patch by patch bit for bit; the scene's hits as
/// `st_scene_update` documents).
#[test]
fn c_threads_trace_then_an_update_between_frames() {
    for mode in common::modes(true) {
        let exe = common::build_program("c/threads_test.c", mode, &["-pthread"]);
        // 16 rays under valgrind (about 50 times slower), 256 otherwise.
        let rays = if mode == common::Mode::Valgrind {
            "16"
        } else {
            "256"
        };
        let out = common::run_in(mode, &exe, &[rays]);
        assert!(out.contains("all checks passed"), "{mode:?}: {out}");
        for (f, what) in ["built", "refitted", "rebuilt"].into_iter().enumerate() {
            assert!(
                out.contains(&format!("frame {f}: {what}")),
                "{mode:?}: {out}"
            );
        }
    }
}
