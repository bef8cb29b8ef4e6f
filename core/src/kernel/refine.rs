//! Bracketing and refinement with eight evaluations per step (docs/METHOD.md §8 steps 2–3).
//!
//! Both take `f` as a function of eight parameters at once (one call of the lane height
//! evaluation, `core/src/height.rs`), so a step costs about one scalar evaluation on
//! AVX2.
//!
//! **Bracketing** samples `f` at `a`, `K` evenly spaced interior points and `b`, eight per call
//! (`⌈(K + 2)/8⌉` calls; [`DEFAULT_SAMPLES`](super::DEFAULT_SAMPLES) `= 6` fills one call), and
//! takes the first sign change.
//!
//! **Refinement** runs at most `N` steps (see the early stop below). A step on the bracket `[a, b]` of width `w` places
//! - [`UNIFORM_POINTS`] evenly spaced points `a + w·j/5`, `j = 1…4`, which alone guarantee that
//!   the next bracket is at most `w/5` wide ([`WORST_SHRINK`]), whatever `f` does, and
//! - four points around the regula falsi estimate `x*`: `x* ± δ` and `x* ± δ/8`, with
//!   `δ = ρ·w`. When the root is within `δ/8` of `x*` the next bracket is `δ/4` wide.
//!
//! The next bracket is the first sign change among the sorted points. The relative radius `ρ`
//! starts at [`RHO_START`]; after a step that caught the root inside `[x* − δ, x* + δ]` it is
//! multiplied by the step's shrink factor (regula falsi's error is quadratic in the width, so
//! its error relative to the width falls as fast as the width), otherwise multiplied by
//! [`RHO_GROWTH`] up to [`RHO_MAX`]. Near a simple root the width therefore falls
//! superlinearly (each successful step squares the relative accuracy), and it never falls
//! slower than 5× per step.
//!
//! **Early stop.** Refinement ends before `N` steps once the bracket is at most [`EARLY_STOP`]
//! times the rounding allowance's lower bound (the allowance computed from the sampling
//! bracket's secant, `super::ROUNDING_ULPS`): the returned `t_error` is the bracket's width
//! plus an allowance at least that large, so further steps could shrink `t_error` by at most a
//! fifth while each costs a full lane call. On the torus's rays this ends `f32` tests after
//! about three steps, `f64` after about four.
//!
//! Bound: after bracketing and `N` steps the bracket is at most
//! `max((b − a) / ((K + 1)·5^N), EARLY_STOP · allowance)` for the shell interval `[a, b]` (up
//! to one ulp of the parameters per step, where the points collapse onto each other).

use crate::num::lanes::LANES;
use crate::num::real::Float;

/// Evenly spaced points per refinement step: `a + w·j/(UNIFORM_POINTS + 1)`.
pub const UNIFORM_POINTS: usize = 4;
/// The guaranteed shrink factor of the bracket per refinement step: `UNIFORM_POINTS + 1`.
pub const WORST_SHRINK: usize = UNIFORM_POINTS + 1;
/// Initial relative radius `ρ` of the points around the regula falsi estimate.
pub const RHO_START: f64 = 1.0 / 16.0;
/// Growth of `ρ` after a step whose root was outside `x* ± ρ·w`.
pub const RHO_GROWTH: f64 = 4.0;
/// Largest `ρ`.
pub const RHO_MAX: f64 = 0.25;
/// Ratio of the inner to the outer offset around the estimate (`δ/8`).
pub const INNER: f64 = 1.0 / 8.0;
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
/// `snap` of zero count as zero). At most `⌈(K + 2)/8⌉` calls.
#[inline(always)]
pub(crate) fn first_sign_change<F: Float, const K: usize>(
    a: F,
    b: F,
    snap: F,
    f8: &mut impl FnMut([F; LANES]) -> [F; LANES],
) -> Option<Bracket<F>> {
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
    for call in 0..(K + 2).div_ceil(LANES) {
        let xs: [F; LANES] = core::array::from_fn(|i| point(call * LANES + i));
        let fs = f8(xs);
        for (i, (x1, f1)) in xs.into_iter().zip(fs).enumerate() {
            let j = call * LANES + i;
            if j > K + 1 {
                break;
            }
            let (f1, br) = bracket_step(j, K + 1, (x0, f0), (x1, f1), snap);
            if br.is_some() {
                return br;
            }
            (x0, f0) = (x1, f1);
        }
    }
    None
}

/// Refines `br` with at most `N` steps of eight evaluations: fewer when the bracket has
/// collapsed to an exact zero or is at most `stop` wide ([`EARLY_STOP`] times the rounding
/// allowance's lower bound; 0 never stops early). Returns the final bracket.
#[inline(always)]
pub(crate) fn refine<F: Float, const N: usize>(
    mut br: Bracket<F>,
    stop: F,
    f8: &mut impl FnMut([F; LANES]) -> [F; LANES],
) -> Bracket<F> {
    let mut rho = F::from_f64(RHO_START);
    let inner = F::from_f64(INNER);
    let fifth = F::ONE / F::from_f64(WORST_SHRINK as f64);
    for _ in 0..N {
        if br.fa == F::ZERO || br.fb == F::ZERO || !(br.b - br.a > stop) {
            break;
        }
        let w = br.b - br.a;
        let x = br.estimate();
        let delta = rho * w;
        let clamp = |v: F| v.max(br.a).min(br.b);
        let u = |j: f64| br.a + w * (fifth * F::from_f64(j));
        let xs = [
            u(1.0),
            u(2.0),
            u(3.0),
            u(4.0),
            clamp(x - delta),
            clamp(x - delta * inner),
            clamp(x + delta * inner),
            clamp(x + delta),
        ];
        let fs = f8(xs);
        let neg_a = br.fa < F::ZERO;
        // b′: the smallest point whose sign differs from f(a)'s (or is zero).
        let (mut nb, mut fnb) = (br.b, br.fb);
        for (xi, fi) in xs.into_iter().zip(fs) {
            let other = fi == F::ZERO || (fi < F::ZERO) != neg_a;
            if other && xi < nb {
                (nb, fnb) = (xi, fi);
            }
        }
        // a′: the largest point below b′ (all of them have f(a)'s sign).
        let (mut na, mut fna) = (br.a, br.fa);
        for (xi, fi) in xs.into_iter().zip(fs) {
            if xi < nb && xi > na {
                (na, fna) = (xi, fi);
            }
        }
        let caught = na >= x - delta && nb <= x + delta;
        rho = if caught {
            (rho * ((nb - na) / w)).max(F::EPSILON)
        } else {
            (rho * F::from_f64(RHO_GROWTH)).min(F::from_f64(RHO_MAX))
        };
        br = if fnb == F::ZERO {
            Bracket::at(nb, fnb)
        } else {
            Bracket {
                a: na,
                b: nb,
                fa: fna,
                fb: fnb,
            }
        };
    }
    br
}
