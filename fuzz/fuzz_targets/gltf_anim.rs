//! Fuzz target `gltf_anim`: arbitrary bytes through the animated glTF/GLB loader of
//! `smoothtri-io` (`smoothtri_io::parse_animated`: skins, morph targets, animation samplers
//! and channels), in memory (external buffers resolve against a folder that does not exist).
//! An accepted file is posed at its rest pose and at a few times of up to three clips (before
//! the first key, inside, at and after the end), and the poses drive a scene: built from the
//! first pose, updated to each following one.
//!
//! Asserts: the loader returns a mesh or an error, never panics; every pose that succeeds has
//! finite positions and normals of unit length or zero, one per vertex; every update of the
//! scene succeeds or returns a typed error, and after a successful update the patches equal
//! those of a fresh build of the same pose, bit for bit. Any panic is a bug.
#![no_main]

use glam::DVec3;
use smoothtri::{BuildOptions, LineField, OwnedScene, Vertices};

/// At most this many triangles go into the scene (the rest of a large mesh is cut off).
const MAX_TRIANGLES: usize = 512;

fn packed(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = if data.starts_with(b"glTF") {
        "/nonexistent-smoothtri-fuzz/input.glb"
    } else {
        "/nonexistent-smoothtri-fuzz/input.gltf"
    };
    let Ok(mut anim) = smoothtri_io::parse_animated(data, path) else {
        return;
    };
    let n = anim.mesh().positions.len();
    let triangles: Vec<[u32; 3]> = anim
        .mesh()
        .triangles
        .iter()
        .take(MAX_TRIANGLES)
        .copied()
        .collect();
    assert!(
        triangles.iter().flatten().all(|&i| (i as usize) < n),
        "index out of range"
    );
    let mut times: Vec<(Option<usize>, f64)> = vec![(None, 0.0)];
    for (c, clip) in anim.clips().iter().enumerate().take(3) {
        let d = clip.duration;
        assert!(d.is_finite() && d >= 0.0, "clip {c}: duration {d}");
        times.extend([-1.0, 0.0, 0.37 * d, d, d + 1.0].map(|t| (Some(c), t)));
    }
    let mut positions = vec![DVec3::ZERO; n];
    let mut normals = vec![DVec3::ZERO; n];
    let mut options = BuildOptions {
        field: LineField::Face,
        seams: true,
        ..BuildOptions::default()
    };
    let mut scene: Option<OwnedScene<f64>> = None;
    for (clip, t) in times {
        let posed = match clip {
            None => anim.pose_rest(&mut positions, &mut normals),
            Some(c) => anim.pose(c, t, &mut positions, &mut normals),
        };
        if posed.is_err() {
            continue;
        }
        assert!(positions.iter().all(|p| p.is_finite()), "non-finite pose");
        // A normal normalised in f64 is unit within a few ulps (about 1e-15); 1e-9 is that
        // bound with room, far below any real error (a skipped normalisation is off by O(1)).
        for v in &normals {
            let l = v.length();
            assert!(
                l == 0.0 || (l - 1.0).abs() < 1e-9,
                "normal of length {l} at {clip:?}, t = {t}"
            );
        }
        let (p, nn) = (packed(&positions), packed(&normals));
        match &mut scene {
            None => {
                scene = OwnedScene::build(
                    Vertices::packed(&p),
                    Vertices::packed(&nn),
                    &triangles,
                    &mut options,
                )
                .ok();
            }
            Some(s) => {
                if s.update(Vertices::packed(&p), Vertices::packed(&nn), &mut options)
                    .is_err()
                {
                    continue;
                }
                if let Ok(fresh) = OwnedScene::<f64>::build(
                    Vertices::packed(&p),
                    Vertices::packed(&nn),
                    &triangles,
                    &mut options,
                ) {
                    assert_eq!(
                        s.scene().patches(),
                        fresh.scene().patches(),
                        "an update differs from a fresh build"
                    );
                }
            }
        }
    }
});
