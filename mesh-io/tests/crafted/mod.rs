//! Crafted hostile files (issue 64), shared by `hostile.rs` (each gives its typed error) and
//! `bounded_memory.rs` (each fails within a bounded peak allocation). Every file is small; what
//! it asks for is not.
#![allow(dead_code)]

/// Standard base64 with padding (the data URIs of the crafted files).
pub fn base64(bytes: &[u8]) -> String {
    const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = c.iter().fold(0u32, |a, &x| a << 8 | x as u32) << (8 * (3 - c.len()));
        for k in 0..4 {
            if k <= c.len() {
                out.push(B64[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The bytes of buffer 0 of [`triangle_gltf`] (104 bytes): a unit right triangle's three `f32`
/// positions (view 0, 36 bytes), a `u32` sparse index 0 (view 1, 4 bytes) and 64 bytes of
/// sparse values, zeros (view 2).
pub fn triangle_bin() -> Vec<u8> {
    let mut out: Vec<u8> = [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    out.extend([0u8; 4 + 64]);
    out
}

/// The length of [`triangle_bin`].
pub const TRIANGLE_BIN_LEN: usize = 104;

/// A glTF drawing one triangle whose POSITION is accessor 0 over buffer 0 (`buffer`, its
/// JSON object, [`triangle_bin`]); `accessors` and `rest` are appended (JSON members without
/// the leading comma) to the accessors and the document.
pub fn triangle_gltf(buffer: &str, accessors: &str, rest: &str) -> String {
    let more = if accessors.is_empty() {
        String::new()
    } else {
        format!(",{accessors}")
    };
    let rest = if rest.is_empty() {
        String::new()
    } else {
        format!(",{rest}")
    };
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"buffers":[{buffer}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":4}},{{"buffer":0,"byteOffset":40,"byteLength":64}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}{more}]{rest}}}"#
    )
}

/// An accessor of `ty` floats without a view, `count: 4000000000`, sparse over views 1 and 2
/// of [`triangle_gltf`] (one element): zeros, as the specification says, but four billion.
pub fn sparse_viewless(ty: &str) -> String {
    format!(
        r#"{{"componentType":5126,"count":4000000000,"type":"{ty}","sparse":{{"count":1,"indices":{{"bufferView":1,"componentType":5125}},"values":{{"bufferView":2}}}}}}"#
    )
}

/// The triangle's buffer as a data URI.
pub fn embedded_buffer() -> String {
    format!(
        r#"{{"uri":"data:application/octet-stream;base64,{}","byteLength":{TRIANGLE_BIN_LEN}}}"#,
        base64(&triangle_bin())
    )
}

/// The triangle's buffer as the external file `uri`.
pub fn external_buffer(uri: &str) -> String {
    format!(r#"{{"uri":"{uri}","byteLength":{TRIANGLE_BIN_LEN}}}"#)
}

/// The issue's 570-byte file: a POSITION accessor that is sparse, has no `bufferView`, and
/// says `count: 4000000000` (one sparse element, its index and value in a data URI).
pub fn sparse_viewless_position() -> Vec<u8> {
    let mut bin = 0u32.to_le_bytes().to_vec();
    bin.extend([1f32, 2.0, 3.0].iter().flat_map(|c| c.to_le_bytes()));
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"buffers":[{{"uri":"data:application/octet-stream;base64,{}","byteLength":16}}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":4}},{{"buffer":0,"byteOffset":4,"byteLength":12}}],"accessors":[{{"componentType":5126,"count":4000000000,"type":"VEC3","min":[0,0,0],"max":[1,2,3],"sparse":{{"count":1,"indices":{{"bufferView":0,"componentType":5125}},"values":{{"bufferView":1}}}}}}]}}"#,
        base64(&bin)
    )
    .into_bytes()
}

/// A POSITION accessor without view or sparse part of `count: 4000000000` (the `gltf` crate
/// refuses those, although the specification allows them).
pub fn viewless_position() -> Vec<u8> {
    br#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"accessors":[{"componentType":5126,"count":4000000000,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}]}"#.to_vec()
}

/// An animation whose sampler input (key times) has no view and `count: 4000000000`.
pub fn viewless_sampler_input() -> Vec<u8> {
    triangle_gltf(
        &embedded_buffer(),
        &format!("{},{}", sparse_viewless("SCALAR"), sparse_viewless("VEC3")),
        r#""animations":[{"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}}],"samplers":[{"input":1,"output":2}]}]"#,
    )
    .into_bytes()
}

/// A morph target whose POSITION deltas have no view and `count: 4000000000`.
pub fn viewless_morph_target() -> Vec<u8> {
    let json = triangle_gltf(&embedded_buffer(), &sparse_viewless("VEC3"), "");
    json.replacen(
        r#"{"attributes":{"POSITION":0}}"#,
        r#"{"attributes":{"POSITION":0},"targets":[{"POSITION":1}]}"#,
        1,
    )
    .into_bytes()
}

/// A skin whose inverse bind matrices have no view and `count: 4000000000`.
pub fn viewless_inverse_bind() -> Vec<u8> {
    let json = triangle_gltf(
        &embedded_buffer(),
        &sparse_viewless("MAT4"),
        r#""skins":[{"joints":[1],"inverseBindMatrices":1}]"#,
    );
    json.replacen(
        r#""nodes":[{"mesh":0}]"#,
        r#""nodes":[{"mesh":0,"children":[1]},{}]"#,
        1,
    )
    .into_bytes()
}

/// A PLY (`ascii` or `binary_little_endian`) whose header declares `count` vertices (x, y, z
/// floats) and `faces` faces, followed by one vertex's worth of data.
pub fn ply_huge(format: &str, count: u64, faces: u64) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex {count}\nproperty float x\nproperty float y\n\
         property float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    if format == "ascii" {
        out.extend(b"0 0 0\n");
    } else {
        out.extend([0u8; 12]);
    }
    out
}

/// Every crafted file that must fail whatever the budget, with its name (the extension picks
/// the loader) and whether it is read with its animations.
pub fn all() -> Vec<(&'static str, Vec<u8>, bool)> {
    vec![
        ("sparse.gltf", sparse_viewless_position(), false),
        ("viewless.gltf", viewless_position(), false),
        ("sampler.gltf", viewless_sampler_input(), true),
        ("morph.gltf", viewless_morph_target(), true),
        ("skin.gltf", viewless_inverse_bind(), true),
        (
            "vertices.ply",
            ply_huge("binary_little_endian", 4_000_000_000, 0),
            false,
        ),
        ("ascii.ply", ply_huge("ascii", 4_000_000_000, 0), false),
        (
            "faces.ply",
            ply_huge("binary_little_endian", 1, 4_000_000_000),
            false,
        ),
    ]
}
