//! The bounded-work ray kernel (docs/METHOD.md §8).
//!
//! Along a ray `x(t)`, the patch is the zero set of `f(t) = σ(t) − σS(X(t))`: the height of the
//! ray point over the triangle's plane minus the surface's height at the ray point's
//! barycentrics (both exact consequences of the construction, docs/METHOD.md §2). The kernel
//!
//! 1. clips the ray to the patch's box, then to its shell (slab and three side walls, exact
//!    quadratics): `[ta, tb]`, and returns without sampling when the ray misses the patch's
//!    band there (a quadratic bound of the surface, [`crate::surface::band`]) or when the
//!    interval starts beyond the caller's best crossing;
//! 2. samples `f` at `ta`, at `K` evenly spaced interior points and at `tb`, and takes the first
//!    sign change (so a ray grazing a bulge twice inside the shell is not missed when the
//!    crossings are at least `(tb − ta)/(K + 1)` apart);
//! 3. refines that bracket with at most `N` steps of eight points each ([`refine`]: at least
//!    5× narrower per step, superlinear near a simple root; it stops early once the bracket
//!    is within [`EARLY_STOP`](refine::EARLY_STOP) of the rounding allowance), and, for
//!    `N ≥ 1`, at most one step of four points around a trusted estimate (over [`Float::L4`]: where the estimate
//!    is good enough, the step that ends the refinement costs half a lane call);
//! 4. evaluates the exact surface normal once at the estimate.
//!
//! `f` is evaluated at eight parameters per call, in the lanes of [`Float::L8`]
//! ([`crate::num::lanes`]). Work per ray is at most [`max_lane_calls`]`(K, N) = ⌈(K + 2)/8⌉ + N`
//! lane calls, one four-point call and one normal evaluation ([`max_height_evals`] height
//! evaluations in all), whatever the input: every loop has a compile-time
//! trip count (a loop may stop early when it has its answer, never run longer). The final
//! bracket's width plus a rounding allowance is returned as [`Hit::t_error`].

pub(crate) mod clip;
pub mod flat;
pub mod refine;

use crate::geometry::Patch;
use crate::geometry::Shape;
use crate::num::lanes::Lane;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::ray::{Hit, Ray};
use crate::surface::band;
use crate::surface::field::Section;
use crate::surface::lanes::Prepared;
use crate::surface::scalar::{normal_local, project_bary};
use clip::{LocalRay, bary_numerators, shell_interval};
use refine::{ESTIMATE_POINTS, first_sign_change, refine};

/// Default number `K` of interior bracketing samples used by [`Patch::intersect`]: with the two
/// ends, eight points, one lane call.
pub const DEFAULT_SAMPLES: usize = 6;

/// Rounding allowance of [`Hit::t_error`], in ulps of the patch's extent `L` (`EXTENT_EDGES` = 4 longest
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
/// `beyond_edge`, the continuation [`close_cracks`](crate::mesh::cracks::close_cracks) relies on), so
/// a crossing found in the margin is off the patch's surface by at most the margin's width,
/// half of the [`ROUNDING_ULPS`] allowance that every `t_error` carries.
/// `tests/suite/watertight.rs` aims thousands of rays per mesh at shared edge points from
/// directions up to 80° off both neighbours' normals: none falls through in `f32` or `f64`.
pub const WALL_MARGIN_ULPS: f64 = 8.0;

/// The largest reach of a wall that [`close_cracks`](crate::mesh::cracks::close_cracks) sets, as a
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

/// The most lane calls (eight height evaluations each) that one patch test
/// with `k` bracketing samples and `n` refinement steps makes: `⌈(k + 2)/8⌉ + n`. Besides
/// these, a test makes at most one call of `ESTIMATE_POINTS` = 4 evaluations (the
/// estimate step around a trusted root estimate); [`max_height_evals`] counts both.
///
/// # Panics
/// Never.
pub const fn max_lane_calls(k: usize, n: usize) -> usize {
    (k + 2).div_ceil(crate::num::lanes::LANES) + n
}

