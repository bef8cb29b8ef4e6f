//! glTF 2.0 through the `gltf` crate: JSON (`.gltf`, buffers in external files or base64 data
//! URIs) or binary (`.glb`, or any file that starts with the GLB magic).
//!
//! Everything the `gltf` crate would index blindly is checked here first, so malformed input
//! is an [`Error`], never a panic: the GLB container ([`crate::glb`]; the crate's own GLB
//! reader is not used), each primitive's POSITION accessor index before the crate's validation
//! (which looks it up unchecked), and, before a primitive is read, the type, count, stride and
//! byte range of each accessor the loader reads (POSITION, NORMAL, indices), sparse parts
//! included. The crate's accessor reader trusts all of these: it asserts on short strides, takes
//! `count - 1`, adds offsets unchecked, and has an `unreachable!()` for float indices. Sparse
//! indices are also checked to increase strictly (the reader would drop the others silently).
//!
//! The default scene is walked node by node ([`parse`] has the rules: transforms composed in
//! `f64`, instancing, normals by the inverse transpose, mirrored nodes re-wound, strips and fans
//! split, other modes skipped with a warning naming mesh, primitive and nodes); errors name the
//! node, mesh, primitive and accessor. [`write_glb`] writes a mesh as GLB (the tessellation's
//! output).

use std::collections::HashMap;
use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use glam::{DMat3, DMat4, DQuat, DVec3};

use crate::error::{Error, Result};
use crate::glb;
use crate::mesh::{LoadedMesh, Mesh};
use crate::options::{
    BYTES_PER_POSITION, BYTES_PER_TRIANGLE, Budget, LoadOptions, read_buffer, read_file,
};
use crate::weld::{Builder, Corner};

/// Reads a `.gltf` or `.glb` file (see the module documentation) within the default
/// [`LoadOptions`] ([`crate::load_with`] takes others).
pub fn load(path: &str) -> Result<LoadedMesh> {
    let options = LoadOptions::default();
    let (bytes, budget) = read_file(path, &options)?;
    parse_budgeted(&bytes, path, &options, &budget)
}

/// Parses the bytes of a glTF or GLB file. `path` names the file in messages, tells `.glb` by
/// its extension, and anchors relative buffer URIs.
///
/// What is drawn is the default scene (`scene`), or the first scene when there is no default:
/// every node reached from its root nodes, each mesh placed by its node's world transform (the
/// node's `matrix`, or `translation · rotation · scale`, composed down the hierarchy in `f64`),
/// once per node that references it (instancing). Positions are transformed by the world
/// matrix, normals by the inverse transpose of its 3×3 part (correct under non-uniform scale)
/// and renormalised, and triangles of a node whose transform mirrors (negative determinant) are
/// re-wound so that they stay counter-clockwise, as the specification says. Without scenes,
/// every root node is drawn; without nodes, every mesh once, untransformed (both with a
/// warning). Primitives in `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` mode are read,
/// indexed or not, their accessors sparse or not; other modes are skipped with a warning naming
/// the mesh, the primitive and the nodes that draw it. Errors name the node, mesh, primitive and
/// accessor.
///
/// External buffers are read within the default [`LoadOptions`]: inside the file's folder
/// only, regular files of at least their `byteLength` ([`crate::parse_with`] takes others).
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    let options = LoadOptions::default();
    parse_budgeted(bytes, path, &options, &Budget::new(path, &options))
}

/// [`parse`] within `options`, what it reads and decodes charged to `budget`.
pub(crate) fn parse_budgeted(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<LoadedMesh> {
    let (doc, buffers) = open(bytes, path, options, budget)?;
    let w = walk(&doc, &buffers, path, budget)?;
    Ok(w.builder.into_loaded(w.warnings))
}

/// The validated document of a glTF or GLB file and the bytes of its buffers (see [`parse`]),
/// the buffers charged to `budget`.
pub(crate) fn open(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<(::gltf::Document, Vec<Vec<u8>>)> {
    let is_glb = bytes.starts_with(&glb::MAGIC)
        || Path::new(path)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json, blob) = if is_glb {
        let g = glb::parse(bytes)
            .map_err(|e| Error::format(path, format!("malformed glTF binary: {e}")))?;
        (g.json, g.bin)
    } else {
        (bytes, None)
    };
    if let Some(v) = version_1(json) {
        return Err(Error::format(
            path,
            format!("glTF {v} is not supported (only glTF 2.0; convert the file to 2.0 first)"),
        ));
    }
    let doc = document(json).map_err(|e| Error::format(path, format!("malformed glTF: {e}")))?;
    let buffers = buffers(&doc, blob, path, options, budget)?;
    Ok((doc, buffers))
}

mod accessors;
mod document;
mod scene;
#[cfg(test)]
pub(crate) mod scene_tests;
#[cfg(test)]
mod tests;
mod write;

pub(crate) use accessors::*;
use document::*;
pub(crate) use scene::*;
#[cfg(test)]
pub(crate) use tests::corruptions;
pub use write::write_glb;
