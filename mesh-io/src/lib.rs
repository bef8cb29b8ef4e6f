//! # smoothtri-io
//!
//! Triangle meshes with vertex normals for [`smoothtri`]: the [`Mesh`] type, loading from
//! files ([`load`], or [`parse`] on bytes, picks the loader by extension: [`obj`], [`ply`],
//! [`gltf`] for `.gltf` and `.glb`, the latter's container checked by [`glb`] first), writing
//! them ([`save`], or [`encode`] to bytes: OBJ, binary PLY, GLB), vertex-normal generation
//! ([`angle_weighted_normals`]), and the core's scene of a mesh ([`Mesh::build_scene`]).
//! Animated glTF files (skins, morph targets, keyframe animations) are posed frame by frame by
//! [`AnimatedMesh`] ([`load_animated`]), in the static mesh's vertex order.
//!
//! Triangle ids are the order of triangles in the file after fan-triangulating polygons, over
//! all objects/primitives in file order (glTF: primitives in the order their nodes are met,
//! depth-first through the default scene, once per node that draws the mesh). Vertex normals
//! come from the file (per corner); where a file has none, angle-weighted vertex normals are
//! computed ([`LoadedMesh::computed_normals`]).
//!
//! Malformed input is an [`Error`] naming the file and the line (OBJ) or the element, node,
//! mesh, primitive or accessor (PLY, glTF); no input makes a loader panic (the fuzz targets in
//! `fuzz/` run them on arbitrary bytes).
//!
//! Loading is bounded and confined ([`LoadOptions`], taken by [`load_with`], [`parse_with`],
//! [`load_animated_with`] and [`parse_animated_with`]; the entry points without options use
//! its default). Every count, size and offset in a file (OBJ and PLY element counts, glTF
//! accessors, sparse accessors, buffer views, buffers, animation samplers, morph targets,
//! skins) is checked against the bytes actually present before anything is allocated, and a
//! load holds at most [`LoadOptions::max_bytes`] (default [`DEFAULT_MAX_BYTES`], 2 GiB) of
//! file, buffers and decoded data, else [`Error::Budget`] names the file and the field. A
//! glTF buffer URI must resolve inside the asset's own folder (no absolute paths, no `..`,
//! percent-encoded or not, no symlink out of it: [`Error::OutsideFolder`]) to a regular file
//! of at least its `byteLength` ([`Error::Resource`] otherwise); only `byteLength` bytes are
//! read. [`LoadOptions::allow_outside_folder`] lifts the folder rule (not the others) for
//! trusted pipelines. Data URIs and the GLB's binary chunk need no file. Images are never
//! read.
//!
//! ```no_run
//! let loaded = smoothtri_io::load("bunny.obj")?;
//! for w in &loaded.warnings {
//!     eprintln!("warning: {w}");
//! }
//! let (lo, hi) = loaded.mesh.bounds();
//! println!("{} triangles in {lo} .. {hi}", loaded.mesh.triangles.len());
//! # Ok::<(), smoothtri_io::Error>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod animation;
mod error;
mod file;
mod mesh;
mod options;
mod weld;

pub mod glb;
pub mod gltf;
pub mod obj;
pub mod ply;

pub use animation::{
    AnimatedMesh, Clip, PoseError, WEIGHT_SUM_TOLERANCE, load_animated, load_animated_with,
    parse_animated, parse_animated_with,
};
pub use error::{Error, Result};
pub use file::{encode, extension, load, load_with, parse, parse_with, save};
pub use mesh::{FloatWidth, LoadedMesh, Mesh};
pub use options::{DEFAULT_MAX_BYTES, LoadOptions};
pub use weld::{angle_weighted_normals, angle_weighted_normals_into};
