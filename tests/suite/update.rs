//! Updating a scene whose vertices move (`OwnedScene::update`, `DynamicScene::update`): the
//! same patches, crack reaches and seams as a fresh build of the moved vertices, bit for bit;
//! hits equal to the fresh build's where the tree was rebuilt and within `t_error` where it was
//! refitted; degenerate triangles become placeholders and come back; bad input leaves the scene
//! as it was.

use crate::common::*;
use glam::{DQuat, DVec3};
use smoothtri::{
    BuildError, BuildOptions, DynamicScene, Executor, LineField, OwnedScene, Patch, PatchError,
    Ray, Scene, SceneSizes, Vertices,
};
use smoothtri_testkit::{Mesh, RayonExecutor, scenes};

/// `m` twisted about the z axis by `turns` radians per unit of height, and bent: positions
/// and normals rotated together (a rigid motion per vertex, so the normals stay those of the
/// deformed surface to first order).
fn twisted(m: &Mesh, turns: f64) -> Mesh {
    let mut out = m.clone();
    for (p, n) in out.positions.iter_mut().zip(out.normals.iter_mut()) {
        let q = DQuat::from_rotation_z(turns * p.z) * DQuat::from_rotation_y(0.3 * turns * p.x);
        *p = q * *p;
        *n = q * *n;
    }
    out
}

/// Rays from around `m` toward its middle.
fn rays(m: &Mesh, n: usize, seed: u64) -> Vec<(DVec3, DVec3)> {
    let (lo, hi) = m.bounds();
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let o = c + rng.unit().normalize_or(DVec3::X) * 2.0 * r;
            (o, c + rng.unit() * 0.4 * r - o)
        })
        .collect()
}

fn owned<F: Float>(m: &Mesh, options: &mut BuildOptions<(), impl Executor>) -> OwnedScene<F> {
    build_owned(m, options).unwrap()
}

fn update<F: Float>(
    s: &mut OwnedScene<F>,
    m: &Mesh,
    options: &mut BuildOptions<(), impl Executor>,
) -> Result<smoothtri::BuildReport, BuildError> {
    let (p, n) = buffers(m);
    s.update(Vertices::packed(&p), Vertices::packed(&n), options)
        .copied()
}

/// What an update must equal: the patches, seams and what the steps reported of a fresh build.
fn same_build<F: Float>(name: &str, a: &Scene<'_, F>, b: &Scene<'_, F>) {
    if let Err(e) = same_parts(&format!("{name}: "), a, b) {
        panic!("{e}");
    }
    let (ra, rb) = (a.report(), b.report());
    assert_eq!(ra.cracks, rb.cracks, "{name}: cracks");
    assert_eq!(ra.vertex_clamps, rb.vertex_clamps, "{name}: vertex clamps");
}

/// The closest hits of `updated` against those of `fresh` on `rays`: bit for bit where the
/// tree was rebuilt; where it was refitted the same hit or miss and `t` within `t_error`.
/// Returns the hits.
fn same_hits<F: Float>(
    name: &str,
    updated: &Scene<'_, F>,
    fresh: &Scene<'_, F>,
    rays: &[(DVec3, DVec3)],
) -> usize {
    let refitted = updated.report().bvh_refitted;
    let inf = F::from_f64(f64::INFINITY);
    let mut hits = 0;
    for &(o, d) in rays {
        let ray = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
        let (a, b) = (
            updated.closest_hit(&ray, F::ZERO, inf, 4),
            fresh.closest_hit(&ray, F::ZERO, inf, 4),
        );
        assert_eq!(
            updated.any_hit(&ray, F::ZERO, inf, 4),
            b.is_some(),
            "{name}: shadow ray"
        );
        match (a, b) {
            (Some(a), Some(b)) if refitted => {
                let tol = a.hit.t_error.to_f64().max(b.hit.t_error.to_f64());
                assert!(
                    (a.hit.t.to_f64() - b.hit.t.to_f64()).abs() <= tol,
                    "{name}: t {:?} vs {:?}",
                    a.hit.t,
                    b.hit.t
                );
                hits += 1;
            }
            (Some(a), Some(b)) => {
                assert_eq!(a, b, "{name}");
                hits += 1;
            }
            (None, None) => {}
            (a, b) => panic!("{name}: {a:?} vs {b:?}"),
        }
    }
    hits
}

/// Updates `scene` to `frame` and checks it against a fresh build of `frame`: [`same_build`],
/// and [`same_hits`] on `n_rays` rays drawn from `seed`. Returns the update's report, the
/// fresh build, and how many of the rays hit both.
fn update_as_fresh<F: Float>(
    label: &str,
    scene: &mut OwnedScene<F>,
    frame: &Mesh,
    options: &mut BuildOptions,
    n_rays: usize,
    seed: u64,
) -> (smoothtri::BuildReport, OwnedScene<F>, usize) {
    let r = update(scene, frame, options).unwrap();
    let fresh = owned::<F>(frame, options);
    same_build(label, &scene.scene(), &fresh.scene());
    let hits = same_hits(
        label,
        &scene.scene(),
        &fresh.scene(),
        &rays(frame, n_rays, seed),
    );
    (r, fresh, hits)
}

