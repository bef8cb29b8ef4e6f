//! The iteration budget `N` of the core's queries, chosen at run time: the one place where a
//! Python integer meets the core's compile-time `N` (`Scene::closest_hit::<N>`,
//! `Scene::any_hit::<N>`). Every query of this crate goes through [`Budget`].

use smoothtri::{Float, Ray, Scene, SceneHit};

/// Runs `$body` with the constant `$k` set to the budget `$n` when `$n` is one of the budgets
/// this module is compiled for, else evaluates `$other`. The list below is the only list of
/// budgets in the crate ([`Budget::new`] accepts what it matches).
macro_rules! at_budget {
    ($n:expr, $other:expr, |$k:ident| $body:expr) => {
        at_budget!(@arms $n, $other, $k, $body;
            0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 20 24 32 40)
    };
    (@arms $n:expr, $other:expr, $k:ident, $body:expr; $($v:literal)*) => {
        match $n {
            $($v => {
                const $k: usize = $v;
                $body
            })*
            _ => $other,
        }
    };
}

/// The budgets [`Budget::new`] accepts, as words (for messages and docs).
pub const SUPPORTED_TEXT: &str = "0..=16, 20, 24, 32, 40";

/// The largest budget accepted.
pub const MAX_BUDGET: usize = 40;

/// A validated iteration budget: `N` refinement steps of the smooth kernel (eight height
/// evaluations each; `N = 0` brackets only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget(usize);

impl Budget {
    /// The budget `n`, or `None` when the crate is not compiled for it ([`SUPPORTED_TEXT`]).
    pub fn new(n: i64) -> Option<Budget> {
        let n = usize::try_from(n).ok()?;
        at_budget!(n, None, |K| Some(Budget(K)))
    }

    /// Every budget accepted, in increasing order.
    pub fn all() -> Vec<usize> {
        (0..=MAX_BUDGET)
            .filter(|&n| at_budget!(n, false, |_K| true))
            .collect()
    }

    /// The number of refinement steps.
    pub fn get(self) -> usize {
        self.0
    }

    /// `scene.closest_hit::<N>(ray, t_min, t_max)`.
    #[inline]
    pub fn closest<F: Float>(
        self,
        scene: &Scene<'_, F>,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<SceneHit<F>> {
        at_budget!(self.0, None, |K| scene.closest_hit::<K>(ray, t_min, t_max))
    }

    /// `scene.any_hit::<N>(ray, t_min, t_max)`.
    #[inline]
    pub fn any<F: Float>(self, scene: &Scene<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        at_budget!(self.0, false, |K| scene.any_hit::<K>(ray, t_min, t_max))
    }
}
