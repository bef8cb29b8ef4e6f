//! Posing against hand-computed poses on small GLBs written by [`Doc`], and those GLBs (also
//! the documents of the [`super::error_tests`]).

use glam::{DMat3, DQuat, DVec3};

use super::pose::{normal_matrix, signed_cofactor};
use super::*;
use crate::gltf::scene_tests::Doc;
use crate::{angle_weighted_normals, glb};

/// Components per element of `ty`.
fn width(ty: &str) -> usize {
    match ty {
        "SCALAR" => 1,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT4" => 16,
        _ => panic!("{ty}"),
    }
}

/// The test documents' accessors of floats and unsigned shorts, the count from the length.
pub(super) trait Data {
    fn f32s(&mut self, v: &[f32], ty: &str) -> usize;
    fn u16s(&mut self, v: &[u16], ty: &str) -> usize;
    /// POSITION data (with the `min`/`max` the specification asks for).
    fn positions(&mut self, v: &[[f32; 3]]) -> usize;
}

impl Data for Doc {
    fn f32s(&mut self, v: &[f32], ty: &str) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.raw(&bytes, 5126, v.len() / width(ty), ty)
    }
    fn u16s(&mut self, v: &[u16], ty: &str) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.raw(&bytes, 5123, v.len() / width(ty), ty)
    }
    fn positions(&mut self, v: &[[f32; 3]]) -> usize {
        self.vec3(v)
    }
}

pub(super) fn pose(a: &mut AnimatedMesh, clip: usize, t: f64) -> Mesh {
    a.posed_mesh(Some(clip), t).unwrap()
}

pub(super) fn assert_close(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).length() < 1e-12, "{what}: {a} vs {b}");
}

/// The quaternion (`x y z w`, f32) of a turn by `deg` degrees about `axis`.
fn turn(axis: DVec3, deg: f64) -> [f32; 4] {
    DQuat::from_axis_angle(axis, deg.to_radians())
        .to_array()
        .map(|x| x as f32)
}

/// A triangle (POSITION, NORMAL +z) on node 1 under node 0; node 0's translation and node 1's
/// rotation are animated (LINEAR), both nodes have other rest values.
pub(super) fn rigid() -> Vec<u8> {
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let n = d.f32s(&[0.0, 0.0, 1.0].repeat(3), "VEC3");
    let t2 = d.f32s(&[0.0, 2.0], "SCALAR");
    let t1 = d.f32s(&[0.0, 1.0], "SCALAR");
    let tr = d.f32s(&[0.0, 0.0, 0.0, 4.0, 0.0, 0.0], "VEC3");
    let rot = d.f32s(
        &[turn(DVec3::X, 0.0), turn(DVec3::X, 90.0)].concat(),
        "VEC4",
    );
    let rest_rot = turn(DVec3::Z, 30.0);
    d.glb(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"children":[1],"translation":[5,0,0]}},{{"mesh":0,"rotation":{rest_rot:?}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}],
"animations":[{{"name":"move","channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}},{{"sampler":1,"target":{{"node":1,"path":"rotation"}}}}],
"samplers":[{{"input":{t2},"output":{tr}}},{{"input":{t1},"output":{rot},"interpolation":"LINEAR"}}]}}]"#
    ))
}

