//! Bracketing and refinement with eight evaluations per step (docs/METHOD.md §8 steps 2–3).
//!
//! Both take `f` as a function of eight parameters at once (one call of the lane height
//! evaluation, `core/src/surface/lanes/`), so a step costs about one scalar evaluation on
//! AVX2.
//!
//! **Bracketing** samples `f` at `a`, `K` evenly spaced interior points and `b`, eight per call
//! (`⌈(K + 2)/8⌉` calls; [`DEFAULT_SAMPLES`](super::DEFAULT_SAMPLES) `= 6` fills one call), and
//! takes the first sign change.
//!
//! **Refinement** runs at most `n` steps (see the early stop below). A step on the bracket `[a, b]` of width `w` places
//! - [`UNIFORM_POINTS`] evenly spaced points `a + w·j/5`, `j = 1…4`, which alone guarantee that
//!   the next bracket is at most `w/5` wide ([`WORST_SHRINK`]), whatever `f` does, and
//! - four points around an estimate `x̂` of the root: `x̂ ± r_in` and `x̂ ± r_out`. When the
//!   root is within `r_in` of `x̂` the next bracket is `2·r_in` wide.
//!
//! The estimate is the zero of the **inverse interpolation** `x(f)` through the bracket's ends
//! and the nearest samples on either side where `f` is strictly monotone over them
//! ([`start_estimate`]: a cubic through four samples, error `O(w⁴)` near a simple root, against
//! regula falsi's `O(w²)`); the first step takes the bracketing call's samples, later steps the
//! previous step's. Its distance `e` to the regula falsi point (the lower order's error, a
//! generous bound of the higher order's where `f` is smooth at the scale of the bracket) sets
//! the radii: `r_in = max(e·`[`INNER_OF_SPREAD`]`, `[`INNER_OF_STOP`]` · stop)`, so that a root
//! caught within it ends the refinement (`stop` the early-stop width below), and
//! `r_out = max(e·`[`OUTER_OF_SPREAD`]`, r_in·`[`OUTER_OF_INNER`]`, w·`[`OUTER_OF_WIDTH`]`)`
//! (where `f` has a kink the two estimates can agree and both be off); regula falsi itself (no
//! neighbour qualified, `e = 0`) takes `r_in ≥ w·OUTER_OF_WIDTH/OUTER_OF_INNER`. The next bracket is the first sign
//! change among the sorted points. On the torus's rays (1024 rays at one patch, N = 8) an
//! `f32` test takes 2.04 lane calls (2.82 with the regula falsi steps this replaced), an `f64`
//! test 3.32 (4.36 before); docs/MEASUREMENTS.md "Cheaper root isolation".
//!
//! **Early stop.** Refinement ends before `n` steps once the bracket is at most [`EARLY_STOP`]
//! times the rounding allowance's lower bound (the allowance computed from the sampling
//! bracket's secant, `super::ROUNDING_ULPS`): the returned `t_error` is the bracket's width
//! plus an allowance at least that large, so further steps could shrink `t_error` by at most a
//! fifth while each costs a full lane call.
//!
//! **Estimate steps.** Where the step's estimate is trusted to the early stop (`e > 0` and
//! `2·r_in ≤ stop`: a root caught within `r_in` ends the refinement), the step evaluates only
//! the [`ESTIMATE_POINTS`] points around it, one call over four lanes (half an eight-point
//! call's work with SSE2 or NEON halves, and on the GPU four evaluations instead of eight).
//! When the root is caught the result is the bracket the eight-point step would have left
//! (unless one of its uniform points fell inside `x̂ ± r_in`); when it is not, the step has
//! still narrowed the bracket (usually to the gap between `x̂ ± r_in` and `x̂ ± r_out`) or
//! left it as it was, and the next step starts from the estimate through the new bracket's
//! samples: another estimate step where that is trusted, otherwise eight-point steps. At most
//! [`ESTIMATE_STEPS`] = 2 such steps per test, on top of the `n` (none at `n = 0`, which
//! brackets only), so the bound below is unchanged and the work bound grows by eight
//! evaluations (`crate::kernel::max_height_evals`). The second step pays where a four-point
//! call costs half an eight-point one (SSE2 and NEON halves, the GPU); with AVX2 or AVX-512
//! the two calls cost about the same.
//!
//! Bound: after bracketing and `n` steps the bracket is at most
//! `max((b − a) / ((K + 1)·5^n), EARLY_STOP · allowance)` for the shell interval `[a, b]` (up
//! to one ulp of the parameters per step, where the points collapse onto each other).

