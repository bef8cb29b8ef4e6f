//! Whole files, the format chosen by the extension: [`load`] and [`parse`] (`.obj`, `.ply`,
//! `.gltf`, `.glb`), [`save`] and [`encode`] (`.obj`, `.ply`, `.glb`).

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::{FloatWidth, LoadedMesh, Mesh};
use crate::options::{Budget, LoadOptions, read_file};
use crate::{gltf, obj, ply};

/// The lower-case extension of `path`, if it has one.
pub fn extension(path: &str) -> Option<String> {
    Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

/// Reads a mesh, choosing the format by extension (`.obj`, `.ply`, `.gltf`, `.glb`), with the
/// default [`LoadOptions`] ([`load_with`]).
///
/// Returns [`Error::Format`] for another extension, [`Error::Io`] when the file cannot be read,
/// and the errors of [`parse`].
pub fn load(path: &str) -> Result<LoadedMesh> {
    load_with(path, &LoadOptions::default())
}

/// Reads a mesh as [`load`] does, within `options` (see [`LoadOptions`]): the file's size is
/// checked against the budget before it is read.
///
/// Returns [`Error::Format`] for another extension, [`Error::Io`] when the file cannot be read
/// or is not a regular file, [`Error::Budget`] when it is larger than the budget, and the
/// errors of [`parse_with`].
pub fn load_with(path: &str, options: &LoadOptions) -> Result<LoadedMesh> {
    format_of(
        path,
        "obj, .ply, .gltf or .glb",
        &["obj", "ply", "gltf", "glb"],
    )?;
    let (bytes, budget) = read_file(path, options)?;
    parse_budgeted(&bytes, path, options, &budget)
}

/// The extension of `path` when it is one of `allowed`; else a format error listing `expected`.
fn format_of(path: &str, expected: &str, allowed: &[&str]) -> Result<String> {
    match extension(path) {
        Some(e) if allowed.contains(&e.as_str()) => Ok(e),
        _ => Err(Error::format(
            path,
            format!("unknown mesh format (expected .{expected})"),
        )),
    }
}

/// Parses the bytes of a mesh file, the format chosen by the extension of `path` as in
/// [`load`] (`path` also names the file in messages and anchors a glTF's external buffers).
///
/// Returns the format's error ([`obj::parse`], [`ply::parse`], [`gltf::parse`]), or
/// [`Error::NoTriangles`] when the file holds none.
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    parse_with(bytes, path, &LoadOptions::default())
}

/// Parses the bytes of a mesh file as [`parse`] does, within `options` (see [`LoadOptions`];
/// `bytes` count against the budget).
///
/// Returns the errors of [`parse`], [`Error::Budget`] when the file and what it decodes to
/// would take more than `options.max_bytes`, and for glTF buffers
/// [`Error::OutsideFolder`] and [`Error::Resource`].
pub fn parse_with(bytes: &[u8], path: &str, options: &LoadOptions) -> Result<LoadedMesh> {
    parse_budgeted(
        bytes,
        path,
        options,
        &Budget::charged(path, options, bytes)?,
    )
}

/// [`parse_with`] of a file whose bytes are already charged to `budget`.
fn parse_budgeted(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<LoadedMesh> {
    let ext = format_of(
        path,
        "obj, .ply, .gltf or .glb",
        &["obj", "ply", "gltf", "glb"],
    )?;
    let out = match ext.as_str() {
        "obj" => obj::parse_budgeted(&String::from_utf8_lossy(bytes), path, budget)?,
        "ply" => ply::parse_budgeted(bytes, path, budget)?,
        _ => gltf::parse_budgeted(bytes, path, options, budget)?,
    };
    if out.mesh.triangles.is_empty() {
        return Err(Error::NoTriangles {
            path: path.to_string(),
        });
    }
    Ok(out)
}

/// The bytes of `mesh` in the format of `path`'s extension: `.obj` ([`obj::write`]), `.ply`
/// (binary, [`ply::write`]) or `.glb` ([`gltf::write_glb`], always `f32`). Numbers are written
/// in `width` where the format allows; `comment` goes into the file's comment lines (OBJ,
/// PLY) or `asset.generator` (glTF).
///
/// Returns [`Error::Format`] for another extension, [`Error::EmptyGltf`] for an empty mesh
/// written as GLB.
pub fn encode(mesh: &Mesh, path: &str, width: FloatWidth, comment: &str) -> Result<Vec<u8>> {
    let ext = format_of(path, "obj, .ply or .glb", &["obj", "ply", "glb"])?;
    Ok(match ext.as_str() {
        "obj" => obj::write(mesh, width, comment),
        "ply" => ply::write(mesh, width, comment),
        _ => gltf::write_glb(mesh, comment)?,
    })
}

/// Writes `mesh` to `path` ([`encode`]); returns the number of bytes written.
///
/// Returns the errors of [`encode`], or [`Error::Io`] when the file cannot be written.
pub fn save(mesh: &Mesh, path: &str, width: FloatWidth, comment: &str) -> Result<usize> {
    let bytes = encode(mesh, path, width, comment)?;
    std::fs::write(path, &bytes).map_err(|e| Error::io(path, e))?;
    Ok(bytes.len())
}