#[test]
fn node_transforms_are_animated_down_the_hierarchy() {
    let bytes = rigid();
    let mut a = parse_animated(&bytes, "r.glb").unwrap();
    assert_eq!(a.clips().len(), 1);
    assert_eq!(a.clips()[0].name.as_deref(), Some("move"));
    assert_eq!(a.clips()[0].duration, 2.0);
    assert!(!a.is_deformable());
    // t = 1: node 0 at (2, 0, 0), node 1 turned 90° about x (its key 1): (x, y, z) → (x, −z, y).
    let m = pose(&mut a, 0, 1.0);
    assert_close(m.positions[0], DVec3::new(2.0, 0.0, 0.0), "v0");
    assert_close(m.positions[1], DVec3::new(3.0, 0.0, 0.0), "v1");
    assert_close(m.positions[2], DVec3::new(2.0, 0.0, 1.0), "v2");
    for n in &m.normals {
        assert_close(*n, DVec3::new(0.0, -1.0, 0.0), "normal");
    }
    // t = 0.5: translation (1, 0, 0), the turn halfway (45°, slerp).
    let m = pose(&mut a, 0, 0.5);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_close(m.positions[2], DVec3::new(1.0, h, h), "v2 at 0.5");
    // Past the end: the last keys.
    let m = pose(&mut a, 0, 10.0);
    assert_close(m.positions[2], DVec3::new(4.0, 0.0, 1.0), "v2 clamped");
}

#[test]
fn the_rest_pose_of_a_rigid_mesh_is_the_static_mesh_bit_for_bit() {
    let bytes = rigid();
    let mut a = parse_animated(&bytes, "r.glb").unwrap();
    let stat = crate::gltf::parse(&bytes, "r.glb").unwrap().mesh;
    assert_eq!(a.mesh().triangles, stat.triangles);
    assert_eq!(a.mesh().positions, stat.positions);
    let m = a.posed_mesh(None, 0.0).unwrap();
    assert_eq!(m.positions, stat.positions);
    assert_eq!(m.normals, stat.normals);
    assert_eq!(m.triangles, stat.triangles);
}

/// A triangle with two morph targets (POSITION and NORMAL deltas on the first, POSITION on the
/// second), default weights (0.5, 0), drawn by node 0 (scale 2, weights animated by STEP keys)
/// and node 1 (its own weights (0, 1)); `normals` says whether it has NORMAL.
pub(super) fn morphed(normals: bool) -> Vec<u8> {
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let n = d.f32s(&[0.0, 0.0, 1.0].repeat(3), "VEC3");
    let d0p = d.f32s(&[0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "VEC3");
    let d0n = d.f32s(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "VEC3");
    let d1p = d.f32s(&[0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0], "VEC3");
    let t = d.f32s(&[0.0, 1.0], "SCALAR");
    let w = d.f32s(&[0.25, 0.75, 1.0, 0.0], "SCALAR");
    let normal = if normals {
        format!(r#","NORMAL":{n}"#)
    } else {
        String::new()
    };
    d.glb(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"scale":[2,2,2]}},{{"mesh":0,"translation":[0,0,10],"weights":[0,1]}}],
"meshes":[{{"weights":[0.5,0],"primitives":[{{"attributes":{{"POSITION":{p}{normal}}},
"targets":[{{"POSITION":{d0p},"NORMAL":{d0n}}},{{"POSITION":{d1p}}}]}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"weights"}}}}],
"samplers":[{{"input":{t},"output":{w},"interpolation":"STEP"}}]}}]"#
    ))
}

