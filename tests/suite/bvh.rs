//! The BVH scene against brute force, and its error paths. The queries run on the kernels
//! `smoothtri-isa` chooses (the widest the CPU has, or the one `SMOOTHTRI_ISA` names: CI runs
//! this file under each one the machine has).

use crate::common::*;
use glam::{DVec3, Vec3};
use smoothtri::accuracy::F64_SPHERE_HIT;
use smoothtri::internal::MAX_LEAF;
use smoothtri::{Aabb, BVH_EMPTY_SLOT, BVH_WIDTH, MAX_DEPTH};
use smoothtri::{Bvh, BvhError, BvhNode, DPatch, DRay, Float, Hit, Patch, Ray};
use smoothtri_isa::Dispatch;
use smoothtri_testkit::scenes::{icosphere, torus};

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
    assert!(bvh.node_count() <= Bvh::<f32>::nodes_needed(ps.len()));
    let mut rng = Rng(11);
    let (mut hits, mut tested, mut ties) = (0, 0, 0u32);
    for i in 0..3000 {
        let o = rng.unit() * rng.range(2.0, 6.0);
        let aim = rng.unit() * 1.5 * rng.f();
        let mut dir = (aim - o).as_vec3();
        // Every fifth ray has a zero direction component or two (the slab test's other path:
        // the origin must lie between that axis's planes).
        match i % 10 {
            0 => dir.z = 0.0,
            5 => (dir.x, dir.y) = (0.0, 0.0),
            _ => {}
        }
        let ray = Ray::new(o.as_vec3(), dir);
        let got = bvh.closest_hit_isa(&ray, 0.0, f32::INFINITY, 6);
        let mut want: Option<(f32, u32)> = None;
        for (i, p) in ps.iter().enumerate() {
            if let Some(h) = p.closest_hit_isa(&ray, 0.0, f32::INFINITY, 6)
                && want.is_none_or(|(t, _)| h.t < t)
            {
                want = Some((h.t, i as u32));
            }
        }
        match (got, want) {
            (Some(g), Some((t, id))) => {
                hits += 1;
                // The same hit, bit for bit: the BVH runs the same kernel over the same range.
                // Two patches can tie (a ray through a shared edge): then the other patch's hit
                // is at exactly the same t.
                assert_eq!(g.t, t, "bvh patch {} vs brute force patch {id}", g.patch);
                let mine = ps[g.patch as usize].closest_hit_isa(&ray, 0.0, f32::INFINITY, 6);
                assert_eq!(
                    mine.map(|h| Hit {
                        patch: g.patch,
                        ..h
                    }),
                    Some(g)
                );
                ties += (g.patch != id) as u32;
            }
            (None, None) => {}
            (g, w) => panic!("bvh {g:?} vs brute force {w:?}"),
        }
        let any = bvh.any_hit_isa(&ray, 0.0, f32::INFINITY, 6);
        assert_eq!(any, want.is_some());
        // Shadow-ray style query bounded before the first hit: nothing, like brute force.
        if let Some((t, _)) = want {
            let short = t * 0.999;
            let brute = ps
                .iter()
                .any(|p| p.closest_hit_isa(&ray, 0.0, short, 6).is_some());
            assert!(!brute, "brute force hits before the closest hit {t}");
            assert!(!bvh.any_hit_isa(&ray, 0.0, short, 6), "shadow ray hits");
        }
        tested += 1;
    }
    eprintln!("{hits} hits of {tested} rays, {ties} ties between patches");
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
        let smooth = bvh.closest_hit_isa(&ray, 0.0, f64::INFINITY, 8);
        if let Some(h) = smooth {
            assert!(
                (h.point.length() - 1.0).abs() <= F64_SPHERE_HIT,
                "{}",
                h.point
            );
        }
        let flat = bvh.closest_with(&ray, 0.0, f64::INFINITY, |_, p, a, b| {
            smoothtri::flat_hit(&p.vertices(), None, &ray, a, b)
        });
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
    let mut small = vec![BvhNode::<f32>::default(); 1];
    assert_eq!(
        Bvh::build(&ps, &mut small, &mut order).unwrap_err(),
        BvhError::StorageTooSmall {
            nodes: 2,
            indices: 3
        }
    );
    // A node whose first slot is itself: a cycle.
    let bad = vec![
        BvhNode::<f32>::new(
            [Aabb::EMPTY; BVH_WIDTH],
            [0, BVH_EMPTY_SLOT, BVH_EMPTY_SLOT, BVH_EMPTY_SLOT],
            [0; 4]
        );
        2
    ];
    assert_eq!(
        Bvh::from_parts(&ps, &bad, &order).unwrap_err(),
        BvhError::CorruptTree
    );
    // Default nodes have no used slot: a tree of nothing, which finds nothing.
    let blank = vec![BvhNode::<f32>::default(); 2];
    let bvh = Bvh::from_parts(&ps, &blank, &order).unwrap();
    let ray = Ray::new(Vec3::splat(2.0), -Vec3::ONE);
    assert!(bvh.closest_hit_isa(&ray, 0.0, f32::INFINITY, 4).is_none());
    for e in [
        BvhError::EmptyScene,
        BvhError::StackOverflow,
        BvhError::CorruptTree,
        BvhError::TooManyPatches,
    ] {
        assert!(e.to_string().len() > 5);
    }
}

