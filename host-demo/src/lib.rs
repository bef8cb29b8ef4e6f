//! Library side of the `smoothtri` demo over the `smoothtri` core.
//!
//! - [`mesh`]: the [`Mesh`] type, normal generation, the file loaders (OBJ, PLY, glTF/GLB,
//!   glTF scenes walked node by node) and writers (OBJ, PLY, GLB: [`mesh::save`]);
//!   [`scenes`]: the built-in scenes.
//! - [`tracer`]: patches and BVH of a mesh in a [`Precision`] ([`Scene`]), and the smooth, flat
//!   and Phong ray queries; [`camera`]: the camera and the up axis ([`camera::Up`]);
//!   [`renderer`]: shading an image.
//! - [`tessellate`]: the smooth surface sampled into welded triangles (for other renderers).
//! - [`commands`]: one module per subcommand, each with a plain options struct and `run`;
//!   [`cli`]: argument parsing (clap) and dispatch to them.
//! - [`image`] (PNG, labels), [`csvio`] (CSV in and out), [`error`] ([`DemoError`]).

pub mod camera;
pub mod cli;
pub mod commands;
pub mod csvio;
pub mod error;
pub mod image;
pub mod mesh;
pub mod peers;
pub mod renderer;
pub mod scenes;
pub mod teapot_data;
pub mod tessellate;
pub mod tracer;

pub use camera::Camera;
pub use error::{DemoError, Result};
pub use mesh::Mesh;
pub use tracer::{Mode, Prec, Precision, Scene};
