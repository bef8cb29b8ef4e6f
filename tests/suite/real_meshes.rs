//! Real exports from Debian's `assimp-testmodels` (installed by `.ci/run`; skipped where the
//! package is absent unless `SMOOTHTRI_REQUIRE_ASSETS` is set), built as the demo builds them
//! (f32, seams, rayon): a 121k-triangle CAD model in binary glTF (82 nodes, creases as split
//! normals, 11k zero-area triangles), a scanned-style animal in OBJ (118 remedied patches), a
//! spider in OBJ with non-manifold edges and degenerate triangles, and a box whose normals
//! point the wrong way. Each build's counts are pinned; rays through each model hit with
//! finite, certified results and unit shading normals; across every edge the seams join
//! (clamped and steep patches included) the shading normal's jump is within `SEAM_JUMP_DEG`,
//! with the creases (split normals) and the edges left without a seam counted and pinned; and
//! the band's cull changes no patch test's result on the way.

use crate::common::buffers;
use glam::DVec3;
use smoothtri::accuracy::SEAM_JUMP_DEG;
use smoothtri::{BuildOptions, DEFAULT_SAMPLES, LineField, OwnedScene, Ray, Vertices};
use smoothtri_testkit::RayonExecutor;

/// `(file under /usr/share/assimp/models, triangles, rejected, remedied)`.
const MODELS: &[(&str, usize, usize, usize)] = &[
    (
        "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
        121_496,
        11_176,
        3,
    ),
    ("OBJ/WusonOBJ.obj", 3732, 0, 118),
    ("OBJ/spider.obj", 1368, 56, 142),
    (
        "glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
        12,
        0,
        2,
    ),
];

#[test]
fn real_meshes_build_and_trace() {
    let Some(root) = smoothtri_testkit::assimp_models().unwrap() else {
        return;
    };
    for &(file, triangles, rejected, remedied) in MODELS {
        let path = root.join(file);
        let loaded =
            smoothtri_io::load(path.to_str().unwrap()).unwrap_or_else(|e| panic!("{file}: {e}"));
        let m = &loaded.mesh;
        let (p, n) = buffers(m);
        let mut options = BuildOptions {
            field: LineField::Face,
            seams: true,
            observer: (),
            executor: RayonExecutor,
        };
        let t0 = std::time::Instant::now();
        let owned = OwnedScene::<f32>::build(
            Vertices::packed(&p),
            Vertices::packed(&n),
            &m.triangles,
            &mut options,
        )
        .unwrap_or_else(|e| panic!("{file}: {e}"));
        let seconds = t0.elapsed().as_secs_f64();
        let scene = owned.scene();
        let r = *scene.report();
        assert_eq!(r.triangles, triangles, "{file}");
        assert_eq!(
            r.rejected.by_reason().iter().map(|(_, k)| k).sum::<usize>(),
            rejected,
            "{file}"
        );
        assert_eq!(r.patches + rejected, triangles, "{file}");
        assert_eq!(r.remedied, remedied, "{file}");
        let fitted = r.seam_edges.unwrap();
        assert!(fitted <= r.cracks.shared_edges, "{file}");
        assert!(r.cracks.widest_gap.is_finite(), "{file}");
        // A grid of rays from outside the bounds toward the model, from two sides.
        let (lo, hi) = m.bounds();
        let (c, size) = ((lo + hi) * 0.5, (hi - lo).length());
        let (mut hits, mut rays) = (0usize, 0usize);
        let (mut missed, mut culled) = (0usize, 0usize);
        for dir in [DVec3::new(1.0, 0.6, 0.3), DVec3::new(-0.4, -1.0, 0.5)] {
            let d = dir.normalize();
            let (u, v) = (d.any_orthonormal_pair().0, d.any_orthonormal_pair().1);
            for i in 0..24 {
                for j in 0..24 {
                    let s = |k: usize| (k as f64 + 0.5) / 24.0 - 0.5;
                    let o = c - d * size + (u * s(i) + v * s(j)) * size * 0.8;
                    let ray = Ray::new(o.as_vec3(), d.as_vec3());
                    rays += 1;
                    // The band's cull changes no patch's result on the way (every patch the
                    // traversal tests, against the same patch without its band).
                    let bvh = scene.bvh();
                    bvh.closest_with(&ray, 0.0, f32::INFINITY, |_, p, a, b| {
                        let (h, st) = p.closest_hit_stats::<DEFAULT_SAMPLES>(&ray, a, b, 4);
                        let unbounded = smoothtri::internal::without_band(p);
                        let (hu, su) =
                            unbounded.closest_hit_stats::<DEFAULT_SAMPLES>(&ray, a, b, 4);
                        assert_eq!(h, hu, "{file}: the band changed a result");
                        if su.height_evals > 0 && hu.is_none() {
                            missed += 1;
                            culled += usize::from(st.height_evals == 0);
                        }
                        h
                    });
                    let Some(h) = scene.closest_hit(&ray, 0.0, f32::INFINITY, 4) else {
                        continue;
                    };
                    hits += 1;
                    let hit = h.hit;
                    assert!(hit.t.is_finite() && hit.t > 0.0, "{file}");
                    assert!(hit.t_error.is_finite() && hit.t_error >= 0.0, "{file}");
                    assert!(hit.point.is_finite() && hit.normal.is_finite(), "{file}");
                    let len = h.shading_normal.length();
                    assert!((len - 1.0).abs() < 1e-5, "{file}: {len}");
                    assert!((h.triangle as usize) < triangles, "{file}");
                }
            }
        }
        assert!(hits * 20 > rays, "{file}: {hits} of {rays} rays hit");
        eprintln!(
            "{file}: {triangles} triangles, {} patches, {rejected} rejected, {remedied} \
             remedied; {} shared edges ({} open, widest gap {:.2e}), {fitted} fitted; built in \
             {seconds:.2} s on {} threads (dev profile); {hits} of {rays} rays hit; the band \
             culled {culled} of {missed} patch tests that entered a shell and found no crossing",
            r.patches,
            r.cracks.shared_edges,
            r.cracks.open_edges,
            r.cracks.widest_gap,
            std::thread::available_parallelism().map_or(1, |n| n.get()),
        );
    }
}

