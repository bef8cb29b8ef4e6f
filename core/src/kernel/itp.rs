//! Fixed-iteration bracketing root refinement: ITP (Oliveira & Takahashi 2020), whose worst
//! case is bisection's (with one iteration of slack, `n0 = 1`) and which converges
//! superlinearly on smooth functions.
//!
//! Parameters: `κ1 = 0.3 / W` (scale-free), `κ2 = 2`, `n0 = 1`, with `W` the initial bracket
//! width; the regula falsi point uses Illinois weights (an end kept twice in a row has its
//! function value halved), which stops regula falsi from stalling on convex functions. These
//! were chosen by measurement (icosphere, cube, torus; `tests/kernel.rs`): with them N = 8
//! reaches f64 rounding on every ray tested, where plain regula falsi (κ1 = 0.1/W) left
//! grazing rays at 1e-10 and smaller κ1 stalled at 1e-8.
//!
//! After `N` iterations the bracket width is at most `W / 2^(N−1)` (ITP's minmax guarantee).

use crate::real::Float;

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
}

/// `true` when `x` counts as "positive side" for bracketing (zero counts as a root, handled by
/// the caller).
#[inline(always)]
fn pos<F: Float>(x: F) -> bool {
    x > F::ZERO
}

/// Refines `br` with exactly `N` ITP iterations of `f` (fewer only when `f` hits an exact zero).
/// Returns the final bracket.
#[inline(always)]
pub(crate) fn refine<F: Float, const N: usize>(
    mut br: Bracket<F>,
    mut f: impl FnMut(F) -> F,
) -> Bracket<F> {
    let w0 = br.b - br.a;
    if !(w0 > F::ZERO) || br.fa == F::ZERO || br.fb == F::ZERO {
        return br;
    }
    let half = F::from_f64(0.5);
    let k1 = F::from_f64(0.3) / w0;
    // r_j = W / 2^j − (b − a)/2; `scale` holds W / 2^j.
    let mut scale = w0;
    // Illinois weights: the function value of an end kept twice in a row is halved for the
    // interpolation, so regula falsi cannot stall on a convex function.
    let (mut ga, mut gb) = (br.fa, br.fb);
    let mut last_kept_a: Option<bool> = None;
    for _ in 0..N {
        let width = br.b - br.a;
        let xh = half * (br.a + br.b);
        let r = (scale - half * width).max(F::ZERO);
        let delta = k1 * width * width;
        let den = gb - ga;
        let xf = (gb * br.a - ga * br.b) / den;
        let xf = if xf.is_fin() { xf } else { xh };
        let sg = if xh >= xf { F::ONE } else { -F::ONE };
        let xt = if delta <= (xh - xf).abs() {
            xf + sg * delta
        } else {
            xh
        };
        let x = if (xt - xh).abs() <= r {
            xt
        } else {
            xh - sg * r
        };
        // Rounding can put the step on an end of the bracket (δ below one ulp, regula falsi on
        // an end): that iteration would make no progress, so bisect instead.
        let x = if x > br.a && x < br.b { x } else { xh };
        let y = f(x);
        if y == F::ZERO {
            return Bracket {
                a: x,
                b: x,
                fa: y,
                fb: y,
            };
        }
        if pos(y) == pos(br.fa) {
            br.a = x;
            br.fa = y;
            // `b` kept twice in a row: halve its weight (Illinois).
            if last_kept_a == Some(false) {
                gb *= half;
            }
            ga = y;
            last_kept_a = Some(false);
        } else {
            br.b = x;
            br.fb = y;
            if last_kept_a == Some(true) {
                ga *= half;
            }
            gb = y;
            last_kept_a = Some(true);
        }
        scale *= half;
    }
    br
}