use crate::num::lanes::LANES;
use crate::num::real::Float;

/// Evenly spaced points per refinement step: `a + w·j/(UNIFORM_POINTS + 1)`.
pub const UNIFORM_POINTS: usize = 4;
/// The guaranteed shrink factor of the bracket per refinement step: `UNIFORM_POINTS + 1`.
pub const WORST_SHRINK: usize = UNIFORM_POINTS + 1;
/// Points of the estimate step (module docs, "Estimate steps"): `x̂ ± r_in` and `x̂ ± r_out`,
/// without the uniform points; at most [`ESTIMATE_STEPS`] per patch test, on top of the `n`
/// steps.
pub const ESTIMATE_POINTS: usize = 4;
/// Estimate steps per patch test at most (module docs, "Estimate steps"), on top of the `n`
/// eight-point steps: a second one where the first's four points missed the root but left a
/// bracket whose new estimate is trusted again.
pub const ESTIMATE_STEPS: usize = 2;
/// The inner radius around a step's estimate, as a fraction of its distance `e` to regula
/// falsi's (at least [`INNER_OF_STOP`] times the early-stop width, so a caught root ends the
/// refinement).
pub const INNER_OF_SPREAD: f64 = 1.0 / 64.0;
/// The smallest inner radius, as a fraction of the early-stop width: a root caught within it
/// ends the refinement (below one half, so that the bracket's rounding cannot take it over).
pub const INNER_OF_STOP: f64 = 0.4;
/// The outer radius around a step's estimate, as a multiple of `e`.
pub const OUTER_OF_SPREAD: f64 = 2.0;
/// The outer radius is at least this multiple of the inner one.
pub const OUTER_OF_INNER: f64 = 8.0;
/// The smallest outer radius, as a fraction of the bracket's width (where `f` is not smooth
/// at the bracket's scale, the estimates can agree and both be off); where the estimate is
/// regula falsi's own (`e = 0`), the inner radius is at least this over [`OUTER_OF_INNER`].
pub const OUTER_OF_WIDTH: f64 = 1.0 / 16.0;
/// Refinement stops early once the bracket is at most this fraction of the rounding
/// allowance's lower bound (module docs): the returned `t_error` is then at most
/// `1 + EARLY_STOP` times the allowance, which no further step could lower.
pub const EARLY_STOP: f64 = 0.25;

/// A bracket `[a, b]` with `f(a)`, `f(b)` of opposite signs (or one of them zero).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bracket<F> {
    pub a: F,
    pub b: F,
    pub fa: F,
    pub fb: F,
}

impl<F: Float> Bracket<F> {
    /// Regula falsi point of the bracket, clamped inside it (the midpoint if degenerate).
    #[inline(always)]
    pub fn estimate(&self) -> F {
        if self.fa == F::ZERO {
            return self.a;
        }
        if self.fb == F::ZERO {
            return self.b;
        }
        let den = self.fb - self.fa;
        let x = (self.fb * self.a - self.fa * self.b) / den;
        if x.is_fin() && x >= self.a && x <= self.b {
            x
        } else {
            F::from_f64(0.5) * (self.a + self.b)
        }
    }

    /// A bracket of zero width at an exact zero `x`.
    #[inline(always)]
    fn at(x: F, fx: F) -> Self {
        Bracket {
            a: x,
            b: x,
            fa: fx,
            fb: fx,
        }
    }
}

