//! Named accuracy bounds: one source of truth for every accuracy figure of the crate.
//!
//! Each constant states what it bounds, relative to what, and which test of the repository's
//! suite (`tests/` of the workspace root) asserts it. The `# Accuracy` sections of this crate's
//! docs, the crate-level table and the README cite these names, and the tests import them
//! (`use smoothtri::accuracy::*`) instead of repeating literals, so a regression fails a test
//! and a change of a bound changes every statement of it.
//!
//! Each bound is a modest margin (about 1.5× to 4×) above the worst value measured, which
//! its documentation gives with the sample it was measured on; `cargo test --release --test
//! NAME -- --nocapture` prints the measured values again.
//!
//! Terms: the *size* of a triangle is its longest edge (the tests of points on edges use the
//! longer of the two edges from `P0`); the *scale* is the larger of the size and the largest
//! absolute coordinate of its vertices (what `f32` coordinates can resolve); differences of
//! unit normals are Euclidean distances (≈ the angle in radians).

// ---------------------------------------------------------------------------------------------
// Construction and evaluation

/// `f64` interpolation: [`Patch::point`](crate::Patch::point) at the vertices reproduces the
/// input vertices, and on each edge the edge curve of
/// [`Patch::edge_point_normal`](crate::Patch::edge_point_normal), to this fraction of the
/// triangle's size; the edge normals at the ends equal the vertex normals to this (absolute).
/// Measured worst: points 5.1e-14, normals 6.3e-16 (20 000 random triangles, normals ≤ 40°,
/// sizes 1e-2…50 at offsets up to 3). Asserted by `tests/suite/patch.rs`
/// (`interpolates_vertices_and_edges`).
pub const F64_INTERPOLATION: f64 = 1e-13;

/// `f32` interpolation: as [`F64_INTERPOLATION`], points relative to the scale, normals
/// absolute. Measured worst: points 5.9e-7, normals 4.6e-7 (same 20 000 triangles). Asserted by
/// `tests/suite/patch.rs` (`interpolates_vertices_and_edges`).
pub const F32_INTERPOLATION: f64 = 1e-6;

/// `f64`: vertex normals all equal to the face normal give the flat triangle: points within
/// this fraction of the scale, normals within this of the face normal. Measured worst: points
/// 1.1e-15, normals 9.8e-14 (20 000 random triangles). Asserted by `tests/suite/patch.rs`
/// (`flat_normals_give_flat_triangle`).
pub const F64_FLAT_TRIANGLE: f64 = 2e-13;

/// `f64`: every point of a patch of a sphere (vertices on it, radial normals) is on the
/// sphere to this fraction of the radius. Measured worst: 1.1e-15 (20 000 random patches,
/// radius 1e-3…1e3, arcs 5°…35°, centres up to 2 radii from the origin). Asserted by
/// `tests/suite/patch.rs` (`spheres_are_exact`) and `tests/suite/robustness.rs` (the octant at scales
/// 1e-20…1e20).
pub const F64_SPHERE_POINT: f64 = 4e-15;

/// `f32`: as [`F64_SPHERE_POINT`]. Measured worst: 5.8e-7 (same 20 000 patches). Asserted by
/// `tests/suite/patch.rs` (`spheres_are_exact`).
pub const F32_SPHERE_POINT: f64 = 1e-6;

/// `f64`: the normal of [`Patch::point_normal`](crate::Patch::point_normal) on a sphere's
/// patch, and of a hit on it, is radial to this. Measured worst: 6.2e-14 (the 20 000 patches of
/// [`F64_SPHERE_POINT`]), 1.2e-15 at the hits of `tests/suite/kernel.rs`. Asserted by
/// `tests/suite/patch.rs` (`spheres_are_exact`) and `tests/suite/kernel.rs` (icosphere and cube).
pub const F64_SPHERE_NORMAL: f64 = 2e-13;

/// `f32`: as [`F64_SPHERE_NORMAL`]; the normal comes from `f32` derivatives. Measured worst:
/// 2.6e-5 (the 20 000 patches), 5.6e-7 at the hits of `tests/suite/kernel.rs`. Asserted by
/// `tests/suite/patch.rs` (`spheres_are_exact`) and `tests/suite/kernel.rs`.
pub const F32_SPHERE_NORMAL: f64 = 5e-5;

