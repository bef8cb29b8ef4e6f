//! The subcommands of `smoothtri`, one module each. Every module has a plain options struct
//! (filled in by [`crate::cli`]) and a `run` function; none of them knows about argument
//! parsing. Where a command's mesh comes from is [`MeshSource`] (`--mesh` or `--scene`).

pub mod eval;
pub mod inspect;
pub mod precision;
pub mod render;
mod source;
pub mod tessellate;
pub mod trace;
pub mod view;

pub use source::MeshSource;