/// The most height evaluations `σS` that one patch test with `k` bracketing samples and `n`
/// refinement steps makes: eight per lane call of [`max_lane_calls`]`(k, n)` plus, for
/// `n ≥ 1`, the four of the estimate step (`ESTIMATE_POINTS` = 4; `n = 0` brackets
/// only). [`KernelStats::height_evals`] never exceeds it.
///
/// # Panics
/// Never.
pub const fn max_height_evals(k: usize, n: usize) -> usize {
    let estimate = if n > 0 { refine::ESTIMATE_POINTS } else { 0 };
    crate::num::lanes::LANES * max_lane_calls(k, n) + estimate
}

/// Statistics of one kernel call, for tests and studies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KernelStats {
    /// Number of height evaluations `σS` performed, eight per lane call and four in the
    /// estimate step (at most [`max_height_evals`]`(K, N)`).
    pub height_evals: u32,
    /// Number of full point-and-normal evaluations (0 or 1).
    pub normal_evals: u32,
    /// Width `tb − ta` of the shell interval that was sampled (in units of the ray parameter
    /// `t`, converted to `f64`); 0 when the ray missed the box or the shell. The worst-case
    /// guarantee of [`Patch::intersect`] is stated in terms of it.
    pub shell_width: f64,
    /// The rounding allowance included in the returned [`Hit::t_error`] (converted to `f64`):
    /// `t_error` is the final bracket's width plus this, `ROUNDING_ULPS · ε · L / |f′|` (`ROUNDING_ULPS` = 16)
    /// with `L = 4 · longest_edge + |P0|` and `|f′|` the flatter of the
    /// sampling and the final brackets' secant slopes. 0 when there is no hit.
    pub rounding: f64,
}

/// [`Patch::intersect_stats`]: the closest crossing of `ray` with `patch` in `[t_min, t_max]`
/// (`K` bracketing samples, `N` refinement steps) completed into a [`Hit`], with the call's
/// [`KernelStats`].
#[inline(always)]
pub(crate) fn intersect_stats<F: Float, const K: usize, const N: usize>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
) -> (Option<Hit<F>>, KernelStats) {
    let mut stats = KernelStats::default();
    let hit = intersect_impl::<F, K, N>(patch, ray, t_min, t_max, &mut stats);
    (hit, stats)
}

#[inline(always)]
fn intersect_impl<F: Float, const K: usize, const N: usize>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
    stats: &mut KernelStats,
) -> Option<Hit<F>> {
    // The normal is evaluated with the crossing's own height precomputation.
    let mut hit = None;
    let world = WorldRay::new(ray)?;
    let c = crossing_then::<F, K, N>(patch, &world, t_min, t_max, None, stats, |c, prep| {
        hit = finish_prepared(patch, ray, c, prep);
    })?;
    stats.normal_evals += 1;
    let hit = hit?;
    stats.rounding = c.rounding.to_f64();
    Some(hit)
}