#[test]
fn morph_targets_add_their_weighted_deltas() {
    let mut a = parse_animated(&morphed(true), "m.glb").unwrap();
    assert!(a.is_deformable());
    assert_eq!(a.mesh().positions.len(), 6);
    // Rest: node 0 with the mesh's weights (0.5, 0), node 1 with its own (0, 1).
    let m = a.posed_mesh(None, 0.0).unwrap();
    assert_close(m.positions[0], DVec3::new(0.0, 0.0, 1.0), "node 0 v0");
    assert_close(m.positions[1], DVec3::new(2.0, 0.0, 0.0), "node 0 v1");
    assert_close(m.normals[0], DVec3::new(0.5, 0.0, 1.0).normalize(), "n0");
    assert_close(m.normals[1], DVec3::Z, "n1");
    assert_close(m.positions[4], DVec3::new(1.0, 0.0, 12.0), "node 1 v1");
    assert_close(m.positions[3], DVec3::new(0.0, 0.0, 10.0), "node 1 v0");
    // STEP: until t = 1 the first key's weights (0.25, 0.75), then (1, 0).
    let m = pose(&mut a, 0, 0.99);
    assert_close(m.positions[0], DVec3::new(0.0, 0.0, 0.5), "v0 at 0.99");
    assert_close(m.positions[1], DVec3::new(2.0, 0.0, 3.0), "v1 at 0.99");
    assert_close(
        m.normals[0],
        DVec3::new(0.25, 0.0, 1.0).normalize(),
        "n0 at 0.99",
    );
    let m = pose(&mut a, 0, 1.0);
    assert_close(m.positions[0], DVec3::new(0.0, 0.0, 2.0), "v0 at 1");
    assert_close(m.positions[1], DVec3::new(2.0, 0.0, 0.0), "v1 at 1");
    // Node 1 is not animated: its own weights at every time.
    assert_close(m.positions[4], DVec3::new(1.0, 0.0, 12.0), "node 1 v1 at 1");
}

#[test]
fn without_normals_each_pose_gets_angle_weighted_normals() {
    let bytes = morphed(false);
    let mut a = parse_animated(&bytes, "m.glb").unwrap();
    assert!(a.computed_normals());
    // The target's NORMAL deltas are ignored, with a warning.
    assert!(
        a.warnings()
            .iter()
            .any(|w| w.contains("NORMAL deltas ignored")),
        "{:?}",
        a.warnings()
    );
    for t in [0.0, 0.5, 1.0] {
        let m = pose(&mut a, 0, t);
        let want = angle_weighted_normals(
            &m.positions,
            m.triangles.iter().map(|t| t.map(|i| i as usize)),
        );
        assert_eq!(m.normals, want, "t = {t}");
    }
    // Rest: node 0's first target at weight 0.5 lifts vertex 0, so the posed triangle (0, 0, 1),
    // (2, 0, 0), (0, 2, 0) lies in the plane x/2 + y/2 + z = 1: every corner gets its normal.
    let m = a.posed_mesh(None, 0.0).unwrap();
    for k in 0..3 {
        assert_close(
            m.normals[k],
            DVec3::new(0.5, 0.5, 1.0).normalize(),
            "rest normal",
        );
    }
}

/// Six vertices on the strip x ∈ {0, 1}, y ∈ {0, 1, 2} (four triangles), normals +z, skinned
/// to joint 0 (node 1, at the origin) and joint 1 (node 2, its child at y = 1): the bottom row
/// to joint 0, the middle half and half, the top to joint 1. Node 2 turns about x by 90° over
/// one second (LINEAR). The skinned node 0 is translated by 100 (ignored, as the specification
/// requires). `joints` and `weights` are the influences.
pub(super) fn skinned(joints: &[u16], weights: &[f32]) -> Vec<u8> {
    let mut d = Doc::default();
    let p = d.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 2.0, 0.0],
        [1.0, 2.0, 0.0],
    ]);
    let n = d.f32s(&[0.0, 0.0, 1.0].repeat(6), "VEC3");
    let i = d.u16s(&[0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4], "SCALAR");
    let j = d.u16s(joints, "VEC4");
    let w = d.f32s(weights, "VEC4");
    #[rustfmt::skip]
    let ibm = d.f32s(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0,
    ], "MAT4");
    let t = d.f32s(&[0.0, 1.0], "SCALAR");
    let r = d.f32s(
        &[turn(DVec3::X, 0.0), turn(DVec3::X, 90.0)].concat(),
        "VEC4",
    );
    d.glb(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"skin":0,"translation":[100,0,0]}},{{"children":[2]}},{{"translation":[0,1,0]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n},"JOINTS_0":{j},"WEIGHTS_0":{w}}},"indices":{i}}}]}}],
