//! Shared body of the mesh-loader targets: write the fuzzer's bytes to a file with the given
//! extension, load it with the demo's loader, and build and probe the patches. A loader may
//! return an error (that is its job); it must never panic, and an accepted mesh must give
//! finite patches, evaluations and hits.

use smoothtri::{Bvh, BvhNode, DPatch, DRay};

pub fn run(ext: &str, data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("smoothtri-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("input.{ext}"));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let Some(p) = path.to_str() else { return };
    let Ok(loaded) = smoothtri_demo::mesh::load(p) else {
        return;
    };
    let mesh = &loaded.mesh;
    let mut patches = Vec::new();
    for t in 0..mesh.triangles.len().min(2000) {
        let (pp, nn) = mesh.triangle(t);
        if let Ok(patch) = DPatch::new_or_tilted(pp, nn) {
            let (x, n) = patch.point_normal(1.0 / 3.0, 1.0 / 3.0);
            assert!(x.is_finite() && n.is_finite(), "non-finite evaluation");
            patches.push(patch);
        }
    }
    if patches.is_empty() {
        return;
    }
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(patches.len())];
    let mut order = vec![0u32; patches.len()];
    let bvh = Bvh::build(&patches, &mut nodes, &mut order).expect("bvh over accepted patches");
    let (lo, hi) = mesh.bounds();
    let c = (lo + hi) * 0.5;
    let ray = DRay::new(
        c + (hi - lo) + glam::DVec3::splat(1.0),
        -(hi - lo) - glam::DVec3::splat(1.0),
    );
    if let Ok(Some(h)) = bvh.closest_hit::<8>(&ray, 0.0, f64::INFINITY) {
        assert!(h.t.is_finite() && h.point.is_finite() && h.normal.is_finite());
    }
}