/// One bracketing sample: `f(x1) = f1` at sample `j` of `0..=last` after `(x0, f0)` at `j − 1`.
/// Returns the value to carry on (an end sample within `snap` of zero counts as zero) and the
/// bracket when the samples so far change sign or meet a zero: `[x0, x1]` with the zero kept at
/// its end (so the secant slope of the bracket, used by the rounding allowance, stays defined).
///
/// The snap decides a crossing at the shell interval's ends, where two patches sharing an edge
/// meet (docs/METHOD.md §8, "Shared edges"): each patch computes `f` at the shared wall in its
/// own frame, and within rounding of a crossing there the two signs are independent, so without
/// it a ray through the edge can see no sign change in either patch.
#[inline(always)]
pub(crate) fn bracket_step<F: Float>(
    j: usize,
    last: usize,
    (x0, f0): (F, F),
    (x1, f1): (F, F),
    snap: F,
) -> (F, Option<Bracket<F>>) {
    let f1 = if (j == 0 || j == last) && f1.abs() <= snap {
        F::ZERO
    } else {
        f1
    };
    if j == 0 {
        return (f1, None);
    }
    let br = Bracket {
        a: x0,
        b: x1,
        fa: f0,
        fb: f1,
    };
    let change = f0 == F::ZERO || f1 == F::ZERO || (f1 > F::ZERO) != (f0 > F::ZERO);
    (f1, if change { Some(br) } else { None })
}

/// Samples `f` at `a`, `K` interior points and `b`, eight per call of `f8`, and returns the
/// first bracket with a sign change or a zero ([`bracket_step`]: values at `a` and `b` within
/// `snap` of zero count as zero), with the start estimate of its first refinement step
/// ([`start_estimate`] from the samples around it). At most `⌈(K + 2)/8⌉` calls.
#[inline(always)]
pub(crate) fn first_sign_change<F: Float, const K: usize>(
    a: F,
    b: F,
    snap: F,
    f8: &mut impl FnMut([F; LANES]) -> [F; LANES],
) -> Option<(Bracket<F>, F)> {
    if !(b >= a) {
        return None;
    }
    let step = (b - a) / F::from_f64((K + 1) as f64);
    let point = |j: usize| {
        if j > K {
            b
        } else {
            a + step * F::from_f64(j as f64)
        }
    };
    let (mut x0, mut f0) = (a, F::ZERO);
    // The sample before `x0` (`None` at the first).
    let mut before: Option<(F, F)> = None;
    for call in 0..(K + 2).div_ceil(LANES) {
        let xs: [F; LANES] = core::array::from_fn(|i| point(call * LANES + i));
        let fs = f8(xs);
        let mut samples = xs.into_iter().zip(fs).enumerate().peekable();
        while let Some((i, (x1, f1))) = samples.next() {
            let j = call * LANES + i;
            if j > K + 1 {
                break;
            }
            let (f1, br) = bracket_step(j, K + 1, (x0, f0), (x1, f1), snap);
            if let Some(br) = br {
                // The sample after `x1`, where this call computed it.
                let after = match samples.peek() {
                    Some(&(_, s)) if j < K + 1 => Some(s),
                    _ => None,
                };
                return Some((br, start_estimate(&br, before, after)));
            }
            if j > 0 {
                before = Some((x0, f0));
            }
            (x0, f0) = (x1, f1);
        }
    }
    None
}

/// The start estimate of the first refinement step of the sampling bracket `br`: the zero of
/// the inverse interpolation `x(f)` through `br`'s ends and the samples `before` and `after`
/// it, where `f` is strictly monotone over them (a cubic through four points, a quadratic
/// through three; error `O(w⁴)` and `O(w³)` for a bracket of width `w` around a simple root,
/// against regula falsi's `O(w²)`); regula falsi ([`Bracket::estimate`]) where no neighbour
/// qualifies or the result is not finite or not inside the bracket.
#[inline(always)]
pub(crate) fn start_estimate<F: Float>(
    br: &Bracket<F>,
    before: Option<(F, F)>,
    after: Option<(F, F)>,
) -> F {
    let rf = br.estimate();
    if br.fa == F::ZERO || br.fb == F::ZERO {
        return rf;
    }
    let rising = br.fb > br.fa;
    // Strictly monotone with the bracket: below `fa` before it (rising), above `fb` after it.
    let before = before.filter(|&(_, f)| if rising { f < br.fa } else { f > br.fa });
    let after = after.filter(|&(_, f)| if rising { f > br.fb } else { f < br.fb });
    let (a, b) = ((br.a, br.fa), (br.b, br.fb));
    let x = match (before, after) {
        (Some(p), Some(q)) => inverse_interpolation([p, a, b, q]),
        (Some(p), None) => inverse_interpolation([p, a, b]),
        (None, Some(q)) => inverse_interpolation([a, b, q]),
        (None, None) => return rf,
    };
    if x.is_fin() && x > br.a && x < br.b {
        x
    } else {
        rf
    }
}

