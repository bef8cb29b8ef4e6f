//! The mesh layer: from a renderer's vertex and index buffers to patches with their cracks
//! closed, optional seamless shading normals and a BVH, in caller-provided storage (no
//! allocation; [`OwnedScene`] with the `alloc` feature owns its storage).
//!
//! # The builder
//!
//! [`Scene::build`] runs, in this order:
//! 1. on [`LineField::Vertex`](crate::LineField::Vertex) only, the per-vertex remedy ([`clamp_vertex_normals`]): one
//!    clamped normal per vertex, shared by the faces around it;
//! 2. one patch per triangle with the per-patch remedy ([`Patch::new_or_tilted_with`](crate::Patch::new_or_tilted_with));
//!    triangles the core rejects (non-finite, degenerate, overflowing input) are skipped and
//!    counted in the [`BuildReport`], never fatal unless none is left;
//! 3. crack closure between neighbours ([`close_cracks`]);
//! 4. with [`BuildOptions::seams`], the seamless shading normals ([`fit_seams`]);
//! 5. the [`Bvh`](crate::Bvh) over the accepted patches.
//!
//! [`SceneSizes::new`] gives the length of every storage slice from the counts and the options
//! alone (never from the data), so a caller can allocate once, up front.
//!
//! Each step is public on its own for renderers that run their own pipeline; they match edges
//! by vertex index, so vertices meant to be smooth across an edge must share their index (a
//! split vertex makes a boundary: creases stay creases).
//!
//! # Seamless shading normals
//!
//! With [`BuildOptions::seams`] (or [`fit_seams`] directly) the shading normal is corrected
//! (docs/METHOD.md, "Seamless shading normals"): a correction of the
//! surface normal that makes it continuous across the shared edges of a mesh, while the surface
//! itself (and its exact geometric normal, [`Patch::point_normal`](crate::Patch::point_normal), [`Hit::normal`](crate::Hit::normal)) stays as it
//! is.
//!
//! The geometric normals of two neighbouring patches differ along their shared edge (by up to
//! 5.8° on the 8×8 torus), which shows as creases in shading. [`fit_seams`] fits, once per
//! mesh, for every edge shared by two patches a *common* edge normal `m(t)` (the average of the
//! two sides' geometric normals) as two tilts of the interpolated vertex normal `g(t)`, in a
//! frame built from the edge's shared data alone (its vertices and their normals:
//! `g = normalize((1 − t)·na + t·nb)`, `ĝ = normalize(ê × g)` with `ê` the chord, `â = g × ĝ`),
//! so that both neighbours fit and evaluate the same common normal even where their edge
//! curves part:
//!
//! ```text
//! m(t) = normalize(g(t) + τ_b(t)·ĝ(t) + τ_a(t)·â(t)),   τ(t) = t(1 − t)·Σ_k c_k (2t − 1)^k
//! ```
//!
//! with `TWIST_TERMS` = 6 coefficients `c_k` each, stored per patch in a [`Seam`]. Where a
//! per-patch clamp gave the two sides different vertex normals, `m` is instead the average of
//! both sides' `g` (each stores the other's two normals). [`Seam::shading_normal`] then returns
//!
//! ```text
//! n_s(X) = normalize(n_g(X) + Σ_j β_j(X)·(m_j(t_j) − n_g(Y_j))),
//! β_j = (X_j X_{j+1})² / Σ_i (X_i X_{i+1})²,   t_j = X_{j+1} / (X_j + X_{j+1})
//! ```
//!
//! (edge `j` runs from `Pj` to `Pj+1`; `β = 0` at the vertices; `Y_j` is the point of edge `j`
//! at `t_j`, the opposite vertex's weight moved onto the edge's two, and `n_g(Y_j)` this
//! patch's exact normal there). On edge `j` only `β_j = 1` is left and `Y_j = X`, so
//! `n_s = m_j` exactly: the same from both sides to rounding. At the vertices `n_s` is the
//! vertex normal; on a sphere `m = n_g` and the correction vanishes (normals stay radial).
//! Points are never changed.
//!
//! Memory: `size_of::<Seam<f32>>()` is 148 bytes (`f64`: 296), beside the patch's 304.

pub(crate) mod build;
pub(crate) mod cracks;
pub(crate) mod dynamic;
pub(crate) mod edges;
pub(crate) mod input;
pub(crate) mod parallel;
pub(crate) mod report;
pub(crate) mod sampling;
pub(crate) mod scene;
pub(crate) mod seams;
pub(crate) mod storage;
pub(crate) mod topology;
pub(crate) mod vertex_normals;

pub use build::REBUILD_COST_RATIO;
pub use dynamic::DynamicScene;
pub use input::{BuildOptions, Vertices};
pub use report::{BuildError, BuildObserver, BuildReport, BuildStage, OnRejected, Rejections};
pub use scene::{Scene, SceneHit};
pub use storage::{SceneSizes, SceneStorage};
#[cfg(feature = "alloc")]
pub(crate) mod owned;

pub use cracks::CrackReport;
pub use edges::{close_cracks, fit_seams};
#[cfg(feature = "alloc")]
pub use owned::OwnedScene;
pub use parallel::{EDGE_WORK_BLOCK, EdgeWork, Executor};
pub use seams::Seam;
pub use topology::{MeshError, SharedEdge, shared_edges};
pub use vertex_normals::{VertexClamp, VertexClampReport, clamp_vertex_normals};
