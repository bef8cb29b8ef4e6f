//! The kernel's work bounds and error budget, as named constants: how many height evaluations
//! a patch test may make, and the rounding allowances that every `t_error`, every snapped
//! interval end and every wall margin is measured in (docs/METHOD.md §8).

use crate::geometry::Patch;
pub use crate::kernel::predicted::PREDICTED_EVALS;
use crate::kernel::refine::{Bracket, ESTIMATE_POINTS, ESTIMATE_STEPS};
use crate::num::lanes::LANES;
use crate::num::real::Float;
use crate::surface::shell::longest_edge;

/// Default number `K` of interior bracketing samples used by [`Patch::closest_hit`](crate::Patch::closest_hit): with the two
/// ends, eight points, one lane call.
pub const DEFAULT_SAMPLES: usize = 6;

/// Rounding allowance of [`Hit::t_error`](crate::Hit::t_error), in ulps of the patch's extent `L` (`EXTENT_EDGES` = 4 longest
/// edges plus the distance from the origin): `KernelStats::rounding = ROUNDING_ULPS · ε · L / |f′|`, the distance the
/// root of `f(τ) = σ(τ) − σS(X(τ))` moves when `f` is off by `ROUNDING_ULPS · ε · L`.
///
/// Derivation (a budget, validated rather than proven). Near the root `f` is the difference of
/// two nearly equal heights, so the sign the kernel sees is decided by `f`'s absolute rounding
/// error, which is the sum of the roundings on the way to it, each a few ulps of the magnitude
/// it acts on:
/// - the ray's world point `o + t0·d` and its map into the local frame (the subtraction of
///   `P0` and three-term dot products with the axes): ulps of `|P0|` plus the point's offset
///   from it;
/// - the local ray point `o + τ·r` and its cross-section barycentrics: ulps of the shell's
///   extent;
/// - the surface height `σS` (three cancellation-free sphere roots anchored at edge points that
///   are themselves sphere roots, and their weighted sum): ulps of the triangle's size.
///
/// Sixteen ulps of `L` cover these stages together, with margin. `tests/suite/kernel.rs` checks the
/// resulting `t_error` against analytic sphere roots (`f32` and `f64`) and against the kernel
/// at `N = 40` on the torus.
pub const ROUNDING_ULPS: f64 = 16.0;

/// The extent `L` of [`ROUNDING_ULPS`]: `L = EXTENT_EDGES · longest_edge + |P0|`.
///
/// Derivation (a budget, like [`ROUNDING_ULPS`]): the points where `f` is evaluated lie in the
/// shell, within one longest edge of `P0` across the triangle plus the shell's height, and the
/// intermediate quantities of `σS` (edge points, sphere-root parameters, the sums of eq. (5))
/// are of the triangle's size; four longest edges bound these magnitudes with room. `|P0|`,
/// the patch's distance from the world origin, is the magnitude of the world coordinates that
/// the map into the local frame rounds.
pub const EXTENT_EDGES: f64 = 4.0;

/// How far each side wall of the shell is moved outward, in ulps of the extent `L` of
/// [`ROUNDING_ULPS`] (world length `WALL_MARGIN_ULPS · ε · L`), so that the domains of two
/// patches sharing an edge overlap instead of touching (docs/METHOD.md §8, "Shared edges").
///
/// Derivation (a budget, like [`ROUNDING_ULPS`]). Two neighbours decide where a ray point lies
/// relative to their common wall in their own frames, each with a rounding error of a few ulps
/// of `L` (the same stages as [`ROUNDING_ULPS`]: the ray's map into the local frame and the
/// cross-section barycentrics), and each decides by the sign of its own `f` at its interval's
/// end. Touching domains therefore let a ray through the shared edge fall between them (about
/// one ray in ten aimed exactly at a shared edge, in `f32` and in `f64`, before this margin).
/// With each domain widened by more than the wall's rounding, a crossing at the edge lies
/// strictly inside both patches' intervals, and the closest-hit rule of the BVH keeps one.
/// Beyond its edge a patch continues along its tangent plane there (`crate::surface::lanes`
/// `beyond_edge`, the continuation [`close_cracks`](crate::mesh::close_cracks) relies on), so
/// a crossing found in the margin is off the patch's surface by at most the margin's width,
/// half of the [`ROUNDING_ULPS`] allowance that every `t_error` carries.
/// `tests/suite/watertight.rs` aims thousands of rays per mesh at shared edge points from
/// directions up to 80° off both neighbours' normals: none falls through in `f32` or `f64`.
pub const WALL_MARGIN_ULPS: f64 = 8.0;

/// The largest reach of a wall that [`close_cracks`](crate::mesh::close_cracks) sets, as a
/// fraction of the wall's altitude (barycentric units); the patch's band
/// (`core/src/surface/band.rs`) is widened for continuations up to it.
///
/// The kernel samples the whole widened interval with the same `K` points, so a reach comparable
/// with the triangle itself coarsens the bracketing until rays that graze an edge lose their
/// crossing there (measured: the cube with one inverted normal, whose curves part by a fifth of
/// the diagonal, reaches 1.6 altitudes without a cap and then misses one ray aimed at a curve).
/// A quarter keeps the interval within 1.5 times the triangle's and closes the cracks of the
/// test meshes except where the gap exceeds it: on that cube and at the teapot's edges next to
/// patches the remedy clamped hard, a few rays aimed between the curves still pass (README,
/// "Shared edges"; `gpu/tests/parity.rs` checks that every ray that passes there does so at a
/// capped edge). A cap of ½ lets 2 instead of 7 of 17 472 such teapot rays pass but loses one
/// ray aimed at a curve of that cube.
pub const MAX_CRACK_REACH: f64 = 0.25;

