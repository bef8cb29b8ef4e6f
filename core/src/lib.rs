//! # smoothtri
//!
//! Ray tracing of *smooth* surfaces straight from triangle meshes with vertex normals, with no
//! tessellation: each triangle and its three vertex normals define a curved patch (Gusyatin &
//! Sorokin 2007). `no_std`, allocation-free, panic-free; `f32` and `f64` from one source.
//!
//! # Accuracy (per function, as tested against independent references)
//!
//! Every figure is a named bound of [`accuracy`] (which says what it was measured on and which
//! test asserts it); sizes are longest edges, scales the larger of the size and the
//! coordinates' magnitude.
//!
//! | function | `f64` | `f32` | against |
//! |---|---|---|---|
//! | [`Patch::point`] at vertices and on edges | [`accuracy::F64_INTERPOLATION`] of the size | [`accuracy::F32_INTERPOLATION`] of the scale | the input vertices; [`Patch::edge_point_normal`] |
//! | [`Patch::point`] of a sphere's patch | [`accuracy::F64_SPHERE_POINT`] of the radius | [`accuracy::F32_SPHERE_POINT`] of the radius | the analytic sphere |
//! | [`Patch::point`], general | [`accuracy::F64_SURFACE_VS_REFERENCE`] of the scale | [`accuracy::F32_VS_F64_POINT`] of the scale | an independent f64 implementation (`tests/data/` of the repository); `f64` |
//! | [`Patch::point_normal`] normal | [`accuracy::F64_SPHERE_NORMAL`] (spheres), [`accuracy::F64_NORMAL_VS_REFERENCE`] | [`accuracy::F32_SPHERE_NORMAL`] (spheres), [`accuracy::F32_VS_F64_NORMAL`] | radial normals; `tests/data/`; `f64` |
//! | [`Patch::derivatives`] | exact (dual numbers) | exact | central differences, within [`accuracy::DERIVATIVES_VS_CENTRAL_DIFFERENCES`] of the size |
//! | [`Patch::edge_point_normal`] | [`accuracy::F64_EDGE_VS_REFERENCE`] of the size, normals [`accuracy::F64_EDGE_NORMAL_VS_REFERENCE`] | normals at the ends [`accuracy::F32_INTERPOLATION`] | `tests/data/`; the vertex normals |
//! | [`Patch::roots_certified`] | sound: no root missing or switched anywhere on a certified patch (interval arithmetic, outward rounded) | the same, on the `f32` data widened | every folded or jumping patch of the domain study refused (`tests/suite/domain.rs`) |
//! | every unit vector returned | length 1 ± [`accuracy::UNIT_LENGTH_ULPS`] ε | the same | |
//! | [`Patch::closest_hit`] `t` | within `t_error` (worst-case bound: [`Patch::closest_hit`]); N = 8: sphere hits to [`accuracy::F64_SPHERE_HIT`] of the radius, the torus at rounding from N = 4 (docs/MEASUREMENTS.md) | sphere hits to [`accuracy::F32_SPHERE_HIT`] of the radius | analytic spheres; the kernel at N = 40 |
//!
//! `FastF32` (feature `micromath`) trades accuracy for a square root without FPU support (its
//! square root is within [`accuracy::FASTF32_SQRT_REL`] relative): its surfaces deviate by up
//! to [`accuracy::FASTF32_SURFACE`] of the size.
//!
//! # Panics
//!
//! No function of this crate panics, for any input: CI links a freestanding binary that calls
//! construction, evaluation, the kernels and the BVH, with a panic handler that references an
//! undefined symbol (`no-panic-check/`). Evaluations of accepted patches return finite values;
//! queries with non-finite rays return no hit.
//!
//! # Building a scene
//!
//! [`Scene::build`] turns a renderer's buffers into a traceable scene in caller storage (no
//! allocation; with the `alloc` feature [`OwnedScene`] owns it). [`SceneSizes::new`] gives the
//! length of every slice from the counts alone:
//!
//! ```
//! use glam::Vec3;
//! use smoothtri::mesh::{Seam, SharedEdge, VertexClamp};
//! use smoothtri::{
//!     BuildOptions, BvhNode, EdgeWork, Patch, Ray, Scene, SceneSizes, SceneStorage, Vertices,
//! };
//!
//! // The upper half of an octahedron with radial normals (exactly the unit sphere), packed.
//! let p = [1.0f32, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0];
//! let ib = [[0u32, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
//! let mut options = BuildOptions::default(); // the paper's line field, no seams
//! let n = SceneSizes::new(5, 4, &options).unwrap();
//! assert_eq!((n.patches, n.nodes, n.edges, n.seams, n.vertices), (4, 3, 12, 0, 0));
//! assert_eq!(n.edge_work, 6); // one block: at most 12 / 2 shared edges
//! // Fixed-size storage, as firmware would hold it.
//! let mut patches = [Patch::<f32>::default(); 4];
//! let (mut ids, mut order, mut tris) = ([0u32; 4], [0u32; 4], [[0u32; 3]; 4]);
//! let mut nodes = [BvhNode::default(); 3];
//! let mut edges = [SharedEdge::default(); 12];
//! let mut work = [EdgeWork::default(); 6];
//! let storage = SceneStorage {
//!     patches: &mut patches, triangle_ids: &mut ids, nodes: &mut nodes, order: &mut order,
//!     seams: &mut [], triangles: &mut tris, edges: &mut edges, edge_work: &mut work,
//!     vertex_positions: &mut [], vertex_normals: &mut [], clamped_normals: &mut [],
//!     vertex_clamps: &mut [],
//! };
//! let (pos, nrm) = (Vertices::packed(&p), Vertices::packed(&p));
//! let scene = Scene::build(pos, nrm, &ib, &mut options, storage).unwrap();
//! let hit = scene.closest_hit(&Ray::new(Vec3::splat(2.0), -Vec3::ONE), 0.0, f32::INFINITY, 4);
//! let hit = hit.unwrap();
//! assert!((hit.hit.point.length() - 1.0).abs() < 2e-6); // the method reproduces spheres
//! assert_eq!(hit.triangle, 0);
//! # let _ = (Seam::<f32>::default(), VertexClamp::<f32>::default());
//! ```
//!
//! # One patch
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
//!
//! # Layers
//!
//! The crate is built in layers that import downward only: numbers (scalars, vectors, dual
//! numbers, intervals, eight-wide lanes), the patch record, the surface (edge spheres, edge
//! curves, line fields, the surface and its shell), the kernel, [`Patch`], [`Bvh`], and
//! [`mesh`] (shared edges, the remedy per vertex, crack closure, seams and the builder). Only
//! the root items, [`accuracy`] and [`mesh`] are public.
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// `!(a > b)` is deliberate throughout: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(feature = "alloc")]
extern crate alloc;

