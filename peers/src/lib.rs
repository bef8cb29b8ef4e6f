//! # smoothtri-peers
//!
//! The two other smooth surfaces that, like smoothtri's, need nothing but a triangle mesh with
//! vertex normals: **Phong tessellation** (Boubekeur & Alexa 2008, [`phong_tess`]) and
//! **Nagata patches** (Nagata 2005, [`nagata`]). Both are quadratic triangular patches
//! ([`QuadPatch`]); one exact ray solver serves both ([`ray_quadratic`]: the ray as two
//! planes, two conics in the patch's parameters, the pencil's cubic, then quadratics), and a
//! mesh of either is traced through smoothtri's own BVH and traversal ([`PeerScene`],
//! [`smoothtri::BoxBvh`]). They are the baselines smoothtri is measured beside (the
//! repository's `benches/peers.rs`, `examples/peers_accuracy.rs`, `examples/terminator.rs`),
//! written from the papers.
//!
//! `f32` and `f64` from one source ([`Real`]). Hits come back as smoothtri's [`smoothtri::Hit`]
//! (`w1, w2` the barycentrics on the patch, `t_error` 0: nothing is certified). The analytic
//! torus ([`torus`]) is the reference surface of the measurements.
//!
//! ```
//! use glam::Vec3;
//! use smoothtri::Ray;
//! // An octant of the unit sphere: vertices on it, normals radial.
//! let p = [Vec3::X, Vec3::Y, Vec3::Z];
//! let patch = smoothtri_peers::nagata::<f32>(p, p).unwrap();
//! let hit = patch.closest_hit(&Ray::new(Vec3::splat(2.0), -Vec3::ONE), 0.0, f32::MAX).unwrap();
//! // Nagata's patch bulges toward the sphere but is a quadratic, not the sphere.
//! assert!((hit.point.length() - 1.0).abs() < 0.05);
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// `!(a > b)` is deliberate throughout: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod nagata;
pub mod phong_tess;
pub mod quadratic;
pub mod ray_quadratic;
pub mod real;
pub mod scene;
pub mod torus;

pub use nagata::nagata;
pub use phong_tess::{ALPHA_DEFAULT, phong_tessellation};
pub use quadratic::{PeerError, QuadPatch};
pub use real::{Real, V3};
pub use scene::{Peer, PeerScene, SceneError, Tracer};
