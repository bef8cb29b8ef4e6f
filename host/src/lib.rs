//! # smoothtri-host
//!
//! What an application on std (the demo, the Python package) needs beside the `no_std` core:
//!
//! - [`RayonExecutor`]: the core builder's executor over rayon's pool, and [`build_scene`], a
//!   mesh's scene as the demo's renders build it;
//! - [`Camera`]: the renders' pinhole camera framed on a mesh, their light, and the shadow
//!   rays' offsets ([`SHADOW_OFFSET_F32`], [`SHADOW_OFFSET_F64`]);
//! - [`scenes`]: the built-in meshes (torus, icosphere, cube, teapot, the tilted-normal sphere)
//!   and the exact surfaces they sample; [`twist`]: the twisting torus, a deforming mesh of any
//!   size with exact normals at any time (the animated scene and the update benchmarks);
//! - [`cracks()`]: the cracks and normal jumps between neighbouring patches, edge by edge
//!   (`smoothtri inspect`);
//! - [`tessellate`]: the smooth surface sampled into welded, watertight triangles for other
//!   renderers (`smoothtri tessellate`), with its measured distance to the surface;
//! - [`error_stats`]: the error statistics of a run's hits against a reference run (the
//!   precision study of `smoothtri precision` and `smoothtri.precision_sweep`).
//!
//! It sits above the core and the loaders ([`smoothtri_io`], whose [`Mesh`] it re-exports) and
//! below the demo, the Python package and the tests' kit (`smoothtri-testkit`, which no shipped
//! crate depends on).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod camera;
mod cracks;
mod executor;
mod grid;
mod precision_stats;
pub mod scenes;
pub mod teapot_data;
pub mod tessellate;
pub mod twist;

pub use camera::{Camera, FOV_DEG, SHADOW_OFFSET_F32, SHADOW_OFFSET_F64};
pub use cracks::{Cracks, EDGE_SAMPLES, cracks};
pub use executor::{RayonExecutor, build_scene};
pub use precision_stats::{ErrorStats, Traced, error_stats, percentile};
pub use smoothtri_io::Mesh;
