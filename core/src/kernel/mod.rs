//! The bounded-work ray kernel (docs/METHOD.md §8).
//!
//! Along a ray `x(t)`, the patch is the zero set of `f(t) = σ(t) − σS(X(t))`: the height of the
//! ray point over the triangle's plane minus the surface's height at the ray point's
//! barycentrics (both exact consequences of the construction, docs/METHOD.md §2). The kernel
//!
//! 1. clips the ray to the patch's box, then to its shell (slab and three side walls, exact
//!    quadratics): `[ta, tb]`;
//! 2. samples `f` at `ta`, at `K` evenly spaced interior points and at `tb`, and takes the first
//!    sign change (so a ray grazing a bulge twice inside the shell is not missed when the
//!    crossings are at least `(tb − ta)/(K + 1)` apart);
//! 3. refines that bracket with exactly `N` steps of eight points each ([`refine`]: at least
//!    5× narrower per step, superlinear near a simple root);
//! 4. evaluates the exact surface normal once at the estimate.
//!
//! `f` is evaluated at eight parameters per call, in the lanes of [`Float::L8`]
//! ([`crate::lanes`]). Work per ray is at most [`max_lane_calls`]`(K, N) = ⌈(K + 2)/8⌉ + N`
//! lane calls plus one normal evaluation, whatever the input: every loop has a compile-time
//! trip count (a loop may stop early when it has its answer, never run longer). The final
//! bracket's width plus a rounding allowance is returned as [`Hit::t_error`].

pub mod clip;
pub mod flat;
pub(crate) mod height;
pub(crate) mod packet;
pub mod refine;

use crate::lanes::Lane;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};
use crate::real::Float;
use crate::surface::{normal_local, project_bary};
use crate::vec::V3;
use clip::{LocalRay, bary_numerators, shell_interval};
use height::{Prepared, f_lanes};
use refine::{first_sign_change, refine};

/// Default number `K` of interior bracketing samples used by [`Patch::intersect`]: with the two
/// ends, eight points, one lane call.
pub const DEFAULT_SAMPLES: usize = 6;

/// The most lane calls ([`crate::lanes`]: eight height evaluations each) that one patch test
/// with `k` bracketing samples and `n` refinement steps makes: `⌈(k + 2)/8⌉ + n`.
///
/// # Panics
/// Never.
pub const fn max_lane_calls(k: usize, n: usize) -> usize {
    (k + 2).div_ceil(crate::lanes::LANES) + n
}

/// Statistics of one kernel call, for tests and studies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KernelStats {
    /// Number of height evaluations `σS` performed, eight per lane call (at most
    /// `8 ·` [`max_lane_calls`]`(K, N)`).
    pub height_evals: u32,
    /// Number of full point-and-normal evaluations (0 or 1).
    pub normal_evals: u32,
    /// Width `tb − ta` of the shell interval that was sampled (in units of the ray parameter
    /// `t`, converted to `f64`); 0 when the ray missed the box or the shell. The worst-case
    /// guarantee of [`Patch::intersect`] is stated in terms of it.
    pub shell_width: f64,
    /// The rounding allowance included in the returned [`Hit::t_error`] (converted to `f64`):
    /// `t_error` is the final bracket's width plus this. 0 when there is no hit.
    pub rounding: f64,
}

impl<F: Float> Patch<F> {
    /// Closest intersection of `ray` with the patch for `t` in `[t_min, t_max]`, with `N`
    /// refinement iterations and [`DEFAULT_SAMPLES`] bracketing samples.
    ///
    /// Returns `None` when the ray misses (including degenerate rays: zero or non-finite
    /// direction, non-finite origin, `t_max < t_min`, NaN bounds). `t_max` may be infinite.
    ///
    /// # Accuracy
    /// `|t − t_true| ≤ hit.t_error` where `t_true` is the crossing inside the final bracket.
    /// `t_error` is the final bracket's width plus a rounding allowance
    /// ([`KernelStats::rounding`], `16 ε L / |f′|` for the patch's extent `L`), and the bracket
    /// is at most `(tb − ta) / ((K + 1)·5^N)` for the shell interval `[ta, tb]`
    /// ([`KernelStats::shell_width`]): one sampling step, divided by at least
    /// [`WORST_SHRINK`](refine::WORST_SHRINK) = 5 by every refinement step (tested on every
    /// patch test of random rays in `tests/kernel.rs`). Convergence is usually far faster: from
    /// N = 4, `f64` hits on the torus are at rounding
    /// ([`TORUS_F64_BY_ITERATIONS`](crate::accuracy::TORUS_F64_BY_ITERATIONS)); at N = 8 `f64`
    /// hits on spheres are on the sphere to [`F64_SPHERE_HIT`](crate::accuracy::F64_SPHERE_HIT).
    /// Rays that cross the surface twice within one sampling step `(tb − ta)/(K + 1)` may be
    /// reported as misses.
    /// # Panics
    /// Never. Work is bounded: at most [`max_lane_calls`]`(K, N)` lane calls (eight height
    /// evaluations each) and one normal evaluation.
    #[inline]
    pub fn intersect<const N: usize>(&self, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        self.intersect_stats::<DEFAULT_SAMPLES, N>(ray, t_min, t_max)
            .0
    }

    /// [`Patch::intersect`] with `K` bracketing samples and `N` refinement iterations chosen by
    /// the caller, also returning the [`KernelStats`] of the call (evaluation counts, the shell
    /// interval's width and the rounding allowance).
    ///
    /// # Accuracy
    /// As [`Patch::intersect`].
    /// # Panics
    /// Never.
    pub fn intersect_stats<const K: usize, const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> (Option<Hit<F>>, KernelStats) {
        let mut stats = KernelStats::default();
        let hit = self.intersect_impl::<K, N>(ray, t_min, t_max, &mut stats);
        (hit, stats)
    }

