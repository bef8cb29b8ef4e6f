//! # smoothtri-testkit
//!
//! What the workspace's tests, benchmarks and demo share, so that none of them reaches into
//! another for it (not published):
//!
//! - [`scenes`]: the built-in meshes (torus, icosphere, cube, teapot, the tilted-normal sphere)
//!   and the exact surfaces they sample; [`twist`]: the twisting torus, a deforming mesh of any
//!   size with exact normals at any time (the animated scene and the update benchmarks);
//! - [`random`]: the tests' deterministic random numbers ([`Rng`]) and random geometry;
//! - [`RayonExecutor`]: the core builder's executor over rayon's pool, and [`build_scene`], a
//!   mesh's scene as the demo's renders build it;
//! - [`Camera`]: the renders' pinhole camera framed on a mesh, and their light;
//! - [`patches32`]: a mesh's patches one by one; [`cracks()`]: the cracks and normal jumps
//!   between neighbouring patches, edge by edge;
//! - [`assimp_models`]: where the real meshes of Debian's `assimp-testmodels` are.
//!
//! It sits above the core and the loaders ([`smoothtri_io`], whose [`Mesh`] it re-exports) and
//! below the GPU crate, the demo and the suite.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod assets;
mod camera;
mod cracks;
mod executor;
mod grid;
mod patches;
pub mod random;
pub mod scenes;
pub mod teapot_data;
pub mod twist;

pub use assets::assimp_models;
pub use camera::{Camera, FOV_DEG, SHADOW_OFFSET_F32, SHADOW_OFFSET_F64};
pub use cracks::{Cracks, EDGE_SAMPLES, cracks};
pub use executor::{RayonExecutor, build_scene};
pub use patches::patches32;
pub use random::Rng;
pub use smoothtri_io::Mesh;
