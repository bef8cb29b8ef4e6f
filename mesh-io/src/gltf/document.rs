//! The document and its buffers: the glTF 1.x refusal, the JSON validated (with the checks the
//! `gltf` crate skips), and the buffers from the GLB's BIN chunk, base64 data URIs or confined
//! files.

use super::*;

/// The version of a glTF 1.x document (`asset.version` "1…", or, when absent, the 1.0 layout
/// of named dictionaries where 2.0 has arrays), `None` for anything else (glTF 2.0, or JSON
/// that the 2.0 parser will judge).
pub(super) fn version_1(json: &[u8]) -> Option<String> {
    let root: serde_json::Value = serde_json::from_slice(json).ok()?;
    let version = match root.get("asset").and_then(|a| a.get("version")) {
        Some(serde_json::Value::String(v)) => Some(v.clone()),
        Some(serde_json::Value::Number(n)) => Some(n.to_string()),
        _ => None,
    };
    match version {
        Some(v) if v.starts_with('1') => Some(v),
        Some(_) => None,
        None => ["meshes", "accessors", "nodes", "buffers"]
            .iter()
            .any(|k| root.get(*k).is_some_and(serde_json::Value::is_object))
            .then(|| "1.0".to_owned()),
    }
}

/// Deserialises and validates a glTF JSON document (the `gltf` crate's checks: indices in
/// range, required fields, enum values).
pub(super) fn document(json: &[u8]) -> std::result::Result<::gltf::Document, ::gltf::Error> {
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
/// relative to the glTF file (confined and size-checked as `options` says: [`read_buffer`]).
/// Each must hold at least its declared `byteLength`; each is charged to `budget` before it is
/// copied or read.
pub(super) fn buffers(
    doc: &::gltf::Document,
    blob: Option<&[u8]>,
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let field = |len: usize| format!("buffer {} ({len} bytes)", b.index());
        let data = match b.source() {
            ::gltf::buffer::Source::Bin => {
                let blob = blob.ok_or_else(|| Error::format(path, "GLB has no binary chunk"))?;
                budget
                    .charge(blob.len() as u64, 1)
                    .map_err(|()| budget.typed(Error::format(path, field(blob.len()))))?;
                blob.to_vec()
            }
            ::gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let b64 = rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        Error::format(path, "unsupported data URI (expected base64)")
                    })?;
                    let len = b64.len() / 4 * 3 + 3;
                    budget
                        .charge(len as u64, 1)
                        .map_err(|()| budget.typed(Error::format(path, field(len))))?;
                    base64_decode(b64)
                        .ok_or_else(|| Error::format(path, "malformed base64 data URI"))?
                } else {
                    read_buffer(path, uri, b.length(), options, budget)?
                }
            }
        };
        if data.len() < b.length() {
            return Err(Error::format(
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

/// Decodes standard or URL-safe base64 (padding optional, whitespace skipped).
pub(super) fn base64_decode(s: &str) -> Option<Vec<u8>> {
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