/// Every frame of a twisting mesh, updated in place, equals a fresh build of that frame, in
/// both precisions, both line fields, with and without seams.
#[test]
fn an_update_equals_a_fresh_build() {
    fn check<F: Float>(name: &str, m: &Mesh, field: LineField, seams: bool) {
        let mut options = BuildOptions {
            field,
            seams,
            ..BuildOptions::default()
        };
        let mut scene = owned::<F>(m, &mut options);
        let (mut refits, mut rebuilds) = (0, 0);
        for (k, turns) in [0.1, 0.25, 0.5, 0.5, 0.0, 1.0].into_iter().enumerate() {
            let frame = twisted(m, turns);
            let label = format!("{name} {field:?} seams={seams} frame {k}");
            let (r, fresh, hits) =
                update_as_fresh(&label, &mut scene, &frame, &mut options, 200, k as u64);
            assert!(hits > 20);
            if r.bvh_refitted {
                refits += 1;
            } else {
                rebuilds += 1;
                assert_eq!(scene.scene().bvh().nodes(), fresh.scene().bvh().nodes());
            }
        }
        eprintln!("{name} {field:?} seams={seams}: {refits} refits, {rebuilds} rebuilds");
    }
    for (name, m) in [
        ("torus", scenes::torus(8, 8, 1.0, 0.4)),
        ("teapot", scenes::teapot(4)),
    ] {
        for field in [LineField::Face, LineField::Vertex] {
            for seams in [false, true] {
                check::<f32>(name, &m, field, seams);
            }
        }
        check::<f64>(name, &m, LineField::Face, true);
    }
}

/// A triangle that collapses mid-animation becomes a placeholder (counted, never hit, the
/// layout unchanged) and comes back when it opens again; one degenerate at the build joins
/// the tree when it opens (the tree is rebuilt).
#[test]
fn degenerate_triangles_come_and_go() {
    let m = scenes::icosphere(2, 1.0);
    let mut options = BuildOptions::default();
    let mut collapsed = m.clone();
    let [a, b, c] = collapsed.triangles[7].map(|i| i as usize);
    let mid = (collapsed.positions[a] + collapsed.positions[b]) * 0.5;
    // Vertices a and b meet: triangle 7 and its neighbour across a–b collapse.
    collapsed.positions[a] = mid;
    collapsed.positions[b] = mid;
    let _ = c;
    let gone = m
        .triangles
        .iter()
        .filter(|t| t.contains(&(a as u32)) && t.contains(&(b as u32)))
        .count();
    assert_eq!(gone, 2);
    let mut scene = owned::<f32>(&m, &mut options);
    let slots = scene.scene().patches().len();
    let r = update(&mut scene, &collapsed, &mut options).unwrap();
    assert_eq!(r.patches, m.triangles.len() - gone);
    assert_eq!(r.rejected.degenerate, gone);
    let s = scene.scene();
    assert_eq!(s.patches().len(), slots, "the layout is kept");
    assert_eq!(
        s.patches()[7].rejected(),
        Some(PatchError::DegenerateTriangle)
    );
    assert!(s.patch_of_triangle(7).is_none());
    same_build(
        "collapsed",
        &s,
        &owned::<f32>(&collapsed, &mut options).scene(),
    );
    for (o, d) in rays(&collapsed, 400, 3) {
        let ray = Ray::new(o.as_vec3(), d.as_vec3());
        if let Some(h) = s.closest_hit(&ray, 0.0, f32::INFINITY, 4) {
            assert!(h.triangle != 7);
        }
    }
    // Open again: the patch is back, as built.
    let r = update(&mut scene, &m, &mut options).unwrap();
    assert_eq!(r.patches, m.triangles.len());
    same_build(
        "reopened",
        &scene.scene(),
        &owned::<f32>(&m, &mut options).scene(),
    );
    // Built collapsed, then opened: the new patches are not in the tree, so it is rebuilt.
    let mut late = owned::<f32>(&collapsed, &mut options);
    let r = update(&mut late, &m, &mut options).unwrap();
    assert!(
        !r.bvh_refitted,
        "a patch the tree left out makes it rebuild"
    );
    same_build(
        "late",
        &late.scene(),
        &owned::<f32>(&m, &mut options).scene(),
    );
    same_hits(
        "late",
        &late.scene(),
        &owned::<f32>(&m, &mut options).scene(),
        &rays(&m, 200, 4),
    );
    // Every triangle collapsed: an empty scene, every query misses; then back.
    let mut flat = m.clone();
    for p in flat.positions.iter_mut() {
        *p = DVec3::ZERO;
    }
    let r = update(&mut scene, &flat, &mut options).unwrap();
    assert_eq!(r.patches, 0);
    let ray = Ray::new(glam::Vec3::new(0.1, 0.2, 3.0), -glam::Vec3::Z);
    assert!(
        scene
            .scene()
            .closest_hit(&ray, 0.0, f32::INFINITY, 4)
            .is_none()
    );
    assert!(!scene.scene().any_hit(&ray, 0.0, f32::INFINITY, 4));
    update(&mut scene, &m, &mut options).unwrap();
    assert!(
        scene
            .scene()
            .closest_hit(&ray, 0.0, f32::INFINITY, 4)
            .is_some()
    );
}

