//! The batch queries of a [`GpuScene`]: closest hits (plain, timed, or with the shading normal)
//! and any hits, each with its refinement budget chosen at run time as the CPU's
//! [`Scene`](smoothtri::mesh::Scene) queries, and each traced by the dispatch
//! ([`crate::dispatch`]).

use glam::Vec3;
use smoothtri::{Hit, Ray};

use crate::dispatch::{Batch, Raw};
use crate::error::GpuError;
use crate::scene::GpuScene;

impl GpuScene {
    /// Closest hits of `rays` in `[t_min, t_max]`, one per slot of `hits` (`hit.patch` is the
    /// index of the patch in the uploaded order of patches, as the CPU's
    /// [`Bvh::closest_hit`](smoothtri::Bvh::closest_hit)). Rays that the CPU rejects
    /// (non-finite, zero direction, NaN or reversed range) are misses; `t_max` may be infinite.
    ///
    /// `n` is the refinement budget, as the CPU's: `n` steps of eight height evaluations each
    /// (`n = 0` brackets only), at most [`MAX_ITERATIONS`](crate::MAX_ITERATIONS). Each budget is
    /// its own pipeline, compiled on its first use and cached on the [`Gpu`](crate::Gpu).
    ///
    /// Returns [`GpuError::LengthMismatch`] unless `hits` is as long as `rays`,
    /// [`GpuError::Iterations`] for `n` above [`MAX_ITERATIONS`](crate::MAX_ITERATIONS) (nothing
    /// is traced, even for an empty batch), [`GpuError::CorruptTree`] or
    /// [`GpuError::StackOverflow`] when the shader reports them, and [`GpuError::Shader`] or
    /// [`GpuError::Device`] when the device fails.
    ///
    /// # Accuracy
    /// As the CPU kernel's in `f32`: `|t − t_true| ≤ hit.t_error` for the crossing inside the
    /// final bracket (tested against analytic spheres and the CPU kernel: `gpu/tests/`).
    pub fn closest_hit(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        n: usize,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(n, false, batch, None, hits, Raw::hit)
    }

    /// [`GpuScene::closest_hit`] (the same budget `n`, hits and errors), also returning the
    /// GPU's own execution time of the kernel's compute passes in seconds (timestamp queries,
    /// summed over the dispatches: without the ray upload and the readback), or `None` when the
    /// adapter has no timestamp queries. For benchmarks.
    pub fn closest_hit_timed(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        n: usize,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<Option<f64>, GpuError> {
        let (batch, mut seconds) = (Batch::new(rays, t_min, t_max), 0.0);
        self.run(n, false, batch, Some(&mut seconds), hits, Raw::hit)?;
        Ok(self.gpu.timestamps.then_some(seconds))
    }

    /// [`GpuScene::closest_hit`] (the same budget `n`, hits and errors) with each hit's shading
    /// normal (world, unit, oriented like [`Hit::normal`]): the scene's
    /// [`Shading`](crate::Shading), i.e. the seamless normal (the CPU's `Scene::shading_normal`,
    /// the same formula in `f32`: within 1e-5 of it for the same hit in the parity tests), the
    /// Phong normal, or the hit's own normal.
    pub fn closest_shaded(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        n: usize,
        out: &mut [Option<(Hit<f32>, Vec3)>],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(n, false, batch, None, out, |raw| {
            raw.hit().map(|h| (h, Vec3::from_array(raw.shading)))
        })
    }

    /// Whether anything is hit in `[t_min, t_max]` along each ray (shadow rays), one per slot
    /// of `occluded`, with the refinement budget `n` and the errors of
    /// [`GpuScene::closest_hit`]; the traversal stops at the first hit.
    pub fn any_hit(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        n: usize,
        occluded: &mut [bool],
    ) -> Result<(), GpuError> {
        let batch = Batch::new(rays, t_min, t_max);
        self.run(n, true, batch, None, occluded, |raw| raw.flags & 1 != 0)
    }
}
