//! The bounded-work ray kernel (docs/METHOD.md §8).
//!
//! Along a ray `x(t)`, the patch is the zero set of `f(t) = σ(t) − σS(X(t))`: the height of the
//! ray point over the triangle's plane minus the surface's height at the ray point's
//! barycentrics (both exact consequences of the construction, docs/METHOD.md §2). The kernel
//!
//! 1. clips the ray to the patch ([`clip::clip`]: its box, then its shell, slab and three side
//!    walls, exact quadratics): `[ta, tb]`, and returns without sampling when the ray misses
//!    the patch's band there (a quadratic bound of the surface, [`crate::surface::band`]) or
//!    when the interval starts beyond the caller's best crossing;
//! 2. samples `f` at `ta`, at `K` evenly spaced interior points and at `tb`, and takes the first
//!    sign change (so a ray grazing a bulge twice inside the shell is not missed when the
//!    crossings are at least `(tb − ta)/(K + 1)` apart);
//! 3. refines that bracket with at most `N` steps of eight points each ([`refine()`]: at least
//!    5× narrower per step, superlinear near a simple root; it stops early once the bracket
//!    is within [`EARLY_STOP`](refine::EARLY_STOP) of the rounding allowance), and, for
//!    `N ≥ 1`, at most one step of four points around a trusted estimate (over [`Float::L4`]: where the estimate
//!    is good enough, the step that ends the refinement costs half a lane call);
//! 4. evaluates the exact surface normal once at the estimate, from the crossing's own
//!    prepared patch ([`Crossing::hit`]).
//!
//! Steps 2–3 are the fallback of the **predicted search** ([`predicted`]) on patches with a
//! predictor and `N ≥ 1`: the predictor's signs at step 2's samples decide the first sign
//! change, and five true evaluations around its crossing usually certify it.
//!
//! A patch is prepared for the height evaluation once per test, into the caller's slot, and a
//! crossing is completed into a hit with the same prepared patch: the BVH keeps the closest
//! crossing's prepared patch in one of two slots (the other takes the next candidate's), so no
//! patch is prepared twice for one hit and no prepared patch is copied.
//!
//! `f` is evaluated at eight parameters per call, in the lanes of [`Float::L8`]
//! ([`crate::num::lanes`]). Work per ray is at most [`max_lane_calls`]`(K, n) = ⌈(K + 2)/8⌉ + n`
//! lane calls, two four-point calls, the predicted search's [`PREDICTED_EVALS`] and one normal
//! evaluation ([`max_height_evals`] height evaluations in all), whatever the input: every loop
//! has a bounded trip count (the refinement's at most [`MAX_ITERATIONS`] steps; a loop may stop
//! early when it has its answer, never run longer). The final bracket's width plus a rounding
//! allowance is returned as [`Hit::t_error`].

//!
//! The error budget and the work bounds are named constants in [`budget`].

pub(crate) mod budget;
pub(crate) mod clip;
pub mod flat;
pub(crate) mod heights;
pub(crate) mod predicted;
pub mod refine;
pub(crate) mod study;

use crate::geometry::Patch;
use crate::geometry::Shape;
use crate::num::lanes::One;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::ray::{Hit, Ray};
use crate::surface::lanes::Prepared;
use crate::surface::scalar::{normal_local, project_bary};
pub(crate) use budget::Budget;
pub use budget::{
    DEFAULT_SAMPLES, MAX_CRACK_REACH, MAX_ITERATIONS, PREDICTED_EVALS, ROUNDING_ULPS,
    WALL_MARGIN_ULPS, iterations, max_height_evals, max_lane_calls,
};
use budget::{end_snap, rounding_allowance, secant};
pub(crate) use clip::WorldRay;
use clip::{Clipped, clip};
pub(crate) use heights::Heights;
use predicted::{Predicted, Signs};
use refine::{ESTIMATE_POINTS, first_sign_change, refine};

/// Statistics of one kernel call, for tests and studies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KernelStats {
    /// Number of height evaluations `σS` performed, eight per lane call and four per
    /// estimate step (at most [`max_height_evals`]`(K, N)`).
    pub height_evals: u32,
    /// Number of full point-and-normal evaluations (0 or 1).
    pub normal_evals: u32,
    /// Width `tb − ta` of the shell interval that was sampled (in units of the ray parameter
    /// `t`, converted to `f64`); 0 when the ray missed the box or the shell. The worst-case
    /// guarantee of [`Patch::closest_hit`] is stated in terms of it.
    pub shell_width: f64,
    /// The rounding allowance included in the returned [`Hit::t_error`] (converted to `f64`):
    /// `t_error` is the final bracket's width plus this, `ROUNDING_ULPS · ε · L / |f′|` (`ROUNDING_ULPS` = 16)
    /// with `L = 4 · longest_edge + |P0|` and `|f′|` the flatter of the
    /// sampling and the final brackets' secant slopes. 0 when there is no hit.
    pub rounding: f64,
}

