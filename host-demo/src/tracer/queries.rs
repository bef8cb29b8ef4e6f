//! Ray-scene queries: the [`Tracer`] strategies (the smooth kernel at a compile-time iteration
//! budget, the flat and Phong baselines) and their choice at run time ([`tracer`]).

use smoothtri::{Bvh, Float, Hit, Ray, flat_hit};

use super::modes::Mode;
use crate::error::{DemoError, Result};

/// A ray-scene query strategy (smooth kernel with a fixed budget, or a flat baseline).
pub trait Tracer<F: Float>: Sync {
    /// Whether the hits are on the smooth patches (their normals may then be corrected by the
    /// scene's seams, [`Scene::shading_normal`](crate::tracer::Scene::shading_normal));
    /// `false` for the flat baselines.
    fn smooth(&self) -> bool {
        false
    }
    /// Closest hit in `[t_min, t_max]`.
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>>;
    /// Whether anything is hit in `[t_min, t_max]`.
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool;
    /// The closest hit in `[t_min, t_max]` with the scene's shading normal
    /// ([`smoothtri::Scene::shading_normal`]: seamless where the scene has seams). The smooth
    /// kernel answers with [`smoothtri::Scene::closest_hit`], which evaluates both normals at
    /// once; the result is the same bit for bit.
    fn closest_shaded(
        &self,
        scene: &smoothtri::Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<(Hit<F>, F::Vec3)> {
        let hit = self.closest(scene.bvh(), ray, t_min, t_max)?;
        Some((hit, scene.shading_normal(&hit)))
    }
}

struct Smooth<const N: usize>;
impl<F: Float, const N: usize> Tracer<F> for Smooth<N> {
    fn smooth(&self) -> bool {
        true
    }
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_hit::<N>(ray, t_min, t_max)
    }
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        bvh.any_hit::<N>(ray, t_min, t_max)
    }
    fn closest_shaded(
        &self,
        scene: &smoothtri::Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<(Hit<F>, F::Vec3)> {
        let h = scene.closest_hit::<N>(ray, t_min, t_max)?;
        Some((h.hit, h.shading_normal))
    }
}

struct Flat {
    phong: bool,
}
impl<F: Float> Tracer<F> for Flat {
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_with(ray, t_min, t_max, |_, p, a, b| {
            let ns = p.normals();
            flat_hit(&p.vertices(), self.phong.then_some(&ns), ray, a, b)
        })
    }
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        self.closest(bvh, ray, t_min, t_max).is_some()
    }
}

/// Largest iteration budget accepted by `--iterations`.
pub const MAX_ITERATIONS: usize = 40;

macro_rules! smooth_dispatch {
    ($n:expr, $($k:literal)*) => {
        match $n {
            $($k => Some(&Smooth::<$k> as &'static dyn Tracer<F>),)*
            _ => None,
        }
    };
}

/// Iteration budgets the demo is compiled for (each is a separate monomorphised kernel; the
/// core takes any `N` at compile time).
pub const SUPPORTED_ITERATIONS: &str = "0..=16, 20, 24, 32, 40";

/// The smooth kernel with an iteration budget of `n` (see [`SUPPORTED_ITERATIONS`]),
/// monomorphised.
pub fn smooth_tracer<F: Float>(n: usize) -> Option<&'static dyn Tracer<F>> {
    smooth_dispatch!(n, 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 20 24 32 40)
}

/// The tracer of `mode` (the budget matters for [`Mode::Smooth`] only).
pub fn tracer<F: Float>(mode: Mode, n: usize) -> Result<&'static dyn Tracer<F>> {
    match mode {
        Mode::Smooth => smooth_tracer(n).ok_or_else(|| {
            DemoError::Usage(format!(
                "--iterations {n} is not supported (use one of {SUPPORTED_ITERATIONS})"
            ))
        }),
        Mode::Flat => Ok(&Flat { phong: false }),
        Mode::Phong => Ok(&Flat { phong: true }),
        Mode::PhongTess | Mode::Nagata => Err(DemoError::Usage(format!(
            "--mode {} is traced by `render` and `trace` only (on the CPU)",
            mode.name()
        ))),
    }
}