/// Clips a world ray to the patch's box, slab and shell: the local ray re-based at `t0`
/// (the middle of the box interval) and the interval `[a, b]` of `τ = t − t0` to search, or
/// `None` when the ray misses the shell (or is degenerate), when the interval misses the
/// patch's band ([`band::BandRay::misses`]: no surface point on it), or when the interval starts beyond
/// `beyond` (`t0 + a > beyond`: every crossing the kernel could return lies there, see
/// [`crossing`]).
#[inline(always)]
pub(crate) fn clip_ray<F: Float>(
    patch: &Patch<F>,
    ray: &WorldRay<F>,
    t_min: F,
    t_max: F,
    beyond: Option<F>,
) -> Option<Clipped<F>> {
    // Every `τ` the search reaches is at least the interval's start `a`, which starts as
    // `ta − t0` and only grows, and rounding is monotone: a crossing's `t` is at least
    // `t0 + a` (before the clamp to `[t_min, t_max]`, which keeps it at least `beyond` when
    // `beyond ≤ t_max`).
    let past = |t0: F, a: F| matches!(beyond, Some(c) if t0 + a > c);
    let (o, d) = (ray.o, ray.d);
    if t_min.is_nan() || t_max.is_nan() || t_max < t_min {
        return None;
    }
    let (ta, tb) = patch
        .bbox
        .ray_interval(o, d, (ray.inv, ray.inv_finite), t_min, t_max)?;
    // Local ray re-based at the middle of the box interval.
    let t0 = F::from_f64(0.5) * (ta + tb);
    if past(t0, ta - t0) {
        return None;
    }
    let lray = LocalRay {
        o: patch.frame.world_to_local(o + d * t0),
        r: patch.frame.world_dir_to_local(d),
    };
    // Slab σmin ≤ σ ≤ σmax.
    let [s_lo, s_hi] = patch.sigma;
    let (mut a, mut b) = (ta - t0, tb - t0);
    if lray.r.z != F::ZERO {
        let inv = F::ONE / lray.r.z;
        let u = (s_lo - lray.o.z) * inv;
        let v = (s_hi - lray.o.z) * inv;
        a = a.max(u.min(v));
        b = b.min(u.max(v));
    } else if lray.o.z < s_lo || lray.o.z > s_hi {
        return None;
    }
    if !(a <= b) {
        return None;
    }
    let edge = crate::surface::shell::longest_edge(&patch.shape);
    let scale = scale_of(patch, edge);
    let margins = wall_margins(patch, edge, scale);
    let [m0, m1, m2] = margins;
    let reach = m0.max(m1).max(m2);
    // The band, first over the slab's interval (a ray that misses it there misses it on the
    // shell's interval inside, and the wall quadratics are not solved), then over the shell's:
    // no surface point on [a, b], nothing to sample.
    let band = band::BandRay::new(&patch.band, &patch.shape, lray.o, lray.r, reach);
    if band.misses(a, b) {
        return None;
    }
    let (a, b) = shell_interval(&patch.shape, &lray, a, b, margins)?;
    if past(t0, a) {
        return None;
    }
    if band.misses(a, b) {
        return None;
    }
    Some(Clipped {
        t0,
        lray,
        a,
        b,
        scale,
    })
}

/// The search part of the kernel (clip, bracket, refine) without the normal: where the ray
/// crosses the patch, or `None`. At most [`max_lane_calls`]`(K, N)` lane calls and one
/// four-point call ([`max_height_evals`]).
///
/// `beyond`, when given, is a ray parameter at or after which the caller discards crossings
/// (the closest one found so far, `≤ t_max`): a patch whose shell interval starts after it is
/// not searched (`None`, no lane call), which returns `None` exactly where the search would
/// have returned a crossing the caller discards.
#[inline(always)]
pub(crate) fn crossing<F: Float, const K: usize, const N: usize>(
    patch: &Patch<F>,
    ray: &WorldRay<F>,
    t_min: F,
    t_max: F,
    beyond: Option<F>,
    stats: &mut KernelStats,
) -> Option<Crossing<F>> {
    crossing_then::<F, K, N>(patch, ray, t_min, t_max, beyond, stats, |_, _| {})
}

