//! # smoothtri
//!
//! Ray tracing of *smooth* surfaces straight from triangle meshes with vertex normals, with no
//! tessellation: each triangle and its three vertex normals define a curved patch (Gusyatin &
//! Sorokin 2007). `no_std`, allocation-free, panic-free; `f32` and `f64` from one source.
//!
//! ```
//! use smoothtri::Patch;
//! use glam::Vec3;
//! // An octant of the unit sphere: vertices on it, normals radial.
//! let p = [Vec3::X, Vec3::Y, Vec3::Z];
//! let patch: Patch = Patch::new(p, p).unwrap();
//! let (x, n) = patch.point_normal(1.0 / 3.0, 1.0 / 3.0);
//! assert!((x.length() - 1.0).abs() < 2e-6); // the method reproduces spheres
//! assert!((n - x).length() < 1e-5);          // with radial normals
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// `!(a > b)` is deliberate throughout: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bvh;
pub mod dual;
pub mod edge;
pub mod error;
#[cfg(feature = "micromath")]
pub mod fast;
pub mod kernel;
mod math;
pub mod patch;
pub mod ray;
pub mod real;
pub mod shell;
pub mod sphere;
pub mod surface;
pub mod vec;

pub use bvh::{Bvh, BvhError, BvhNode};
pub use error::PatchError;
#[cfg(feature = "micromath")]
pub use fast::FastF32;
pub use kernel::flat::{flat_hit, moller_trumbore};
pub use kernel::{DEFAULT_SAMPLES, KernelStats};
pub use patch::{DPatch, Patch};
pub use ray::{DHit, DRay, Hit, Ray};
pub use real::{Float, Real};
