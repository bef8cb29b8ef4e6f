//! # smoothtri-testkit
//!
//! What the workspace's tests and benchmarks share, so that none of them reaches into another
//! for it (not published; no shipped crate depends on it):
//!
//! - [`random`]: the tests' deterministic random numbers ([`Rng`]) and random geometry;
//! - [`patches32`]: a mesh's patches one by one; [`flat_triangles32`] and [`triangle_boxes`]: its
//!   flat triangles and their boxes;
//! - [`assimp_models`]: where the real meshes of Debian's `assimp-testmodels` are;
//! - for the tests' convenience, the shipped host crate's items they use, re-exported from
//!   [`smoothtri_host`]: the built-in [`scenes`] and [`twist`], [`RayonExecutor`] and
//!   [`build_scene`], [`Camera`] and its shadow offsets, [`cracks()`].
//!
//! It sits above the core, the loaders ([`smoothtri_io`], whose [`Mesh`] it re-exports) and
//! the host crate, and below the GPU crate's tests, the demo's tests and the suite.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod assets;
mod flat;
mod patches;
pub mod random;

pub use assets::assimp_models;
pub use flat::{flat_triangles32, triangle_boxes};
pub use patches::patches32;
pub use random::Rng;
pub use smoothtri_host::{
    Camera, Cracks, EDGE_SAMPLES, FOV_DEG, RayonExecutor, SHADOW_OFFSET_F32, SHADOW_OFFSET_F64,
    build_scene, cracks, scenes, teapot_data, twist,
};
pub use smoothtri_io::Mesh;