"skins":[{{"joints":[1,2],"inverseBindMatrices":{ibm}}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":2,"path":"rotation"}}}}],
"samplers":[{{"input":{t},"output":{r}}}]}}]"#
    ))
}

/// [`skinned`]'s document with its JSON rewritten by `edit` (the GLB rebuilt around it).
pub(super) fn skinned_glb(
    joints: &[u16],
    weights: &[f32],
    edit: impl Fn(String) -> String,
) -> Vec<u8> {
    let bytes = skinned(joints, weights);
    let g = glb::parse(&bytes).unwrap();
    let json = edit(String::from_utf8_lossy(g.json).trim_end().to_string());
    glb::build(json.as_bytes(), g.bin)
}

pub(super) const JOINTS: [u16; 24] = [
    0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0,
];
#[rustfmt::skip]
pub(super) const WEIGHTS: [f32; 24] = [
    1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
    0.5, 0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0,
    0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
];

#[test]
fn skins_blend_their_joints_matrices() {
    let bytes = skinned_glb(&JOINTS, &WEIGHTS, |s| s);
    let mut a = parse_animated(&bytes, "s.glb").unwrap();
    assert!(a.is_deformable());
    // Rest: every joint matrix is the identity (joint 1's bind pose is its rest pose), and the
    // skinned node's translation by 100 is ignored, so the rest pose is the file's positions,
    // which the static loader moves by 100.
    let stat = crate::gltf::parse(&bytes, "s.glb").unwrap().mesh;
    let rest = a.posed_mesh(None, 0.0).unwrap();
    for (p, q) in rest.positions.iter().zip(&stat.positions) {
        assert_close(*p + DVec3::new(100.0, 0.0, 0.0), *q, "rest");
    }
    // t = 1: joint 1 turned 90° about x around (0, 1, 0): (x, y, z) → (x, 1 − z, y − 1).
    let m = pose(&mut a, 0, 1.0);
    let at = |x: f64, y: f64| {
        (0..6)
            .find(|&k| stat.positions[k] == DVec3::new(x + 100.0, y, 0.0))
            .unwrap()
    };
    // The top row follows joint 1: (1, 2, 0) → (1, 1, 1), its normal +z → (0, −1, 0).
    assert_close(m.positions[at(1.0, 2.0)], DVec3::new(1.0, 1.0, 1.0), "top");
    assert_close(
        m.normals[at(1.0, 2.0)],
        DVec3::new(0.0, -1.0, 0.0),
        "top normal",
    );
    // The bottom row stays.
    assert_close(
        m.positions[at(1.0, 0.0)],
        DVec3::new(1.0, 0.0, 0.0),
        "bottom",
    );
    assert_close(m.normals[at(1.0, 0.0)], DVec3::Z, "bottom normal");
    // The middle row, half and half: both joints leave (1, 1, 0) in place; the blended matrix
    // is ½(I + R), a non-uniform map whose inverse transpose turns +z by 45° about x.
    assert_close(
        m.positions[at(1.0, 1.0)],
        DVec3::new(1.0, 1.0, 0.0),
        "middle",
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_close(
        m.normals[at(1.0, 1.0)],
        DVec3::new(0.0, -h, h),
        "middle normal",
    );
    // Halfway (45°, slerp), the top vertex: (1, 1, 0) about the joint → (1, cos 45°, sin 45°).
    let m = pose(&mut a, 0, 0.5);
    assert_close(
        m.positions[at(0.0, 2.0)],
        DVec3::new(0.0, 1.0 + h, h),
        "top at 0.5",
    );
    // Every normal unit length at many times.
    for k in 0..=40 {
        let m = pose(&mut a, 0, k as f64 * 0.03);
        for n in &m.normals {
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
    }
}

#[test]
fn cubic_spline_translations_follow_the_hermite_curve() {
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let t = d.f32s(&[0.0, 1.0], "SCALAR");
    // Per key: in-tangent, value, out-tangent. x(u) = 4u³ − 6u² + 3u: x(0) = 0, x(1) = 1,
    // x'(0) = x'(1) = 3.
    #[rustfmt::skip]
    let v = d.f32s(&[
        0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  3.0, 0.0, 0.0,
        3.0, 0.0, 0.0,  1.0, 0.0, 0.0,  0.0, 0.0, 0.0,
    ], "VEC3");
    let bytes = d.glb(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}}],
"samplers":[{{"input":{t},"output":{v},"interpolation":"CUBICSPLINE"}}]}}]"#
    ));
    let mut a = parse_animated(&bytes, "c.glb").unwrap();
    for u in [0.0, 0.25, 0.5, 0.8, 1.0] {
        let m = pose(&mut a, 0, u);
        let x = 4.0 * u * u * u - 6.0 * u * u + 3.0 * u;
        assert!(
            (m.positions[0].x - x).abs() < 1e-15,
            "{u}: {}",
            m.positions[0]
        );
    }
}

