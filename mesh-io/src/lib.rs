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
mod weld;

pub mod glb;
pub mod gltf;
pub mod obj;
pub mod ply;

pub use animation::{
    AnimatedMesh, Clip, PoseError, WEIGHT_SUM_TOLERANCE, load_animated, parse_animated,
};
pub use error::{Error, Result};
pub use file::{encode, extension, load, parse, save};
pub use mesh::{FloatWidth, LoadedMesh, Mesh};
pub use weld::{angle_weighted_normals, angle_weighted_normals_into};
