//! glTF 2.0 through the `gltf` crate: JSON (`.gltf`, buffers in external files or base64 data
//! URIs) or binary (`.glb`, or any file that starts with the GLB magic).
//!
//! Everything the `gltf` crate would index blindly is checked here first, so malformed input
//! is a [`DemoError`], never a panic: the GLB container ([`super::glb`]; the crate's own GLB
//! reader is not used), each primitive's POSITION accessor index before the crate's validation
//! (which looks it up unchecked), and, before a primitive is read, the type, count, stride and
//! byte range of each accessor the loader reads (POSITION, NORMAL, indices), sparse parts
//! included. The crate's accessor reader trusts all of these: it asserts on short strides, takes
//! `count - 1`, adds offsets unchecked, and has an `unreachable!()` for float indices.

use std::collections::HashMap;
use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use glam::{DMat3, DMat4, DVec3, Mat4};

use super::{Builder, Corner, LoadedMesh, glb};
use crate::error::{DemoError, Result};

/// Reads a `.gltf` or `.glb` file (see the module documentation).
pub fn load(path: &str) -> Result<LoadedMesh> {
    let bytes = std::fs::read(path).map_err(|e| DemoError::io(path, e))?;
    parse(&bytes, path)
}

/// Parses the bytes of a glTF or GLB file. `path` names the file in messages, tells `.glb` by
/// its extension, and anchors relative buffer URIs.
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    let is_glb = bytes.starts_with(&glb::MAGIC)
        || Path::new(path)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json, blob) = if is_glb {
        let g = glb::parse(bytes)
            .map_err(|e| DemoError::format(path, format!("malformed glTF binary: {e}")))?;
        (g.json, g.bin)
    } else {
        (bytes, None)
    };
    let doc =
        document(json).map_err(|e| DemoError::format(path, format!("malformed glTF: {e}")))?;
    let buffers = buffers(&doc, blob, path)?;
    let mesh_xf = mesh_transforms(&doc);
    let mut warnings = Vec::new();
    let mut positions = Vec::new();
    let mut tris: Vec<[Corner; 3]> = Vec::new();
    for mesh in doc.meshes() {
        let xf = mesh_xf
            .get(&mesh.index())
            .copied()
            .unwrap_or(DMat4::IDENTITY);
        let nxf = DMat3::from_mat4(xf).inverse().transpose();
        for prim in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), prim.index());
            if prim.mode() != ::gltf::mesh::Mode::Triangles {
                warnings.push(format!(
                    "{at}: mode {:?} is not triangles, skipped",
                    prim.mode()
                ));
                continue;
            }
            let checks = [
                (
                    "POSITION",
                    prim.get(&::gltf::Semantic::Positions),
                    Want::Vec3F32,
                ),
                (
                    "NORMAL",
                    prim.get(&::gltf::Semantic::Normals),
                    Want::Vec3F32,
                ),
                ("indices", prim.indices(), Want::Index),
            ];
            for (what, acc, want) in checks {
                if let Some(acc) = acc {
                    check_accessor(&acc, want, &buffers)
                        .map_err(|m| DemoError::format(path, format!("{at}: {what} {m}")))?;
                }
            }
            let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
            let Some(pos) = reader.read_positions() else {
                warnings.push(format!("{at}: no POSITION, skipped"));
                continue;
            };
            let first = positions.len();
            for p in pos {
                let p = xf.transform_point3(DVec3::from_array(p.map(f64::from)));
                if !p.is_finite() {
                    return Err(DemoError::format(path, "non-finite vertex position"));
                }
                positions.push(p);
            }
            let count = positions.len() - first;
            let normals: Option<Vec<DVec3>> = reader.read_normals().map(|it| {
                it.map(|n| nxf * DVec3::from_array(n.map(f64::from)))
                    .collect()
            });
            if let Some(ns) = &normals {
                if ns.len() != count {
                    return Err(DemoError::format(path, "NORMAL and POSITION counts differ"));
                }
                if ns.iter().any(|n| !n.is_finite()) {
                    return Err(DemoError::format(path, "non-finite vertex normal"));
                }
            }
            let idx: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count as u32).collect(),
            };
            if !idx.len().is_multiple_of(3) {
                return Err(DemoError::format(
                    path,
                    format!("index count {} is not a multiple of 3", idx.len()),
                ));
            }
            for c in idx.chunks_exact(3) {
                let mut t: [Corner; 3] = [(0, None); 3];
                for (slot, &i) in t.iter_mut().zip(c) {
                    let i = i as usize;
                    if i >= count {
                        return Err(DemoError::format(
                            path,
                            format!("index {i} out of range (0..{count})"),
                        ));
                    }
                    *slot = (first + i, normals.as_ref().and_then(|n| n.get(i).copied()));
                }
                tris.push(t);
            }
        }
    }
    Ok(Builder { positions, tris }.into_loaded(warnings))
}