/// `(file, measured edges, creases, edges without a seam)` of `smoothtri inspect`'s edge
/// measurement (f64 patches, edges matched by position, 9 samples between the vertices).
const JUMPS: &[(&str, usize, usize, usize)] = &[
    ("OBJ/WusonOBJ.obj", 5392, 0, 0),
    ("OBJ/spider.obj", 1764, 152, 10),
    ("PLY/Wuson.ply", 4, 5388, 4),
    (
        "glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
        5,
        13,
        5,
    ),
];

/// The seamless shading normal is continuous across every edge the seams join, on real files
/// (the animal's 219 edges next to clamped patches included); what is not joined is counted.
#[test]
fn real_meshes_shading_jumps() {
    let Some(root) = smoothtri_testkit::assimp_models().unwrap() else {
        return;
    };
    for &(file, edges, creases, unjoined) in JUMPS {
        let loaded = smoothtri_io::load(root.join(file).to_str().unwrap())
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let c = smoothtri_testkit::cracks(&loaded.mesh, LineField::Face);
        eprintln!(
            "{file}: {} edges measured ({} next to clamped patches), {} creases, {} without a \
             seam (max {:.4}°); shading jump max {:.6}° mean {:.2e}° (surface normal: max \
             {:.2}°)",
            c.edges,
            c.remedied,
            c.creases,
            c.unjoined,
            c.max_unjoined_jump_deg,
            c.max_shading_jump_deg,
            c.mean_shading_jump_deg,
            c.max_surface_jump_deg
        );
        assert_eq!(
            (c.edges, c.creases, c.unjoined),
            (edges, creases, unjoined),
            "{file}"
        );
        assert!(
            c.max_shading_jump_deg <= SEAM_JUMP_DEG,
            "{file}: {}°",
            c.max_shading_jump_deg
        );
    }
}
