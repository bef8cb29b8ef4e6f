//! The integration suite of the workspace, one test binary: each module below was its own
//! `tests/*.rs` file. One binary compiles the core's generic code (f32 and f64) once instead of
//! once per file, which is most of the suite's build time.
//!
//! Run one module with a filter: `cargo test --release --test suite torus:: -- --nocapture`.

#[macro_use]
mod common;

mod box_bvh;
mod builder;
mod bvh;
mod domain;
mod isa;
mod kernel;
mod linefield;
mod patch;
mod real_meshes;
mod reference;
mod regressions;
mod robustness;
mod seam;
mod shell;
mod stress_meshes;
mod torus;
mod update;
mod update_props;
mod watertight;
