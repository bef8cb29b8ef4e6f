//! The BVH scene against brute force, and its error paths.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::bvh::MAX_DEPTH;
use smoothtri::{Bvh, BvhError, BvhNode, DPatch, DRay, Patch, Ray};
use smoothtri_demo::scenes::{icosphere, torus};

#[test]
fn closest_and_any_hit_equal_brute_force() {
    let mesh = torus(16, 12, 1.0, 0.4);
    let ps: Vec<Patch> = (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap()
        })
        .collect();
    let mut nodes = vec![BvhNode::default(); Bvh::<f32>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    assert!(bvh.node_count() < 2 * ps.len());
    let mut rng = Rng(11);
    let (mut hits, mut tested) = (0, 0);
    for _ in 0..3000 {
        let o = rng.unit() * rng.range(2.0, 6.0);
        let aim = rng.unit() * 1.5 * rng.f();
        let ray = Ray::new(o.as_vec3(), (aim - o).as_vec3());
        let got = bvh.closest_hit::<6>(&ray, 0.0, f32::INFINITY).unwrap();
        let mut want: Option<(f32, u32)> = None;
        for (i, p) in ps.iter().enumerate() {
            if let Some(h) = p.intersect::<6>(&ray, 0.0, f32::INFINITY)
                && want.is_none_or(|(t, _)| h.t < t)
            {
                want = Some((h.t, i as u32));
            }
        }
        match (got, want) {
            (Some(g), Some((t, id))) => {
                hits += 1;
                assert!((g.t - t).abs() <= 1e-6 * t.abs().max(1.0), "{} vs {t}", g.t);
                if g.patch != id {
                    // Two patches at the same t (shared edge): both answers are right.
                    assert!((g.t - t).abs() <= 1e-6);
                }
            }
            (None, None) => {}
            (g, w) => panic!("bvh {g:?} vs brute force {w:?}"),
        }
        let any = bvh.any_hit::<6>(&ray, 0.0, f32::INFINITY).unwrap();
        assert_eq!(any, want.is_some());
        // Shadow-ray style query bounded before the first hit: nothing.
        if let Some((t, _)) = want {
            assert!(
                !bvh.any_hit::<6>(&ray, 0.0, t * 0.999).unwrap()
                    || ps
                        .iter()
                        .any(|p| p.intersect::<6>(&ray, 0.0, t * 0.999).is_some())
            );
        }
        tested += 1;
    }
    assert!(hits > 500 && tested == 3000, "{hits} hits");
}

#[test]
fn f64_scene_and_flat_leaf_test() {
    let mesh = icosphere(2, 1.0);
    let ps: Vec<DPatch> = (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            DPatch::new(p, n).unwrap()
        })
        .collect();
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let mut rng = Rng(12);
    for _ in 0..500 {
        let o = rng.unit() * 4.0;
        let ray = DRay::new(o, rng.unit() * 0.5 - o);
        let smooth = bvh.closest_hit::<8>(&ray, 0.0, f64::INFINITY).unwrap();
        if let Some(h) = smooth {
            assert!((h.point.length() - 1.0).abs() < 1e-12);
        }
        let flat = bvh
            .closest_with(&ray, 0.0, f64::INFINITY, |p, a, b| {
                smoothtri::flat_hit(&p.vertices(), None, &ray, a, b)
            })
            .unwrap();
        if let Some(f) = flat {
            // Flat triangles are inscribed: inside the sphere, and the smooth hit comes first.
            assert!(f.point.length() <= 1.0 + 1e-12);
            let s = smooth.expect("a ray hitting the inscribed polyhedron hits the sphere");
            assert!(s.t <= f.t + 1e-12);
        }
    }
}

#[test]
fn errors_are_reported() {
    let none: [Patch; 0] = [];
    let mut nodes = vec![BvhNode::<f32>::default(); 4];
    let mut order = vec![0u32; 4];
    assert_eq!(
        Bvh::build(&none, &mut nodes, &mut order).unwrap_err(),
        BvhError::EmptyScene
    );
    let p: Patch = Patch::new([Vec3::X, Vec3::Y, Vec3::Z], [Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
    let ps = vec![p; 3];
    let mut small = vec![BvhNode::<f32>::default(); 2];
    assert_eq!(
        Bvh::build(&ps, &mut small, &mut order).unwrap_err(),
        BvhError::StorageTooSmall {
            nodes: 5,
            indices: 3
        }
    );
    // Corrupted storage: a node whose children point back to the root.
    let bad = vec![BvhNode::<f32>::default(); 2];
    let bvh = Bvh::from_parts(&ps, &bad, &order);
    let ray = Ray::new(Vec3::ZERO, Vec3::ONE);
    let r = bvh.closest_hit::<4>(&ray, -10.0, 10.0);
    assert!(
        matches!(
            r,
            Err(BvhError::CorruptTree) | Err(BvhError::StackOverflow) | Ok(None)
        ),
        "{r:?}"
    );
    for e in [
        BvhError::EmptyScene,
        BvhError::StackOverflow,
        BvhError::CorruptTree,
        BvhError::TooManyPatches,
    ] {
        assert!(e.to_string().len() > 5);
    }
}

#[test]
fn degenerate_geometry_keeps_depth_bounded() {
    // Many patches with identical boxes: SAH finds no split; the depth bound still holds and
    // queries see every patch.
    let p = DPatch::new(
        [DVec3::X, DVec3::Y, DVec3::Z],
        [DVec3::X, DVec3::Y, DVec3::Z],
    )
    .unwrap();
    let ps = vec![p; 5000];
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let ray = DRay::new(DVec3::splat(2.0), -DVec3::ONE);
    let h = bvh
        .closest_hit::<8>(&ray, 0.0, f64::INFINITY)
        .unwrap()
        .unwrap();
    assert!((h.point.length() - 1.0).abs() < 1e-12);
    assert!(bvh.node_count() <= 2 * ps.len());
    let _ = MAX_DEPTH;
}
