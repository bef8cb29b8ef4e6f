//! `GpuScene::update`: a scene moved in place to an updated CPU scene traces exactly as a fresh
//! upload of that CPU scene (the same bytes in its buffers), for every kind of scene; another
//! mesh is a typed error that leaves the scene as it was.
//! `cargo test -p smoothtri-gpu --test update`.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::{BuildOptions, Hit, LineField, OwnedScene, Scene, Vertices};
use smoothtri_gpu::Gpu;
use smoothtri_gpu::{GpuError, GpuScene};
use smoothtri_testkit::twist::{twist_pose, twisting_torus};
use smoothtri_testkit::{Camera, Mesh, RayonExecutor};
use std::sync::Arc;

/// The twisting torus's grid side: 2·SIDE² triangles.
const SIDE: usize = 16;
/// The budget traced.
const N: usize = 4;

fn packed(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn options() -> BuildOptions<(), RayonExecutor> {
    BuildOptions {
        field: LineField::Face,
        seams: true,
        observer: (),
        executor: RayonExecutor,
    }
}

fn build(m: &Mesh) -> OwnedScene<f32> {
    let (p, n) = (packed(&m.positions), packed(&m.normals));
    OwnedScene::<f32>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        &mut options(),
    )
    .expect("the twisting torus builds")
}

/// `m` posed at time `t` of the twist.
fn posed(m: &Mesh, t: f64) -> Mesh {
    let mut out = m.clone();
    twist_pose(SIDE, t, &mut out.positions, &mut out.normals);
    out
}

/// The four kinds of scene the demo uploads, by name.
const KINDS: [&str; 4] = ["smooth", "seamless", "flat", "phong"];

fn upload(gpu: &Arc<Gpu>, kind: &str, s: &Scene<'_, f32>) -> GpuScene {
    let bvh = s.bvh();
    match kind {
        "smooth" => GpuScene::smooth(gpu, bvh),
        "seamless" => GpuScene::smooth_seamless(gpu, bvh, s.seams()),
        "flat" => GpuScene::flat(gpu, bvh),
        _ => GpuScene::phong(gpu, bvh),
    }
    .expect("upload")
}

/// Closest hits with shading normals of a 64×48 camera's rays that frame the torus.
fn trace(gs: &GpuScene, m: &Mesh) -> Vec<Option<(Hit<f32>, Vec3)>> {
    let rays = Camera::for_mesh(m, 0.6, 0.5, 64, 48).rays_f32();
    let mut out = vec![None; rays.len()];
    gs.closest_shaded(&rays, 0.0, f32::INFINITY, N, &mut out)
        .expect("trace");
    out
}

/// Compares hits bit for bit (`t`, `t_error`, point, normal, patch, shading normal).
fn bits(h: &[Option<(Hit<f32>, Vec3)>]) -> Vec<Option<Vec<u32>>> {
    h.iter()
        .map(|o| {
            o.map(|(h, s)| {
                let mut v = vec![h.t.to_bits(), h.t_error.to_bits(), h.patch];
                v.extend([h.w1.to_bits(), h.w2.to_bits(), u32::from(h.front_face)]);
                for x in [h.point, h.normal, s] {
                    v.extend(x.to_array().map(f32::to_bits));
                }
                v
            })
        })
        .collect()
}

#[test]
fn updated_scenes_trace_as_fresh_uploads() {
    let Some(gpu) = gpu() else { return };
    let rest = twisting_torus(SIDE, 0.0);
    for kind in KINDS {
        let mut cpu = build(&rest);
        let mut gs = upload(&gpu, kind, &cpu.scene());
        let before = bits(&trace(&gs, &rest));
        for t in [0.15, 0.35] {
            let m = posed(&rest, t);
            let (p, n) = (packed(&m.positions), packed(&m.normals));
            cpu.update(Vertices::packed(&p), Vertices::packed(&n), &mut options())
                .expect("update");
            let s = cpu.scene();
            let seams = (kind == "seamless").then(|| s.seams());
            gs.update(s.bvh(), seams).expect("GPU update");
            let fresh = upload(&gpu, kind, &s);
            let (a, b) = (bits(&trace(&gs, &m)), bits(&trace(&fresh, &m)));
            let hits = a.iter().flatten().count();
            assert!(hits > 200, "{kind} t = {t}: {hits} hits frame the torus");
            assert_eq!(a, b, "{kind} t = {t}: updated ≠ fresh upload");
            assert_eq!(gs.memory_bytes(), fresh.memory_bytes(), "{kind}: bytes");
            assert_ne!(a, before, "{kind} t = {t}: the update moved nothing");
        }
        // A fresh CPU build of the last pose (its own tree, perhaps of another node count).
        let m = posed(&rest, 0.35);
        let rebuilt = build(&m);
        let s = rebuilt.scene();
        gs.update(s.bvh(), (kind == "seamless").then(|| s.seams()))
            .expect("GPU update from a fresh build");
        assert_eq!(
            bits(&trace(&gs, &m)),
            bits(&trace(&upload(&gpu, kind, &s), &m)),
            "{kind}: updated from a fresh build ≠ its upload"
        );
    }
}

#[test]
fn another_mesh_is_a_typed_error_and_changes_nothing() {
    let Some(gpu) = gpu() else { return };
    let rest = twisting_torus(SIDE, 0.0);
    let cpu = build(&rest);
    let s = cpu.scene();
    let mut gs = upload(&gpu, "seamless", &s);
    let before = bits(&trace(&gs, &rest));
    let other = build(&twisting_torus(SIDE - 2, 0.0));
    let o = other.scene();
    assert_eq!(
        gs.update(o.bvh(), Some(o.seams())),
        Err(GpuError::SceneMismatch {
            what: "patch",
            scene: s.patches().len(),
            given: o.patches().len(),
        })
    );
    assert_eq!(
        gs.update(s.bvh(), None),
        Err(GpuError::SceneMismatch {
            what: "seam",
            scene: s.patches().len(),
            given: 0,
        })
    );
    assert_eq!(
        gs.update(s.bvh(), Some(&s.seams()[1..])),
        Err(GpuError::SceneMismatch {
            what: "seam",
            scene: s.patches().len(),
            given: s.patches().len() - 1,
        })
    );
    assert_eq!(
        bits(&trace(&gs, &rest)),
        before,
        "a refused update changed the scene"
    );
}
