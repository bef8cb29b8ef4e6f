//! Every malformed-animation error, and corrupted animated files, on the GLBs of
//! [`super::tests`].

use glam::DVec3;

use super::tests::{
    Data, JOINTS, WEIGHTS, assert_close, morphed, pose, rigid, skinned, skinned_glb,
};
use super::*;
use crate::glb;
use crate::gltf::scene_tests::Doc;

/// The error of parsing `bytes` as `a.glb`, without the file prefix.
fn error(bytes: &[u8]) -> String {
    let e = parse_animated(bytes, "a.glb")
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("a.glb: "), "{e}");
    assert!(!e.contains('\n'), "{e}");
    e["a.glb: ".len()..].to_string()
}

#[test]
fn malformed_skins_are_errors_naming_the_field() {
    // A joint index past the skin's two joints.
    let mut j = JOINTS;
    j[8] = 2;
    assert_eq!(
        error(&skinned_glb(&j, &WEIGHTS, |s| s)),
        "node 0, mesh 0, primitive 0: JOINTS_n names joint 2, outside skin 0's 2 joints (drawn by node 0)"
    );
    // Weights that sum to 0.9.
    let mut w = WEIGHTS;
    w[8] = 0.4;
    let e = error(&skinned_glb(&JOINTS, &w, |s| s));
    assert!(
        e.starts_with("node 0, mesh 0, primitive 0: the weights of vertex 2 sum to 0.9"),
        "{e}"
    );
    assert!(e.ends_with("not 1 (tolerance 0.002)"), "{e}");
    // Within the tolerance: accepted and renormalised (the blend is still affine).
    let mut w = WEIGHTS;
    w[8] = 0.5005;
    let mut a = parse_animated(&skinned_glb(&JOINTS, &w, |s| s), "a.glb").unwrap();
    let m = pose(&mut a, 0, 0.0);
    assert_close(m.positions[2], DVec3::new(1.0, 1.0, 0.0), "renormalised");
    // A negative weight.
    let mut w = WEIGHTS;
    w[8] = -0.5;
    w[9] = 1.5;
    assert!(
        error(&skinned_glb(&JOINTS, &w, |s| s)).ends_with("vertex 2 has the negative weight -0.5")
    );
    // A non-finite weight.
    let mut w = WEIGHTS;
    w[8] = f32::NAN;
    assert!(
        error(&skinned_glb(&JOINTS, &w, |s| s))
            .ends_with("WEIGHTS_0 accessor 4: element 2 is not finite")
    );
    // JOINTS_0 without WEIGHTS_0; no influences at all on a skinned node.
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(r#","WEIGHTS_0":4"#, "", 1)
    }));
    assert!(e.ends_with("JOINTS_0 has no WEIGHTS_0"), "{e}");
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(r#","JOINTS_0":3,"WEIGHTS_0":4"#, "", 1)
    }));
    assert!(e.ends_with("the node has a skin but the primitive has no JOINTS_0 and WEIGHTS_0"));
    // Joints as floats: an unsupported accessor type.
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(r#""JOINTS_0":3"#, r#""JOINTS_0":4"#, 1)
    }));
    assert!(
        e.ends_with("JOINTS_0 accessor 4 holds Vec4 of F32, expected Vec4 of U8 or U16"),
        "{e}"
    );
    // Too few inverse bind matrices (the accessor is cut to one).
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(
            r#""count":2,"type":"MAT4""#,
            r#""count":1,"type":"MAT4""#,
            1,
        )
    }));
    assert_eq!(
        e,
        "skin 0: inverseBindMatrices accessor 5 has 1 matrices for 2 joints"
    );
}

#[test]
fn malformed_samplers_are_errors_naming_the_channel() {
    let at = "animation 0, channel 0 (node 2 rotation), sampler 0";
    // A NaN key.
    let bytes = skinned_glb(&JOINTS, &WEIGHTS, |s| s);
    let mut g = bytes.clone();
    // The rotation output is the last accessor: poison its last float.
    let end = g.len();
    g[end - 4..].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        error(&g),
        format!("{at}: output accessor 7: element 1 is not finite")
    );
    // Output count that does not match the input's.
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(
            r#""count":2,"type":"VEC4""#,
            r#""count":1,"type":"VEC4""#,
            1,
        )
    }));
    assert_eq!(
        e,
        format!("{at}: output accessor 7 has 1 values for 2 key times (1 per key)")
    );
    // CUBICSPLINE wants three values per key.
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(
            r#""output":7}"#,
            r#""output":7,"interpolation":"CUBICSPLINE"}"#,
            1,
        )
    }));
    assert_eq!(
        e,
        format!("{at}: output accessor 7 has 2 values for 2 key times (3 per key)")
    );
    // A rotation output of the wrong type (VEC3).
    let e = error(&skinned_glb(&JOINTS, &WEIGHTS, |s| {
        s.replacen(r#""output":7"#, r#""output":1"#, 1)
    }));
    assert_eq!(
        e,
        format!(
            "{at}: output accessor 1 holds Vec3 of F32, expected Vec4 of F32 or normalized I8, U8, I16 or U16"
        )
    );
}

