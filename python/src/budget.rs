//! The iteration budget `n` of the core's queries, chosen at run time: any value up to the
//! core's `MAX_ITERATIONS`, run on the kernels of the widest instruction set the CPU has
//! (`smoothtri_isa::kernels`; `SMOOTHTRI_ISA` overrides, the same bits on each). Every query
//! of this crate goes through [`Budget`].

use smoothtri::{MAX_ITERATIONS, Ray, Scene, SceneHit};

/// The budgets [`Budget::new`] accepts, as words (for messages and docs).
pub const SUPPORTED_TEXT: &str = "0..=64";

/// A validated iteration budget: `n` refinement steps of the smooth kernel (eight height
/// evaluations each; `n = 0` brackets only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget(usize);

impl Budget {
    /// The budget `n`, or `None` beyond `0..=MAX_ITERATIONS` ([`SUPPORTED_TEXT`]).
    pub fn new(n: i64) -> Option<Budget> {
        let n = usize::try_from(n).ok()?;
        (n <= MAX_ITERATIONS).then_some(Budget(n))
    }

    /// Every budget accepted, in increasing order.
    pub fn all() -> Vec<usize> {
        (0..=MAX_ITERATIONS).collect()
    }

    /// The number of refinement steps.
    pub fn get(self) -> usize {
        self.0
    }

    /// `scene.closest_hit(ray, t_min, t_max, n)` on the process's kernels.
    #[inline]
    pub fn closest<F: smoothtri_isa::Precision>(
        self,
        scene: &Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<SceneHit<F>> {
        smoothtri_isa::kernels().scene_closest_hit(scene, ray, t_min, t_max, self.0)
    }

    /// `scene.any_hit(ray, t_min, t_max, n)` on the process's kernels.
    #[inline]
    pub fn any<F: smoothtri_isa::Precision>(
        self,
        scene: &Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> bool {
        smoothtri_isa::kernels().scene_any_hit(scene, ray, t_min, t_max, self.0)
    }
}
