//! The predicted search (docs/METHOD.md §8, "The predicted search"): certify the crossing the
//! patch's predictor ([`crate::surface::predictor`]) points at, instead of searching for it
//! with true heights.
//!
//! For a patch with a predictor and a refinement budget `n ≥ 1` (crack reach included: `f` and
//! `f̃` share the surface's continuation beyond the edges, and a crossing at a wall, where the
//! end snap decides, goes to the bracketing by step 1's rule):
//! 1. **Signs** ([`signs`]): the predictor's `f̃` at the bracketing samples (the same points as
//!    [`first_sign_change`](super::refine::first_sign_change), eight per pass of
//!    [`Float::L8`]). Where `|f̃|` exceeds the margin (the predictor's bound plus twice the end
//!    snap, for the rounding of `f` and `f̃`), `f` has `f̃`'s sign. The first sign change among
//!    the samples is then decided without a true height: uncertain samples between two samples
//!    of opposite signs widen the bracket; an uncertain first sample, an uncertain sample before
//!    the bracket, or uncertain samples with no sign change after them leave the decision to
//!    the true heights (the bracketing). No sign change with every sample certain is a miss
//!    (no true height at all).
//! 2. **Predicted crossing** ([`root`]): [`ROOT_PASSES`] passes of eight lanes of `f̃` inside
//!    the bracket, then regula falsi: `τp` and `f̃`'s slope there.
//! 3. **Certify** ([`certify`]): one true evaluation at `τp`, one step of length `e` with the
//!    predictor's slope to `τ1`, and four true evaluations at `τ1 ± r_in`, `τ1 ± r_out` (one
//!    four-point call) with refinement's radii but a smaller inner share: `r_in = max(e·`[`STEP_SPREAD`]`,
//!    `[`INNER_OF_STOP`]` · stop)`, `r_out = max(e·`[`OUTER_OF_SPREAD`]`, r_in·`[`OUTER_OF_INNER`]`)`.
//!    In `f32` the step lands well within the early stop and the inner pair is the certifying
//!    pair: the root between them ends the search. The bracket narrows to the first sign
//!    change among these points; an end that only the predictor signed (at most one) gets a
//!    true evaluation (a contradiction, which a valid bound never gives, returns to the
//!    bracketing).
//! 4. **Refine** ([`refine`](super::refine::refine)) what is left of that bracket: usually
//!    nothing.
//!
//! The first-root rule is the bracketing's (the first sign change among the same samples), so hits
//! and misses only change where the predictor's bound fails or a sample is within rounding of
//! a double crossing. `t_error` comes from the final bracket of true heights; its rounding
//! allowance uses the flatter of the final bracket's secant and the sampling bracket's, as
//! always, the latter from the predicted values at its ends (each within the bound of the true
//! one; moving them toward zero by the margin would bound the true secant, but inflates the
//! allowance wherever a sample lies just beyond the margin: docs/MEASUREMENTS.md).
//!
//! Work: at most [`PREDICTED_EVALS`] true evaluations before refinement (the contradiction
//! fallback adds the bracketing), counted in
//! [`max_height_evals`](super::max_height_evals).
//!
//! # Panics
//! No function panics.

use super::refine::{
    Bracket, ESTIMATE_POINTS, INNER_OF_STOP, OUTER_OF_INNER, OUTER_OF_SPREAD, narrow,
};
use crate::geometry::Predictor;
use crate::num::lanes::LANES;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::lanes::Prepared;

/// Passes of eight lanes of `f̃` that locate its root inside the sampling bracket (each
/// narrows it ninefold) before regula falsi.
pub const ROOT_PASSES: usize = 2;

/// The inner radius around the stepped crossing `τ1`, as a fraction of the step's length `e`
/// (at least [`INNER_OF_STOP`] early-stop widths): the stepped point's error is the step times
/// the relative error of the predictor's slope, which refinement's
/// [`INNER_OF_SPREAD`](super::refine::INNER_OF_SPREAD) = 1/64 overstates (it leaves many more
/// `f32` hits to refinement after the five evaluations: docs/MEASUREMENTS.md, "The predicted
/// search"); `f64`, whose early stop is far below the step's error, refines either way.
pub const STEP_SPREAD: f64 = 1.0 / 256.0;