/// Deserialises and validates a glTF JSON document (the `gltf` crate's checks: indices in
/// range, required fields, enum values).
fn document(json: &[u8]) -> std::result::Result<::gltf::Document, ::gltf::Error> {
    use ::gltf::json::validation::{Checked, Error};
    let root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json)?;
    // The crate's validation looks up each primitive's POSITION accessor without a bounds check
    // (`root.accessors[i]` in its primitive hook, which panics when `i` is out of range), so
    // those indices are checked first, reported as the validation would.
    let position = Checked::Valid(::gltf::json::mesh::Semantic::Positions);
    let mut bad = Vec::new();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if let Some(i) = prim.attributes.get(&position)
                && i.value() >= root.accessors.len()
            {
                let at = ::gltf::json::Path::new()
                    .field("meshes")
                    .index(m)
                    .field("primitives")
                    .index(p)
                    .field("attributes")
                    .key("POSITION");
                bad.push((at, Error::IndexOutOfBounds));
            }
        }
    }
    if !bad.is_empty() {
        return Err(::gltf::Error::Validation(bad));
    }
    ::gltf::Document::from_json(root)
}

/// The data of every buffer, in index order: the GLB's BIN chunk, a base64 data URI, or a file
/// relative to the glTF file. Each must hold at least its declared `byteLength`.
fn buffers(doc: &::gltf::Document, blob: Option<&[u8]>, path: &str) -> Result<Vec<Vec<u8>>> {
    let base = Path::new(path).parent().unwrap_or(Path::new("."));
    let mut out = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            ::gltf::buffer::Source::Bin => blob
                .map(<[u8]>::to_vec)
                .ok_or_else(|| DemoError::format(path, "GLB has no binary chunk"))?,
            ::gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let b64 = rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        DemoError::format(path, "unsupported data URI (expected base64)")
                    })?;
                    base64_decode(b64)
                        .ok_or_else(|| DemoError::format(path, "malformed base64 data URI"))?
                } else {
                    let p = base.join(uri);
                    let ps = p.display().to_string();
                    std::fs::read(&p).map_err(|e| DemoError::io(&ps, e))?
                }
            }
        };
        if data.len() < b.length() {
            return Err(DemoError::format(
                path,
                format!(
                    "buffer {} is shorter ({} bytes) than declared ({})",
                    b.index(),
                    data.len(),
                    b.length()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// World transform of the first node (scenes in order, nodes depth-first in order) that
/// instantiates each mesh, by mesh index. Each node is visited once, so a node hierarchy with
/// a cycle (which the `gltf` crate's validation lets through) ends instead of recursing forever.
fn mesh_transforms(doc: &::gltf::Document) -> HashMap<usize, DMat4> {
    let mut out = HashMap::new();
    let mut seen = vec![false; doc.nodes().len()];
    for scene in doc.scenes() {
        let mut stack: Vec<(::gltf::Node<'_>, DMat4)> =
            scene.nodes().map(|n| (n, DMat4::IDENTITY)).collect();
        stack.reverse();
        while let Some((n, parent)) = stack.pop() {
            match seen.get_mut(n.index()) {
                Some(s) if !*s => *s = true,
                _ => continue,
            }
            let m = parent * Mat4::from_cols_array_2d(&n.transform().matrix()).as_dmat4();
            if let Some(mesh) = n.mesh() {
                out.entry(mesh.index()).or_insert(m);
            }
            let first_child = stack.len();
            stack.extend(n.children().map(|c| (c, m)));
            stack[first_child..].reverse();
        }
    }
    out
}

/// What the loader reads from an accessor.
#[derive(Clone, Copy, Debug)]
enum Want {
    /// `VEC3` of `FLOAT` (POSITION, NORMAL).
    Vec3F32,
    /// `SCALAR` of an unsigned integer type (indices).
    Index,
}

/// Checks that the `gltf` crate can read `acc` as `want` without panicking and without
/// falling short: element type, `count ≥ 1`, strides at least the element size, and every
/// byte read (base, sparse indices and sparse values) inside its buffer view and buffer.
fn check_accessor(
    acc: &::gltf::Accessor<'_>,
    want: Want,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let i = acc.index();
    let (dims, ty) = (acc.dimensions(), acc.data_type());
    let (ok, expected) = match want {
        Want::Vec3F32 => (
            dims == Dimensions::Vec3 && ty == DataType::F32,
            "Vec3 of F32",
        ),
        Want::Index => (
            dims == Dimensions::Scalar
                && matches!(ty, DataType::U8 | DataType::U16 | DataType::U32),
            "Scalar of U8, U16 or U32",
        ),
    };
    if !ok {
        return Err(format!(
            "accessor {i} holds {dims:?} of {ty:?}, expected {expected}"
        ));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("accessor {i} has count 0"));
    }
    let elem = acc.size();
    if let Some(view) = acc.view() {
        check_view(&view, acc.offset(), count, elem, buffers)
            .map_err(|m| format!("accessor {i}: {m}"))?;
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!(
                "accessor {i}: sparse count {n} is outside 1..={count}"
            ));
        }
        let ix = sparse.indices();
        check_view(&ix.view(), ix.offset(), n, ix.index_type().size(), buffers)
            .map_err(|m| format!("accessor {i}, sparse indices: {m}"))?;
        let vals = sparse.values();
        check_view(&vals.view(), vals.offset(), n, elem, buffers)
            .map_err(|m| format!("accessor {i}, sparse values: {m}"))?;
    }
    Ok(())
}

/// Checks that `count` elements of `elem` bytes, `offset` bytes into `view` and its stride
/// apart, lie inside the view, and the view inside its buffer's data (overflow-free).
fn check_view(
    view: &::gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "buffer view {v} has byteStride {stride}, less than the {elem}-byte elements"
        ));
    }
    let end = count
        .checked_sub(1)
        .and_then(|c| stride.checked_mul(c))
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{count} elements of {elem} bytes (stride {stride}) from byte {offset} do not fit \
             in buffer view {v} ({} bytes)",
            view.length()
        ));
    }
    let b = view.buffer().index();
    let have = buffers.get(b).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|e| e > have)
    {
        return Err(format!(
            "buffer view {v} ({} bytes from byte {}) reaches past the end of buffer {b} \
             ({have} bytes)",
            view.length(),
            view.offset()
        ));
    }
    Ok(())
}