/// [`crossing`], handing the crossing and the patch's height precomputation to `keep` when
/// there is one, so that a caller who completes the crossing into a hit
/// ([`finish_prepared`]) does not build the precomputation a second time.
#[inline(always)]
pub(crate) fn crossing_then<F: Float, const K: usize, const N: usize>(
    patch: &Patch<F>,
    ray: &WorldRay<F>,
    t_min: F,
    t_max: F,
    beyond: Option<F>,
    stats: &mut KernelStats,
    keep: impl FnOnce(&Crossing<F>, &Prepared<F>),
) -> Option<Crossing<F>> {
    let cl = clip_ray(patch, ray, t_min, t_max, beyond)?;
    let (a, b) = (cl.a, cl.b);
    stats.shell_width = (b - a).to_f64();
    let prep = Prepared::new(&patch.shape);
    let sp = <F::L8 as crate::num::lanes::LaneOps>::splat;
    let (o, r) = (cl.lray.o, cl.lray.r);
    let (o8, r8) = ([sp(o.x), sp(o.y), sp(o.z)], [sp(r.x), sp(r.y), sp(r.z)]);
    let evals = core::cell::Cell::new(0u32);
    let count = |n: usize| evals.set(evals.get().saturating_add(n as u32));
    let mut f = |taus: [F; crate::num::lanes::LANES]| {
        count(crate::num::lanes::LANES);
        prep.f(o8, r8, <F::L8 as Lane>::from_array(taus)).to_array()
    };
    let found = first_sign_change::<F, K>(a, b, end_snap(cl.scale), &mut f);
    let Some((bracket, start)) = found else {
        stats.height_evals += evals.get();
        return None;
    };
    // The allowance of `complete` is at least the one from the sampling bracket's secant
    // (it takes the flatter of two secants): a bracket below a fraction of it is converged.
    let floor = rounding_allowance(cl.scale, secant(&bracket));
    let stop = floor * F::from_f64(refine::EARLY_STOP);
    let mut f4 = |taus: [F; ESTIMATE_POINTS]| {
        count(ESTIMATE_POINTS);
        four_points(&prep, o, r, taus)
    };
    let (fin, tau) = refine::<F, N>(bracket, start, stop, &mut f, &mut f4);
    stats.height_evals += evals.get();
    let c = complete(patch, &cl, &bracket, &fin, tau, t_min, t_max)?;
    keep(&c, &prep);
    Some(c)
}

/// `f` at four parameters of the local ray `o + τ·r` ([`refine`]'s estimate step): one call
/// over [`Float::L4`] where it holds four lanes (bit for bit the same lanes of an eight-lane
/// call: the same operations per lane), else one eight-lane call.
#[inline(always)]
fn four_points<F: Float>(
    prep: &Prepared<F>,
    o: V3<F>,
    r: V3<F>,
    taus: [F; ESTIMATE_POINTS],
) -> [F; ESTIMATE_POINTS] {
    use crate::num::lanes::LaneOps;
    use crate::num::real::Lane4;
    if <F::L4 as Lane4>::POINTS == ESTIMATE_POINTS {
        let sp = <F::L4 as LaneOps>::splat;
        let (o4, r4) = ([sp(o.x), sp(o.y), sp(o.z)], [sp(r.x), sp(r.y), sp(r.z)]);
        return prep.f(o4, r4, F::L4::from_array4(taus)).to_array4();
    }
    let sp = <F::L8 as LaneOps>::splat;
    let (o8, r8) = ([sp(o.x), sp(o.y), sp(o.z)], [sp(r.x), sp(r.y), sp(r.z)]);
    let [a, b, c, d] = taus;
    let taus8 = [a, b, c, d, d, d, d, d];
    let [fa, fb, fc, fd, ..] = prep
        .f(o8, r8, <F::L8 as Lane>::from_array(taus8))
        .to_array();
    [fa, fb, fc, fd]
}

/// `|f(b) − f(a)| / (b − a)` of a bracket (`+∞` or NaN when it has zero width).
#[inline(always)]
pub(crate) fn secant<F: Float>(br: &refine::Bracket<F>) -> F {
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
    scale_of(patch, crate::surface::shell::longest_edge(&patch.shape))
}

/// [`rounding_scale`] from the patch's longest edge `edge`.
#[inline(always)]
fn scale_of<F: Float>(patch: &Patch<F>, edge: F) -> F {
    edge * F::from_f64(EXTENT_EDGES) + patch.frame.origin.length()
}