/// The Lagrange interpolation of `x` as a function of `f` through `points` `(x, f)` (distinct
/// `f`), evaluated at `f = 0`: `Σ_i x_i Π_{j≠i} f_j / (f_j − f_i)`.
#[inline(always)]
fn inverse_interpolation<F: Float, const M: usize>(points: [(F, F); M]) -> F {
    let mut x = F::ZERO;
    for (i, &(xi, fi)) in points.iter().enumerate() {
        let mut w = F::ONE;
        for (j, &(_, fj)) in points.iter().enumerate() {
            if j != i {
                w *= fj / (fj - fi);
            }
        }
        x += xi * w;
    }
    x
}

/// Refines `br` with at most `n` steps of eight evaluations (`f8`) and at most one step of
/// [`ESTIMATE_POINTS`] (`f4`): fewer when the bracket has collapsed to an exact zero or is at
/// most `stop` wide ([`EARLY_STOP`] times the rounding allowance's lower bound; 0 never stops
/// early). `start` is the first step's estimate ([`first_sign_change`]); later steps take
/// theirs from the previous step's samples ([`start_estimate`]). Returns the final bracket and
/// the estimate of the root inside it (the inverse interpolation through its ends and the
/// last step's samples beside it, as the next step would have started from, or regula falsi
/// once the bracket is within `stop`; within the bracket, so within its width of the root).
///
/// The four-point step (module docs, "Estimate steps") is taken once, at the first step whose
/// estimate is trusted to the early stop, when `n ≥ 1` (`n = 0` brackets only); it is not one
/// of the `n`, which keep their guaranteed shrink. The caller bounds `n`
/// ([`MAX_ITERATIONS`](super::MAX_ITERATIONS)).
#[inline(always)]
pub(crate) fn refine<F: Float>(
    mut br: Bracket<F>,
    start: F,
    stop: F,
    n: usize,
    f8: &mut impl FnMut([F; LANES]) -> [F; LANES],
    f4: &mut impl FnMut([F; ESTIMATE_POINTS]) -> [F; ESTIMATE_POINTS],
) -> (Bracket<F>, F) {
    let fifth = F::ONE / F::from_f64(WORST_SHRINK as f64);
    let inner_of_stop = F::from_f64(INNER_OF_STOP);
    let mut x = start;
    let mut estimate_steps = ESTIMATE_STEPS;
    let mut steps = 0usize;
    // `n` uniform steps and at most `ESTIMATE_STEPS` estimate steps (the sum cannot
    // overflow: the caller passes `iterations(n)`, at most `MAX_ITERATIONS`).
    for _ in 0..n + ESTIMATE_STEPS {
        if br.fa == F::ZERO || br.fb == F::ZERO || !(br.b - br.a > stop) {
            break;
        }
        let w = br.b - br.a;
        // Radii around the estimate from its distance to regula falsi's, `e` (the lower-order
        // estimate's error, a bound on the higher-order one's where `f` is smooth at the scale
        // of the bracket); regula falsi itself (no neighbour qualified) has `e = 0`.
        let e = (x - br.estimate()).abs();
        let r_in = (e * F::from_f64(INNER_OF_SPREAD)).max(stop * inner_of_stop);
        let r_in = if e > F::ZERO {
            r_in
        } else {
            r_in.max(w * F::from_f64(OUTER_OF_WIDTH / OUTER_OF_INNER))
        };
        let r_out = (e * F::from_f64(OUTER_OF_SPREAD))
            .max(r_in * F::from_f64(OUTER_OF_INNER))
            .max(w * F::from_f64(OUTER_OF_WIDTH));
        let clamp = |v: F| v.max(br.a).min(br.b);
        let around = [
            clamp(x - r_out),
            clamp(x - r_in),
            clamp(x + r_in),
            clamp(x + r_out),
        ];
        // Trusted: a root caught within `r_in` of the estimate ends the refinement (the
        // bracket `2·r_in` is within `stop`), where the uniform points would not be needed.
        let trusted = e > F::ZERO && r_in + r_in <= stop;
        let (next, before, after) = if n > 0 && estimate_steps > 0 && trusted {
            estimate_steps -= 1;
            narrow(&br, &around, &f4(around))
        } else {
            if steps == n {
                break;
            }
            steps += 1;
            let u = |j: f64| br.a + w * (fifth * F::from_f64(j));
            let [o0, i0, i1, o1] = around;
            let xs = [u(1.0), u(2.0), u(3.0), u(4.0), o0, i0, i1, o1];
            narrow(&br, &xs, &f8(xs))
        };
        br = next;
        // A bracket within `stop` ends the refinement and takes the regula falsi point below:
        // no estimate to interpolate for it.
        if br.b - br.a > stop {
            x = start_estimate(&br, before, after);
        }
    }
    // Within the early-stop width the samples' values are rounding noise, which interpolation
    // through four of them amplifies (sphere hits in f32 land 3× farther from the analytic
    // root); regula falsi through the bracket's ends is a convex combination of them.
    if !(br.b - br.a > stop) {
        x = br.estimate();
    }
    (br, x)
}