/// True height evaluations of the predicted search before refinement, at most: one at the
/// predicted crossing, four around the stepped one, and one for the end of the narrowed
/// bracket that only the predictor had signed (at most one end is; docs/METHOD.md §8, "The
/// predicted search").
pub const PREDICTED_EVALS: usize = 1 + ESTIMATE_POINTS + 1;

/// What the predictor's signs at the bracketing samples decide ([`signs`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Signs<F> {
    /// Every sample is certain and none changes sign: no crossing.
    Miss,
    /// The first sign change: the bracket with the predicted values at its ends.
    Bracket(Bracket<F>),
    /// The predictor cannot decide: bracket with true heights.
    Unsure,
}

/// The local ray of a patch test and the predictor with its patch.
#[derive(Clone, Copy)]
pub(crate) struct Predicted<'a, F> {
    pub predictor: &'a Predictor<F>,
    pub prep: &'a Prepared<F>,
    pub o: V3<F>,
    pub r: V3<F>,
}

impl<F: Float> Predicted<'_, F> {
    #[inline(always)]
    fn f8(&self, taus: [F; LANES]) -> [F; LANES] {
        self.predictor.f8(self.prep, self.o, self.r, taus)
    }
}

/// Whether `f` changes sign (or vanishes) between two values.
#[inline(always)]
fn changes<F: Float>(fa: F, fb: F) -> bool {
    fa == F::ZERO || fb == F::ZERO || (fa < F::ZERO) != (fb < F::ZERO)
}

/// Step 1 (module docs): the predictor's signs at `a`, `K` evenly spaced interior points and
/// `b` (the points of `first_sign_change`), certain where `|f̃| > margin`.
#[inline(always)]
pub(crate) fn signs<F: Float, const K: usize>(
    p: &Predicted<'_, F>,
    a: F,
    b: F,
    margin: F,
) -> Signs<F> {
    if !(b >= a) || !(margin >= F::ZERO) {
        return Signs::Unsure;
    }
    let step = (b - a) / F::from_f64((K + 1) as f64);
    let point = |j: usize| {
        if j > K {
            b
        } else {
            a + step * F::from_f64(j as f64)
        }
    };
    // The last certain sample (all certain samples so far share its sign), and whether an
    // uncertain one came after it.
    let mut last: Option<(F, F)> = None;
    let mut unsure = false;
    for call in 0..(K + 2).div_ceil(LANES) {
        let xs: [F; LANES] = core::array::from_fn(|i| point(call * LANES + i));
        let gs = p.f8(xs);
        for (i, (x, g)) in xs.into_iter().zip(gs).enumerate() {
            if call * LANES + i > K + 1 {
                break;
            }
            if !(g.abs() > margin) {
                if last.is_none() {
                    return Signs::Unsure;
                }
                unsure = true;
                continue;
            }
            match last {
                Some((x0, g0)) if changes(g0, g) => {
                    return Signs::Bracket(Bracket {
                        a: x0,
                        b: x,
                        fa: g0,
                        fb: g,
                    });
                }
                // Same sign after an uncertain sample: a double crossing could hide there.
                Some(_) if unsure => return Signs::Unsure,
                _ => last = Some((x, g)),
            }
        }
    }
    if unsure { Signs::Unsure } else { Signs::Miss }
}

/// Step 2 (module docs): the predicted crossing `τp` in `br` (predicted values at its ends)
/// and `f̃`'s slope there (the secant of the last pass's bracket).
#[inline(always)]
pub(crate) fn root<F: Float>(p: &Predicted<'_, F>, br: &Bracket<F>) -> (F, F) {
    let (mut lo, mut glo, mut hi, mut ghi) = (br.a, br.fa, br.b, br.fb);
    let ninth = F::ONE / F::from_f64((LANES + 1) as f64);
    for _ in 0..ROOT_PASSES {
        let w = hi - lo;
        let xs: [F; LANES] =
            core::array::from_fn(|i| lo + w * (ninth * F::from_f64((i + 1) as f64)));
        let gs = p.f8(xs);
        let (mut x0, mut g0) = (lo, glo);
        for (x, g) in xs.into_iter().zip(gs) {
            if changes(g0, g) {
                (hi, ghi) = (x, g);
                break;
            }
            (x0, g0) = (x, g);
        }
        (lo, glo) = (x0, g0);
    }
    let slope = (ghi - glo) / (hi - lo);
    let tp = lo - glo / slope;
    let tp = if tp.is_fin() && tp >= lo && tp <= hi {
        tp
    } else {
        F::from_f64(0.5) * (lo + hi)
    };
    (tp, slope)
}