/// Decodes standard or URL-safe base64 (padding optional, whitespace skipped).
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        } as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube `[-1, 1]³` with radial normals: 8 positions, 8 normals (`f32`), 36 `u32`
    /// indices.
    fn cube_bin() -> Vec<u8> {
        let m = crate::scenes::cube();
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
        let mut j = json.as_bytes().to_vec();
        j.resize(j.len().div_ceil(4) * 4, b' ');
        let mut b = bin.to_vec();
        b.resize(b.len().div_ceil(4) * 4, 0);
        let mut out = Vec::new();
        out.extend(glb::MAGIC);
        out.extend(glb::VERSION.to_le_bytes());
        out.extend(((12 + 8 + j.len() + 8 + b.len()) as u32).to_le_bytes());
        out.extend((j.len() as u32).to_le_bytes());
        out.extend(glb::CHUNK_JSON);
        out.extend(j);
        out.extend((b.len() as u32).to_le_bytes());
        out.extend(glb::CHUNK_BIN);
        out.extend(b);
        out
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
        let cube = crate::scenes::cube();
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
            assert!(e.starts_with("m.gltf: mesh 0 primitive 0: "), "{why}: {e}");
            assert!(e.contains(msg), "{why}: {e}");
        }
    }

    /// A node hierarchy with a cycle passes the `gltf` crate's validation; walking it used to
    /// overflow the stack.
    #[test]
    fn a_node_cycle_ends() {
        let bytes =
            embedded(|s| s.replacen(r#"{"translation":[3,0,0]}"#, r#"{"children":[0]}"#, 1));
        assert_is_the_cube(&parse(&bytes, "m.gltf").unwrap());
    }

    /// Random byte corruptions of a valid GLB (header, chunk headers, JSON text and binary
    /// data alike) load or fail with an error, never panic.
    #[test]
    fn corrupted_glbs_never_panic() {
        let bin = cube_bin();
        let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
        let good = glb_file(&json, &bin);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let digits = b"0123456789";
        for _ in 0..3000 {
            let mut b = good.clone();
            for _ in 0..1 + next() % 4 {
                let at = (next() % b.len() as u64) as usize;
                // Half the time a digit, so that JSON numbers change but stay numbers.
                b[at] = if next() % 2 == 0 && b[at].is_ascii_digit() {
                    digits[(next() % 10) as usize]
                } else {
                    next() as u8
                };
            }
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
}
