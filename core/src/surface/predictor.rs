//! The predictor of the crossing (issue 63, "certify, don't search"): the quartic interpolant
//! of the height `σS` over the section barycentrics, at the [`POINTS`] points of the degree-4
//! lattice `(i, j, k)/4`, `i + j + k = 4`.
//!
//! Along a ray, `f̃(τ) = z(τ) − P(X(τ))` predicts the kernel's `f(τ) = z(τ) − σS(X(τ))`; its
//! root is where a search would take its first true evaluation. Today it serves only the study
//! of the rates (`smoothtri::internal::predictor_study`, `cargo bench --bench predictor`): how
//! often one true evaluation, one step with the predictor's slope and a pair at the early-stop
//! width certify the root. It carries no bound yet and never enters a hit or `t_error`.
//!
//! # Accuracy
//! Exact at the lattice points (the true heights there, rounded to `F`); between them, what the
//! study measures (`max_error`).
//!
//! # Panics
//! No function panics.

use crate::geometry::Shape;
use crate::num::lanes::One;
use crate::num::real::Float;
use crate::surface::lanes::Prepared;

/// The interpolant's degree.
pub(crate) const DEGREE: usize = 4;

/// The lattice points of [`DEGREE`]: `(DEGREE + 1)(DEGREE + 2)/2`.
pub(crate) const POINTS: usize = (DEGREE + 1) * (DEGREE + 2) / 2;

/// The lattice's multi-indices `(i, j, k)`, `i + j + k = DEGREE` (each once: a test).
const LATTICE: [[u8; 3]; POINTS] = [
    [0, 0, 4],
    [0, 1, 3],
    [0, 2, 2],
    [0, 3, 1],
    [0, 4, 0],
    [1, 0, 3],
    [1, 1, 2],
    [1, 2, 1],
    [1, 3, 0],
    [2, 0, 2],
    [2, 1, 1],
    [2, 2, 0],
    [3, 0, 1],
    [3, 1, 0],
    [4, 0, 0],
];

/// The quartic interpolant of a patch's height over its section barycentrics.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Predictor<F> {
    /// The true height at each lattice point of [`LATTICE`]'s order.
    heights: [F; POINTS],
}

impl<F: Float> Predictor<F> {
    /// The interpolant of the patch `prep` (prepared for the height evaluation): [`POINTS`]
    /// true heights.
    pub(crate) fn new(prep: &Prepared<F>) -> Self {
        let d = F::from_f64(DEGREE as f64);
        let heights = LATTICE.map(|m| {
            let [b0, b1, b2] = m.map(|c| One(F::from_f64(f64::from(c)) / d));
            prep.heights([b0, b1, b2]).0
        });
        Predictor { heights }
    }

    /// `P(β)` at barycentrics `b` (summing to one), in the lattice's Lagrange form:
    /// `Σ σS(α/4)·Π_r ℓ_{α_r}(β_r)` with `ℓ_m(x) = Π_{s<m} (4x − s)/(s + 1)`.
    pub(crate) fn at(&self, b: [F; 3]) -> F {
        let d = F::from_f64(DEGREE as f64);
        // ℓ_m(b_r) for m = 0..=DEGREE, each r.
        let factors = b.map(|x| {
            let mut l = [F::ONE; DEGREE + 1];
            let mut acc = F::ONE;
            for (s, slot) in l.iter_mut().enumerate().skip(1) {
                let s1 = F::from_f64((s - 1) as f64);
                acc = acc * (d * x - s1) / F::from_f64(s as f64);
                *slot = acc;
            }
            l
        });
        let [f0, f1, f2] = factors;
        let mut sum = F::ZERO;
        for (m, h) in LATTICE.iter().zip(self.heights) {
            let [i, j, k] = m.map(usize::from);
            let (Some(a), Some(b), Some(c)) = (f0.get(i), f1.get(j), f2.get(k)) else {
                continue;
            };
            sum += h * (*a * *b * *c);
        }
        sum
    }

    /// The largest `|P − σS|` over the degree-`grid` lattice of the triangle, over the longest
    /// edge of `shape` (in `f64`).
    pub(crate) fn max_error(&self, shape: &Shape<F>, prep: &Prepared<F>, grid: usize) -> f64 {
        let g = F::from_f64(grid as f64);
        let mut worst = 0.0f64;
        for i in 0..=grid {
            for j in 0..=grid - i {
                let k = grid - i - j;
                let b = [i, j, k].map(|c| F::from_f64(c as f64) / g);
                let truth = prep.heights(b.map(One)).0;
                let err = (self.at(b) - truth).abs().to_f64();
                worst = worst.max(err);
            }
        }
        worst / crate::surface::shell::longest_edge(shape).to_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::random_patches;

    #[test]
    fn the_lattice_holds_every_multi_index_once() {
        for (n, m) in LATTICE.iter().enumerate() {
            assert_eq!(m.iter().map(|&c| usize::from(c)).sum::<usize>(), DEGREE);
            assert!(LATTICE.iter().take(n).all(|o| o != m));
        }
    }

    /// At the lattice points the interpolant returns the true heights (the Lagrange basis is
    /// one there and zero at the others, up to rounding of the products).
    #[test]
    fn the_interpolant_is_exact_at_the_lattice() {
        for (patch, _) in random_patches(7, 50) {
            let prep = Prepared::new(&patch.shape);
            let p = Predictor::new(&prep);
            for (m, h) in LATTICE.iter().zip(p.heights) {
                let b = m.map(|c| f64::from(c) / DEGREE as f64);
                assert!((p.at(b) - h).abs() <= 1e-12 * (1.0 + h.abs()), "{m:?}");
            }
        }
    }

    /// A quartic in the barycentrics is reproduced everywhere (the interpolant's defining
    /// property), checked with the Lagrange form alone on a polynomial's values.
    #[test]
    fn quartics_are_reproduced() {
        let poly = |[a, b, c]: [f64; 3]| a * a * b * c + 3.0 * b.powi(4) - c * c + 0.5 * a;
        let p = Predictor {
            heights: LATTICE.map(|m| poly(m.map(|c| f64::from(c) / DEGREE as f64))),
        };
        for (x, y) in [(0.1, 0.2), (0.33, 0.33), (0.7, 0.05), (0.0, 0.9)] {
            let b = [1.0 - x - y, x, y];
            assert!((p.at(b) - poly(b)).abs() < 1e-12, "{b:?}");
        }
    }
}
