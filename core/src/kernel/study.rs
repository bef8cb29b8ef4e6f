//! The study of issue 63's predicted search on given rays: what one ray's search of one patch
//! would cost if it started from the predictor's crossing ([`crate::surface::predictor`]) and
//! only certified it, beside today's search on the same ray and patch. For
//! `cargo bench --bench predictor`; not part of the API.
//!
//! The predicted search, as the issue describes it:
//! 1. the predictor's first crossing `τp` in the shell interval (its `f̃` sampled densely and
//!    bisected: no true evaluation);
//! 2. one true evaluation there, and one step with the predictor's slope: `τ1`;
//! 3. the certifying pair `τ1 ± 0.4·stop` (`stop` today's early-stop width): certified when
//!    `f` changes sign across it (3 true evaluations);
//! 4. otherwise four more points, `τ2 + {±0.4, ±1.2}·stop` around the pair's secant root
//!    `τ2`: certified when two of the six points, at most `stop` apart, bracket a sign
//!    change (7);
//! 5. otherwise today's search (7 plus today's evaluations).
//!
//! # Panics
//! No function panics.

use super::budget::{end_snap, rounding_allowance, secant};
use super::clip::{WorldRay, clip};
use super::heights::{Heights, target};
use super::refine::{EARLY_STOP, first_sign_change};
use super::{KernelStats, Test, bary_at, crossing};
use crate::geometry::Patch;
use crate::num::lanes::{LANES, One};
use crate::num::real::Float;
use crate::ray::Ray;
use crate::surface::lanes::Prepared;
use crate::surface::predictor::Predictor;

/// Intervals of the dense scan of `f̃` for its first sign change.
const SCAN: usize = 64;
/// Bisection steps of `f̃`'s root.
const BISECT: usize = 60;
/// Half the certifying pair's width, in early-stop widths.
const PAIR: f64 = 0.4;

/// What the predicted search would do on one ray's crossing of one patch, beside today's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PredictorOutcome {
    /// True height evaluations of the predicted search: 3 (certified by the pair), 7
    /// (certified by four more points) or 7 plus [`PredictorOutcome::today_evals`] (fallback).
    pub evals: u32,
    /// The stage that certified: 1 the pair, 2 the four points, 0 none (fallback).
    pub stage: u8,
    /// Today's search's height evaluations on the same ray, patch and budget.
    pub today_evals: u32,
    /// `|τp − τ|`: the predictor's crossing from today's, in early-stop widths; infinite
    /// when `f̃` has no sign change in the shell interval.
    pub predicted_off: f64,
    /// `|τ1 − τ|`: after one step with the predictor's slope, in early-stop widths.
    pub stepped_off: f64,
    /// Whether a certified bracket holds today's crossing (within today's `t_error`); `true`
    /// on fallback, which is today's search.
    pub agrees: bool,
    /// Today's crossing: `t` and `t_error` (world units of the ray's `dir`).
    pub today: [f64; 2],
    /// The certified bracket in `t` (world units); both ends at today's `t` on fallback.
    pub certified: [f64; 2],
}