/// [`Patch::closest_hit_stats`]: the closest crossing of `ray` with `patch` in `[t_min, t_max]`
/// (`K` bracketing samples, a refinement budget `n`) completed into a [`Hit`], with the
/// call's [`KernelStats`]; `f` evaluated by `heights`.
#[inline(always)]
pub(crate) fn closest_hit_stats<F: Float, const K: usize>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    [t_min, t_max]: [F; 2],
    n: usize,
    heights: &impl Heights<F>,
) -> (Option<Hit<F>>, KernelStats) {
    let mut stats = KernelStats::default();
    let hit = closest_hit_impl::<F, K>(patch, ray, [t_min, t_max], n, &mut stats, heights);
    (hit, stats)
}

#[inline(always)]
fn closest_hit_impl<F: Float, const K: usize>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    [t_min, t_max]: [F; 2],
    n: usize,
    stats: &mut KernelStats,
    heights: &impl Heights<F>,
) -> Option<Hit<F>> {
    let world = WorldRay::new(ray)?;
    let mut prepared = None;
    let test = Test::closest(t_min, t_max, n);
    let c = crossing::<F, K>(patch, &world, test, stats, &mut prepared, heights)?;
    let hit = c.hit(patch, prepared.as_ref()?, ray);
    stats.normal_evals += 1;
    let hit = hit?;
    stats.rounding = c.rounding.to_f64();
    Some(hit)
}

/// What a patch test searches: the caller's range `[t_min, t_max]`, the parameter `beyond`
/// at or after which the caller discards crossings ([`crossing`]), and the refinement budget
/// `n`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Test<F> {
    pub t_min: F,
    pub t_max: F,
    pub beyond: Option<F>,
    pub n: Budget,
    /// Whether the predicted search may run ([`predicted`]); `false` only for the study of
    /// the bracketing alone.
    pub predict: bool,
}

impl<F> Test<F> {
    /// The test of one patch alone: `[t_min, t_max]`, nothing found before, budget `n`.
    #[inline(always)]
    pub(crate) fn closest(t_min: F, t_max: F, n: usize) -> Self {
        Test {
            t_min,
            t_max,
            beyond: None,
            n: Budget::new(n),
            predict: true,
        }
    }
}

/// Where `ray` crosses `patch` in `[t_min, t_max]` (clip, bracket, refine; no normal yet),
/// or `None`. At most [`max_lane_calls`]`(K, n)` lane calls and two four-point calls
/// ([`max_height_evals`]), made by `heights`. The patch's height evaluation is prepared into
/// `prepared` (once the ray reaches its shell; otherwise the slot is left alone), where it
/// stays for completing the crossing into a hit ([`Crossing::hit`]) without preparing the
/// patch again.
///
/// `test.beyond`, when given, is a ray parameter at or after which the caller discards
/// crossings (the closest one found so far, `≤ t_max`): a patch whose shell interval starts
/// after it is not searched (`None`, no lane call), which returns `None` exactly where the
/// search would have returned a crossing the caller discards.
#[inline(always)]
pub(crate) fn crossing<F: Float, const K: usize>(
    patch: &Patch<F>,
    ray: &WorldRay<F>,
    test: Test<F>,
    stats: &mut KernelStats,
    prepared: &mut Option<Prepared<F>>,
    heights: &impl Heights<F>,
) -> Option<Crossing<F>> {
    let Test {
        t_min,
        t_max,
        beyond,
        n,
        ..
    } = test;
    let cl = clip(patch, ray, t_min, t_max, beyond)?;
    let (a, b) = (cl.a, cl.b);
    stats.shell_width = (b - a).to_f64();
    let prep = &*prepared.insert(Prepared::new(&patch.shape));
    let (o, r) = (cl.lray.o, cl.lray.r);
    let evals = core::cell::Cell::new(0u32);
    let count = |n: usize| evals.set(evals.get().saturating_add(n as u32));
    let mut f = |taus: [F; crate::num::lanes::LANES]| {
        count(crate::num::lanes::LANES);
        heights.f8(prep, o, r, taus)
    };
    let mut f4 = |taus: [F; ESTIMATE_POINTS]| {
        count(ESTIMATE_POINTS);
        heights.f4(prep, o, r, taus)
    };
    let snap = end_snap(cl.scale);
    let predictor = &patch.predictor;
    if test.predict && n.get() > 0 && predictor.usable() {
        let p = Predicted {
            predictor,
            prep,
            o,
            r,
        };
        let margin = predictor.bound() + snap + snap;
        match predicted::signs::<F, K>(&p, a, b, margin) {
            Signs::Miss => return None,
            Signs::Bracket(br) => {
                let stop =
                    rounding_allowance(cl.scale, secant(&br)) * F::from_f64(refine::EARLY_STOP);
                let (tp, slope) = predicted::root(&p, &br);
                let mut f1 = |tau: F| {
                    count(1);
                    let [o1, r1] = [o, r].map(|v| [One(v.x), One(v.y), One(v.z)]);
                    prep.f(o1, r1, One(tau)).0
                };
                if let Some((next, before, after)) =
                    predicted::certify(br, tp, slope, stop, &mut f1, &mut f4)
                {
                    let start = refine::start_estimate(&next, before, after);
                    let (fin, tau) = refine(next, start, stop, n.get(), &mut f, &mut f4);
                    stats.height_evals += evals.get();
                    return complete(&patch.shape, &cl, &br, &fin, tau, [t_min, t_max], prep);
                }
            }
            Signs::Unsure => {}
        }
    }
    let found = first_sign_change::<F, K>(a, b, snap, &mut f);
    let Some((bracket, start)) = found else {
        stats.height_evals += evals.get();
        return None;
    };
    // The allowance of `complete` is at least the one from the sampling bracket's secant
    // (it takes the flatter of two secants): a bracket below a fraction of it is converged.
    let floor = rounding_allowance(cl.scale, secant(&bracket));
    let stop = floor * F::from_f64(refine::EARLY_STOP);
    let (fin, tau) = refine(bracket, start, stop, n.get(), &mut f, &mut f4);
    stats.height_evals += evals.get();
    complete(&patch.shape, &cl, &bracket, &fin, tau, [t_min, t_max], prep)
}