/// Bad input in an update is a typed error, and the scene stays the last valid one.
#[test]
fn bad_updates_leave_the_scene_as_it_was() {
    let m = scenes::torus(8, 8, 1.0, 0.4);
    let mut options = BuildOptions {
        seams: true,
        ..BuildOptions::default()
    };
    let mut scene = owned::<f32>(&m, &mut options);
    let moved = twisted(&m, 0.3);
    update(&mut scene, &moved, &mut options).unwrap();
    let before: Vec<Patch> = scene.scene().patches().to_vec();
    let probe = rays(&moved, 100, 9);
    let hits = |s: &OwnedScene<f32>| -> Vec<_> {
        probe
            .iter()
            .map(|&(o, d)| {
                s.scene()
                    .closest_hit(&Ray::new(o.as_vec3(), d.as_vec3()), 0.0, f32::INFINITY, 4)
            })
            .collect()
    };
    let want = hits(&scene);
    let (p, n) = buffers(&m);
    let mut nan = p.clone();
    nan[3 * 5 + 1] = f64::NAN;
    let mut huge = p.clone();
    huge[3 * 9] = 1e300; // finite in f64, infinite in f32
    for (why, result) in [
        (
            "NaN",
            scene
                .update(Vertices::packed(&nan), Vertices::packed(&n), &mut options)
                .copied(),
        ),
        (
            "beyond f32",
            scene
                .update(Vertices::packed(&huge), Vertices::packed(&n), &mut options)
                .copied(),
        ),
        (
            "short",
            scene
                .update(
                    Vertices::packed(&p[3..]),
                    Vertices::packed(&n[3..]),
                    &mut options,
                )
                .copied(),
        ),
        (
            "mismatch",
            scene
                .update(
                    Vertices::packed(&p),
                    Vertices::packed(&n[3..]),
                    &mut options,
                )
                .copied(),
        ),
        (
            "options",
            scene
                .update(
                    Vertices::packed(&p),
                    Vertices::packed(&n),
                    &mut BuildOptions::default(),
                )
                .copied(),
        ),
    ] {
        let e = result.expect_err(why);
        match why {
            "NaN" => assert_eq!(e, BuildError::NonFiniteVertex { vertex: 5 }),
            "beyond f32" => assert_eq!(e, BuildError::NonFiniteVertex { vertex: 9 }),
            "short" => assert!(matches!(e, BuildError::VertexCountChanged { .. })),
            "mismatch" => assert!(matches!(e, BuildError::VertexCountMismatch { .. })),
            _ => assert_eq!(e, BuildError::OptionsChanged),
        }
        assert!(e.to_string().len() > 10);
        assert_eq!(
            scene.scene().patches(),
            &before[..],
            "{why}: the scene is unchanged"
        );
        assert_eq!(hits(&scene), want, "{why}: the queries are unchanged");
    }
    // And the next good update works.
    update(&mut scene, &m, &mut options).unwrap();
    same_build(
        "after errors",
        &scene.scene(),
        &owned::<f32>(&m, &mut options).scene(),
    );
}

/// The tree is refitted while the mesh moves a little, and rebuilt once a refit would cost
/// more than `REBUILD_COST_RATIO` times a fresh tree.
#[test]
fn the_tree_is_refitted_then_rebuilt() {
    let m = scenes::teapot(4);
    let mut options = BuildOptions::default();
    let mut scene = owned::<f32>(&m, &mut options);
    let r = update(&mut scene, &twisted(&m, 0.01), &mut options).unwrap();
    assert!(r.bvh_refitted, "a small motion refits");
    // Scramble: every vertex moved far from its place.
    let mut rng = Rng(11);
    let mut scrambled = m.clone();
    for p in scrambled.positions.iter_mut() {
        *p += rng.unit() * 2.0;
    }
    let r = update(&mut scene, &scrambled, &mut options).unwrap();
    assert!(
        !r.bvh_refitted,
        "a scrambled mesh rebuilds (cost {})",
        r.bvh_cost
    );
}