#[test]
fn key_times_must_increase() {
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let t = d.f32s(&[0.0, 1.0, 1.0], "SCALAR");
    let v = d.f32s(&[0.0; 9], "VEC3");
    let t_ok = d.f32s(&[0.0, 1.0, 2.0], "SCALAR");
    let z = d.f32s(&[0.0; 12], "VEC4");
    let bytes = |sampler: &str| {
        d.glb(&format!(
            r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}],
"animations":[{{"name":"walk","channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}}],"samplers":[{sampler}]}}]"#
        ))
    };
    assert_eq!(
        error(&bytes(&format!(r#"{{"input":{t},"output":{v}}}"#))),
        r#"animation 0 "walk", channel 0 (node 0 translation), sampler 0: input accessor 1: key time 2 (1 s) is not after key time 1 (1 s): times must increase"#
    );
    // A zero quaternion as a rotation key.
    let e = error(&bytes(&format!(r#"{{"input":{t_ok},"output":{z}}}"#)).replace_channel());
    assert_eq!(
        e,
        r#"animation 0 "walk", channel 0 (node 0 rotation), sampler 0: output accessor 4: rotation key 0 is not a unit quaternion"#
    );
}

/// Swaps the channel path of a test GLB from translation to rotation (the GLB rebuilt).
trait ReplaceChannel {
    fn replace_channel(&self) -> Vec<u8>;
}

impl ReplaceChannel for Vec<u8> {
    fn replace_channel(&self) -> Vec<u8> {
        let g = glb::parse(self).unwrap();
        let json = String::from_utf8_lossy(g.json).trim_end().replacen(
            r#""path":"translation""#,
            r#""path":"rotation""#,
            1,
        );
        glb::build(json.as_bytes(), g.bin)
    }
}

#[test]
fn channels_break_the_specification_s_rules_with_an_error() {
    let with = |edit: &dyn Fn(String) -> String| error(&skinned_glb(&JOINTS, &WEIGHTS, edit));
    // A node index out of range (the gltf crate does not validate channel targets).
    assert_eq!(
        with(&|s: String| s.replacen(r#""node":2,"path""#, r#""node":9,"path""#, 1)),
        "animation 0, channel 0 (node 9 rotation): node 9 does not exist"
    );
    // An unknown path.
    assert_eq!(
        with(&|s: String| s.replacen(r#""path":"rotation""#, r#""path":"colour""#, 1)),
        "animation 0, channel 0: its target path is not valid"
    );
    // Weights on a node without morph targets.
    assert_eq!(
        with(&|s: String| s.replacen(r#""path":"rotation""#, r#""path":"weights""#, 1)),
        "animation 0, channel 0 (node 2 weights): the node has no mesh with morph targets"
    );
    // Two channels on one target.
    let e = with(&|s: String| {
        s.replacen(
            r#""channels":[{"sampler":0,"target":{"node":2,"path":"rotation"}}]"#,
            r#""channels":[{"sampler":0,"target":{"node":2,"path":"rotation"}},{"sampler":0,"target":{"node":2,"path":"rotation"}}]"#,
            1,
        )
    });
    assert_eq!(
        e,
        "animation 0, channel 1 (node 2 rotation): a second channel of the animation targets it"
    );
    // An animated node with a matrix.
    assert_eq!(
        with(&|s: String| s.replacen(
            r#"{"translation":[0,1,0]}"#,
            r#"{"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,1,0,1]}"#,
            1
        )),
        "animation 0, channel 0 (node 2 rotation): the node has a matrix (an animated node must have translation, rotation and scale)"
    );
    // A sampler input that is not an accessor: the document's validation names the field.
    assert_eq!(
        with(&|s: String| s.replacen(r#""input":6"#, r#""input":60"#, 1)),
        "malformed glTF: invalid glTF: animations[0].samplers[0].input: Index out of bounds;"
    );
}

#[test]
fn malformed_morph_targets_are_errors() {
    let bytes = morphed(true);
    let g = glb::parse(&bytes).unwrap();
    let json = String::from_utf8_lossy(g.json).trim_end().to_string();
    let with = |from: &str, to: &str| {
        assert!(json.contains(from), "{from}");
        error(&glb::build(json.replacen(from, to, 1).as_bytes(), g.bin))
    };
    // A node's weights of the wrong length.
    assert_eq!(
        with(r#""weights":[0,1]"#, r#""weights":[0,1,0]"#),
        "node 1: the node's weights has 3 values for 2 morph targets"
    );
    // A target's deltas of another count than the primitive's vertices (the first view holds
    // three positions; the delta accessor is cut to two).
    let e = with(
        r#""bufferView":2,"componentType":5126,"count":3"#,
        r#""bufferView":2,"componentType":5126,"count":2"#,
    );
    assert_eq!(
        e,
        "node 0, mesh 0, primitive 0: target 0 POSITION accessor 2 has 2 elements for 3 vertices"
    );
    // Animated weights: one key of two targets per key time expected, one value given.
    let e = with(
        r#""componentType":5126,"count":4,"type":"SCALAR""#,
        r#""componentType":5126,"count":3,"type":"SCALAR""#,
    );
    assert_eq!(
        e,
        "animation 0, channel 0 (node 0 weights), sampler 0: output accessor 6 has 3 values for 2 key times (2 per key of 2 morph targets)"
    );
}

/// Random byte corruptions of animated GLBs (the skin, the morph targets) load or fail with an
/// error, and whatever loads poses (or fails to) without panicking, at many times.
#[test]
fn corrupted_animated_glbs_never_panic() {
    let goods = [
        skinned(&JOINTS, &WEIGHTS),
        morphed(true),
        morphed(false),
        rigid(),
    ];
    for good in goods {
        for b in crate::gltf::corruptions(&good, 0x2545_f491_4f6c_dd1d, 1500) {
            let Ok(mut a) = parse_animated(&b, "/nonexistent-smoothtri-test/a.glb") else {
                continue;
            };
            let _ = a.posed_mesh(None, 0.0);
            for c in 0..a.clips().len() {
                for t in [-1.0, 0.0, 0.3, 0.5, 1.0, 7.0] {
                    let _ = a.posed_mesh(Some(c), t);
                }
            }
        }
    }
}
