//! The BVH over caller boxes (`BoxBvh`): over the patches' boxes it is the patches' tree bit
//! for bit, and over flat triangles' boxes with Möller–Trumbore in the leaves it equals a
//! brute-force loop.

use crate::common::*;
use glam::Vec3;
use smoothtri::{Aabb, BoxBvh, Bvh, BvhError, BvhNode, Patch, Ray, flat_hit, moller_trumbore};
use smoothtri_testkit::scenes::{teapot, torus};
use smoothtri_testkit::{flat_triangles32, triangle_boxes};

fn patches_of(mesh: &smoothtri_io::Mesh) -> Vec<Patch> {
    (0..mesh.triangles.len())
        .filter_map(|t| {
            let (p, n) = mesh.triangle(t);
            Patch::new_or_tilted(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).ok()
        })
        .collect()
}

/// `BoxBvh::build` over the patches' boxes gives the nodes and order of `Bvh::build` over the
/// patches, bit for bit, and the same closest hits (fails if the box builder reads other boxes
/// or orders its work differently).
#[test]
fn box_tree_over_patch_boxes_is_the_patch_tree() {
    for mesh in [torus(8, 8, 1.0, 0.4), torus(35, 35, 1.0, 0.4), teapot(4)] {
        let ps = patches_of(&mesh);
        let n = ps.len();
        let mut nodes = vec![BvhNode::default(); Bvh::<f32>::nodes_needed(n)];
        let mut order = vec![0u32; n];
        let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
        let boxes: Vec<Aabb> = ps.iter().map(|p| p.bounds()).collect();
        let mut nodes2 = vec![BvhNode::default(); BoxBvh::<f32>::nodes_needed(n)];
        let mut order2 = vec![0u32; n];
        let tree = BoxBvh::build(&boxes, &mut nodes2, &mut order2).unwrap();
        assert_eq!(tree.nodes(), bvh.nodes());
        assert_eq!(tree.order(), bvh.order());
        assert_eq!(bvh.tree().nodes(), bvh.nodes());
        assert_eq!(tree.memory_bytes(), bvh.memory_bytes());
        // The leaf test through the box tree: the patch's own kernel.
        for r in camera_rays_around(&mesh, 40) {
            let a = bvh.closest_hit(&r, 0.0, f32::INFINITY, 4);
            let b = tree.closest_with(&r, 0.0, f32::INFINITY, |id, t0, t1| {
                ps[id as usize].closest_hit(&r, t0, t1, 4)
            });
            assert_eq!(a, b);
            assert_eq!(
                bvh.any_hit(&r, 0.0, f32::INFINITY, 4),
                tree.any_with(&r, 0.0, f32::INFINITY, |id, t0, t1| {
                    ps[id as usize].closest_hit(&r, t0, t1, 4).is_some()
                })
            );
        }
    }
}

/// Rays from a ring of eyes around `mesh` toward points near its centre.
fn camera_rays_around(mesh: &smoothtri_io::Mesh, k: usize) -> Vec<Ray> {
    let (lo, hi) = mesh.positions.iter().fold(
        (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
    let mut rng = Rng(5);
    (0..k * k)
        .map(|_| {
            let eye = c + rng.unit() * 2.0 * r;
            let aim = c + rng.unit() * 0.4 * r * rng.f();
            Ray::new(eye.as_vec3(), (aim - eye).as_vec3())
        })
        .collect()
}

/// Flat triangles in the box tree (the triangles' own boxes, Möller–Trumbore in the leaves):
/// the closest hit and the shadow query equal a loop over every triangle (fails if the
/// traversal skips a box the ray enters or keeps a farther hit).
#[test]
fn flat_triangles_equal_brute_force() {
    let mesh = torus(20, 14, 1.0, 0.4);
    let tris = flat_triangles32(&mesh);
    let boxes = triangle_boxes(&tris);
    let mut nodes = vec![BvhNode::default(); BoxBvh::<f32>::nodes_needed(tris.len())];
    let mut order = vec![0u32; tris.len()];
    let tree = BoxBvh::build(&boxes, &mut nodes, &mut order).unwrap();
    let (mut hits, mut rays) = (0, 0);
    for r in camera_rays_around(&mesh, 50) {
        rays += 1;
        let got = tree.closest_with(&r, 0.0, f32::MAX, |id, a, b| {
            flat_hit(&tris[id as usize], None, &r, a, b)
        });
        let want = tris
            .iter()
            .enumerate()
            .filter_map(|(i, t)| moller_trumbore(t, &r, 0.0, f32::MAX).map(|h| (h.0, i)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(got.map(|h| h.t), want.map(|w| w.0));
        if let (Some(g), Some(w)) = (got, want) {
            hits += 1;
            // A tie between two triangles (a ray through a shared edge) may name either.
            let other = moller_trumbore(&tris[g.patch as usize], &r, 0.0, f32::MAX);
            assert_eq!(other.map(|h| h.0), Some(w.0));
        }
        let any = tree.any_with(&r, 0.0, f32::MAX, |id, a, b| {
            moller_trumbore(&tris[id as usize], &r, a, b).is_some()
        });
        assert_eq!(any, want.is_some());
    }
    assert!(hits > rays / 4, "{hits} of {rays} rays hit");
}

/// The box tree's error paths: no boxes, short storage, corrupt storage.
#[test]
fn box_tree_errors() {
    let b = Aabb::<f32>::new(Vec3::ZERO, Vec3::ONE);
    assert_eq!(
        BoxBvh::<f32>::build(&[], &mut [], &mut []).err(),
        Some(BvhError::EmptyScene)
    );
    assert_eq!(
        BoxBvh::build(&[b, b, b], &mut [BvhNode::default(); 1], &mut [0; 3]).err(),
        Some(BvhError::StorageTooSmall {
            nodes: 2,
            indices: 3
        })
    );
    let (mut nodes, mut order) = ([BvhNode::default(); 2], [0u32; 3]);
    let tree = BoxBvh::build(&[b, b, b], &mut nodes, &mut order).unwrap();
    let (nodes, order) = (tree.nodes().to_vec(), tree.order().to_vec());
    assert!(BoxBvh::from_parts(3, &nodes, &order).is_ok());
    // An index beyond the count the owner names.
    assert_eq!(
        BoxBvh::from_parts(2, &nodes, &order).err(),
        Some(BvhError::CorruptTree)
    );
    assert_eq!(
        BoxBvh::<f32>::from_parts(3, &[], &order).err(),
        Some(BvhError::EmptyScene)
    );
}
