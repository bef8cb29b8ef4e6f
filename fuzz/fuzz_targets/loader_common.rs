//! Shared body of the mesh-loader targets: write the fuzzer's bytes to a file with the given
//! extension, load it with the loaders of `smoothtri-io`, and build and probe the patches. A
//! loader may return an error (that is its job); it must never panic, and an accepted mesh must
//! give finite patches, evaluations and hits.

use smoothtri::{BuildOptions, DRay, LineField};

pub fn run(ext: &str, data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("smoothtri-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("input.{ext}"));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let Some(p) = path.to_str() else { return };
    let Ok(loaded) = smoothtri_io::load(p) else {
        return;
    };
    let mesh = &loaded.mesh;
    // The scene as the demo builds it (the core's builder, with seams; on one thread, the same
    // bit for bit), at most 2000 triangles.
    let mut head = mesh.clone();
    head.triangles.truncate(2000);
    let mut options = BuildOptions {
        field: LineField::Face,
        seams: true,
        ..BuildOptions::default()
    };
    let Ok(built) = head.build_scene::<f64, _, _>(&mut options) else {
        return;
    };
    let scene = built.scene();
    for patch in scene.patches().iter().filter(|p| p.rejected().is_none()) {
        let (x, n) = patch.point_normal(1.0 / 3.0, 1.0 / 3.0);
        assert!(x.is_finite() && n.is_finite(), "non-finite evaluation");
    }
    let (lo, hi) = mesh.bounds();
    let c = (lo + hi) * 0.5;
    let ray = DRay::new(
        c + (hi - lo) + glam::DVec3::splat(1.0),
        -(hi - lo) - glam::DVec3::splat(1.0),
    );
    if let Some(h) = scene.closest_hit(&ray, 0.0, f64::INFINITY, 8) {
        let p = h.hit.point;
        assert!(h.hit.t.is_finite() && p.is_finite() && h.hit.normal.is_finite());
        assert!(h.shading_normal.is_finite(), "non-finite shading normal");
    }
}
