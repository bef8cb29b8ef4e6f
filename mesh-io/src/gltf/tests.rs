//! The loader's unit tests: every field checked, corrupted files never panic, GLB round trips.

use super::*;

/// `count` copies of `good`, each with one to four random bytes changed (half the time a digit
/// by a digit, so that JSON numbers change but stay numbers), from a xorshift generator seeded
/// with `seed`: the corrupted files the never-panic tests feed the loaders.
pub(crate) fn corruptions(good: &[u8], seed: u64, count: usize) -> impl Iterator<Item = Vec<u8>> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let good = good.to_vec();
    (0..count).map(move |_| {
        let mut b = good.clone();
        for _ in 0..1 + next() % 4 {
            let at = (next() % b.len() as u64) as usize;
            b[at] = if next() % 2 == 0 && b[at].is_ascii_digit() {
                b"0123456789"[(next() % 10) as usize]
            } else {
                next() as u8
            };
        }
        b
    })
}

/// The cube `[-1, 1]³` with radial unit normals, 12 triangles counter-clockwise seen from
/// outside (the data of the built-in `cube` scene).
pub(super) fn cube() -> Mesh {
    const X: [f64; 8] = [-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0];
    const Y: [f64; 8] = [-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0];
    const Z: [f64; 8] = [-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0];
    let positions: Vec<DVec3> = (0..8).map(|k| DVec3::new(X[k], Y[k], Z[k])).collect();
    Mesh {
        normals: positions.iter().map(|p| p.normalize()).collect(),
        positions,
        triangles: vec![
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
        ],
    }
}

/// [`cube`]: 8 positions, 8 normals (`f32`), 36 `u32` indices.
fn cube_bin() -> Vec<u8> {
    let m = cube();
    let mut bin = Vec::new();
    for v in m.positions.iter().chain(&m.normals) {
        for c in v.to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for t in &m.triangles {
        for i in t {
            bin.extend(i.to_le_bytes());
        }
    }
    bin
}

/// glTF JSON of [`cube_bin`] in buffer 0 (`buffer` is its JSON object); `edit` rewrites
/// the text to inject a fault.
fn cube_json(buffer: &str, edit: impl Fn(String) -> String) -> String {
    edit(format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0,"children":[1]}},{{"translation":[3,0,0]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
"buffers":[{buffer}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":96}},{{"buffer":0,"byteOffset":192,"byteLength":144}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]}},
{{"bufferView":1,"componentType":5126,"count":8,"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":36,"type":"SCALAR"}}]}}"#
    ))
}

/// A GLB of `json` and `bin`, both padded as the specification requires.
fn glb_file(json: &str, bin: &[u8]) -> Vec<u8> {
    glb::build(json.as_bytes(), Some(bin))
}

/// The cube as a glTF with its buffer in a base64 data URI, with `edit` applied.
fn embedded(edit: impl Fn(String) -> String) -> Vec<u8> {
    const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let bin = cube_bin();
    let mut b64 = String::new();
    for c in bin.chunks(3) {
        let n = c.iter().fold(0u32, |a, &x| a << 8 | x as u32) << (8 * (3 - c.len()));
        for k in 0..=c.len() {
            b64.push(B64[(n >> (18 - 6 * k) & 63) as usize] as char);
        }
    }
    let buffer = format!(
        r#"{{"uri":"data:application/octet-stream;base64,{b64}","byteLength":{}}}"#,
        bin.len()
    );
    cube_json(&buffer, edit).into_bytes()
}

fn assert_is_the_cube(m: &LoadedMesh) {
    let cube = cube();
    assert_eq!(m.mesh.triangles.len(), 12);
    assert_eq!(m.mesh.positions.len(), 8);
    assert!(!m.computed_normals && m.warnings.is_empty());
    for t in 0..12 {
        let (p, n) = m.mesh.triangle(t);
        let (q, k) = cube.triangle(t);
        for c in 0..3 {
            assert!((p[c] - q[c]).length() < 1e-6 && (n[c] - k[c]).length() < 1e-6);
        }
    }
}

#[test]
fn a_valid_glb_loads() {
    let bin = cube_bin();
    let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
    let bytes = glb_file(&json, &bin);
    assert_is_the_cube(&parse(&bytes, "cube.glb").unwrap());
    // The magic decides, not the extension.
    assert_is_the_cube(&parse(&bytes, "cube.gltf").unwrap());
}

#[test]
fn a_valid_embedded_gltf_loads() {
    assert_is_the_cube(&parse(&embedded(|s| s), "cube.gltf").unwrap());
}

