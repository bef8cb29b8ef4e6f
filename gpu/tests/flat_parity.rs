//! Parity of the GPU's own flat-triangle pipeline (`FlatScene`) with the CPU's Möller–Trumbore
//! through smoothtri's BVH over the same boxes: every hit and miss, `t` within rounding, the
//! same triangle (or one at the same `t`: a ray through a shared edge).
//! `cargo test -p smoothtri-gpu --test flat_parity -- --nocapture`.

mod common;

use common::*;
use smoothtri::{BoxBvh, BvhNode, flat_hit, moller_trumbore};
use smoothtri_gpu::FlatScene;
use smoothtri_testkit::scenes::{teapot, torus};
use smoothtri_testkit::{flat_triangles32, triangle_boxes};

#[test]
fn flat_pipeline_equals_cpu_moller_trumbore() {
    let Some(gpu) = gpu() else { return };
    for (name, mesh) in [
        ("torus 35×35", torus(35, 35, 1.0, 0.4)),
        ("teapot", teapot(4)),
    ] {
        let tris = flat_triangles32(&mesh);
        let scene = FlatScene::new(&gpu, &tris).expect("upload");
        let boxes = triangle_boxes(&tris);
        let mut nodes = vec![BvhNode::default(); BoxBvh::<f32>::nodes_needed(tris.len())];
        let mut order = vec![0u32; tris.len()];
        let tree = BoxBvh::build(&boxes, &mut nodes, &mut order).unwrap();
        let rays = random_rays(3, 6000, 1.5);
        let mut got = vec![None; rays.len()];
        scene
            .closest_hit(&rays, 0.0, f32::INFINITY, &mut got)
            .expect("trace");
        let (mut hits, mut max_dt) = (0, 0.0f32);
        for (r, g) in rays.iter().zip(&got) {
            let want = tree.closest_with(r, 0.0, f32::MAX, |i, a, b| {
                flat_hit(&tris[i as usize], None, r, a, b)
            });
            match (g, want) {
                (Some(g), Some(w)) => {
                    hits += 1;
                    let tol =
                        16.0 * f32::EPSILON * (w.t.abs() + r.origin.length() / r.dir.length());
                    assert!((g.t - w.t).abs() <= tol, "{name}: t {} vs {}", g.t, w.t);
                    max_dt = max_dt.max((g.t - w.t).abs());
                    if g.triangle != w.patch {
                        // A tie: the GPU's triangle is hit at the same t.
                        let other = moller_trumbore(&tris[g.triangle as usize], r, 0.0, f32::MAX);
                        assert!(
                            other.is_some_and(|o| (o.0 - w.t).abs() <= tol),
                            "{name}: triangle"
                        );
                    } else {
                        assert!((g.w1 - w.w1).abs() < 1e-4 && (g.w2 - w.w2).abs() < 1e-4);
                    }
                }
                (None, None) => {}
                // Only a ray through a triangle's rim may fall on either side of rounding.
                (Some(g), None) => assert!(
                    g.w1.min(g.w2).min(1.0 - g.w1 - g.w2) < 1e-5,
                    "{name}: GPU hit {g:?}"
                ),
                (None, Some(w)) => assert!(
                    w.w1.min(w.w2).min(1.0 - w.w1 - w.w2) < 1e-5,
                    "{name}: CPU hit {w:?}"
                ),
            }
        }
        println!(
            "{name}: {hits} of {} rays hit, max |Δt| {max_dt:.2e}",
            rays.len()
        );
        assert!(hits > rays.len() / 10);
    }
}