/// `f64`: the exact derivatives of [`Patch::derivatives`](crate::Patch::derivatives) (dual
/// numbers) against central differences of [`Patch::point`](crate::Patch::point) with step
/// 1e-5, relative to the size; and the edge curves' tangents (central differences of
/// [`Patch::edge_point_normal`](crate::Patch::edge_point_normal)) against the surface's
/// derivative along the edge and perpendicular to the edge normal and the surface normal there,
/// to the same. The difference is the central difference's own error. Measured worst: 6.0e-9
/// (20 000 random patches, normals ≤ 40°). Asserted by `tests/suite/patch.rs`
/// (`derivatives_match_finite_differences`).
pub const DERIVATIVES_VS_CENTRAL_DIFFERENCES: f64 = 2e-8;

/// `f32` against `f64` on the same (`f32`) input: surface points to this fraction of the
/// scale. Measured worst: 4.2e-7 (2000 random patches × 4 points, `tests/suite/patch.rs`), 2.9e-7
/// (the 600 points of `tests/data/`). Asserted by `tests/suite/patch.rs` (`f32_tracks_f64`) and
/// `tests/suite/reference.rs`.
pub const F32_VS_F64_POINT: f64 = 1e-6;

/// `f32` against `f64` on the same input: unit normals of
/// [`Patch::point_normal`](crate::Patch::point_normal) to this. Measured worst: 3.1e-7 (2000
/// random patches × 4 points). Asserted by `tests/suite/patch.rs` (`f32_tracks_f64`).
pub const F32_VS_F64_NORMAL: f64 = 1e-6;

/// `f64` surface points against the independent `f64` implementation whose results are vendored
/// in `tests/data/` (600 points), relative to the scale. The reference works in world
/// coordinates and differs from our shift-invariant evaluation by ~100 ulps of the coordinates
/// on small triangles far from the origin. Measured worst: 1.8e-14. Asserted by
/// `tests/suite/reference.rs`.
pub const F64_SURFACE_VS_REFERENCE: f64 = 3e-14;

/// The same comparison as [`F64_SURFACE_VS_REFERENCE`], relative to the triangle's size
/// (larger, for the reference's small triangles far from the origin). Measured worst: 9.4e-12.
/// Asserted by `tests/suite/reference.rs`.
pub const F64_SURFACE_VS_REFERENCE_OF_SIZE: f64 = 2e-11;

/// `f64` surface normals against `tests/data/`, whose normals come from numerical
/// differentiation (the difference is theirs). Measured worst: 1.2e-8. Asserted by
/// `tests/suite/reference.rs`.
pub const F64_NORMAL_VS_REFERENCE: f64 = 3e-8;

/// `f64` edge-curve points of [`Patch::edge_point_normal`](crate::Patch::edge_point_normal)
/// against `tests/data/` (900 points), relative to the size. Measured worst: 1.5e-13. Asserted
/// by `tests/suite/reference.rs`.
pub const F64_EDGE_VS_REFERENCE: f64 = 3e-13;

/// `f64` edge-curve normals against `tests/data/`. Measured worst: 3.5e-10. Asserted by
/// `tests/suite/reference.rs`.
pub const F64_EDGE_NORMAL_VS_REFERENCE: f64 = 1e-9;

/// Every unit vector the crate returns (face normal, vertex normals, surface, edge and hit
/// normals) has length `1 ± UNIT_LENGTH_ULPS · ε` of its precision, for every accepted patch
/// and every argument. Measured worst: 3.9 ε (`f32`), 3 ε (`f64`) over 20 000 cases of each
/// property of `tests/suite/robustness.rs` (extreme magnitudes, skinny triangles, normals near 90°).
/// Asserted by `tests/suite/robustness.rs` and `tests/suite/regressions.rs`.
pub const UNIT_LENGTH_ULPS: f64 = 8.0;

// ---------------------------------------------------------------------------------------------
// Ray kernel