#[test]
fn pose_errors_are_typed() {
    let mut a = parse_animated(&rigid(), "r.glb").unwrap();
    let n = a.mesh().positions.len();
    let (mut p, mut q) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
    assert_eq!(
        a.pose(1, 0.0, &mut p, &mut q),
        Err(PoseError::NoClip { clip: 1, clips: 1 })
    );
    assert!(matches!(
        a.pose(0, f64::NAN, &mut p, &mut q),
        Err(PoseError::Time(t)) if t.is_nan()
    ));
    let e = a.pose(0, 0.0, &mut p[..2], &mut q).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the mesh has 3 vertices; the buffers hold 2 positions and 3 normals"
    );
    // A pose that overflows f64: eight nested nodes, each scaled by 3e38 by the animation (at
    // rest by 1), over a vertex at 1e10.
    let mut d = Doc::default();
    let pos = d.positions(&[[0.0, 0.0, 0.0], [1e10, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let t = d.f32s(&[0.0], "SCALAR");
    let s = d.f32s(&[3e38, 3e38, 3e38], "VEC3");
    let nodes: Vec<String> = (0..8)
        .map(|k| format!(r#"{{"children":[{}]}}"#, k + 1))
        .chain([r#"{"mesh":0}"#.to_string()])
        .collect();
    let channels: Vec<String> = (0..8)
        .map(|k| format!(r#"{{"sampler":0,"target":{{"node":{k},"path":"scale"}}}}"#))
        .collect();
    let bytes = d.glb(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos}}}}}]}}],
"animations":[{{"channels":[{}],"samplers":[{{"input":{t},"output":{s}}}]}}]"#,
        nodes.join(","),
        channels.join(",")
    ));
    let mut a = parse_animated(&bytes, "o.glb").unwrap();
    assert!(a.posed_mesh(None, 0.0).is_ok());
    assert_eq!(
        a.posed_mesh(Some(0), 0.0).unwrap_err(),
        PoseError::NonFinite { vertex: 1 }
    );
}

#[test]
fn the_normal_matrix_is_the_inverse_transpose_or_the_signed_cofactor() {
    let m = DMat3::from_cols(
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.5, 1.0, 0.0),
        DVec3::new(0.0, 0.3, -4.0),
    );
    let n = DVec3::new(0.2, -0.7, 0.4);
    let want = (m.inverse().transpose() * n).normalize();
    assert_close((signed_cofactor(m) * n).normalize(), want, "cofactor");
    assert_close(
        (normal_matrix(m) * n).normalize(),
        want,
        "inverse transpose",
    );
    // Singular (a zero scale in x): finite, and the normal of the flattened surface.
    let flat = DMat3::from_diagonal(DVec3::new(0.0, 1.0, 1.0));
    let nm = normal_matrix(flat);
    assert!(nm.is_finite());
    assert_close((nm * DVec3::X).normalize_or_zero(), DVec3::X, "flattened");
}
