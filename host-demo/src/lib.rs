//! Library side of the `smoothtri` demo over the `smoothtri` core.
//!
//! - Meshes come from [`smoothtri_io`] (the [`Mesh`](smoothtri_io::Mesh) type, the file loaders
//!   and writers) and the built-in scenes, the camera and the builder's executor from
//!   [`smoothtri_host`]; [`up`]: the up axis of a mesh ([`up::Up`]).
//! - [`tracer`]: patches and BVH of a mesh in a [`Precision`] ([`Scene`]), and the smooth, flat
//!   and Phong ray queries; [`renderer`]: shading an image on the CPU; [`gpu`]: the same on the
//!   GPU (`smoothtri-gpu`), for every command with `--gpu`.
//! - [`animate`]: a glTF file's animation or the twisting torus posed frame by frame
//!   (`render --time`, `view --animate`).
//! - [`commands`]: one module per subcommand, each with a plain options struct and `run`;
//!   [`cli`]: argument parsing (clap) and dispatch to them.
//! - [`image`] (PNG, labels), [`csvio`] (CSV in and out), [`error`] ([`DemoError`]);
//!   [`output`]: every file a command writes, checked before the work and written whole or
//!   not at all.

pub mod animate;
pub mod cli;
pub mod commands;
pub mod csvio;
pub mod error;
pub mod gpu;
pub mod image;
pub mod output;
pub mod peers;
pub mod renderer;
pub mod tracer;
pub mod up;

pub use error::{DemoError, Result};
pub use tracer::{Mode, Prec, Precision, Scene};