/// `f64`: the kernel's own height evaluation (`core/src/surface/lanes/`, no dual numbers) against the
/// generic one of [`Patch::height`](crate::Patch::height), relative to the triangle's size.
/// Measured worst: 9.2e-15 (98 472 random patches, normals up to ~37°, 66 points each; 5.4e-17
/// on the 393 patches of the unit test). Asserted by the unit test
/// `equals_the_generic_height_within_rounding` of `core/src/surface/lanes/tests.rs`.
#[cfg(test)]
pub(crate) const KERNEL_HEIGHT_VS_SURFACE: f64 = 3e-14;

/// `f64` hits (N = 8) on meshes that are exactly a sphere for the method (an icosphere, and a
/// cube with averaged normals): every hit point on the analytic sphere to this fraction of the
/// radius. Measured worst: 7.7e-16 (3000 random rays per mesh, 2231 and 2249 hits). Asserted by
/// `tests/suite/kernel.rs`, `tests/suite/bvh.rs` and `tests/suite/robustness.rs` (the octant at any scale, with
/// the returned `t_error`).
pub const F64_SPHERE_HIT: f64 = 2e-15;

/// `f32`: as [`F64_SPHERE_HIT`]. Measured worst: 3.5e-7 (same rays). Asserted by
/// `tests/suite/kernel.rs` and `tests/suite/robustness.rs`.
pub const F32_SPHERE_HIT: f64 = 1e-6;

/// `f64` hits (N = 8) of [`F64_SPHERE_HIT`]: `|t − t_true|·|dir|`, the distance along the ray
/// to the analytic intersection, to this fraction of the radius. Measured worst: 1.7e-14.
/// Asserted by `tests/suite/kernel.rs`.
pub const F64_SPHERE_HIT_T: f64 = 5e-14;

// ---------------------------------------------------------------------------------------------
// FastF32 (feature `micromath`)

/// The square root of `FastF32` (micromath's estimate refined by one Newton step), relative to
/// the correctly rounded one, for every positive `f32`. Measured worst: 1.73e-3 (4096 points
/// in every pair of binades from 2^-120 to 2^120; the pattern repeats every factor 4).
/// Asserted by `tests/fast.rs`.
pub const FASTF32_SQRT_REL: f64 = 2e-3;

/// A patch built in `FastF32` against the `f64` patch of the same input: surface points to
/// this fraction of the triangle's size (spheres are no longer reproduced exactly). Measured
/// worst: 4.9e-3 (5000 random patches, normals ≤ 40°; 3.7e-3 on the 300 of the test). Asserted
/// by `tests/fast.rs`.
pub const FASTF32_SURFACE: f64 = 8e-3;

/// `FastF32` hits (N = 8) of a ray along the face normal through the centroid against the
/// `f64` hit, as a distance along the ray relative to the size. Measured worst: 3.7e-4 (5000
/// random patches; 2.5e-4 on the 300 of the test). Asserted by `tests/fast.rs`.
pub const FASTF32_HIT: f64 = 1e-3;

// ---------------------------------------------------------------------------------------------
// Seamless shading normals (`crate::mesh::seams`)

/// Jump of [`Seam::shading_normal`](crate::mesh::Seam::shading_normal) across shared edges, in
/// degrees (the angle between the two neighbours' shading normals at the same edge point): on a
/// fitted edge each side's shading normal is the common normal, which both build from the same
/// fit in frames that agree to rounding, so the jump is rounding. Measured worst (50 points per
/// edge, every shared edge: curves that part, clamped and folded patches included): 0 in
/// `f64` on every mesh of the suite; in `f32` 2e-5° on the 8×8 torus (the geometric normal:
/// 5.83°), 2.7e-4° on the built-in teapot (45 clamped and 6 folded patches; the geometric normal
/// up to 119°), 2.2e-4° on the 8×8 teapot, 7e-5° on the stress meshes; on real files (f64, 9
/// points between the vertices) 1e-4° on a 3.7k-triangle animal with 219 edges next to clamped
/// patches and below 1e-4° on a 121k-triangle CAD model. Asserted by `tests/suite/seam.rs` and
/// `tests/suite/real_meshes.rs`.
pub const SEAM_JUMP_DEG: f64 = 1e-3;
