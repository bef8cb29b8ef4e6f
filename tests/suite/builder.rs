//! The scene builder (`Scene::build`, `OwnedScene`): the same patches, BVH and seams as the
//! steps called one by one, bit for bit; strided and packed, `f32` and `f64` input alike;
//! storage of exactly the sizes `SceneSizes` gives; every typed error; reports that count what
//! was rejected and remedied; queries that agree with the BVH's and the seams' own.

use crate::common::*;
use glam::DVec3;
use smoothtri::mesh::{
    Seam, SharedEdge, VertexClamp, clamp_vertex_normals, close_cracks, fit_seams,
};
use smoothtri::{
    BuildError, BuildOptions, Bvh, BvhNode, Float, LineField, OnRejected, OwnedScene, Patch,
    PatchError, Ray, Scene, SceneSizes, Vertices,
};
use smoothtri_testkit::{Mesh, scenes};

/// What the builder must equal: the steps of `smoothtri::mesh` called one by one (per-vertex
/// remedy on the shared field, patches with the per-patch remedy, crack closure, seams).
fn by_steps<F: Float>(m: &Mesh, options: &BuildOptions) -> (Vec<Patch<F>>, Vec<u32>, Vec<Seam<F>>) {
    let pos: Vec<F::Vec3> = m.positions.iter().map(|p| F::from_dvec3(*p)).collect();
    let mut nrm: Vec<F::Vec3> = m.normals.iter().map(|n| F::from_dvec3(*n)).collect();
    if options.field == LineField::Vertex {
        let given = nrm.clone();
        let mut scratch = vec![VertexClamp::<F>::default(); pos.len()];
        clamp_vertex_normals(&pos, &given, &m.triangles, &mut nrm, &mut scratch).unwrap();
    }
    let (mut patches, mut ids, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    for (t, tri) in m.triangles.iter().enumerate() {
        let [p, n] = [&pos, &nrm].map(|v| tri.map(|i| v[i as usize]));
        if let Ok(patch) = Patch::<F>::new_or_tilted_with(p, n, options.field) {
            patches.push(patch);
            ids.push(t as u32);
            tris.push(*tri);
        }
    }
    let mut edges = vec![SharedEdge::default(); 3 * patches.len()];
    close_cracks(&mut patches, &tris, pos.len(), &mut edges).unwrap();
    let mut seams = vec![Seam::<F>::default(); patches.len()];
    if options.seams {
        fit_seams(&patches, &tris, pos.len(), &mut edges, &mut seams).unwrap();
    } else {
        seams.clear();
    }
    (patches, ids, seams)
}

fn camera_rays(m: &Mesh, n: usize, seed: u64) -> Vec<(DVec3, DVec3)> {
    let (lo, hi) = m.bounds();
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            let o = c + rng.unit() * 2.0 * r;
            (o, c + rng.unit() * 0.4 * r * rng.f() - o)
        })
        .collect()
}

fn check_equals_steps<F: Float>(name: &str, m: &Mesh, mut options: BuildOptions) {
    let owned = build_owned::<F>(m, &mut options).unwrap();
    let scene = owned.scene();
    let (patches, ids, seams) = by_steps::<F>(m, &options);
    // These meshes have a slot for every triangle and no placeholder: the slots are the steps'
    // patches.
    assert!(scene.patches().iter().all(|p| p.rejected().is_none()));
    assert_eq!(scene.patches(), &patches[..], "{name}: patches");
    assert_eq!(scene.triangle_ids(), &ids[..], "{name}: triangle ids");
    assert_eq!(scene.seams(), &seams[..], "{name}: seams");
    let r = scene.report();
    assert_eq!(r.triangles, m.triangles.len());
    assert_eq!(r.patches, patches.len());
    let rejected = r.rejected.by_reason().iter().map(|(_, n)| n).sum::<usize>();
    assert_eq!(rejected + r.patches, r.triangles, "{name}");
    assert_eq!(
        r.remedied,
        patches
            .iter()
            .filter(|p| p.normal_clamp().is_some())
            .count()
    );
    assert_eq!(r.seam_edges.is_some(), options.seams);
    assert_eq!(
        r.vertex_clamps.is_some(),
        options.field == LineField::Vertex
    );
    // The same hits as a BVH built over the steps' patches, with the seams' shading normal and
    // the input triangle.
    let mut nodes = vec![BvhNode::default(); Bvh::<F>::nodes_needed(patches.len())];
    let mut order = vec![0u32; patches.len()];
    let bvh = Bvh::build(&patches, &mut nodes, &mut order).unwrap();
    let inf = F::from_f64(f64::INFINITY);
    let mut hits = 0;
    for (o, d) in camera_rays(m, 400, 5) {
        let ray = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
        let got = scene.closest_hit(&ray, F::ZERO, inf, 4);
        let want = bvh.closest_hit(&ray, F::ZERO, inf, 4);
        assert_eq!(got.map(|h| h.hit), want, "{name}");
        assert_eq!(
            scene.any_hit(&ray, F::ZERO, inf, 4),
            want.is_some(),
            "{name}"
        );
        if let (Some(g), Some(w)) = (got, want) {
            hits += 1;
            let i = w.patch as usize;
            assert_eq!(g.triangle, ids[i]);
            let sn = match seams.get(i) {
                Some(s) => s.correct(&patches[i], w.w1, w.w2, w.normal),
                None => w.normal,
            };
            assert_eq!(g.shading_normal, sn, "{name}");
            assert_eq!(scene.patch_of_triangle(g.triangle), Some(&patches[i]));
            assert_eq!(scene.patch_index(g.triangle), Some(i));
        }
    }
    assert!(hits > 50, "{name}: {hits} hits");
    eprintln!("{name}: {} patches, {hits} of 400 rays hit", patches.len());
}