/// The bracket after sampling `f` at the points `xs` inside `br` (values `fs`): the first sign
/// change among them and `br`'s ends, and the nearest samples outside it on either side (for
/// the next estimate).
#[inline(always)]
#[allow(clippy::type_complexity)]
pub(crate) fn narrow<F: Float, const M: usize>(
    br: &Bracket<F>,
    xs: &[F; M],
    fs: &[F; M],
) -> (Bracket<F>, Option<(F, F)>, Option<(F, F)>) {
    let neg_a = br.fa < F::ZERO;
    // b′: the smallest point whose sign differs from f(a)'s (or is zero).
    let (mut nb, mut fnb) = (br.b, br.fb);
    for (&xi, &fi) in xs.iter().zip(fs) {
        let other = fi == F::ZERO || (fi < F::ZERO) != neg_a;
        if other && xi < nb {
            (nb, fnb) = (xi, fi);
        }
    }
    // a′: the largest point below b′ (all of them have f(a)'s sign).
    let (mut na, mut fna) = (br.a, br.fa);
    for (&xi, &fi) in xs.iter().zip(fs) {
        if xi < nb && xi > na {
            (na, fna) = (xi, fi);
        }
    }
    // The nearest samples outside the new bracket, for the next estimate.
    let mut before: Option<(F, F)> = None;
    let mut after: Option<(F, F)> = None;
    let all = xs
        .iter()
        .copied()
        .zip(fs.iter().copied())
        .chain([(br.a, br.fa), (br.b, br.fb)]);
    for (xi, fi) in all {
        if xi < na && before.is_none_or(|(xb, _)| xi > xb) {
            before = Some((xi, fi));
        }
        if xi > nb && after.is_none_or(|(xa, _)| xi < xa) {
            after = Some((xi, fi));
        }
    }
    let next = if fnb == F::ZERO {
        Bracket::at(nb, fnb)
    } else {
        Bracket {
            a: na,
            b: nb,
            fa: fna,
            fb: fnb,
        }
    };
    (next, before, after)
}

#[cfg(test)]
mod tests {
    use super::*;

    use core::cell::Cell;

