//! Adversarial input: degenerate rays, an empty scene, corrupt trees (node, leaf and patch
//! indices outside the storage, cycles, a tree deeper than the stack), non-finite scene data.
//! Every case gives misses or a typed error, and the device keeps working afterwards (no
//! device loss): each test ends by tracing a sphere correctly.

mod common;
use common::*;
use glam::Vec3;
use smoothtri::BVH_EMPTY_SLOT;
use smoothtri::{Patch, PatchData, Ray};
use smoothtri_gpu::{
    FrameView, Gpu, GpuError, GpuFrame, GpuNode, GpuScene, MAX_ITERATIONS, SceneKind,
};
use smoothtri_testkit::patches32;
use smoothtri_testkit::scenes::icosphere;
use std::sync::Arc;

/// A correct trace after the adversarial ones: the device is alive.
fn still_works(gpu: &Arc<Gpu>) {
    let patches = patches32(&icosphere(1, 1.0));
    let tree = Tree::new(&patches);
    let scene = GpuScene::smooth(gpu, &tree.bvh(&patches)).expect("upload");
    let rays = [Ray::new(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::new(0.0, 0.0, -1.0),
    )];
    let mut hits = [None];
    scene
        .closest_hit(&rays, 0.0, f32::INFINITY, 4, &mut hits)
        .expect("trace");
    let h = hits[0].expect("hit");
    assert!(
        (h.t - 4.0).abs() < 1e-5 && (h.normal - Vec3::Z).length() < 1e-5,
        "{h:?}"
    );
}

fn unit_patch() -> Patch {
    let p = [Vec3::X, Vec3::Y, Vec3::Z];
    Patch::new(p, p).expect("patch")
}

#[test]
fn degenerate_rays_are_misses() {
    let Some(gpu) = gpu() else { return };
    let patches = [unit_patch()];
    let tree = Tree::new(&patches);
    let bvh = tree.bvh(&patches);
    let scene = GpuScene::smooth(&gpu, &bvh).expect("upload");
    let o = Vec3::splat(2.0);
    let toward = -Vec3::ONE;
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let cases: Vec<(Ray, f32, f32)> = vec![
        (Ray::new(o, Vec3::ZERO), 0.0, inf),
        (Ray::new(o, Vec3::NAN), 0.0, inf),
        (Ray::new(Vec3::new(nan, 0.0, 0.0), toward), 0.0, inf),
        (Ray::new(o, Vec3::new(inf, -1.0, -1.0)), 0.0, inf),
        (Ray::new(Vec3::splat(inf), toward), 0.0, inf),
        (Ray::new(o, toward), 5.0, 1.0),
        (Ray::new(o, toward), nan, 1.0),
        (Ray::new(o, toward), 0.0, nan),
        (Ray::new(o, -toward), 0.0, inf),
        (Ray::new(o, toward), -inf, -1.0),
    ];
    for (ray, a, b) in cases {
        let mut hit = [None];
        scene.closest_hit(&[ray], a, b, 4, &mut hit).expect("trace");
        assert!(hit[0].is_none(), "{ray:?} [{a}, {b}]: {:?}", hit[0]);
        assert!(bvh.closest_hit(&ray, a, b, 4).is_none());
        let mut occ = [true];
        scene.any_hit(&[ray], a, b, 4, &mut occ).expect("trace");
        assert!(!occ[0], "{ray:?}");
    }
    // Extreme but finite rays: finite answers or misses.
    let extreme = [
        Ray::new(Vec3::splat(1e30), Vec3::splat(-1.0)),
        Ray::new(Vec3::splat(2.0), Vec3::splat(-1e-30)),
        Ray::new(Vec3::splat(2.0), Vec3::new(-1e30, -1e30, -1e30)),
        Ray::new(Vec3::splat(-3e38), Vec3::splat(3e38)),
        Ray::new(Vec3::splat(2.0), Vec3::new(-1.0, -1.0, -1e-40)),
    ];
    let mut hits = vec![None; extreme.len()];
    scene
        .closest_hit(&extreme, 0.0, f32::INFINITY, 4, &mut hits)
        .expect("trace");
    for h in hits.iter().flatten() {
        assert!(
            h.t.is_finite() && h.point.is_finite() && h.normal.is_finite(),
            "{h:?}"
        );
    }
    // Slices of different lengths, budgets out of range: typed errors.
    let mut two = [None, None];
    assert_eq!(
        scene.closest_hit(&[Ray::new(o, toward)], 0.0, inf, 4, &mut two),
        Err(GpuError::LengthMismatch { rays: 1, out: 2 })
    );
    let mut one = [None];
    assert_eq!(
        scene.closest_hit(
            &[Ray::new(o, toward)],
            0.0,
            inf,
            MAX_ITERATIONS + 1,
            &mut one
        ),
        Err(GpuError::Iterations(MAX_ITERATIONS + 1))
    );
    // No rays: nothing to do.
    scene
        .closest_hit(&[], 0.0, inf, 4, &mut [])
        .expect("empty batch");
    still_works(&gpu);
}