#[test]
fn the_builder_equals_the_steps_bit_for_bit() {
    for (name, m) in [
        ("torus 8x8", scenes::torus(8, 8, 1.0, 0.4)),
        ("teapot", scenes::teapot(4)),
        ("irregular icosphere", irregular()),
    ] {
        for field in [LineField::Face, LineField::Vertex] {
            for seams in [false, true] {
                let options = BuildOptions {
                    field,
                    seams,
                    ..BuildOptions::default()
                };
                check_equals_steps::<f32>(name, &m, options);
                check_equals_steps::<f64>(name, &m, options);
            }
        }
    }
}

/// Storage of exactly the sizes `SceneSizes` gives (arrays on the stack would do as well),
/// interleaved `f32` input read with a stride, against packed `f64` input rounded once.
#[test]
fn strided_input_into_exact_storage() {
    let m = scenes::teapot(4);
    let mut options = BuildOptions {
        field: LineField::Vertex,
        seams: true,
        ..BuildOptions::default()
    };
    // Interleaved: position, a 2-float attribute the builder skips, normal.
    let vb: Vec<f32> = m
        .positions
        .iter()
        .zip(&m.normals)
        .flat_map(|(p, n)| {
            let (p, n) = (p.as_vec3(), n.as_vec3());
            [p.x, p.y, p.z, 0.5, 0.25, n.x, n.y, n.z]
        })
        .collect();
    let v = m.positions.len();
    let pos = Vertices::strided(&vb, 0, 8, v).unwrap();
    let nrm = Vertices::strided(&vb, 5, 8, v).unwrap();
    let n = SceneSizes::new(v, m.triangles.len(), &options).unwrap();
    assert_eq!(n.patches, m.triangles.len());
    assert_eq!(n.nodes, m.triangles.len() - 1);
    assert_eq!(
        (n.seams, n.edges, n.vertices),
        (n.patches, 3 * n.patches, v)
    );
    let mut store = Store::<f32>::new(&n, None);
    let scene = Scene::<f32>::build(pos, nrm, &m.triangles, &mut options, store.storage()).unwrap();
    let owned = build_owned::<f32>(&m, &mut options).unwrap();
    let o = owned.scene();
    assert_eq!(scene.patches(), o.patches());
    assert_eq!(scene.seams(), o.seams());
    assert_eq!(scene.report(), o.report());
    assert_eq!(scene.bvh().nodes(), o.bvh().nodes());
    assert_eq!(scene.bvh().order(), o.bvh().order());
    // What the scene holds, against what the sizes allot (the scratch is not held).
    let bytes = n.bytes::<f32>().unwrap();
    assert!(
        scene.memory_bytes() < bytes,
        "{} vs {bytes}",
        scene.memory_bytes()
    );
    eprintln!(
        "teapot, shared field, seams: storage {bytes} B, the scene holds {} B ({:.0} B per triangle)",
        scene.memory_bytes(),
        scene.memory_bytes() as f64 / m.triangles.len() as f64
    );
}