    /// `f` over `M` points at once (eight for a lane call, four for an estimate step),
    /// counting calls.
    fn lanes<'a, const M: usize>(
        f: impl Fn(f64) -> f64 + 'a,
        calls: &'a Cell<usize>,
    ) -> impl FnMut([f64; M]) -> [f64; M] + 'a {
        move |xs: [f64; M]| {
            calls.set(calls.get() + 1);
            xs.map(&f)
        }
    }

    #[test]
    fn the_start_estimate_is_exact_where_the_inverse_is_a_cubic() {
        // x(f) = 0.1 + 0.2 f + 0.01 f² + 0.003 f³: its zero is x(0) = 0.1.
        let x = |f: f64| 0.1 + 0.2 * f + 0.01 * f * f + 0.003 * f * f * f;
        let br = Bracket {
            a: x(-1.0),
            b: x(2.0),
            fa: -1.0,
            fb: 2.0,
        };
        let cubic = start_estimate(&br, Some((x(-3.0), -3.0)), Some((x(5.0), 5.0)));
        assert!((cubic - 0.1).abs() < 1e-15, "{cubic}");
        // Three points: the quadratic, nearer than regula falsi.
        let quad = start_estimate(&br, Some((x(-3.0), -3.0)), None);
        assert!((quad - 0.1).abs() < (br.estimate() - 0.1).abs(), "{quad}");
        // A neighbour that breaks monotonicity is left out: no neighbour, regula falsi.
        let rf = start_estimate(&br, Some((x(-3.0), 0.5)), Some((x(5.0), 1.0)));
        assert_eq!(rf, br.estimate());
        // A zero at an end is the estimate.
        let z = Bracket { fa: 0.0, ..br };
        assert_eq!(start_estimate(&z, Some((x(-3.0), -3.0)), None), z.a);
    }

    /// Brackets `f` on `[a, b]` with six interior samples and refines with a budget of `n`
    /// steps and early-stop width `stop` (asserting that the estimate lies in the final
    /// bracket): the first sign change's bracket, the final bracket, and the lane calls and
    /// four-point calls made in all.
    fn bracket_and_refine(
        f: impl Fn(f64) -> f64 + Copy,
        [a, b]: [f64; 2],
        stop: f64,
        n: usize,
    ) -> (Bracket<f64>, Bracket<f64>, [usize; 2]) {
        let (calls, fours) = (Cell::new(0), Cell::new(0));
        let mut f8 = lanes(f, &calls);
        let mut f4 = lanes::<ESTIMATE_POINTS>(f, &fours);
        let found = first_sign_change::<f64, 6>(a, b, 0.0, &mut f8);
        assert!(found.is_some(), "a sign change in [{a}, {b}]");
        let (br, start) = found.unwrap_or((Bracket::at(a, 0.0), a));
        let (fin, x) = refine(br, start, stop, n, &mut f8, &mut f4);
        assert!(fin.a <= x && x <= fin.b);
        (br, fin, [calls.get(), fours.get()])
    }

    #[test]
    fn a_smooth_root_takes_one_estimate_step_and_a_step_never_shrinks_less_than_five_times() {
        // Smooth: the bracketing samples' cubic lands within the early stop (at a ratio of
        // stop to bracket like the kernel's in f32, 1e-4 to 1e-3).
        let root = 0.2784179903218099; // x³ + x = 0.3
        let stop = 1e-5;
        let (_, fin, calls) = bracket_and_refine(|x| x * x * x + x - 0.3, [0.2, 0.4], stop, 8);
        assert!(
            fin.a <= root && root <= fin.b && fin.b - fin.a <= stop,
            "{fin:?}"
        );
        assert_eq!(
            calls,
            [1, 1],
            "bracketing and one estimate step of four points"
        );

        // A jump: the estimates are useless, the uniform points still shrink 5× per step.
        let jump = |x: f64| if x < 0.6180339887 { -1.0 } else { 1.0 };
        let (br, fin, calls) = bracket_and_refine(jump, [0.0, 1.0], 0.0, 4);
        assert_eq!(calls, [5, 0]);
        assert!(
            fin.b - fin.a <= (br.b - br.a) / 625.0 * (1.0 + 1e-12),
            "{fin:?}"
        );
        assert!(fin.a < 0.6180339887 && 0.6180339887 <= fin.b, "{fin:?}");
    }

    #[test]
    fn a_second_estimate_step_catches_a_root_the_first_missed() {
        // Steep and curved at the bracketing's scale: the first estimate's four points miss
        // the root but leave a bracket whose next estimate is trusted and caught.
        let root = core::f64::consts::LN_2 / 3.0;
        let stop = 6e-4;
        let (_, fin, calls) = bracket_and_refine(|x| libm::exp(3.0 * x) - 2.0, [0.0, 1.0], stop, 8);
        assert!(
            fin.a <= root && root <= fin.b && fin.b - fin.a <= stop,
            "{fin:?}"
        );
        assert_eq!(
            calls,
            [1, ESTIMATE_STEPS],
            "bracketing and two estimate steps of four points, no eight-point step"
        );
    }
}
