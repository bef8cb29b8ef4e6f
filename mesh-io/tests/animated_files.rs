//! The two animated glTF files of Debian's `assimp-testmodels`, posed against poses computed
//! by hand from their data: `glTF2/simple_skin/simple_skin.gltf` (a two-joint skin, no
//! normals) and `glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf` (two
//! morph targets with normals). Skipped when the package is missing, unless
//! `SMOOTHTRI_REQUIRE_ASSETS` is set (`smoothtri_testkit::assimp_models`).

use std::path::PathBuf;

use glam::{DQuat, DVec3};
use smoothtri_io::{AnimatedMesh, Mesh, angle_weighted_normals};

/// The file under the assimp models, or `None` (skipped).
fn asset(rel: &str) -> Option<PathBuf> {
    let root = smoothtri_testkit::assimp_models().unwrap()?;
    let p = root.join(rel);
    assert!(p.is_file(), "{} is missing", p.display());
    Some(p)
}

const SKIN: &str = "glTF2/simple_skin/simple_skin.gltf";
const MORPH: &str = "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";

fn load(p: &std::path::Path) -> (AnimatedMesh, Mesh) {
    let path = p.to_str().unwrap();
    let anim = smoothtri_io::load_animated(path).unwrap();
    let stat = smoothtri_io::load(path).unwrap().mesh;
    (anim, stat)
}

/// The same vertices, normals and triangles as the static loader's.
fn assert_static(anim: &AnimatedMesh, stat: &Mesh) {
    assert_eq!(anim.mesh().triangles, stat.triangles);
    assert_eq!(anim.mesh().positions, stat.positions);
    assert_eq!(anim.mesh().normals, stat.normals);
}

/// Poses at 97 times over the clip and past its ends: finite, unit normals.
fn assert_sane(anim: &mut AnimatedMesh) {
    let d = anim.clips()[0].duration;
    for k in 0..=96 {
        let t = -0.5 + k as f64 * (d + 1.0) / 96.0;
        let m = anim.posed_mesh(Some(0), t).unwrap();
        assert!(m.positions.iter().all(|p| p.is_finite()), "t = {t}");
        for n in &m.normals {
            assert!((n.length() - 1.0).abs() < 1e-12, "t = {t}: {n}");
        }
    }
}

/// simple_skin: vertices at x ∈ {0, 1}, y ∈ {0, 0.5, …, 2}; joint 0 is node 1 (at y = 1),
/// joint 1 its child node 2, whose rotation about z is animated (keys every 0.5 s: 0°, 45°,
/// 90°, 90°, 45°, 0°, 0°, −45°, −90°, −90°, −45°, 0°, where "45°" is stored as the rounded
/// quaternion (0, 0, ±0.383, 0.924), [`Q45`]); both inverse bind matrices translate by
/// (−0.5, −1, 0); a vertex's weights are (1 − y/2, y/2). So a vertex `v` is posed at
/// `(1 − y/2)·(v − (0.5, 0, 0)) + (y/2)·((0, 1, 0) + R(θ)(v − (0.5, 1, 0)))`.
fn skin_pose(v: DVec3, deg: f64) -> DVec3 {
    let w1 = v.y / 2.0;
    let r = DQuat::from_rotation_z(deg.to_radians());
    (v - DVec3::new(0.5, 0.0, 0.0)) * (1.0 - w1)
        + (DVec3::Y + r * (v - DVec3::new(0.5, 1.0, 0.0))) * w1
}

/// The angle (degrees) of the file's "45°" keys, (0, 0, 0.383, 0.924) in `f32`.
fn q45() -> f64 {
    2.0 * f64::from(0.383f32).atan2(f64::from(0.924f32)).to_degrees()
}

#[test]
fn simple_skin_poses_as_its_joints_say() {
    let Some(p) = asset(SKIN) else { return };
    let (mut anim, stat) = load(&p);
    assert_static(&anim, &stat);
    assert!(anim.computed_normals() && anim.is_deformable());
    assert_eq!(anim.clips().len(), 1);
    assert_eq!(anim.clips()[0].duration, 5.5);
    assert_eq!(stat.positions.len(), 10);
    // Key times and times between keys (slerp: the angle halfway, a quarter of the way).
    let q45 = q45();
    assert!((q45 - 45.0).abs() < 0.05);
    for (t, deg) in [
        (0.0, 0.0),
        (0.25, q45 / 2.0),
        (0.5, q45),
        (0.625, q45 + 0.25 * (90.0 - q45)),
        (1.0, 90.0),
        (1.25, 90.0),
        (3.25, -q45 / 2.0),
        (4.0, -90.0),
        (5.5, 0.0),
        (9.0, 0.0),
    ] {
        let m = anim.posed_mesh(Some(0), t).unwrap();
        for (k, v) in stat.positions.iter().enumerate() {
            let want = skin_pose(*v, deg);
            assert!(
                (m.positions[k] - want).length() < 1e-12,
                "t = {t}, vertex {v}: {} vs {want}",
                m.positions[k]
            );
        }
        // Computed in every pose, as the static loader computes them from the file's.
        let want = angle_weighted_normals(
            &m.positions,
            m.triangles.iter().map(|t| t.map(|i| i as usize)),
        );
        assert_eq!(m.normals, want, "t = {t}");
    }
    // At rest (no animation) the joints' rest transforms times their inverse bind matrices
    // move the whole mesh by (−0.5, 0, 0); the static mesh is the unskinned bind geometry.
    let rest = anim.posed_mesh(None, 0.0).unwrap();
    for (a, b) in rest.positions.iter().zip(&stat.positions) {
        assert_eq!(*a, *b - DVec3::new(0.5, 0.0, 0.0));
    }
    assert_eq!(rest.normals, stat.normals);
    assert_sane(&mut anim);
}