/// Step 3 (module docs): the bracket `br` (predicted values at its ends) narrowed by true
/// evaluations around the predicted crossing `tp` (`f̃`'s slope `slope` there), with the
/// nearest samples outside it for the next estimate; `None` where a true value contradicts a
/// predicted sign at an end of the result (take the bracketing).
#[inline(always)]
#[allow(clippy::type_complexity)]
pub(crate) fn certify<F: Float>(
    br: Bracket<F>,
    tp: F,
    slope: F,
    stop: F,
    f1: &mut impl FnMut(F) -> F,
    f4: &mut impl FnMut([F; ESTIMATE_POINTS]) -> [F; ESTIMATE_POINTS],
) -> Option<(Bracket<F>, Option<(F, F)>, Option<(F, F)>)> {
    let clamp = |t: F| t.max(br.a).min(br.b);
    let fp = f1(tp);
    let t1 = tp - fp / slope;
    let t1 = if t1.is_fin() { clamp(t1) } else { tp };
    // Radii as refinement's (`super::refine`): from the step's length `e`, the error of the
    // predicted crossing that the true value corrected (a generous bound of the stepped
    // point's own error), at least the early stop's share for the inner pair.
    let e = (t1 - tp).abs();
    let r_in = (e * F::from_f64(STEP_SPREAD)).max(stop * F::from_f64(INNER_OF_STOP));
    let r_out = (e * F::from_f64(OUTER_OF_SPREAD)).max(r_in * F::from_f64(OUTER_OF_INNER));
    let around = [
        clamp(t1 - r_out),
        clamp(t1 - r_in),
        clamp(t1 + r_in),
        clamp(t1 + r_out),
    ];
    let [f0, f1v, f2, f3] = f4(around);
    let [x0, x1, x2, x3] = around;
    let xs = [tp, x0, x1, x2, x3];
    let fs = [fp, f0, f1v, f2, f3];
    let (mut next, before, after) = narrow(&br, &xs, &fs);
    // An end that kept its predicted value: the true height (one of the five where a point
    // was clamped onto the end) must have the predicted sign. At most one end needs a new
    // evaluation: `τp` and the four points lie in `br`, so where none lies strictly inside
    // the result, each of its ends is one of them or the end of `br` beside it.
    let mut check = |x: F, g: F| {
        let known = xs.iter().zip(fs.iter()).find(|&(&xi, _)| xi == x);
        let v = match known {
            Some((_, &v)) => v,
            None => f1(x),
        };
        if v != F::ZERO && !changes(v, g) {
            Some(v)
        } else {
            None
        }
    };
    if next.a == br.a && next.fa == br.fa {
        next.fa = check(next.a, br.fa)?;
    }
    if next.b == br.b && next.fb == br.fb {
        next.fb = check(next.b, br.fb)?;
    }
    Some((next, before, after))
}

#[cfg(test)]
mod tests {
    use super::super::heights::target;
    use super::super::{Test, crossing, max_height_evals};
    use super::*;
    use crate::kernel::{DEFAULT_SAMPLES, KernelStats, WorldRay};
    use crate::ray::Ray;
    use crate::testing::{Rng, random_patches};