#[test]
fn empty_scene_gives_misses() {
    let Some(gpu) = gpu() else { return };
    for kind in [SceneKind::Smooth, SceneKind::Flat] {
        let scene = GpuScene::from_parts(&gpu, kind, &[], &[], &[]).expect("upload");
        let rays = [Ray::new(Vec3::splat(2.0), -Vec3::ONE); 3];
        let mut hits = [None; 3];
        scene
            .closest_hit(&rays, 0.0, f32::INFINITY, 4, &mut hits)
            .expect("trace");
        assert!(hits.iter().all(Option::is_none));
    }
    still_works(&gpu);
}

/// A node of four slots `(child, count)` sharing the box `[lo, hi]` (slots with
/// `BVH_EMPTY_SLOT` are unused).
fn node(lo: Vec3, hi: Vec3, slots: [(u32, u32); 4]) -> GpuNode {
    GpuNode {
        lo: [0, 1, 2].map(|a| [lo[a]; 4]),
        hi: [0, 1, 2].map(|a| [hi[a]; 4]),
        child: slots.map(|s| s.0),
        count: slots.map(|s| s.1),
    }
}

const NONE: (u32, u32) = (BVH_EMPTY_SLOT, 0);

/// A node whose only slot is the leaf `order[first..first + count]`.
fn leaf(lo: Vec3, hi: Vec3, first: u32, count: u32) -> GpuNode {
    node(lo, hi, [(first, count), NONE, NONE, NONE])
}

/// A node whose only slot is the child node `first`.
fn inner(lo: Vec3, hi: Vec3, first: u32) -> GpuNode {
    leaf(lo, hi, first, 0)
}

/// Traces one ray through the unit patch's box with the given tree.
fn trace(
    gpu: &Arc<Gpu>,
    data: &[PatchData<f32>],
    nodes: &[GpuNode],
    order: &[u32],
) -> Result<Vec<Option<smoothtri::Hit>>, GpuError> {
    let scene = GpuScene::from_parts(gpu, SceneKind::Smooth, data, nodes, order)?;
    let rays = [Ray::new(Vec3::splat(2.0), -Vec3::ONE); 100];
    let mut hits = vec![None; rays.len()];
    scene.closest_hit(&rays, 0.0, f32::INFINITY, 4, &mut hits)?;
    Ok(hits)
}

