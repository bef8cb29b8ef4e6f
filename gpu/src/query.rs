//! The batch queries of a [`GpuScene`]: closest hits (with a budget fixed at compile time or
//! chosen at run time, timed, or with the shading normal) and any hits, each one traced by the
//! dispatch ([`crate::dispatch`]).

use glam::Vec3;
use smoothtri::{Hit, Ray};

use crate::dispatch::{Batch, Raw};
use crate::error::GpuError;
use crate::scene::GpuScene;

impl GpuScene {
    /// Closest hits of `rays` in `[t_min, t_max]` with `N` refinement steps, one per slot of
    /// `hits` (`hit.patch` is the index of the patch in the uploaded order of patches, as
    /// the CPU's [`Bvh::closest_hit`](smoothtri::Bvh::closest_hit)). Rays that the CPU rejects
    /// (non-finite, zero direction, NaN or reversed range) are misses; `t_max` may be infinite.
    ///
    /// # Accuracy
    /// As the CPU kernel's in `f32`: `|t − t_true| ≤ hit.t_error` for the crossing inside the
    /// final bracket (tested against analytic spheres and the CPU kernel: `gpu/tests/`).
    pub fn closest_hit<const N: usize>(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<(), GpuError> {
        self.closest_hit_with(N, rays, t_min, t_max, hits)
    }

    /// [`GpuScene::closest_hit`] with the budget chosen at run time (at most
    /// [`MAX_ITERATIONS`](crate::MAX_ITERATIONS); each budget is its own pipeline, compiled once).
    pub fn closest_hit_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(iterations, false, batch, None, hits, Raw::hit)
    }

    /// [`GpuScene::closest_hit_with`], also returning the GPU's own execution time of the
    /// kernel's compute passes in seconds (timestamp queries, summed over the dispatches:
    /// without the ray upload and the readback), or `None` when the adapter has no timestamp
    /// queries. For benchmarks; the hits are the same as [`GpuScene::closest_hit_with`]'s.
    pub fn closest_hit_timed(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<Option<f64>, GpuError> {
        let (batch, mut seconds) = (Batch::new(rays, t_min, t_max), 0.0);
        self.run(iterations, false, batch, Some(&mut seconds), hits, Raw::hit)?;
        Ok(self.gpu.timestamps.then_some(seconds))
    }

    /// [`GpuScene::closest_hit_with`] with each hit's shading normal (world, unit, oriented like
    /// [`Hit::normal`]): the scene's [`Shading`](crate::Shading), i.e. the seamless normal (the
    /// CPU's `Scene::shading_normal`, the same formula in `f32`: within 1e-5 of it for the same
    /// hit in the parity tests), the Phong normal, or the hit's own normal.
    pub fn closest_shaded_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        out: &mut [Option<(Hit<f32>, Vec3)>],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(iterations, false, batch, None, out, |raw| {
            raw.hit().map(|h| (h, Vec3::from_array(raw.shading)))
        })
    }

    /// Whether anything is hit in `[t_min, t_max]` along each ray (shadow rays), with `N`
    /// refinement steps; the traversal stops at the first hit.
    pub fn any_hit<const N: usize>(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        occluded: &mut [bool],
    ) -> Result<(), GpuError> {
        self.any_hit_with(N, rays, t_min, t_max, occluded)
    }

    /// [`GpuScene::any_hit`] with the budget chosen at run time.
    pub fn any_hit_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        occluded: &mut [bool],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(iterations, true, batch, None, occluded, |raw| {
            raw.flags & 1 != 0
        })
    }
}
