//! Clipping a ray to a patch's shell (docs/METHOD.md §8 step 1): the slab `σmin ≤ σ ≤ σmax` and the
//! three side walls `Xi = 0`, each wall a quadratic in the ray parameter (parallel sections) or
//! a ruled surface whose lines the ray meets where a quadratic in the edge parameter vanishes
//! (tilted sections, [`crate::surface::field`]).

use crate::geometry::Shape;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::field::Section;
use crate::surface::shell::{cross2_poly, moved_corners};

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

/// Real roots of `c0 + c1·x + c2·x²` (numerically careful; up to two, NaN-free; `None` slots).
#[inline(always)]
pub(crate) fn quadratic_roots<F: Float>(c: [F; 3]) -> [Option<F>; 2] {
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

/// The three barycentric numerators of the local point `x` in its cross-section `A(λ)`
/// (`λ` from `sec`, [`Section::param`]; `x.z` for parallel sections) and their sum (twice the
/// cross-section's projected area).
#[inline(always)]
pub(crate) fn bary_numerators<F: Float>(
    shape: &Shape<F>,
    sec: &Section<F>,
    x: V3<F>,
) -> ([F; 3], F) {
    let [p0, p1, p2] = shape.p;
    let [d0, d1, d2] = shape.d;
    let s = sec.param(x);
    let a0 = p0 + d0 * s - x;
    let a1 = p1 + d1 * s - x;
    let a2 = p2 + d2 * s - x;
    let c = |u: V3<F>, v: V3<F>| u.x * v.y - u.y * v.x;
    let n = [c(a1, a2), c(a2, a0), c(a0, a1)];
    let [n0, n1, n2] = n;
    (n, n0 + n1 + n2)
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
/// `k` moved outward by the barycentric `margin[k]` (`crate::kernel::wall_margins`), are
/// satisfied.
/// Fixed work: at most 8 breakpoints, at most 21 compare-and-swaps, 7 midpoint tests.
#[inline(always)]
pub(crate) fn shell_interval<F: Float>(
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
        let (n, area) = bary_numerators(shape, &sec, ray.at(tau));
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
