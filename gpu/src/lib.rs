//! # smoothtri-gpu
//!
//! smoothtri's bounded-work ray kernel as a WGSL compute shader (wgpu, Vulkan backend): the
//! patches and the BVH of a scene go to the GPU as storage buffers, and a batch of rays is traced
//! with one invocation per ray, in `f32`, with the mathematics of the CPU kernel
//! (docs/METHOD.md §2–§8): box and shell clip, bracketing at 8 points, exactly `n` refinement
//! steps of 8 points each, the certified `t_error` (final bracket plus the rounding allowance
//! `16 ε L / |f′|`), and the exact surface normal once per ray (forward-mode derivatives written
//! out in the shader, no finite differences).
//!
//! Two ways in. **Batches**, mirroring the CPU API: [`GpuScene::closest_hit`] fills a slice of
//! [`Option<Hit>`](smoothtri::Hit) for a slice of [`Ray`](smoothtri::Ray)s (the CPU's
//! [`Bvh::closest_hit`](smoothtri::Bvh::closest_hit) per ray), [`GpuScene::any_hit`] a slice of
//! `bool` (shadow rays), each with its refinement budget `n` given at run time, as the CPU's
//! `Scene::closest_hit` (each budget is its own pipeline, compiled once).
//! [`GpuScene::closest_shaded`] adds each hit's shading normal: the seamless normal of
//! smooth patches uploaded with their seams ([`GpuScene::smooth_seamless`], the CPU's
//! `Scene::shading_normal` in WGSL) or the Phong normal of flat triangles ([`GpuScene::phong`]).
//! **Frames**, for real-time use: [`GpuScene::render_frame`] makes the camera rays of a
//! [`FrameView`], traces them, shades each closest hit with the scene's normal and a shadow ray,
//! and writes the colours into a [`GpuFrame`], all in one compute pass; [`GpuSurface::present`]
//! draws the frame into a window's swap chain, so nothing comes back but the frame's counters
//! ([`GpuFrame::read`] reads the pixels for screenshots).
//!
//! Every failure is a [`GpuError`]: no adapter, buffers over the device's limits, a corrupt tree
//! (detected by the shader, which never reads outside a buffer), a lost device. Nothing here
//! panics on bad input.
//!
//! # Bounded work
//! Per patch test at most `8 + 8·n + 8` height evaluations ([`SAMPLES`]` + 2` bracketing
//! points, `n` steps of 8 and, for `n ≥ 1`, two estimate steps of 4: the CPU's
//! `smoothtri::max_height_evals` less its predicted search, which the GPU does not run), every
//! loop of the kernel with a constant trip count; per ray at most one
//! visit per BVH node, one test per index of the tree's order, and [`STACK`] pending nodes; per
//! pixel of a frame two such rays (the camera ray and at most one shadow ray) and at most four
//! exact normals (the hit's and, for the seamless normal, three edge points').
//!
//! ```no_run
//! use glam::Vec3;
//! use smoothtri::{Bvh, BvhNode, Patch, Ray};
//! use smoothtri_gpu::{Gpu, GpuScene};
//!
//! let p = [Vec3::X, Vec3::Y, Vec3::Z];
//! let patches = [Patch::<f32>::new(p, p).unwrap()];
//! let mut nodes = [BvhNode::default(); 1];
//! let mut order = [0u32; 1];
//! let bvh = Bvh::build(&patches, &mut nodes, &mut order).unwrap();
//! let gpu = Gpu::new()?; // GpuError::NoAdapter without a Vulkan device
//! let scene = GpuScene::smooth(&gpu, &bvh)?;
//! let rays = [Ray::new(Vec3::splat(2.0), -Vec3::ONE)];
//! let mut hits = [None; 1];
//! scene.closest_hit(&rays, 0.0, f32::INFINITY, 4, &mut hits)?;
//! assert!((hits[0].unwrap().point.length() - 1.0).abs() < 1e-5);
//! # Ok::<(), smoothtri_gpu::GpuError>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod device;
mod dispatch;
mod error;
mod flat_tris;
mod frame;
mod query;
mod records;
mod scene;
mod shader;
mod update;

pub use device::Gpu;
pub use error::GpuError;
pub use flat_tris::{FLAT_SHADER, FlatHit, FlatScene};
pub use frame::{FramePixel, FrameStats, FrameView, GpuFrame, GpuSurface};
pub use records::{GpuNode, flat_record, seam_record, smooth_record};
pub use scene::{GpuScene, SceneKind};
pub use shader::{
    DEFAULT_ITERATIONS, FLAT_VEC4, HIT_BYTES, MAX_ITERATIONS, PATCH_VEC4, RAY_BYTES, SAMPLES,
    SEAM_VEC4, SHADER, STACK, Shading, UPDATE_SHADER,
};
pub use update::GpuUpdate;