/// The floats of buffer view `view` of the morph cube (its JSON read here, not by the loader).
fn view_f32s(json: &serde_json::Value, bin: &[u8], view: usize) -> Vec<f64> {
    let v = &json["bufferViews"][view];
    let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
    let len = v["byteLength"].as_u64().unwrap() as usize;
    bin[off..off + len]
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
        .collect()
}

fn vec3s(f: &[f64]) -> Vec<DVec3> {
    f.chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect()
}

#[test]
fn the_morph_cube_is_its_base_plus_the_weighted_deltas() {
    let Some(p) = asset(MORPH) else { return };
    let (mut anim, stat) = load(&p);
    assert_static(&anim, &stat);
    assert!(!anim.computed_normals() && anim.is_deformable());
    assert_eq!(anim.clips().len(), 1);
    assert_eq!(anim.clips()[0].name.as_deref(), Some("Square"));
    // The file's data by buffer view (accessor i uses view i): normals 0, positions 2, the
    // targets' normals 3 and 6 and positions 4 and 7, key times 10, weights 11 (two per key).
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
    let bin = std::fs::read(p.with_file_name("AnimatedMorphCube.bin")).unwrap();
    let base = vec3s(&view_f32s(&json, &bin, 2));
    let normals = vec3s(&view_f32s(&json, &bin, 0));
    let (dp0, dp1) = (
        vec3s(&view_f32s(&json, &bin, 4)),
        vec3s(&view_f32s(&json, &bin, 7)),
    );
    let (dn0, dn1) = (
        vec3s(&view_f32s(&json, &bin, 3)),
        vec3s(&view_f32s(&json, &bin, 6)),
    );
    let times = view_f32s(&json, &bin, 10);
    let weights = view_f32s(&json, &bin, 11);
    assert_eq!(weights.len(), 2 * times.len());
    assert_eq!(anim.clips()[0].duration, *times.last().unwrap());
    // The node: scale 100 and its rotation (0, 0.7071067, −0.7071068, 0), within 1e-7 the half
    // turn about (0, 1, −1)/√2, (x, y, z) → (−x, −z, −y).
    let r: Vec<f64> = json["nodes"][0]["rotation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| f64::from(x.as_f64().unwrap() as f32))
        .collect();
    let q = DQuat::from_xyzw(r[0], r[1], r[2], r[3]).normalize();
    let v = DVec3::new(0.3, -0.5, 0.8);
    assert!((q * v - DVec3::new(-v.x, -v.z, -v.y)).length() < 1e-6);
    let world = |v: DVec3| (q * v) * 100.0;
    let turn = |n: DVec3| (q * n).normalize();
    // Which static vertex is file vertex i: the one at its rest place with its rest normal.
    let order: Vec<usize> = (0..base.len())
        .map(|i| {
            (0..stat.positions.len())
                .find(|&k| {
                    (stat.positions[k] - world(base[i])).length() < 1e-5
                        && (stat.normals[k] - turn(normals[i])).length() < 1e-5
                })
                .unwrap()
        })
        .collect();
    let n = times.len();
    for key in [0, 1, n / 4, n / 2, 3 * n / 4, n - 2, n - 1] {
        let (w0, w1) = (weights[2 * key], weights[2 * key + 1]);
        let m = anim.posed_mesh(Some(0), times[key]).unwrap();
        for (i, &k) in order.iter().enumerate() {
            let want = world(base[i] + dp0[i] * w0 + dp1[i] * w1);
            assert!(
                (m.positions[k] - want).length() < 1e-12,
                "key {key}, vertex {i}: {} vs {want}",
                m.positions[k]
            );
            let wn = turn(normals[i] + dn0[i] * w0 + dn1[i] * w1);
            assert!(
                (m.normals[k] - wn).length() < 1e-12,
                "key {key}, vertex {i}: normal {} vs {wn}",
                m.normals[k]
            );
        }
    }
    // Halfway between two keys: the weights halfway (linear).
    let key = n / 2;
    let t = 0.5 * (times[key] + times[key + 1]);
    let m = anim.posed_mesh(Some(0), t).unwrap();
    for (i, &k) in order.iter().enumerate() {
        let w0 = 0.5 * (weights[2 * key] + weights[2 * key + 2]);
        let w1 = 0.5 * (weights[2 * key + 1] + weights[2 * key + 3]);
        let want = world(base[i] + dp0[i] * w0 + dp1[i] * w1);
        assert!((m.positions[k] - want).length() < 1e-12, "vertex {i}");
    }
    // The rest pose (the mesh's default weights, zeros) is the static mesh, bit for bit.
    let rest = anim.posed_mesh(None, 0.0).unwrap();
    assert_eq!(rest.positions, stat.positions);
    assert_eq!(rest.normals, stat.normals);
    assert_sane(&mut anim);
}