    #[inline(always)]
    fn intersect_impl<const K: usize, const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        stats: &mut KernelStats,
    ) -> Option<Hit<F>> {
        let c = self.crossing::<K, N>(ray, t_min, t_max, stats)?;
        stats.normal_evals += 1;
        let hit = self.finish(ray, &c)?;
        stats.rounding = c.rounding.to_f64();
        Some(hit)
    }

    /// Clips a world ray to the patch's box, slab and shell: the local ray re-based at `t0`
    /// (the middle of the box interval) and the interval `[a, b]` of `τ = t − t0` to search, or
    /// `None` when the ray misses the shell (or is degenerate).
    #[inline(always)]
    pub(crate) fn clip_ray(&self, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Clipped<F>> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() || d.length2() == F::ZERO {
            return None;
        }
        if t_min.is_nan() || t_max.is_nan() || t_max < t_min {
            return None;
        }
        let (ta, tb) = self.bbox.ray_interval(o, d, t_min, t_max)?;
        // Local ray re-based at the middle of the box interval.
        let t0 = F::from_f64(0.5) * (ta + tb);
        let lray = LocalRay {
            o: self.world_to_local(o + d * t0),
            r: self.world_dir_to_local(d),
        };
        // Slab σmin ≤ σ ≤ σmax.
        let [s_lo, s_hi] = self.sigma;
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
        let (a, b) = shell_interval(self, &lray, a, b)?;
        Some(Clipped { t0, lray, a, b })
    }

    /// The search part of the kernel (clip, bracket, refine) without the normal: where the ray
    /// crosses the patch, or `None`. At most [`max_lane_calls`]`(K, N)` lane calls.
    #[inline(always)]
    pub(crate) fn crossing<const K: usize, const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        stats: &mut KernelStats,
    ) -> Option<Crossing<F>> {
        let cl = self.clip_ray(ray, t_min, t_max)?;
        let (a, b) = (cl.a, cl.b);
        stats.shell_width = (b - a).to_f64();
        let prep = Prepared::new(self);
        let sp = <F::L8 as crate::lanes::LaneOps>::splat;
        let (o, r) = (cl.lray.o, cl.lray.r);
        let (o8, r8) = ([sp(o.x), sp(o.y), sp(o.z)], [sp(r.x), sp(r.y), sp(r.z)]);
        let mut f = |taus: [F; crate::lanes::LANES]| {
            stats.height_evals += crate::lanes::LANES as u32;
            f_lanes(&prep, o8, r8, <F::L8 as Lane>::from_array(taus)).to_array()
        };
        let bracket = first_sign_change::<F, K>(a, b, &mut f)?;
        let fin = refine::<F, N>(bracket, &mut f);
        self.complete(&cl, &bracket, &fin, t_min, t_max)
    }

    /// The crossing at the final bracket `fin` (refined from the sampling bracket `bracket`)
    /// of the clipped ray `cl`: `t`, `t_error` with its rounding allowance, barycentrics.
    #[inline(always)]
    pub(crate) fn complete(
        &self,
        cl: &Clipped<F>,
        bracket: &refine::Bracket<F>,
        fin: &refine::Bracket<F>,
        t_min: F,
        t_max: F,
    ) -> Option<Crossing<F>> {
        let tau = fin.estimate();
        let bary = bary_at(self, cl.lray.at(tau));
        // Re-basing can round the hit an ulp outside the caller's range: clamp it.
        let t = (cl.t0 + tau).max(t_min).min(t_max);
        // Rounding allowance: the sign of f is only known to about `16 ε L` (L: the patch's
        // size plus its distance from the world origin), which moves the root by that over the
        // slope |f'|. The slope is the smaller of the sampling bracket's and the final
        // bracket's secants: near convergence the final bracket's end values are themselves
        // rounding noise and its secant can be far too steep (which made f32 hits at N ≥ 8
        // fall outside `t_error` on 0.85 % of the torus's camera rays).
        let secant = |br: &refine::Bracket<F>| (br.fb - br.fa).abs() / (br.b - br.a);
        let slope = if fin.b > fin.a {
            secant(fin).min(secant(bracket))
        } else {
            secant(bracket)
        };
        let scale = crate::shell::longest_edge(self) * F::from_f64(4.0) + self.origin.length();
        let rounding = F::from_f64(16.0) * F::EPSILON * scale / slope;
        let rounding = if rounding.is_fin() { rounding } else { F::ZERO };
        let t_error = (fin.b - fin.a) + rounding;
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

    /// Completes a [`Crossing`] of this patch into a [`Hit`]: the exact surface normal (one
    /// height evaluation over value-and-two-derivatives jets, `height::derivatives`) and the world hit point. `None` if the normal is not
    /// finite (never for an accepted patch).
    #[inline(always)]
    pub(crate) fn finish(&self, ray: &Ray<F>, c: &Crossing<F>) -> Option<Hit<F>> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        let [du1, du2] = height::derivatives(self, &Prepared::new(self), c.bary);
        let normal = self.local_dir_to_world(normal_local(self, c.bary, du1, du2));
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
}

/// A ray clipped to a patch's shell ([`Patch::clip_ray`]).
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
pub(crate) fn bary_at<F: Float>(patch: &Patch<F>, x: V3<F>) -> [F; 3] {
    let ([_, n1, n2], area) = bary_numerators(patch, x);
    let inv = F::ONE / area;
    project_bary(n1 * inv, n2 * inv)
}