/// The wall margin [`WALL_MARGIN_ULPS`]` · ε · scale` as a barycentric offset: the walls
/// `Xi = 0` move to `Xi = −margin`, i.e. the margin's world width over the triangle's smallest
/// altitude (`2·area / longest edge`, `edge` the longest edge). 0 where that is not finite.
#[inline(always)]
pub(crate) fn wall_margin<F: Float>(shape: &Shape<F>, edge: F, scale: F) -> F {
    let [_, p1, p2] = shape.p;
    let m = F::from_f64(WALL_MARGIN_ULPS) * F::EPSILON * scale * edge / (p1.x * p2.y);
    if m.is_fin() { m } else { F::ZERO }
}

/// The three walls' barycentric offsets: [`wall_margin`] plus the patch's crack reach
/// ([`close_cracks`](crate::mesh::cracks::close_cracks); 0 unless measured).
#[inline(always)]
pub(crate) fn wall_margins<F: Float>(patch: &Patch<F>, edge: F, scale: F) -> [F; 3] {
    let m = wall_margin(&patch.shape, edge, scale);
    patch.reach.map(|r| r + m)
}

/// The value of `f` within which a sample at the shell interval's ends counts as a zero
/// ([`refine::bracket_step`]): [`ROUNDING_ULPS`]` · ε · L`, the rounding of `f` that the
/// allowance of every `t_error` already covers, so a crossing snapped to an end stays within
/// its `t_error`.
#[inline(always)]
pub(crate) fn end_snap<F: Float>(scale: F) -> F {
    F::from_f64(ROUNDING_ULPS) * F::EPSILON * scale
}

/// The crossing at `tau`, the estimate inside the final bracket `fin` (refined from the
/// sampling bracket `bracket`), of the clipped ray `cl`: `t`, `t_error` with its rounding
/// allowance, barycentrics.
#[inline(always)]
pub(crate) fn complete<F: Float>(
    patch: &Patch<F>,
    cl: &Clipped<F>,
    bracket: &refine::Bracket<F>,
    fin: &refine::Bracket<F>,
    tau: F,
    t_min: F,
    t_max: F,
) -> Option<Crossing<F>> {
    let bary = bary_at(&patch.shape, cl.lray.at(tau));
    // Re-basing can round the hit an ulp outside the caller's range: clamp it.
    let t = (cl.t0 + tau).max(t_min).min(t_max);
    // Rounding allowance ([`ROUNDING_ULPS`] ε L / |f′|, L from [`EXTENT_EDGES`]): the sign of
    // f is only known to about `16 ε L`, which moves the root by that over the slope |f'|. The
    // slope is the smaller of the sampling bracket's and the final bracket's secants: near
    // convergence the final bracket's end values are themselves rounding noise and its secant
    // can be far too steep (which made f32 hits at N ≥ 8 fall outside `t_error` on 0.85 % of
    // the torus's camera rays).
    let slope = if fin.b > fin.a {
        secant(fin).min(secant(bracket))
    } else {
        secant(bracket)
    };
    let rounding = rounding_allowance(cl.scale, slope);
    // A zero at an end of the bracket is the root up to the rounding of `f` (exact, or an
    // interval end snapped by `refine::bracket_step`): the allowance covers it.
    let width = if fin.fa == F::ZERO || fin.fb == F::ZERO {
        F::ZERO
    } else {
        fin.b - fin.a
    };
    let t_error = width + rounding;
    if t.is_fin() && t_error.is_fin() {
        Some(Crossing {
            t,
            t_error,
            rounding,
            bary,
        })
    } else {
        None
    }
}

/// Completes a [`Crossing`] of `patch` into a [`Hit`]: the exact surface normal (one height
/// evaluation over value-and-two-derivatives jets, `Prepared::derivatives`) and the world hit
/// point. `None` if the normal is not finite (never for an accepted patch).
#[inline(always)]
pub(crate) fn finish<F: Float>(patch: &Patch<F>, ray: &Ray<F>, c: &Crossing<F>) -> Option<Hit<F>> {
    finish_prepared(patch, ray, c, &Prepared::new(&patch.shape))
}