/// The largest refinement budget `n` of a patch test: every query takes any `n` and runs
/// `min(n, MAX_ITERATIONS)` ([`iterations`]).
///
/// Sixty-four is the GPU kernel's limit as well (its pipelines are compiled per budget, up to
/// this one), and is far past where more steps change anything: each step shrinks the
/// bracket at least [`WORST_SHRINK`](super::refine::WORST_SHRINK) = 5 times, so after 23 steps
/// a bracket is below `f64`'s ε of the interval it started from (`5^−23 ≈ 8·10^−17`) and
/// after 11 below `f32`'s (`5^−11 ≈ 2·10^−8`); the early stop ends refinement there
/// (docs/METHOD.md §8). The bound keeps the work of one patch test at most
/// [`max_lane_calls`]`(K, MAX_ITERATIONS)` lane calls whatever the caller passes.
pub const MAX_ITERATIONS: usize = 64;

/// The refinement budget a query runs for a requested `n`: `min(n, MAX_ITERATIONS)`
/// ([`MAX_ITERATIONS`]).
///
/// # Panics
/// Never.
pub const fn iterations(n: usize) -> usize {
    if n < MAX_ITERATIONS {
        n
    } else {
        MAX_ITERATIONS
    }
}

/// A refinement budget at most [`MAX_ITERATIONS`]: bounded once per query
/// ([`Budget::new`]), so that each patch test of the query runs it as it is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Budget(usize);

impl Budget {
    /// The budget a query runs for a requested `n`: [`iterations`]`(n)`.
    #[inline(always)]
    pub(crate) const fn new(n: usize) -> Self {
        Budget(iterations(n))
    }

    /// The number of steps, at most [`MAX_ITERATIONS`].
    #[inline(always)]
    pub(crate) const fn get(self) -> usize {
        self.0
    }
}

/// The most lane calls (eight height evaluations each) that one patch test
/// with `k` bracketing samples and a refinement budget `n` makes: `⌈(k + 2)/8⌉ + min(n,`
/// [`MAX_ITERATIONS`]`)` (the budget a query runs, [`iterations`]). Besides these, a test
/// makes at most `ESTIMATE_STEPS` = 2 calls of `ESTIMATE_POINTS` = 4 evaluations (the
/// estimate steps around a trusted root estimate); [`max_height_evals`] counts both.
///
/// # Panics
/// Never.
pub const fn max_lane_calls(k: usize, n: usize) -> usize {
    k.saturating_add(2).div_ceil(LANES) + iterations(n)
}

/// The most height evaluations `σS` that one patch test with `k` bracketing samples and a
/// refinement budget `n` makes: eight per lane call of [`max_lane_calls`]`(k, n)` plus, for
/// `n ≥ 1`, the four of each estimate step (`ESTIMATE_STEPS · ESTIMATE_POINTS` = 2 · 4) and
/// the predicted search's [`PREDICTED_EVALS`] = 6 (where a true height contradicts the
/// predictor, today's bracketing follows them; `n = 0` brackets only).
/// [`KernelStats::height_evals`](crate::KernelStats::height_evals) never exceeds it.
///
/// # Panics
/// Never.
pub const fn max_height_evals(k: usize, n: usize) -> usize {
    let estimate = if n > 0 {
        ESTIMATE_STEPS * ESTIMATE_POINTS + PREDICTED_EVALS
    } else {
        0
    };
    LANES
        .saturating_mul(max_lane_calls(k, n))
        .saturating_add(estimate)
}

/// `|f(b) − f(a)| / (b − a)` of a bracket (`+∞` or NaN when it has zero width).
#[inline(always)]
pub(crate) fn secant<F: Float>(br: &Bracket<F>) -> F {
    (br.fb - br.fa).abs() / (br.b - br.a)
}

/// The rounding allowance [`ROUNDING_ULPS`]` · ε · L / slope` (`L` from [`EXTENT_EDGES`]);
/// 0 where it is not finite (a zero slope).
#[inline(always)]
pub(crate) fn rounding_allowance<F: Float>(scale: F, slope: F) -> F {
    let rounding = F::from_f64(ROUNDING_ULPS) * F::EPSILON * scale / slope;
    if rounding.is_fin() { rounding } else { F::ZERO }
}

/// The extent `L = `[`EXTENT_EDGES`]` · longest_edge + |P0|` of [`ROUNDING_ULPS`] and
/// [`WALL_MARGIN_ULPS`].
#[inline(always)]
pub(crate) fn rounding_scale<F: Float>(patch: &Patch<F>) -> F {
    scale_of(patch, longest_edge(&patch.shape))
}

/// [`rounding_scale`] from the patch's longest edge `edge`.
#[inline(always)]
pub(crate) fn scale_of<F: Float>(patch: &Patch<F>, edge: F) -> F {
    edge * F::from_f64(EXTENT_EDGES) + patch.frame.origin.length()
}

/// The value of `f` within which a sample at the shell interval's ends counts as a zero
/// ([`bracket_step`](crate::kernel::refine::bracket_step)): [`ROUNDING_ULPS`]` · ε · L`, the rounding of `f` that the
/// allowance of every `t_error` already covers, so a crossing snapped to an end stays within
/// its `t_error`.
#[inline(always)]
pub(crate) fn end_snap<F: Float>(scale: F) -> F {
    F::from_f64(ROUNDING_ULPS) * F::EPSILON * scale
}