#[test]
fn a_glb_with_a_bad_container_is_one_error() {
    let bin = cube_bin();
    let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
    let mut bytes = glb_file(&json, &bin);
    bytes.truncate(bytes.len() - 4);
    let e = parse(&bytes, "m.glb").unwrap_err().to_string();
    assert!(
        e.starts_with("m.glb: malformed glTF binary: the GLB header declares a length of"),
        "{e}"
    );
    let e = parse(&embedded(|s| s), "m.glb").unwrap_err().to_string();
    assert!(e.contains("not the GLB magic"), "{e}");
}

/// Documents the `gltf` crate accepts (its validation passes) but whose accessors its
/// reader would panic on, or read out of range: each is one error naming the problem.
#[test]
fn accessors_the_gltf_reader_would_panic_on_are_errors() {
    let cases: [(&str, &str, &str, &str); 7] = [
        (
            r#""componentType":5125"#,
            r#""componentType":5126"#,
            "indices accessor 2 holds Scalar of F32",
            "float indices: unreachable!() in Reader::read_indices",
        ),
        (
            r#""bufferView":1,"componentType":5126,"count":8"#,
            r#""bufferView":1,"componentType":5126,"count":0"#,
            "NORMAL accessor 1 has count 0",
            "count 0: count - 1 overflows",
        ),
        (
            r#""byteOffset":0,"byteLength":96}"#,
            r#""byteOffset":0,"byteLength":96,"byteStride":4}"#,
            "byteStride 4, less than the 12-byte elements",
            "stride below the element size: assertion",
        ),
        (
            r#""componentType":5126,"count":8,"type":"VEC3","min""#,
            r#""componentType":5121,"count":8,"type":"SCALAR","min""#,
            "POSITION accessor 0 holds Scalar of U8, expected Vec3 of F32",
            "element size mismatch: assertion",
        ),
        (
            r#""byteOffset":0,"byteLength":96}"#,
            r#""byteOffset":18446744073709551615,"byteLength":96}"#,
            "reaches past the end of buffer 0",
            "offset + length overflows",
        ),
        (
            r#""bufferView":1,"componentType":5126,"count":8,"type":"VEC3"}"#,
            r#""bufferView":1,"componentType":5126,"count":8,"type":"VEC3","sparse":{"count":0,"indices":{"bufferView":2,"componentType":5125},"values":{"bufferView":1}}}"#,
            "sparse count 0 is outside 1..=8",
            "sparse count 0: count - 1 overflows",
        ),
        (
            r#""byteOffset":192,"byteLength":144"#,
            r#""byteOffset":300,"byteLength":144"#,
            "buffer view 2 (144 bytes from byte 300) reaches past the end of buffer 0",
            "view past the buffer: indices silently missing",
        ),
    ];
    for (from, to, msg, why) in cases {
        let bytes = embedded(|s| {
            assert!(s.contains(from), "{why}: template lacks {from}");
            s.replacen(from, to, 1)
        });
        let e = parse(&bytes, "m.gltf").map(|_| ()).unwrap_err().to_string();
        assert!(
            e.starts_with("m.gltf: node 0, mesh 0, primitive 0: "),
            "{why}: {e}"
        );
        assert!(e.contains(msg), "{why}: {e}");
    }
}

/// A node hierarchy with a cycle passes the `gltf` crate's validation; walking it used to
/// overflow the stack.
#[test]
fn a_node_cycle_ends() {
    let bytes = embedded(|s| s.replacen(r#"{"translation":[3,0,0]}"#, r#"{"children":[0]}"#, 1));
    let mut m = parse(&bytes, "m.gltf").unwrap();
    assert_eq!(
        m.warnings,
        ["node 0 is reached a second time (the node hierarchy must be a forest): drawn once"]
    );
    m.warnings.clear();
    assert_is_the_cube(&m);
}

/// Random byte corruptions of a valid GLB (header, chunk headers, JSON text and binary
/// data alike) load or fail with an error, never panic.
#[test]
fn corrupted_glbs_never_panic() {
    let bin = cube_bin();
    let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
    let good = glb_file(&json, &bin);
    for b in corruptions(&good, 0x9e37_79b9_7f4a_7c15, 3000) {
        let _ = parse(&b, "/nonexistent-smoothtri-test/m.glb");
    }
}

/// A POSITION index past the accessors made the `gltf` crate's validation itself panic
/// (found by [`corrupted_glbs_never_panic`]).
#[test]
fn a_position_index_out_of_range_is_an_error() {
    let bytes = embedded(|s| s.replacen(r#""POSITION":0"#, r#""POSITION":7"#, 1));
    let e = parse(&bytes, "m.gltf").map(|_| ()).unwrap_err().to_string();
    assert_eq!(
        e,
        "m.gltf: malformed glTF: invalid glTF: \
         meshes[0].primitives[0].attributes[\"POSITION\"]: Index out of bounds;"
    );
}
