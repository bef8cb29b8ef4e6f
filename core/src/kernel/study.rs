//! The study of the predicted search ([`super::predicted`]) on given rays: one ray's test of
//! one patch with the predicted search and with the bracketing alone, side by side, and a
//! patch's predictor error against its bound. For `cargo bench --bench predictor` and the
//! predictor's validation tests; not part of the API.
//!
//! # Panics
//! No function panics.

use super::clip::WorldRay;
use super::heights::target;
use super::{KernelStats, Test, crossing};
use crate::geometry::Patch;
use crate::num::real::Float;
use crate::ray::Ray;
use crate::surface::lanes::Prepared;
use crate::surface::shell::longest_edge;

/// One search of one patch by one ray: the crossing's `t` and `t_error` (world units of the
/// ray's `dir`) and its true height evaluations; `None` for no crossing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Search {
    /// `t`, `t_error` of the crossing (`None`: no crossing).
    pub crossing: Option<[f64; 2]>,
    /// True height evaluations made.
    pub evals: u32,
}

/// The test of `patch` by `ray` in `[t_min, t_max]` at the budget `n` (the default bracketing
/// samples): with the predicted search (the kernel's, where the patch has a predictor) and
/// with the bracketing alone.
pub fn search_study<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
    n: usize,
) -> [Search; 2] {
    [true, false].map(|predict| {
        let Some(world) = WorldRay::new(ray) else {
            return Search::default();
        };
        let mut stats = KernelStats::default();
        let test = Test {
            predict,
            ..Test::closest(t_min, t_max, n)
        };
        let c = crossing::<F, { super::DEFAULT_SAMPLES }>(
            patch,
            &world,
            test,
            &mut stats,
            &mut None,
            &target(),
        );
        Search {
            crossing: c.map(|c| [c.t.to_f64(), c.t_error.to_f64()]),
            evals: stats.height_evals,
        }
    })
}

/// The patch's predictor (`core/src/surface/predictor.rs`): the largest `|P − σS|` over the
/// degree-`grid` lattice of its triangle and its bound, both over the longest edge; `None`
/// where the patch has no predictor.
pub fn predictor_error<F: Float>(patch: &Patch<F>, grid: usize) -> Option<[f64; 2]> {
    let p = &patch.predictor;
    if !p.usable() {
        return None;
    }
    let prep = Prepared::new(&patch.shape);
    let edge = longest_edge(&patch.shape).to_f64();
    Some([
        p.max_error(&patch.shape, &prep, grid),
        p.bound().to_f64() / edge,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Rng, random_patches};

    /// Rays aimed at random interior points of random patches from within about 50° of the
    /// face normal (no grazing double crossing): both searches find the crossing, within
    /// each other's `t_error` (`f64`), and on patches with a predictor the predicted search
    /// makes fewer true evaluations.
    #[test]
    fn both_searches_find_the_same_crossing() {
        let mut rng = Rng(63);
        let (mut hits, mut predicted, mut sums) = (0, 0, [0u32; 2]);
        for (patch, size) in random_patches(11, 200) {
            let usable = predictor_error(&patch, 4).is_some();
            for _ in 0..8 {
                let (w1, w2) = (0.1 + 0.4 * rng.unit(), 0.1 + 0.4 * rng.unit());
                let target = patch.point(w1, w2);
                let dir = -(patch.face_normal() + rng.vec() * 0.6).normalize();
                let ray = Ray::new(target - dir * (2.0 * size), dir);
                let [p, b] = search_study(&patch, &ray, 0.0, f64::INFINITY, 8);
                let (Some([tp, ep]), Some([tb, eb])) = (p.crossing, b.crossing) else {
                    assert_eq!(p.crossing.is_some(), b.crossing.is_some(), "{p:?} {b:?}");
                    continue;
                };
                hits += 1;
                predicted += usize::from(usable);
                if usable {
                    sums[0] += p.evals;
                    sums[1] += b.evals;
                }
                assert!((tp - tb).abs() <= ep + eb, "{p:?} {b:?}");
            }
        }
        assert!(hits > 1000, "{hits} hits");
        // In `f64` the predictor's step is far from the early stop, so refinement follows;
        // still at most two thirds of the bracketing's evaluations on average.
        assert!(
            predicted > 1000,
            "{predicted} hits on patches with a predictor"
        );
        assert!(3 * sums[0] <= 2 * sums[1], "{sums:?} true evaluations");
    }
}