#[test]
fn rejected_triangles_are_counted_and_reported() {
    // Four triangles: good, degenerate (repeated index), non-finite position, and zero
    // normals (which the remedy repairs: the face normal stands in).
    let p = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [f64::NAN, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
    ];
    let mut n = p.map(|v| v.map(|c: f64| if c.is_nan() { 1.0 } else { c }));
    n[4] = [0.0; 3];
    n[5] = [0.0; 3];
    n[6] = [0.0; 3];
    let (pf, nf): (Vec<f64>, Vec<f64>) = (
        p.iter().flatten().copied().collect(),
        n.iter().flatten().copied().collect(),
    );
    let tris = [[0u32, 1, 2], [0, 0, 1], [3, 1, 2], [4, 5, 6]];
    let mut listed = Vec::new();
    let owned = OwnedScene::<f64>::build(
        Vertices::packed(&pf),
        Vertices::packed(&nf),
        &tris,
        &mut BuildOptions::default().with_observer(OnRejected(|t, e| listed.push((t, e)))),
    )
    .unwrap();
    let r = *owned.scene().report();
    assert_eq!((r.triangles, r.patches), (4, 2));
    assert_eq!(r.rejected.degenerate, 1);
    assert_eq!(r.rejected.non_finite, 1);
    assert_eq!(
        r.rejected.by_reason().iter().map(|(_, n)| n).sum::<usize>(),
        2
    );
    assert_eq!(r.first_rejected, Some((1, PatchError::DegenerateTriangle)));
    assert_eq!((r.remedied, r.first_remedied), (1, Some(3)));
    // Slots: triangles 0, 2 (a placeholder: its vertex is not finite) and 3 (remedied); the
    // degenerate triangle 1 repeats an index and has no slot.
    let slots = owned.scene().patches();
    assert_eq!(owned.scene().triangle_ids(), &[0, 2, 3]);
    assert_eq!(slots[1].rejected(), Some(PatchError::NonFinite));
    assert!(slots[1].bounds().min().x > slots[1].bounds().max().x);
    assert!(slots[2].normal_clamp().is_some());
    assert_eq!(
        listed,
        [
            (1, PatchError::DegenerateTriangle),
            (2, PatchError::NonFinite)
        ]
    );
    let scene = owned.scene();
    assert!(scene.patch_of_triangle(0).is_some());
    assert!(scene.patch_of_triangle(1).is_none());
    assert!(scene.patch_of_triangle(2).is_none());
    assert_eq!(scene.patch_index(3), Some(2));
    assert!(scene.patch_of_triangle(9).is_none());
    // From inside the unit octant outward: triangle 0 first (the remedied triangle 3 lies
    // beyond it).
    let ray = Ray::<f64>::new(DVec3::splat(0.1), DVec3::ONE);
    let h = scene.closest_hit(&ray, 0.0, f64::INFINITY, 4).unwrap();
    assert_eq!(h.triangle, 0);
    // No seams asked for: the shading normal is the geometric one.
    assert_eq!(h.shading_normal, h.hit.normal);
}

#[test]
fn bad_input_and_storage_are_typed_errors() {
    let m = scenes::icosphere(1, 1.0);
    let (pos, nrm) = buffers(&m);
    let (pv, nv) = (Vertices::packed(&pos), Vertices::packed(&nrm));
    let build = |tris: &[[u32; 3]], nv: Vertices<'_, f64>| {
        OwnedScene::<f32>::build(pv, nv, tris, &mut BuildOptions::default()).map(|_| ())
    };
    assert_eq!(build(&[], nv), Err(BuildError::NoTriangles));
    let v = m.positions.len() as u32;
    assert_eq!(
        build(&[[0, 1, 2], [0, 1, v]], nv),
        Err(BuildError::IndexOutOfRange {
            triangle: 1,
            index: v
        })
    );
    assert_eq!(
        build(&m.triangles, Vertices::packed(&nrm[3..])),
        Err(BuildError::VertexCountMismatch {
            positions: v as usize,
            normals: v as usize - 1
        })
    );
    assert!(matches!(
        build(&[[0, 0, 0]], nv),
        Err(BuildError::NoUsableTriangles {
            triangles: 1,
            first: PatchError::DegenerateTriangle
        })
    ));
    // Layouts that do not fit their buffer.
    assert!(matches!(
        Vertices::strided(&pos, 1, 3, m.positions.len()),
        Err(BuildError::VertexLayout { .. })
    ));
    assert!(matches!(
        Vertices::strided(&pos, 0, 2, 4),
        Err(BuildError::VertexLayout { .. })
    ));
    assert!(Vertices::strided(&pos, 0, 3, m.positions.len()).is_ok());
    assert!(Vertices::strided(&pos, 0, 3, 0).unwrap().is_empty());
    // Every storage slice one short is refused by name.
    let mut options = BuildOptions {
        field: LineField::Vertex,
        seams: true,
        ..BuildOptions::default()
    };
    let n = SceneSizes::new(m.positions.len(), m.triangles.len(), &options).unwrap();
    for short in 0..12 {
        let mut store = Store::<f64>::new(&n, Some(short));
        match Scene::<f64>::build(pv, nv, &m.triangles, &mut options, store.storage()) {
            Err(BuildError::StorageTooSmall {
                buffer,
                needed,
                given,
            }) => {
                assert_eq!(given + 1, needed, "{buffer}");
                assert!(!buffer.is_empty());
            }
            other => panic!("slice {short} short: {other:?}"),
        }
    }
    for e in [
        BuildError::NoTriangles,
        BuildError::TooLarge,
        BuildError::IndexOutOfRange {
            triangle: 3,
            index: 9,
        },
    ] {
        assert!(e.to_string().len() > 10, "{e}");
    }
    assert_eq!(SceneSizes::new(3, usize::MAX, &options), None);
}

