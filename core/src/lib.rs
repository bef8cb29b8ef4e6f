//! # smoothtri
//!
//! Ray tracing of *smooth* surfaces straight from triangle meshes with vertex normals, with no
//! tessellation: each triangle and its three vertex normals define a curved patch (Gusyatin &
//! Sorokin 2007). `no_std`, allocation-free, panic-free; `f32` and `f64` from one source.
//!
//! # Accuracy (per function, as tested against independent references)
//!
//! | function | `f64` | `f32` | reference |
//! |---|---|---|---|
//! | [`Patch::point`] at vertices and on edges | ≤ 1e-12 of the size | ≤ 1e-5 of the scale | the input vertices; [`Patch::edge_point_normal`] |
//! | [`Patch::point`] of a sphere's patch | ≤ 1e-12 of the radius | ≤ 2e-6 | the analytic sphere |
//! | [`Patch::point`], general | ≤ 2e-14 of the coordinates' magnitude | ≤ 1e-6 of the scale vs `f64` | independent f64 implementation (`tests/data/` of the repository) |
//! | [`Patch::point_normal`] normal | ≤ 1e-10 (spheres) | ≤ 2e-5 | radial normals; f64 |
//! | [`Patch::derivatives`] | exact (dual numbers) | exact | central differences ≤ 1e-6 of the size |
//! | [`Patch::edge_point_normal`] | ≤ 1.5e-13 of the size, normals ≤ 1e-8 | | `tests/data/` |
//! | [`Patch::intersect`] `t` | within `t_error` (+ rounding slack); N = 8 reaches rounding on spheres and the torus | on the sphere to ≤ 5e-7 | analytic spheres; the kernel at N = 40 |
//!
//! `FastF32` (feature `micromath`) trades accuracy for a square root without FPU support: its
//! surfaces deviate by up to 5e-3 of the size.
//!
//! # Panics
//!
//! No function of this crate panics, for any input: CI links a freestanding binary that calls
//! construction, evaluation, the kernels and the BVH, with a panic handler that references an
//! undefined symbol (`no-panic-check/`). Evaluations of accepted patches return finite values;
//! queries with non-finite rays return no hit.
//!
//! # Example
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

pub mod aabb;
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

pub use aabb::Aabb;
pub use bvh::{Bvh, BvhError, BvhNode};
pub use error::PatchError;
#[cfg(feature = "micromath")]
pub use fast::FastF32;
pub use kernel::flat::{flat_hit, moller_trumbore};
pub use kernel::{DEFAULT_SAMPLES, KernelStats};
pub use patch::{DPatch, Patch};
pub use ray::{DHit, DRay, Hit, Ray};
pub use real::{Float, Real};