mod aabb;
pub mod accuracy;
mod bvh;
mod error;
mod exec;
mod geometry;
mod kernel;
pub mod mesh;
mod num;
mod patch;
mod ray;
mod surface;
#[cfg(test)]
mod testing;

#[doc(hidden)]
pub mod internal;
pub mod isa;

pub use aabb::Aabb;
pub use bvh::{BVH_EMPTY_SLOT, BVH_STACK, BVH_WIDTH, BoxBvh, Bvh, BvhError, BvhNode, MAX_DEPTH};
pub use error::PatchError;
pub use geometry::PatchData;
pub use kernel::flat::{flat_hit, moller_trumbore};
pub use kernel::{
    DEFAULT_SAMPLES, KernelStats, MAX_ITERATIONS, PREDICTED_EVALS, iterations, max_height_evals,
    max_lane_calls,
};
#[cfg(feature = "alloc")]
pub use mesh::OwnedScene;
pub use mesh::{
    BuildError, BuildObserver, BuildOptions, BuildReport, BuildStage, DynamicScene, EdgeWork,
    Executor, OnRejected, Rejections, Scene, SceneHit, SceneSizes, SceneStorage, Vertices,
};
#[cfg(feature = "micromath")]
pub use num::fast::FastF32;
pub use num::real::Float;
pub use patch::{DPatch, MIN_NORMAL_COS, NORMAL_CLAMP_DEG, Patch};
pub use ray::{DHit, DRay, Hit, Ray};
pub use surface::field::LineField;