/// Storage not made by `Bvh::build` over these patches (handed to `Bvh::from_parts`) is
/// refused once, each way it can point outside itself, with exactly the error documented for
/// it; storage that passes answers every query.
#[test]
fn corrupt_storage_is_reported() {
    // Forty sphere octants along x (enough for the root to have child nodes); the ray runs
    // along x through all of them.
    let octant = |x: f32| {
        let p = [Vec3::X, Vec3::Y, Vec3::Z];
        Patch::<f32>::new(p.map(|v| v + Vec3::X * x), p).unwrap()
    };
    let ps: Vec<Patch> = (0..40).map(|i| octant(3.0 * i as f32)).collect();
    let mut nodes = vec![BvhNode::<f32>::default(); Bvh::<f32>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let used = Bvh::build(&ps, &mut nodes, &mut order)
        .unwrap()
        .node_count();
    let (nodes, order) = (&nodes[..used], &order[..]);
    let root = nodes[0];
    assert!(
        (0..BVH_WIDTH).any(|k| root.count(k) == 0 && root.child(k) != BVH_EMPTY_SLOT),
        "the root has child nodes"
    );
    let ray = Ray::new(Vec3::new(-5.0, 0.3, 0.3), Vec3::X);
    let query = |bvh: Result<Bvh<f32>, BvhError>| {
        bvh.map(|bvh| {
            let closest = bvh.closest_hit_isa(&ray, 0.0, f32::INFINITY, 4).is_some();
            let any = bvh.any_hit_isa(&ray, 0.0, f32::INFINITY, 4);
            assert_eq!(closest, any, "closest_hit and any_hit disagree");
            closest
        })
    };
    // The intact storage answers.
    assert_eq!(query(Bvh::from_parts(&ps, nodes, order)), Ok(true));
    // No patches or no nodes.
    assert_eq!(
        query(Bvh::from_parts(&ps[..0], nodes, order)),
        Err(BvhError::EmptyScene)
    );
    assert_eq!(
        query(Bvh::from_parts(&ps, &nodes[..0], order)),
        Err(BvhError::EmptyScene)
    );
    // A child index outside the node storage.
    assert_eq!(
        query(Bvh::from_parts(&ps, &nodes[..1], order)),
        Err(BvhError::CorruptTree)
    );
    // Leaf ranges outside the index storage.
    assert_eq!(
        query(Bvh::from_parts(&ps, nodes, &order[..0])),
        Err(BvhError::CorruptTree)
    );
    // Patch indices outside the patches.
    assert_eq!(
        query(Bvh::from_parts(&ps[..1], nodes, order)),
        Err(BvhError::CorruptTree)
    );
    // A cycle (every node is the root, whose child nodes are 1 and up): a child that does not
    // come after its parent.
    let cycle = vec![root; nodes.len()];
    assert_eq!(
        query(Bvh::from_parts(&ps, &cycle, order)),
        Err(BvhError::CorruptTree)
    );
    // A chain deeper than the builder makes: node k has the child node k + 1, the last a leaf
    // of one patch.
    let b = root.bounds(0);
    let e = Aabb::EMPTY;
    let slots = |child: u32, count: u32| {
        BvhNode::new(
            [b, e, e, e],
            [child, BVH_EMPTY_SLOT, BVH_EMPTY_SLOT, BVH_EMPTY_SLOT],
            [count, 0, 0, 0],
        )
    };
    let mut deep: Vec<BvhNode<f32>> = (0..MAX_DEPTH as u32).map(|k| slots(k + 1, 0)).collect();
    deep.push(slots(0, 1));
    assert_eq!(
        query(Bvh::from_parts(&ps, &deep, order)),
        Err(BvhError::StackOverflow)
    );
}

/// Depth (levels of nodes, the root alone is 1) and largest leaf of the tree in `nodes`,
/// checking that every node is reached once and every patch index once.
fn shape<F: Float>(nodes: &[BvhNode<F>], n: usize) -> (usize, usize) {
    let mut seen = vec![false; nodes.len()];
    let mut patches = vec![0u32; n];
    let (mut depth, mut leaf) = (0, 0);
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, level)) = stack.pop() {
        assert!(!seen[i], "node {i} reached twice");
        seen[i] = true;
        depth = depth.max(level);
        for k in 0..BVH_WIDTH {
            let (child, count) = (nodes[i].child(k), nodes[i].count(k) as usize);
            if child == BVH_EMPTY_SLOT {
                assert_eq!(count, 0);
                continue;
            }
            if count == 0 {
                assert!(child as usize > i, "a child before its parent");
                stack.push((child as usize, level + 1));
            } else {
                leaf = leaf.max(count);
                for slot in &mut patches[child as usize..child as usize + count] {
                    *slot += 1;
                }
            }
        }
    }
    assert!(seen.iter().all(|&s| s), "unreached nodes");
    assert!(
        patches.iter().all(|&c| c == 1),
        "patch slots not covered once"
    );
    (depth, leaf)
}