    /// A predictor whose bound is wrong (its heights raised, its bound zero) signs brackets
    /// before the true crossing of rays coming down the face normal (or none at all, where
    /// the whole shell interval lies within the shift above the surface: a miss, which only a
    /// valid bound prevents). Where the true heights contradict it, the search returns to the
    /// bracketing: the same crossing bit for bit as the bracketing alone, after
    /// [`PREDICTED_EVALS`] more evaluations at most, within [`max_height_evals`].
    #[test]
    fn a_contradicted_predictor_returns_to_the_bracketing() {
        const N: usize = 8;
        let mut rng = Rng(65);
        let (mut contradicted, mut most) = (0, 0u32);
        for (patch, size) in random_patches(5, 100) {
            if !patch.predictor.usable() {
                continue;
            }
            let mut wrong = patch;
            wrong.predictor = patch.predictor.shifted(0.05 * size);
            for _ in 0..8 {
                let aim = patch.point(0.1 + 0.4 * rng.unit(), 0.1 + 0.4 * rng.unit());
                let dir = -patch.face_normal();
                let Some(world) = WorldRay::new(&Ray::new(aim - dir * (2.0 * size), dir)) else {
                    continue;
                };
                let search = |p: &crate::Patch<f64>, predict: bool| {
                    let mut stats = KernelStats::default();
                    let test = Test {
                        predict,
                        ..Test::closest(0.0, f64::INFINITY, N)
                    };
                    let c = crossing::<f64, DEFAULT_SAMPLES>(
                        p,
                        &world,
                        test,
                        &mut stats,
                        &mut None,
                        &target(),
                    );
                    (c.map(|c| (c.t, c.t_error)), stats.height_evals)
                };
                let (got, evals) = search(&wrong, true);
                let (want, alone) = search(&patch, false);
                assert!(evals as usize <= max_height_evals(DEFAULT_SAMPLES, N));
                // Five evaluations and at most one end check, then the bracketing, bit for
                // bit; otherwise the predicted search certified the crossing itself.
                match (got, want) {
                    (Some(g), Some(w)) if g == w && evals >= alone + 5 => {
                        contradicted += 1;
                        most = most.max(evals - alone);
                    }
                    (Some((t, e)), Some((tw, ew))) => assert!((t - tw).abs() <= e + ew),
                    _ => assert!(
                        got.is_none() || want.is_some(),
                        "{got:?} where the bracketing finds nothing"
                    ),
                }
            }
        }
        assert!(
            contradicted > 100,
            "{contradicted} rays returned to the bracketing"
        );
        assert!(
            (5..=PREDICTED_EVALS as u32).contains(&most),
            "{most} more evaluations than the bracketing"
        );
    }

    /// The end check of [`certify`]: a true height that contradicts an end's predicted sign
    /// returns `None`, after [`PREDICTED_EVALS`] evaluations where the five points all lie
    /// strictly inside (the work bound's predicted share, reached); with a true sign change
    /// inside, the five certify it.
    #[test]
    fn certify_checks_the_end_only_the_predictor_signed() {
        let br = Bracket {
            a: 0.0,
            b: 1.0,
            fa: 1.0,
            fb: -1.0,
        };
        let count = core::cell::Cell::new(0usize);
        let run = |f: &dyn Fn(f64) -> f64, slope: f64| {
            count.set(0);
            let mut f1 = |x: f64| {
                count.set(count.get() + 1);
                f(x)
            };
            let mut f4 = |xs: [f64; ESTIMATE_POINTS]| {
                count.set(count.get() + ESTIMATE_POINTS);
                xs.map(f)
            };
            let out = certify(br, 0.5, slope, 0.01, &mut f1, &mut f4);
            (out.map(|(b, _, _)| b), count.get())
        };
        // Positive over the whole bracket: the predicted sign at `b` is wrong.
        let (out, evals) = run(&|x| 1.0 - 0.5 * x, -10.0);
        assert!(out.is_none());
        assert_eq!(evals, PREDICTED_EVALS);
        // A root at 0.574 and the predictor's slope right: the step lands on it, the inner
        // pair brackets it.
        let (out, evals) = run(&|x| 0.574 - x, -1.0);
        let b = out.unwrap_or(br);
        assert!(b.a <= 0.574 && 0.574 <= b.b && b.b - b.a <= 0.01, "{b:?}");
        assert_eq!(evals, 1 + ESTIMATE_POINTS);
    }
}