/// [`PredictorOutcome`] of `ray` and `patch` in `[t_min, t_max]` at refinement budget `n`
/// (the default bracketing samples), or `None` when today's search finds no crossing.
pub fn predictor_study<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
    n: usize,
) -> Option<PredictorOutcome> {
    const K: usize = super::DEFAULT_SAMPLES;
    let world = WorldRay::new(ray)?;
    let heights = target::<F>();
    let mut stats = KernelStats::default();
    let mut prepared = None;
    let test = Test::closest(t_min, t_max, n);
    let today = crossing::<F, K>(patch, &world, test, &mut stats, &mut prepared, &heights)?;
    let prep = prepared?;
    let cl = clip(patch, &world, t_min, t_max, None)?;
    let (o, r) = (cl.lray.o, cl.lray.r);
    let mut f8 = |taus: [F; LANES]| heights.f8(&prep, o, r, taus);
    let (bracket, _) = first_sign_change::<F, K>(cl.a, cl.b, end_snap(cl.scale), &mut f8)?;
    let stop = rounding_allowance(cl.scale, secant(&bracket)) * F::from_f64(EARLY_STOP);
    let stop64 = stop.to_f64();
    let tau = (today.t - cl.t0).to_f64();
    let off = |x: F| (x.to_f64() - tau).abs() / stop64;

    let shape = &patch.shape;
    let predictor = Predictor::new(&prep);
    let predicted = |t: F| {
        let x = cl.lray.at(t);
        x.z - predictor.at(bary_at(shape, &prep, x))
    };
    let truth = |t: F| {
        let [o, r] = [o, r].map(|v| [One(v.x), One(v.y), One(v.z)]);
        prep.f(o, r, One(t)).0
    };

    let world_t = |x: F| (cl.t0 + x).to_f64();
    let mut outcome = PredictorOutcome {
        today_evals: stats.height_evals,
        today: [today.t.to_f64(), today.t_error.to_f64()],
        certified: [today.t.to_f64(); 2],
        predicted_off: f64::INFINITY,
        stepped_off: f64::INFINITY,
        ..PredictorOutcome::default()
    };
    let fallback = PredictorOutcome {
        evals: 7 + stats.height_evals,
        stage: 0,
        agrees: true,
        ..outcome
    };
    let Some(tp) = first_root(cl.a, cl.b, &predicted) else {
        return Some(fallback);
    };
    outcome.predicted_off = off(tp);
    // One true evaluation, one step with the predictor's slope.
    let fp = truth(tp);
    let h = ((cl.b - cl.a) * F::from_f64(1e-4)).max(stop);
    let slope = (predicted(tp + h) - predicted(tp - h)) / (h + h);
    let step = fp / slope;
    let t1 = if step.is_fin() { tp - step } else { tp };
    outcome.stepped_off = off(t1);
    // The pair, then four more points around its secant root.
    let half = stop * F::from_f64(PAIR);
    let pair = [t1 - half, t1 + half].map(|t| (t, truth(t)));
    let [(a, fa), (b, fb)] = pair;
    // Certified by `stage` with `evals` true evaluations: the bracket `[lo, hi]`.
    let certified = |stage: u8, evals: u32, lo: F, hi: F| {
        let e = today.t_error.to_f64();
        Some(PredictorOutcome {
            evals,
            stage,
            agrees: lo.to_f64() - e <= tau && tau <= hi.to_f64() + e,
            certified: [world_t(lo), world_t(hi)],
            ..outcome
        })
    };
    if changes(fa, fb) {
        return certified(1, 3, a, b);
    }
    let root = a - fa * (b - a) / (fb - fa);
    let reach = stop * F::from_f64(4.0);
    let t2 = if root.is_fin() {
        root.max(t1 - reach).min(t1 + reach)
    } else {
        t1
    };
    let four = [-3.0, -1.0, 1.0, 3.0].map(|k| {
        let t = t2 + half * F::from_f64(k);
        (t, truth(t))
    });
    let [p0, p1] = pair;
    let [p2, p3, p4, p5] = four;
    let points = [p0, p1, p2, p3, p4, p5];
    // The narrowest pair of points at most `stop` apart across which `f` changes sign: two
    // neighbours (a sign change across a wider pair is also across a neighbouring one inside).
    let mut best: Option<(F, F)> = None;
    for (i, &(a, fa)) in points.iter().enumerate() {
        for &(b, fb) in points.iter().skip(i + 1) {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            if hi - lo <= stop && changes(fa, fb) && best.is_none_or(|(l, h)| hi - lo < h - l) {
                best = Some((lo, hi));
            }
        }
    }
    if let Some((a, b)) = best {
        return certified(2, 7, a, b);
    }
    Some(PredictorOutcome {
        predicted_off: outcome.predicted_off,
        stepped_off: outcome.stepped_off,
        ..fallback
    })
}

/// The largest `|P − σS|` of the patch's predictor over the degree-16 lattice of its triangle,
/// over its longest edge.
pub fn predictor_error<F: Float>(patch: &Patch<F>) -> f64 {
    let prep = Prepared::new(&patch.shape);
    Predictor::new(&prep).max_error(&patch.shape, &prep, 16)
}

/// Whether `f` changes sign (or vanishes) between two values.
fn changes<F: Float>(fa: F, fb: F) -> bool {
    fa == F::ZERO || fb == F::ZERO || (fa < F::ZERO) != (fb < F::ZERO)
}

/// The first root of `g` in `[a, b]`: the first sign change of [`SCAN`] intervals, bisected
/// [`BISECT`] times.
fn first_root<F: Float>(a: F, b: F, g: &impl Fn(F) -> F) -> Option<F> {
    let n = F::from_f64(SCAN as f64);
    let at = |j: usize| a + (b - a) * F::from_f64(j as f64) / n;
    let mut lo = (a, g(a));
    for j in 1..=SCAN {
        let t = at(j);
        let hi = (t, g(t));
        if changes(lo.1, hi.1) {
            let (mut x0, mut g0, mut x1) = (lo.0, lo.1, hi.0);
            for _ in 0..BISECT {
                let m = (x0 + x1) * F::from_f64(0.5);
                let gm = g(m);
                if changes(g0, gm) {
                    x1 = m;
                } else {
                    (x0, g0) = (m, gm);
                }
            }
            return Some((x0 + x1) * F::from_f64(0.5));
        }
        lo = hi;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Rng, random_patches};

    /// Rays aimed at random interior points of random patches from within about 50° of the
    /// face normal (no grazing double crossing): the outcome's counts are the stages' (3, 7,
    /// or 7 plus today's), and every certified bracket holds today's crossing within its
    /// `t_error` (`f64`: both searches end at the same simple root).
    #[test]
    fn certified_brackets_hold_today_s_crossing() {
        let mut rng = Rng(63);
        let mut hits = 0;
        for (patch, size) in random_patches(11, 200) {
            for _ in 0..8 {
                let (w1, w2) = (0.1 + 0.4 * rng.unit(), 0.1 + 0.4 * rng.unit());
                let target = patch.point(w1, w2);
                let dir = -(patch.face_normal() + rng.vec() * 0.6).normalize();
                let ray = Ray::new(target - dir * (2.0 * size), dir);
                let Some(o) = predictor_study(&patch, &ray, 0.0, f64::INFINITY, 8) else {
                    continue;
                };
                hits += 1;
                match o.stage {
                    1 => assert_eq!(o.evals, 3),
                    2 => assert_eq!(o.evals, 7),
                    _ => assert_eq!(o.evals, 7 + o.today_evals),
                }
                assert!(o.agrees, "{o:?}");
            }
        }
        assert!(hits > 1000, "{hits} hits");
    }
}