/// [`finish`] with the patch's height precomputation at hand (from [`crossing_then`]).
#[inline(always)]
pub(crate) fn finish_prepared<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    c: &Crossing<F>,
    prep: &Prepared<F>,
) -> Option<Hit<F>> {
    let shape = &patch.shape;
    let [du1, du2] = prep.derivatives(shape, c.bary);
    finish_with(patch, ray, c, normal_local(shape, c.bary, du1, du2))
}

/// [`finish`] with the local-frame geometric normal at `c.bary` already at hand (the seamless
/// shading normal computes it with its edge points' normals in one evaluation).
#[inline(always)]
pub(crate) fn finish_with<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    c: &Crossing<F>,
    normal_local: V3<F>,
) -> Option<Hit<F>> {
    let o = F::from_glam(ray.origin);
    let d = F::from_glam(ray.dir);
    let normal = patch.frame.local_dir_to_world(normal_local);
    let [_, w1, w2] = c.bary;
    if !normal.all_finite() {
        return None;
    }
    Some(Hit {
        t: c.t,
        t_error: c.t_error,
        point: F::to_glam(o + d * c.t),
        normal: F::to_glam(normal),
        w1,
        w2,
        front_face: normal.dot(d) < F::ZERO,
        patch: 0,
    })
}

/// A world ray prepared once for all the patches it is tested against: origin and direction
/// in the kernel's vectors and the direction's reciprocals for the box test
/// ([`Aabb::ray_interval`](crate::aabb::Aabb::ray_interval)), the same values each patch test
/// computed for itself before.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WorldRay<F> {
    /// Origin, world coordinates.
    pub o: V3<F>,
    /// Direction.
    pub d: V3<F>,
    /// `1 / d` per axis, 0 where `d` is 0 (that axis is then tested by the origin alone).
    pub inv: V3<F>,
    /// Whether every component of `inv` is finite (false for a subnormal component of `d`).
    pub inv_finite: bool,
}

impl<F: Float> WorldRay<F> {
    /// `ray` prepared, or `None` when its origin or direction is not finite or the direction
    /// is zero (no patch test can hit such a ray).
    #[inline(always)]
    pub(crate) fn new(ray: &Ray<F>) -> Option<Self> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() || d.length2() == F::ZERO {
            return None;
        }
        let inv = crate::aabb::reciprocal(d);
        Some(WorldRay {
            o,
            d,
            inv,
            inv_finite: inv.all_finite(),
        })
    }
}

/// A ray clipped to a patch's shell ([`clip_ray`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Clipped<F> {
    /// The world parameter the local ray is re-based at.
    pub t0: F,
    /// The local ray (`τ = t − t0`).
    pub lray: LocalRay<F>,
    /// Start of the shell interval in `τ`.
    pub a: F,
    /// End of the shell interval in `τ`.
    pub b: F,
    /// The patch's extent `L` ([`rounding_scale`]), computed once per test.
    pub scale: F,
}

/// Where a ray crosses a patch, before the normal is evaluated (the BVH keeps the closest
/// crossing and evaluates one normal per ray).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Crossing<F> {
    /// Ray parameter (world units of the ray's `dir`), clamped to the query range.
    pub t: F,
    /// As [`Hit::t_error`].
    pub t_error: F,
    /// The rounding allowance included in `t_error`.
    pub rounding: F,
    /// Barycentrics of the crossing (projected onto the triangle).
    pub bary: [F; 3],
}

/// Barycentrics (projected onto the triangle) of the local point `x` in the cross-section at
/// its height.
#[inline(always)]
pub(crate) fn bary_at<F: Float>(shape: &Shape<F>, x: V3<F>) -> [F; 3] {
    let ([_, n1, n2], area) = bary_numerators(shape, &Section::new(shape), x);
    let inv = F::ONE / area;
    project_bary(n1 * inv, n2 * inv)
}