/// A default patch is a storage placeholder that no ray reaches.
#[test]
fn default_patches_are_never_hit() {
    let p = Patch::<f32>::default();
    let mut rng = Rng(3);
    for _ in 0..200 {
        let o = rng.unit() * 2.0;
        let ray = Ray::new(o.as_vec3(), (-o + rng.unit() * 0.1).as_vec3());
        assert!(p.closest_hit(&ray, 0.0, f32::INFINITY, 4).is_none());
    }
}

/// The observer sees each step start once, in order, then `Done`; and the rejected triangles.
#[test]
fn the_observer_sees_every_step_in_order() {
    use smoothtri::{BuildObserver, BuildStage};
    #[derive(Default)]
    struct Log(Vec<BuildStage>, Vec<u32>);
    impl BuildObserver for Log {
        fn rejected(&mut self, t: u32, _: PatchError) {
            self.1.push(t);
        }
        fn stage(&mut self, s: BuildStage) {
            self.0.push(s);
        }
    }
    let mut m = scenes::teapot(4);
    m.triangles.push([0, 0, 1]);
    let (pos, nrm) = buffers(&m);
    for (field, seams, want) in [
        (
            LineField::Face,
            false,
            vec![BuildStage::Patches, BuildStage::Edges, BuildStage::Bvh],
        ),
        (
            LineField::Vertex,
            true,
            vec![
                BuildStage::VertexNormals,
                BuildStage::Patches,
                BuildStage::Edges,
                BuildStage::Bvh,
            ],
        ),
    ] {
        let mut log = Log::default();
        OwnedScene::<f32>::build(
            Vertices::packed(&pos),
            Vertices::packed(&nrm),
            &m.triangles,
            &mut BuildOptions {
                field,
                seams,
                observer: &mut log,
                executor: (),
            },
        )
        .unwrap();
        let mut want = want;
        want.push(BuildStage::Done);
        assert_eq!(log.0, want);
        assert_eq!(log.1, vec![m.triangles.len() as u32 - 1]);
        assert!(want.iter().all(|s| !s.name().is_empty()));
    }
}

/// `m` built with `options` on the calling thread, on rayon's pool and in the most shuffled
/// order ([`Backwards`]), in that order.
fn on_each_executor<F: Float>(m: &Mesh, options: BuildOptions) -> [OwnedScene<F>; 3] {
    [
        build_owned(m, &mut { options }).unwrap(),
        build_owned(
            m,
            &mut options.with_executor(smoothtri_testkit::RayonExecutor),
        )
        .unwrap(),
        build_owned(m, &mut options.with_executor(Backwards)).unwrap(),
    ]
}

/// The build is bit for bit the same on one thread, on rayon's pool and in the most shuffled
/// order, in both line fields and both precisions (teapot: open cracks, remedied patches).
#[test]
fn parallel_builds_are_bit_identical() {
    fn check<F: Float>(m: &Mesh, field: LineField) {
        let options = BuildOptions {
            field,
            seams: true,
            ..BuildOptions::default()
        };
        let [serial, pool, back] = on_each_executor::<F>(m, options);
        for other in [&pool, &back] {
            let (a, b) = (serial.scene(), other.scene());
            assert_eq!(a.patches(), b.patches());
            assert_eq!(a.seams(), b.seams());
            assert_eq!(a.report(), b.report());
            assert_eq!(a.bvh().nodes(), b.bvh().nodes());
            assert_eq!(a.bvh().order(), b.bvh().order());
        }
        let r = *serial.scene().report();
        assert!(r.cracks.shared_edges > 1000 && r.seam_edges.unwrap() > 1000);
    }
    let m = scenes::teapot(4);
    for field in [LineField::Face, LineField::Vertex] {
        check::<f32>(&m, field);
        check::<f64>(&m, field);
    }
}

/// A scene large enough that the top of its tree is bounded and binned in parts on the
/// executor (ranges of at least 4 Ki boxes): the tree is bit for bit the same on one thread,
/// on rayon's pool and with the parts run last first.
#[test]
fn large_trees_are_bit_identical_on_any_executor() {
    let m = smoothtri_testkit::twist::twisting_torus(130, 0.3);
    assert!(m.triangles.len() >= 2 * 16 * 1024);
    let options = BuildOptions::default();
    let [serial, pool, back] = on_each_executor::<f32>(&m, options);
    for other in [&pool, &back] {
        let (a, b) = (serial.scene(), other.scene());
        assert_eq!(a.bvh().nodes(), b.bvh().nodes());
        assert_eq!(a.bvh().order(), b.bvh().order());
        assert_eq!(a.report(), b.report());
    }
}
