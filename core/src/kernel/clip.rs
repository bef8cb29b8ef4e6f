//! Clipping a ray to a patch (docs/METHOD.md §8 step 1), in one call, [`clip`]: the patch's
//! world box, then in the local frame the slab `σmin ≤ σ ≤ σmax`, the patch's band (a
//! quadratic bound of the surface, [`crate::surface::band`]) over the slab's interval, the
//! three side walls `Xi = −margin_i` (each a quadratic in the ray parameter for parallel
//! sections, or a ruled surface whose lines the ray meets where a quadratic in the edge
//! parameter vanishes for tilted sections, [`crate::surface::field`]), and the band again over
//! the walls' interval. The walls are moved out by a rounding margin plus the patch's crack
//! reach ([`wall_margins`]).

use super::budget::{WALL_MARGIN_ULPS, scale_of};
use crate::geometry::{Band, Patch, Shape};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::ray::Ray;
use crate::surface::band;
use crate::surface::field::Section;
use crate::surface::shell::{cross2_poly, longest_edge, moved_corners};

/// A world ray prepared once for all the patches it is tested against: origin and direction
/// in the kernel's vectors and the direction's reciprocals for the box test
/// ([`Aabb::ray_interval`](crate::aabb::Aabb::ray_interval)), computed once per ray rather than
/// once per patch test.
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

/// A ray clipped to a patch's shell ([`clip`]).
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
    /// The patch's extent `L` ([`rounding_scale`](super::budget::rounding_scale)), computed once per test.
    pub scale: F,
}
/// A ray in a patch's local frame, re-based at `t0` so that polynomials in `τ = t − t0` stay
/// well-conditioned.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalRay<F> {
    /// Local origin at `t = t0`.
    pub o: V3<F>,
    /// Local direction.
    pub r: V3<F>,
}

impl<F: Float> LocalRay<F> {
    /// Local point at `τ` (relative parameter).
    #[inline(always)]
    pub fn at(&self, tau: F) -> V3<F> {
        self.o + self.r * tau
    }
}