/// The crossing at `tau`, the estimate inside the final bracket `fin` (refined from the
/// sampling bracket `bracket`), of the clipped ray `cl`: `t`, `t_error` with its rounding
/// allowance, barycentrics (in the section map of `prepared`, the patch's).
#[inline(always)]
fn complete<F: Float>(
    shape: &Shape<F>,
    cl: &Clipped<F>,
    bracket: &refine::Bracket<F>,
    fin: &refine::Bracket<F>,
    tau: F,
    [t_min, t_max]: [F; 2],
    prepared: &Prepared<F>,
) -> Option<Crossing<F>> {
    let bary = bary_at(shape, prepared, cl.lray.at(tau));
    // Re-basing can round the hit an ulp outside the caller's range: clamp it.
    let t = (cl.t0 + tau).max(t_min).min(t_max);
    // Rounding allowance ([`ROUNDING_ULPS`] ε L / |f′|, L from [`EXTENT_EDGES`]): the sign of
    // f is only known to about `16 ε L`, which moves the root by that over the slope |f'|. The
    // slope is the smaller of the sampling bracket's and the final bracket's secants: near
    // convergence the final bracket's end values are themselves rounding noise and its secant
    // can be far too steep (with it alone, f32 hits at N ≥ 8 fell outside `t_error` on some
    // of the torus's camera rays: docs/MEASUREMENTS.md).
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

impl<F: Float> Crossing<F> {
    /// The crossing of `patch` (the patch it was found on, `prepared` for it by [`crossing`])
    /// completed into a [`Hit`]: the exact surface normal (one height evaluation over
    /// value-and-two-derivatives jets, [`Prepared::derivatives`]) and the world hit point.
    /// `None` if the normal is not finite (never for an accepted patch).
    #[inline(always)]
    pub(crate) fn hit(
        &self,
        patch: &Patch<F>,
        prepared: &Prepared<F>,
        ray: &Ray<F>,
    ) -> Option<Hit<F>> {
        let shape = &patch.shape;
        let [du1, du2] = prepared.derivatives(shape, self.bary);
        self.hit_with_normal(patch, ray, normal_local(shape, self.bary, du1, du2))
    }

    /// [`Crossing::hit`] with the local-frame geometric normal at `self.bary` already at hand
    /// (the seamless shading normal computes it with its edge points' normals in one
    /// evaluation).
    #[inline(always)]
    pub(crate) fn hit_with_normal(
        &self,
        patch: &Patch<F>,
        ray: &Ray<F>,
        normal_local: V3<F>,
    ) -> Option<Hit<F>> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        let normal = patch.frame.local_dir_to_world(normal_local);
        let [_, w1, w2] = self.bary;
        if !normal.all_finite() {
            return None;
        }
        Some(Hit {
            t: self.t,
            t_error: self.t_error,
            point: F::to_glam(o + d * self.t),
            normal: F::to_glam(normal),
            w1,
            w2,
            front_face: normal.dot(d) < F::ZERO,
            patch: 0,
        })
    }
}

/// Barycentrics (projected onto the triangle) of the local point `x` in the cross-section at
/// its height (the section map of `prepared`, this patch's).
#[inline(always)]
fn bary_at<F: Float>(shape: &Shape<F>, prepared: &Prepared<F>, x: V3<F>) -> [F; 3] {
    let ([_, n1, n2], area) = prepared.section().bary_numerators(shape, x);
    let inv = F::ONE / area;
    project_bary(n1 * inv, n2 * inv)
}
