//! Ray-scene queries: the [`Tracer`] strategies (the smooth kernel at an iteration budget, the
//! flat and Phong baselines) and their choice at run time ([`tracer`]).

use smoothtri::{Bvh, Hit, Ray, flat_hit};
use smoothtri_isa::{Dispatch, Precision};

use super::modes::Mode;
use crate::error::{DemoError, Result};

/// A ray-scene query strategy (smooth kernel with a fixed budget, or a flat baseline).
pub trait Tracer<F: Precision>: Sync {
    /// Whether the hits are on the smooth patches (their normals may then be corrected by the
    /// scene's seams, [`Scene::shading_normal`](crate::tracer::Scene::shading_normal));
    /// `false` for the flat baselines.
    fn smooth(&self) -> bool {
        self.smooth_budget().is_some()
    }
    /// The refinement budget of the smooth kernel; `None` for the flat baselines.
    fn smooth_budget(&self) -> Option<usize> {
        None
    }
    /// Closest hit in `[t_min, t_max]`.
    fn closest_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>>;
    /// Whether anything is hit in `[t_min, t_max]`.
    fn any_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool;
    /// The closest hit in `[t_min, t_max]` with the scene's shading normal
    /// ([`smoothtri::Scene::shading_normal`]: seamless where the scene has seams). The smooth
    /// kernel ([`Tracer::smooth_budget`]) answers with [`smoothtri::Scene::closest_hit`] (on
    /// [`smoothtri_isa::kernels`]), which evaluates both normals at once; the result is the
    /// same bit for bit.
    fn closest_shaded(
        &self,
        scene: &smoothtri::Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<(Hit<F>, F::Vec3)> {
        if let Some(n) = self.smooth_budget() {
            let h = scene.closest_hit_isa(ray, t_min, t_max, n)?;
            return Some((h.hit, h.shading_normal));
        }
        let hit = self.closest_hit(scene.bvh(), ray, t_min, t_max)?;
        Some((hit, scene.shading_normal(&hit)))
    }
}

/// The smooth kernel with a refinement budget of `n` steps, on the instruction set chosen at
/// run time ([`smoothtri_isa::kernels`]: the same hits, bit for bit, as the core's queries).
struct Smooth {
    n: usize,
}
impl<F: Precision> Tracer<F> for Smooth {
    fn smooth_budget(&self) -> Option<usize> {
        Some(self.n)
    }
    fn closest_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_hit_isa(ray, t_min, t_max, self.n)
    }
    fn any_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        bvh.any_hit_isa(ray, t_min, t_max, self.n)
    }
}

struct Flat {
    phong: bool,
}
impl<F: Precision> Tracer<F> for Flat {
    fn closest_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_with(ray, t_min, t_max, |_, p, a, b| {
            let ns = p.normals();
            flat_hit(&p.vertices(), self.phong.then_some(&ns), ray, a, b)
        })
    }
    fn any_hit(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        self.closest_hit(bvh, ray, t_min, t_max).is_some()
    }
}

/// Largest iteration budget accepted by `--iterations`: the core's
/// [`smoothtri::MAX_ITERATIONS`].
pub const MAX_ITERATIONS: usize = smoothtri::MAX_ITERATIONS;

/// One smooth tracer per budget `0..=MAX_ITERATIONS` (values, not instantiations: every budget
/// runs the same kernel), so that [`smooth_tracer`] hands out `'static` trait objects.
static SMOOTH: [Smooth; MAX_ITERATIONS + 1] = {
    let mut all = [const { Smooth { n: 0 } }; MAX_ITERATIONS + 1];
    let mut n = 0;
    while n <= MAX_ITERATIONS {
        all[n] = Smooth { n };
        n += 1;
    }
    all
};

/// The smooth kernel with an iteration budget of `n`, or `None` when `n` is above
/// [`MAX_ITERATIONS`].
pub fn smooth_tracer<F: Precision>(n: usize) -> Option<&'static dyn Tracer<F>> {
    SMOOTH.get(n).map(|t| t as &'static dyn Tracer<F>)
}

/// The tracer of `mode` (the budget matters for [`Mode::Smooth`] only).
pub fn tracer<F: Precision>(mode: Mode, n: usize) -> Result<&'static dyn Tracer<F>> {
    match mode {
        Mode::Smooth => smooth_tracer(n).ok_or_else(|| {
            DemoError::Usage(format!(
                "--iterations {n} is above the largest budget, {MAX_ITERATIONS}"
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
