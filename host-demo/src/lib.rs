//! Library side of the `smoothtri` demo over the `smoothtri` core.
//!
//! - [`mesh`]: the [`Mesh`] type, normal generation and the file loaders (OBJ, PLY, glTF/GLB);
//!   [`scenes`]: the built-in scenes.
//! - [`tracer`]: patches and BVH of a mesh in a [`Precision`] ([`Scene`]), and the smooth, flat
//!   and Phong ray queries; [`camera`]: the camera; [`renderer`]: shading an image.
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
pub mod renderer;
pub mod scenes;
pub mod teapot_data;
pub mod tracer;

pub use camera::Camera;
pub use error::{DemoError, Result};
pub use mesh::Mesh;
pub use tracer::{Mode, Prec, Precision, Scene};