#[test]
fn corrupt_trees_are_typed_errors() {
    let Some(gpu) = gpu() else { return };
    let p = unit_patch();
    let data = [p.data()];
    let (lo, hi) = (p.bounds().min(), p.bounds().max());
    // A correct one-leaf tree hits.
    let ok = trace(&gpu, &data, &[leaf(lo, hi, 0, 1)], &[0]).expect("valid tree");
    assert!(ok.iter().all(Option::is_some));
    let cases: Vec<(&str, Vec<GpuNode>, Vec<u32>, GpuError)> = vec![
        (
            "child index outside the nodes",
            vec![inner(lo, hi, 1000)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "last node as first child",
            vec![inner(lo, hi, 0)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "u32::MAX - 1 child (u32::MAX marks an unused slot)",
            vec![inner(lo, hi, u32::MAX - 1)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "leaf range outside the order",
            vec![leaf(lo, hi, 0, 5)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "leaf start outside the order",
            vec![leaf(lo, hi, 7, 1)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "leaf range overflowing u32",
            vec![leaf(lo, hi, u32::MAX - 1, 2)],
            vec![0],
            GpuError::CorruptTree,
        ),
        (
            "patch index outside the patches",
            vec![leaf(lo, hi, 0, 1)],
            vec![9],
            GpuError::CorruptTree,
        ),
        (
            "a cycle (a node is its own child)",
            vec![inner(lo, hi, 0), leaf(lo, hi, 0, 1)],
            vec![0],
            GpuError::CorruptTree,
        ),
    ];
    for (what, nodes, order, want) in cases {
        assert_eq!(trace(&gpu, &data, &nodes, &order), Err(want), "{what}");
    }
    // Deeper than the stack: every level leaves three leaves pending (all boxes equal, so the
    // last slot, the next node, is visited first).
    let depth = 70u32;
    let mut nodes: Vec<GpuNode> = (0..depth)
        .map(|k| node(lo, hi, [(0, 1), (0, 1), (0, 1), (k + 1, 0)]))
        .collect();
    nodes.push(leaf(lo, hi, 0, 1));
    assert_eq!(
        trace(&gpu, &data, &nodes, &[0]),
        Err(GpuError::StackOverflow),
        "a chain of {depth} levels"
    );
    // Non-finite scene data: answers (of any kind) or typed errors, never a lost device.
    let mut bad = p.data();
    bad.sigma = [f32::NAN, f32::INFINITY];
    bad.k[1] = [f32::NAN, -f32::INFINITY];
    bad.axes[0] = [f32::NAN; 3];
    let nan = Vec3::NAN;
    for nodes in [
        vec![leaf(lo, hi, 0, 1)],
        vec![leaf(nan, nan, 0, 1)],
        vec![inner(nan, hi, 0)],
    ] {
        if let Ok(hits) = trace(&gpu, &[bad], &nodes, &[0]) {
            assert_eq!(hits.len(), 100);
        }
    }
    still_works(&gpu);
}

/// More rays than one dispatch takes (2^20): the chunks line up with the rays.
#[test]
fn batches_larger_than_a_dispatch() {
    let Some(gpu) = gpu() else { return };
    let patches = [unit_patch()];
    let tree = Tree::new(&patches);
    let scene = GpuScene::smooth(&gpu, &tree.bvh(&patches)).expect("upload");
    let n = (1 << 20) + 1000;
    let toward = Ray::new(Vec3::splat(2.0), -Vec3::ONE);
    let away = Ray::new(Vec3::splat(2.0), Vec3::ONE);
    let rays: Vec<Ray> = (0..n)
        .map(|i| if i % 997 == 0 { toward } else { away })
        .collect();
    let mut occluded = vec![false; n];
    scene
        .any_hit(&rays, 0.0, f32::INFINITY, 1, &mut occluded)
        .expect("trace");
    for (i, &o) in occluded.iter().enumerate() {
        assert_eq!(o, i % 997 == 0, "ray {i}");
    }
}

#[test]
fn timed_trace_returns_the_same_hits_and_a_kernel_time() {
    let Some(gpu) = gpu() else { return };
    let patches = patches32(&icosphere(2, 1.0));
    let tree = Tree::new(&patches);
    let scene = GpuScene::smooth(&gpu, &tree.bvh(&patches)).expect("upload");
    let rays: Vec<Ray> = (0..2000)
        .map(|i| {
            let a = i as f32 * 0.01;
            Ray::new(
                Vec3::new(a.cos() * 3.0, a.sin() * 3.0, 0.3),
                Vec3::new(-a.cos(), -a.sin(), -0.1),
            )
        })
        .collect();
    let mut plain = vec![None; rays.len()];
    let mut timed = vec![None; rays.len()];
    scene
        .closest_hit(&rays, 0.0, f32::INFINITY, 4, &mut plain)
        .expect("trace");
    let seconds = scene
        .closest_hit_timed(&rays, 0.0, f32::INFINITY, 4, &mut timed)
        .expect("timed trace");
    assert_eq!(plain, timed);
    assert!(plain.iter().flatten().count() == rays.len());
    if let Some(s) = seconds {
        assert!(s.is_finite() && s >= 0.0, "kernel time {s}");
    }
    still_works(&gpu);
}

/// A frame looking at the unit patch down the diagonal.
fn frame_view() -> FrameView {
    let forward = -Vec3::ONE.normalize();
    let right = forward.cross(Vec3::Z).normalize();
    FrameView {
        eye: Vec3::splat(2.0),
        forward,
        right,
        up: right.cross(forward),
        tan_half: 0.3,
        light: Vec3::ONE.normalize(),
        eps: 1e-4,
        heat: None,
    }
}

/// Frames: a zero or oversized frame is `TooLarge`, a scene with the wrong number of seams is
/// `LengthMismatch`, an empty scene shows only the background, a corrupt tree is a typed error
/// from the frame pass as from the batch queries, and a frame of another device is refused.
#[test]
fn frames_fail_with_typed_errors() {
    let Some(gpu) = gpu() else { return };
    assert!(matches!(
        GpuFrame::new(&gpu, 0, 10),
        Err(GpuError::TooLarge { .. })
    ));
    assert!(matches!(
        GpuFrame::new(&gpu, 16384, 16384),
        Err(GpuError::TooLarge { .. })
    ));
    let p = unit_patch();
    let patches = [p];
    let tree = Tree::new(&patches);
    let bvh = tree.bvh(&patches);
    assert!(matches!(
        GpuScene::smooth_seamless(&gpu, &bvh, &[]),
        Err(GpuError::LengthMismatch { .. })
    ));
    let mut frame = GpuFrame::new(&gpu, 16, 12).expect("frame");
    // The patch is in view: some pixels hit it.
    let scene = GpuScene::smooth(&gpu, &bvh).expect("upload");
    let stats = scene
        .render_frame(4, &frame_view(), &mut frame)
        .expect("frame");
    let (_, pixels) = frame.read().expect("read");
    let hits = pixels.iter().filter(|p| p.patch == Some(0)).count();
    assert!(hits > 0 && stats.rays >= 16 * 12, "{hits} {stats:?}");
    assert!(stats.max_t_error > 0.0 && stats.max_t_error.is_finite());
    for kind in [SceneKind::Smooth, SceneKind::Flat] {
        let empty = GpuScene::from_parts(&gpu, kind, &[], &[], &[]).expect("upload");
        let stats = empty
            .render_frame(4, &frame_view(), &mut frame)
            .expect("frame");
        let (_, pixels) = frame.read().expect("read");
        assert!(pixels.iter().all(|p| p.patch.is_none()));
        assert_eq!((stats.rays, stats.max_t_error), (16 * 12, 0.0));
    }
    let (lo, hi) = (p.bounds().min(), p.bounds().max());
    let corrupt = GpuScene::from_parts(
        &gpu,
        SceneKind::Smooth,
        &[p.data()],
        &[inner(lo, hi, 1000)],
        &[0],
    )
    .expect("upload");
    assert_eq!(
        corrupt.render_frame(4, &frame_view(), &mut frame),
        Err(GpuError::CorruptTree)
    );
    assert_eq!(
        scene.render_frame(MAX_ITERATIONS + 1, &frame_view(), &mut frame),
        Err(GpuError::Iterations(MAX_ITERATIONS + 1))
    );
    let other = Gpu::new().expect("a second device");
    let mut theirs = GpuFrame::new(&other, 4, 4).expect("frame");
    assert!(matches!(
        scene.render_frame(4, &frame_view(), &mut theirs),
        Err(GpuError::Device(_))
    ));
    still_works(&gpu);
}