/// Many patches with identical boxes: SAH finds no split and the midpoint split falls back to
/// halving, so the tree is balanced: `⌈log2(n / MAX_LEAF)⌉` halvings, two per level of
/// four-wide nodes, leaves of at most `MAX_LEAF`; queries see every patch.
#[test]
fn identical_boxes_give_a_balanced_tree() {
    let p = DPatch::new(
        [DVec3::X, DVec3::Y, DVec3::Z],
        [DVec3::X, DVec3::Y, DVec3::Z],
    )
    .unwrap();
    let ps = vec![p; 5000];
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let used = bvh.node_count();
    let ray = DRay::new(DVec3::splat(2.0), -DVec3::ONE);
    let h = bvh.closest_hit_isa(&ray, 0.0, f64::INFINITY, 8).unwrap();
    assert!((h.point.length() - 1.0).abs() <= F64_SPHERE_HIT);
    let mut tested = 0;
    bvh.closest_with(&ray, 0.0, f64::INFINITY, |_, p, a, b| {
        tested += 1;
        p.closest_hit_isa(&ray, a, b, 8)
    });
    assert_eq!(tested, ps.len(), "patch tests");
    assert!(used <= Bvh::<f64>::nodes_needed(ps.len()), "{used} nodes");
    let (depth, leaf) = shape(&nodes[..used], ps.len());
    eprintln!(
        "{} identical patches: {used} nodes, depth {depth}, largest leaf {leaf}",
        ps.len()
    );
    let halvings = (ps.len() as f64 / MAX_LEAF as f64).log2().ceil() as usize;
    let balanced = halvings.div_ceil(2);
    assert_eq!(depth, balanced, "depth");
    assert!(leaf <= MAX_LEAF, "leaf of {leaf}");
}

/// Patches at exponentially growing distances and sizes along a line: every SAH split peels
/// off the farthest few, so the tree would be a chain as deep as the scene is long; the builder
/// stops splitting at `MAX_DEPTH` (the last leaf takes what is left) and queries still succeed.
#[test]
fn depth_never_exceeds_max_depth() {
    let octant = [DVec3::X, DVec3::Y, DVec3::Z];
    let ps: Vec<DPatch> = (0..650)
        .map(|i| {
            let s = 1.25f64.powi(i);
            DPatch::new(octant.map(|v| (v * 0.1 + DVec3::X) * s), octant).unwrap()
        })
        .collect();
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let used = bvh.node_count();
    // Along the line, through every patch's box.
    let ray = DRay::new(DVec3::new(-10.0, 0.3, 0.3), DVec3::X);
    let h = bvh.closest_hit_isa(&ray, 0.0, f64::INFINITY, 8);
    assert!(h.is_some());
    assert!(bvh.any_hit_isa(&ray, 0.0, f64::INFINITY, 8));
    let (depth, leaf) = shape(&nodes[..used], ps.len());
    eprintln!(
        "{} patches on a geometric line: {used} nodes, depth {depth}, largest leaf {leaf}",
        ps.len()
    );
    assert!(depth < MAX_DEPTH, "depth {depth}");
    assert!(
        leaf > MAX_LEAF,
        "the scene should reach the depth limit (a leaf taking what is left), or it tests nothing"
    );
}