/// Clips a world ray to the patch's box, slab and shell: the local ray re-based at `t0`
/// (the middle of the box interval) and the interval `[a, b]` of `τ = t − t0` to search, or
/// `None` when the ray misses the shell (or is degenerate), when the interval misses the
/// patch's band ([`BandRay::misses`]: no surface point on it), or when the interval starts beyond
/// `beyond` (`t0 + a > beyond`: every crossing the kernel could return lies there, see
/// [`crossing`](super::crossing)).
#[inline(always)]
pub(crate) fn clip<F: Float>(
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
    let edge = longest_edge(&patch.shape);
    let scale = scale_of(patch, edge);
    let margins = wall_margins(patch, edge, scale);
    let [m0, m1, m2] = margins;
    let reach = m0.max(m1).max(m2);
    // The band, first over the slab's interval (a ray that misses it there misses it on the
    // shell's interval inside, and the wall quadratics are not solved), then over the shell's:
    // no surface point on [a, b], nothing to sample.
    let band = BandRay::new(&patch.band, &patch.shape, lray.o, lray.r, reach);
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

/// The wall margin [`WALL_MARGIN_ULPS`]` · ε · scale` as a barycentric offset: the walls
/// `Xi = 0` move to `Xi = −margin`, i.e. the margin's world width over the triangle's smallest
/// altitude (`2·area / longest edge`, `edge` the longest edge). 0 where that is not finite.
#[inline(always)]
fn wall_margin<F: Float>(shape: &Shape<F>, edge: F, scale: F) -> F {
    let [_, p1, p2] = shape.p;
    let m = F::from_f64(WALL_MARGIN_ULPS) * F::EPSILON * scale * edge / (p1.x * p2.y);
    if m.is_fin() { m } else { F::ZERO }
}

/// The three walls' barycentric offsets: [`wall_margin`] plus the patch's crack reach
/// ([`close_cracks`](crate::mesh::close_cracks); 0 unless measured).
#[inline(always)]
fn wall_margins<F: Float>(patch: &Patch<F>, edge: F, scale: F) -> [F; 3] {
    let m = wall_margin(&patch.shape, edge, scale);
    patch.reach.map(|r| r + m)
}

/// A local ray `o + τ·r` against a patch's band widened for the walls' largest barycentric
/// reach: what [`BandRay::misses`] needs of the ray, computed once for the kernel's two tests
/// (over the slab's interval, then over the shell's).
pub(crate) struct BandRay<F> {
    /// The band's coefficients.
    c: [F; 3],
    /// The band's bounds widened for the reach.
    lo: F,
    hi: F,
    /// The ray's origin and direction heights.
    oz: F,
    rz: F,
    /// Barycentrics of the origin and their change along `r`.
    bo: [F; 3],
    br: [F; 3],
    /// Leading coefficient of `h`: `−q(β′)`.
    h2: F,
}

impl<F: Float> BandRay<F> {
    /// The ray `o + τ·r` against `band` of `shape`, widened for the barycentric `reach`.
    /// The ray terms for the local ray `o + τ·r` and a wall reach `reach`.
    #[inline(always)]
    fn new(band: &Band<F>, shape: &Shape<F>, o: V3<F>, r: V3<F>, reach: F) -> Self {
        let widen = band.per_reach * reach;
        let br = band::bary_xy(shape, r.x, r.y, true);
        BandRay {
            c: band.c,
            lo: band.lo - widen,
            hi: band.hi + widen,
            oz: o.z,
            rz: r.z,
            bo: band::bary_xy(shape, o.x, o.y, false),
            br,
            h2: -band::q(band.c, br),
        }
    }

    /// Whether the ray misses the band for `τ` in `[a, b]`: `h(τ) = z − q(β)` stays above `hi`
    /// or below `lo` on the whole interval (so no surface point lies on it). `false` where
    /// anything is not finite.
    ///
    /// `h` is a quadratic: between its end values it deviates from their chord by
    /// `h2·(τ − a)(τ − b)`, at most `|h2|·w²/4` in the direction of `−h2`'s sign.
    /// Whether no point of `[a, b]` lies in the band: the range of the quadratic `h` there
    /// (its ends and its bow) outside `[lo, hi]`.
    #[inline(always)]
    fn misses(&self, a: F, b: F) -> bool {
        let at = |t: F| {
            let [o0, o1, o2] = self.bo;
            let [r0, r1, r2] = self.br;
            self.oz + self.rz * t - band::q(self.c, [o0 + r0 * t, o1 + r1 * t, o2 + r2 * t])
        };
        let (ha, hb) = (at(a), at(b));
        let w = b - a;
        let bow = self.h2 * w * w * F::from_f64(0.25);
        let hmin = ha.min(hb) - bow.max(F::ZERO);
        let hmax = ha.max(hb) - bow.min(F::ZERO);
        hmin.is_fin() && hmax.is_fin() && (hmin > self.hi || hmax < self.lo)
    }
}

/// Real roots of `c0 + c1·x + c2·x²` (numerically careful; up to two, NaN-free; `None` slots).
#[inline(always)]
fn quadratic_roots<F: Float>(c: [F; 3]) -> [Option<F>; 2] {
    let [c0, c1, c2] = c;
    let scale = c1.abs().max(c0.abs());
    if c2.abs() <= F::EPSILON * F::from_f64(1e-3) * scale || c2 == F::ZERO {
        if c1 != F::ZERO {
            let x = -c0 / c1;
            return [if x.is_fin() { Some(x) } else { None }, None];
        }
        return [None, None];
    }
    let disc = c1 * c1 - F::from_f64(4.0) * c2 * c0;
    if !(disc >= F::ZERO) || !disc.is_fin() {
        return [None, None];
    }
    let sq = disc.sqrt();
    let q = if c1 < F::ZERO {
        F::from_f64(-0.5) * (c1 - sq)
    } else {
        F::from_f64(-0.5) * (c1 + sq)
    };
    let r1 = q / c2;
    let r2 = if q != F::ZERO { c0 / q } else { r1 };
    let ok = |x: F| if x.is_fin() { Some(x) } else { None };
    [ok(r1), ok(r2)]
}

/// Coefficients (in `τ`) of the three wall quadratics `num_k(τ) + margin_k · Σ_j num_j(τ)`
/// along the local ray: the walls `Xk = −margin_k` (`Σ_j num_j`, twice the cross-section's
/// area, is positive in a valid shell).
#[inline(always)]
fn wall_polys<F: Float>(shape: &Shape<F>, ray: &LocalRay<F>, margin: [F; 3]) -> [[F; 3]; 3] {
    let o = ray.o;
    let r = ray.r;
    // a_i(τ) − q(τ) = (p_i + o.z·d_i − o) + τ (r.z·d_i − r), in the xy-plane.
    let lin = |p: V3<F>, d: V3<F>| (p + d * o.z - o, d * r.z - r);
    let [p0, p1, p2] = shape.p;
    let [d0, d1, d2] = shape.d;
    let (u0, v0) = lin(p0, d0);
    let (u1, v1) = lin(p1, d1);
    let (u2, v2) = lin(p2, d2);
    let w = [
        cross2_poly(u1, v1, u2, v2),
        cross2_poly(u2, v2, u0, v0),
        cross2_poly(u0, v0, u1, v1),
    ];
    // Twice the cross-section's area, coefficient by coefficient.
    let [mut sum, w1, w2] = w;
    for ((s, b), c) in sum.iter_mut().zip(w1).zip(w2) {
        *s = *s + b + c;
    }
    let mut out = w;
    for (c, m) in out.iter_mut().zip(margin) {
        for (o, s) in c.iter_mut().zip(sum) {
            *o += m * s;
        }
    }
    out
}

/// Where the local ray meets the walls `Xk = −margin_k` of a shell with tilted sections: each
/// wall is the ruled surface of the lines `p(t) + λ·g(t)` between two moved corners (base
/// point and direction linear in `t`), and the ray meets the line of `t` where the permuted
/// inner product of their Plücker coordinates, `r·(p × g) + g·(o × r)`, vanishes: a quadratic
/// in `t`. Each root gives the ray parameter of the meeting point. Up to two per wall, `None`
/// where there is none (or it is not finite).
#[inline(always)]
fn ruled_wall_crossings<F: Float>(
    shape: &Shape<F>,
    ray: &LocalRay<F>,
    margin: [F; 3],
) -> [Option<F>; 6] {
    let corner = |x: [F; 3]| {
        let mut b = V3::zero();
        let mut g = V3::zero();
        for ((p, d), w) in shape.p.iter().zip(shape.d.iter()).zip(x) {
            b = b + *p * w;
            g = g + *d * w;
        }
        (b, g)
    };
    let [c0, c1, c2] = moved_corners(margin).map(corner);
    let (o, r) = (ray.o, ray.r);
    let m = o.cross(r);
    let mut out = [None; 6];
    // Wall k (opposite vertex k) runs from corner k+1 to corner k+2.
    let walls = [(c1, c2), (c2, c0), (c0, c1)];
    for (k, ((pa, ga), (pb, gb))) in walls.into_iter().enumerate() {
        let (pe, ge) = (pb - pa, gb - ga);
        let q = [
            r.dot(pa.cross(ga)) + ga.dot(m),
            r.dot(pa.cross(ge) + pe.cross(ga)) + ge.dot(m),
            r.dot(pe.cross(ge)),
        ];
        for (j, t) in quadratic_roots(q).into_iter().enumerate() {
            let tau = t.and_then(|t| {
                let (p, g) = (pa + pe * t, ga + ge * t);
                let rg = r.cross(g);
                let tau = (p - o).cross(g).dot(rg) / rg.length2();
                if tau.is_fin() { Some(tau) } else { None }
            });
            if let Some(slot) = out.get_mut(2 * k + j) {
                *slot = tau;
            }
        }
    }
    out
}

/// Maximum number of breakpoints (two interval ends and two roots per wall).
const MAX_BREAKS: usize = 8;

/// The parameter interval `[τa, τb]` of the local ray inside the shell: the hull of the
/// sub-intervals of `[τ_lo, τ_hi]` (already clipped to the slab) where all three walls, wall
/// `k` moved outward by the barycentric `margin[k]` ([`wall_margins`]), are
/// satisfied.
/// Fixed work: at most 8 breakpoints, at most 21 compare-and-swaps, 7 midpoint tests.
#[inline(always)]
fn shell_interval<F: Float>(
    shape: &Shape<F>,
    ray: &LocalRay<F>,
    tau_lo: F,
    tau_hi: F,
    margin: [F; 3],
) -> Option<(F, F)> {
    if !crate::surface::field::parallel(shape) {
        return tilted_shell_interval(shape, ray, tau_lo, tau_hi, margin);
    }
    let polys = wall_polys(shape, ray, margin);
    let mut roots = [None; 6];
    for (slots, poly) in roots.chunks_exact_mut(2).zip(polys) {
        for (slot, x) in slots.iter_mut().zip(quadratic_roots(poly)) {
            *slot = x;
        }
    }
    interval_of(roots, tau_lo, tau_hi, |tau| {
        polys
            .iter()
            .all(|&[c0, c1, c2]| c0 + tau * (c1 + tau * c2) >= F::ZERO)
    })
}

/// [`shell_interval`] for tilted sections ([`Section`]): the walls are ruled surfaces
/// ([`ruled_wall_crossings`]) and a point is inside where its barycentrics in its own section
/// satisfy `Xk + margin_k ≥ 0`. Not inlined, so the parallel path stays lean.
#[inline(never)]
fn tilted_shell_interval<F: Float>(
    shape: &Shape<F>,
    ray: &LocalRay<F>,
    tau_lo: F,
    tau_hi: F,
    margin: [F; 3],
) -> Option<(F, F)> {
    let sec = Section::new(shape);
    let roots = ruled_wall_crossings(shape, ray, margin);
    interval_of(roots, tau_lo, tau_hi, |tau| {
        let (n, area) = sec.bary_numerators(shape, ray.at(tau));
        n.iter()
            .zip(margin)
            .all(|(&nk, m)| nk + m * area >= F::ZERO)
    })
}

/// The hull of the pieces of `[τ_lo, τ_hi]` between the wall crossings `roots` whose midpoints
/// are `inside` (or the single point `τ_lo` of a zero-length interval, if inside).
#[inline(always)]
fn interval_of<F: Float>(
    roots: [Option<F>; 6],
    tau_lo: F,
    tau_hi: F,
    inside: impl Fn(F) -> bool,
) -> Option<(F, F)> {
    let mut brk = [tau_hi; MAX_BREAKS];
    let mut count = 1usize;
    if let Some(b) = brk.get_mut(0) {
        *b = tau_lo;
    }
    for x in roots.into_iter().flatten() {
        if x > tau_lo && x < tau_hi {
            if let Some(slot) = brk.get_mut(count) {
                *slot = x;
            }
            count += 1;
        }
    }
    // Insertion sort of the filled slots (at most seven; τ_lo stays first, every root lying
    // after it). The slots after them hold τ_hi, which every root precedes, so the array is
    // sorted through the first unfilled slot: the pieces are the windows of `brk[..=count]`.
    for i in 1..count.min(MAX_BREAKS) {
        let mut j = i;
        while let (Some(&x), Some(&y)) = (brk.get(j.wrapping_sub(1)), brk.get(j))
            && y < x
        {
            brk.swap(j - 1, j);
            j -= 1;
        }
    }
    let filled = brk.get(..=count).unwrap_or(&brk);
    let mut first: Option<F> = None;
    let mut last: Option<F> = None;
    for w in filled.windows(2) {
        if let [a, b] = *w
            && b > a
            && inside(F::from_f64(0.5) * (a + b))
        {
            if first.is_none() {
                first = Some(a);
            }
            last = Some(b);
        }
    }
    match (first, last) {
        (Some(a), Some(b)) => Some((a, b)),
        _ => {
            // A ray that only touches the shell at a point (or is inside over a zero-length
            // interval) can still cross the surface there: test the single point.
            if tau_hi <= tau_lo && inside(tau_lo) {
                Some((tau_lo, tau_lo))
            } else {
                None
            }
        }
    }
}