/// With the shared field, an update that refits keeps the tree's order: the per-vertex remedy
/// must not borrow the order's room for its flags while a refit will read it (a finding of the
/// `scene_update` fuzz target, `fuzz/corpus/scene_update/`).
#[test]
fn a_shared_field_refit_keeps_the_trees_order() {
    for (name, m) in [
        ("torus", scenes::torus(8, 8, 1.0, 0.4)),
        ("teapot", scenes::teapot(4)),
    ] {
        let mut options = BuildOptions {
            field: LineField::Vertex,
            ..BuildOptions::default()
        };
        let mut scene = owned::<f32>(&m, &mut options);
        let mut before = scene.scene().bvh().order().to_vec();
        let moved = twisted(&m, 0.01);
        let r = update(&mut scene, &moved, &mut options).unwrap();
        assert!(r.bvh_refitted, "{name}: a small motion refits");
        let mut after = scene.scene().bvh().order().to_vec();
        before.sort_unstable();
        after.sort_unstable();
        assert_eq!(after, before, "{name}: the refitted tree's order");
        let fresh = owned::<f32>(&moved, &mut options);
        let hits = same_hits(name, &scene.scene(), &fresh.scene(), &rays(&m, 64, 5));
        // The rays aim within 0.4 of the bounds' diagonal of the middle: the teapot takes 16.
        assert!(hits >= 10, "{name}: {hits} hits");
    }
}

/// An update on rayon's pool, or in the most shuffled chunk order, equals one on the calling
/// thread bit for bit; a `DynamicScene` in caller storage equals an `OwnedScene`.
#[test]
fn parallel_and_caller_storage_updates_are_bit_identical() {
    // Large enough for the BVH's subtrees to be built as tasks.
    let m = scenes::teapot(12);
    let frame = twisted(&m, 0.4);
    let base = BuildOptions {
        field: LineField::Face,
        seams: true,
        ..BuildOptions::default()
    };
    let mut serial = owned::<f32>(&m, &mut { base });
    update(&mut serial, &frame, &mut { base }).unwrap();
    let mut pool = owned::<f32>(&m, &mut base.with_executor(RayonExecutor));
    update(&mut pool, &frame, &mut base.with_executor(RayonExecutor)).unwrap();
    let mut back = owned::<f32>(&m, &mut base.with_executor(Backwards));
    update(&mut back, &frame, &mut base.with_executor(Backwards)).unwrap();
    for other in [&pool, &back] {
        let (a, b) = (serial.scene(), other.scene());
        same_build("parallel", &a, &b);
        assert_eq!(a.bvh().nodes(), b.bvh().nodes());
        assert_eq!(a.bvh().order(), b.bvh().order());
        assert_eq!(a.report(), b.report());
    }
    // Caller storage.
    let sizes = SceneSizes::new(m.positions.len(), m.triangles.len(), &base).unwrap();
    let mut store = Store::<f32>::new(&sizes, None);
    let (p, n) = buffers(&m);
    let mut dynamic = DynamicScene::<f32>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        &mut { base },
        store.storage(),
    )
    .unwrap();
    let (p, n) = buffers(&frame);
    dynamic
        .update(Vertices::packed(&p), Vertices::packed(&n), &mut { base })
        .unwrap();
    let (a, b) = (serial.scene(), dynamic.scene());
    same_build("caller storage", &a, &b);
    assert_eq!(a.bvh().nodes(), b.bvh().nodes());
    assert_eq!(dynamic.report(), a.report());
}

/// The animated files of `assimp-testmodels` (skinned, morphed), posed at several times of
/// their first clip and updated in place: each pose equals a fresh build of it.
#[test]
fn animated_files_update_as_fresh_builds() {
    let Some(root) = smoothtri_testkit::assimp_models().unwrap() else {
        return;
    };
    for file in [
        "glTF2/simple_skin/simple_skin.gltf",
        "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    ] {
        let path = root.join(file);
        let mut anim = smoothtri_io::load_animated(path.to_str().unwrap())
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let duration = anim.clips().first().map_or(0.0, |c| c.duration);
        assert!(duration > 0.0, "{file}: no animation");
        let rest = anim.posed_mesh(None, 0.0).unwrap();
        for seams in [false, true] {
            let mut options = BuildOptions {
                seams,
                ..BuildOptions::default()
            };
            let mut scene = owned::<f32>(&rest, &mut options);
            for k in 1u32..=5 {
                let t = duration * f64::from(k) / 5.0;
                let frame = anim.posed_mesh(Some(0), t).unwrap();
                let label = format!("{file} seams={seams} t={t:.2}");
                let (_, _, hits) =
                    update_as_fresh(&label, &mut scene, &frame, &mut options, 300, u64::from(k));
                assert!(hits > 10, "{label}: too few hits to compare");
            }
        }
    }
}
