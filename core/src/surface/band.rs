//! The band: a bound of the surface much tighter than the shell's slab, for culling a ray
//! before its samples (docs/METHOD.md §8, "Culling").
//!
//! In the local frame every surface point `(x, y, z)` satisfies `lo ≤ z − q(β) ≤ hi`, where `β`
//! are the barycentrics of `(x, y)` in the triangle and
//! `q(β) = c0·β1β2 + c1·β2β0 + c2·β0β1` (zero at the vertices, like the surface) is the
//! least-squares fit of the shell's [`SAMPLES`] surface points. Along a ray `β` is affine in the
//! ray parameter, so `h(τ) = z(τ) − q(β(τ))` is a quadratic: if its range over the clipped
//! interval lies outside `[lo, hi]`, no surface point lies on that part of the ray and the
//! kernel returns without sampling `f` (`kernel/clip.rs`). The shell's slab bounds `z` alone; the band
//! follows the surface's curvature, so on the test meshes it is 2–5 times thinner and, more
//! to the point, it is thin near the edges, where most rays that enter a neighbour's shell pass
//! above its surface.
//!
//! # How the band is bounded
//! Like the shell's height range ([`crate::surface::shell`]), from the same samples: the
//! residuals' range (and 0, the vertices') widened by [`MARGIN_REL`] of its width plus
//! [`MARGIN_ABS`] of the triangle's size, validated rather than proven (`tests/suite/shell.rs`
//! checks dense samples of random patches against it with a clearance, as for the shell). Then
//! it is widened for what the samples cannot see:
//! - the kernel's rounding: a crossing found where `|f|` is within twice the kernel's rounding
//!   allowance of zero (a sign change of the rounded `f`, or a sample snapped to zero at the
//!   interval's end) may lie that far off the surface along the line field, which moves
//!   `z − q` by `|f|·(1 + |∇q|·|D_xy|)`: four times the kernel's end snap (its
//!   `ROUNDING_ULPS · ε · L`) scaled so, which also covers the rounding of `h` itself;
//! - the walls moved out by crack closure: beyond its edges the surface continues along a plane
//!   ([`crate::surface::lanes`]), from which `z − q` drifts by the slopes' mismatch times the
//!   distance plus `q`'s curvature times its square: [`Band::per_reach`] per unit of
//!   barycentric reach, bounded for reaches up to crack closure's cap
//!   ([`MAX_CRACK_REACH`](crate::kernel::MAX_CRACK_REACH)), applied by the kernel with the
//!   patch's largest reach.
//!
//! Beyond 45° ([`BAND_MIN_NORMAL_COS`]) the surface can be too wild for a quadratic and a sampled
//! residual (measured: patches with normals 50° off their face leave a band that has every
//! patch within 45° clear by a sixth of its width); such patches get an unbounded band and are
//! never culled.

use crate::geometry::{Band, Shape};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::scalar::point_from_height;
use crate::surface::shell::{
    EDGE_SAMPLES, MARGIN_ABS, MARGIN_REL, SAMPLES, longest_edge, sample_bary,
};

/// The least cosine of the angle between a vertex normal and the face normal of a patch that
/// gets a bounded band (45°); steeper patches are never culled (see the module docs).
pub const BAND_MIN_NORMAL_COS: f64 = core::f64::consts::FRAC_1_SQRT_2;

/// Barycentrics `β` of the local point `(x, y)` in the triangle (`P0 = 0`, `P1 = (p1x, 0)`,
/// `P2 = (p2x, p2y)`), with the affine map's linear part applied to a direction as `lin`.
#[inline(always)]
pub(crate) fn bary_xy<F: Float>(shape: &Shape<F>, x: F, y: F, lin: bool) -> [F; 3] {
    let [_, p1, p2] = shape.p;
    let b2 = y / p2.y;
    let b1 = (x - p2.x * b2) / p1.x;
    let b0 = if lin { -b1 - b2 } else { F::ONE - b1 - b2 };
    [b0, b1, b2]
}

/// `q(β)` of the coefficients `c`.
#[inline(always)]
pub(crate) fn q<F: Float>(c: [F; 3], [b0, b1, b2]: [F; 3]) -> F {
    let [c0, c1, c2] = c;
    c0 * (b1 * b2) + c1 * (b2 * b0) + c2 * (b0 * b1)
}

/// The band of `shape` from the shell's [`SAMPLES`] heights `heights` (`heights[i]` at
/// [`sample_bary`]`(i)`), its height range `sigma`, the kernel's end snap `snap` (the rounding
/// of `f` it treats as zero) and the largest barycentric reach `reach_cap` that crack closure
/// may set; [`Band::UNBOUNDED`] for a patch steeper than 45° ([`BAND_MIN_NORMAL_COS`]) or where the
/// fit is not finite.
pub(crate) fn fit<F: Float>(
    shape: &Shape<F>,
    heights: &[F; SAMPLES],
    sigma: [F; 2],
    snap: F,
    reach_cap: F,
) -> Band<F> {
    let cos_min = F::from_f64(BAND_MIN_NORMAL_COS);
    if shape.n.iter().any(|n| !(n.z >= cos_min)) {
        return Band::UNBOUNDED;
    }
    let points = core::array::from_fn::<_, SAMPLES, _>(|i| {
        let x = sample_bary::<F>(i);
        let h = heights.get(i).copied().unwrap_or(F::ZERO);
        point_from_height(shape, x, h)
    });
    let basis = |p: V3<F>| {
        let [b0, b1, b2] = bary_xy(shape, p.x, p.y, false);
        [b1 * b2, b2 * b0, b0 * b1]
    };
    // Normal equations of the least-squares fit, solved by Cramer's rule.
    let mut m = [[F::ZERO; 3]; 3];
    let mut r = [F::ZERO; 3];
    for p in points {
        let phi = basis(p);
        for (row, (ri, &pi)) in m.iter_mut().zip(r.iter_mut().zip(phi.iter())) {
            for (mij, &pj) in row.iter_mut().zip(phi.iter()) {
                *mij += pi * pj;
            }
            *ri += pi * p.z;
        }
    }
    let det3 = |[[a, b, c], [d, e, f], [g, h, i]]: [[F; 3]; 3]| {
        a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    };
    let det = det3(m);
    let column = |k: usize| {
        let mut mk = m;
        for (row, &ri) in mk.iter_mut().zip(r.iter()) {
            if let Some(v) = row.get_mut(k) {
                *v = ri;
            }
        }
        det3(mk) / det
    };
    let c = [column(0), column(1), column(2)];
    // The residuals' range, with the vertices' 0, widened like the shell's.
    let (mut lo, mut hi) = (F::ZERO, F::ZERO);
    for p in points {
        let res = p.z - q(c, bary_xy(shape, p.x, p.y, false));
        lo = lo.min(res);
        hi = hi.max(res);
    }
    let size = longest_edge(shape);
    let margin = F::from_f64(MARGIN_REL) * (hi - lo) + F::from_f64(MARGIN_ABS) * size;
    // Slopes: |∇q| over the triangle widened by the largest reach (|β| ≤ 1.5), from
    // |∂q/∂βi| ≤ Σ|c|·1.5 and Σ|∇βi| = perimeter / (2·area); |D_xy| ≤ the largest |di_xy|.
    let [p0, p1, p2] = shape.p;
    let [c0, c1, c2] = c;
    let csum = c0.abs() + c1.abs() + c2.abs();
    let perimeter = (p1 - p0).length() + (p2 - p1).length() + (p0 - p2).length();
    let two_area = p1.x * p2.y;
    let grad_q = F::from_f64(1.5) * csum * perimeter / two_area;
    let dxy = shape
        .d
        .iter()
        .fold(F::ZERO, |m, d| m.max((d.x * d.x + d.y * d.y).sqrt()));
    let rounding = F::from_f64(4.0) * snap * (F::ONE + grad_q * dxy);
    // Continuation beyond an edge by reach r (barycentric): the section's edges are at most
    // `ell = longest + 2·max|σ|·|D_xy|` long, so the point moves at most `2·r·ell` in xy from
    // its edge point; the plane it moves in is normal to the interpolated vertex normal `n`,
    // so `z − q` changes by at most `|n_xy/n_z + ∇q|` times that (sampled at the edge points,
    // doubled) plus `½·‖∇²q‖·(2·r·ell)²` with `‖∇²q‖ ≤ Σ|c|·(Σ|∇βi|)²`, the square bounded
    // with `r ≤ reach_cap`.
    let smax = sigma.iter().fold(F::ZERO, |m, s| m.max(s.abs()));
    let ell = size + F::from_f64(2.0) * smax * dxy;
    let mut mismatch = F::ZERO;
    for (i, p) in points.iter().enumerate().take(3 * EDGE_SAMPLES) {
        let x = sample_bary::<F>(i);
        let mut n = V3::zero();
        for (ni, xi) in shape.n.iter().zip(x) {
            n = n + *ni * xi;
        }
        let [b0, b1, b2] = bary_xy(shape, p.x, p.y, false);
        // ∇q = Σ ∂q/∂βi ∇βi with ∇β2 = (−p2x/(p1x·p2y), 1/p2y)… written through the
        // directional derivatives along x and y.
        let dq = [c1 * b2 + c2 * b1, c0 * b2 + c2 * b0, c0 * b1 + c1 * b0];
        let gx = dq_dir(dq, bary_xy(shape, F::ONE, F::ZERO, true));
        let gy = dq_dir(dq, bary_xy(shape, F::ZERO, F::ONE, true));
        let (sx, sy) = (n.x / n.z + gx, n.y / n.z + gy);
        mismatch = mismatch.max((sx * sx + sy * sy).sqrt());
    }
    let inv_alt = perimeter / two_area;
    let hess = csum * inv_alt * inv_alt;
    let two_ell = F::from_f64(2.0) * ell;
    let per_reach =
        two_ell * (F::from_f64(2.0) * mismatch + F::from_f64(0.5) * hess * two_ell * reach_cap);
    let band = Band {
        c,
        lo: lo - margin - rounding,
        hi: hi + margin + rounding,
        per_reach,
    };
    if band.is_finite() && det.is_fin() && det != F::ZERO {
        band
    } else {
        Band::UNBOUNDED
    }
}

/// `Σ ∂q/∂βi · dβi`: the derivative of `q` along the direction whose barycentric change is `db`.
#[inline(always)]
fn dq_dir<F: Float>([d0, d1, d2]: [F; 3], [e0, e1, e2]: [F; 3]) -> F {
    d0 * e0 + d1 * e1 + d2 * e2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{DEFAULT_SAMPLES, MAX_CRACK_REACH};
    use crate::patch::Patch;
    use crate::ray::Ray;
    use crate::surface::field::LineField;
    use crate::surface::scalar::{height, point_local};
    use crate::surface::shell::sample_scalar;
    use crate::testing::{Rng, random_patches_on};
    use glam::DVec3;

    #[test]
    fn sample_barycentrics_are_where_the_shell_samples() {
        let mut tested = 0;
        for (patch, size) in random_patches_on(3, 200, LineField::Face) {
            for i in 0..SAMPLES {
                let a = height(&patch.shape, sample_bary::<f64>(i));
                let b = sample_scalar(&patch.shape, i);
                assert!((a - b).abs() <= 1e-12 * size, "sample {i}: {a} vs {b}");
            }
            tested += 1;
        }
        assert!(tested > 150, "{tested}");
    }

    /// Rays through random points near the surface (inside the triangle, beyond its edges where
    /// the walls reach, at offsets from 1e-4 to 0.3 of its size, from every direction): the
    /// kernel with the band returns bit for bit what it returns without it. Returns how many
    /// rays entered the shell without crossing the surface, and how many of those the band
    /// culled.
    fn culling_changes_nothing<F: Float>(
        convert: impl Fn(&Patch<f64>) -> Option<Patch<F>>,
        ray: impl Fn(DVec3, DVec3) -> Ray<F>,
    ) -> (usize, usize) {
        let mut rng = Rng(11);
        let (mut entered, mut culled, mut bounded) = (0usize, 0usize, 0usize);
        let fields = [LineField::Face, LineField::Vertex];
        for (k, (patch64, size)) in fields
            .into_iter()
            .flat_map(|f| random_patches_on(5, 300, f))
            .enumerate()
        {
            let Some(mut patch) = convert(&patch64) else {
                continue;
            };
            // A third of the patches keep the rounding-level reach, a third reach up to a
            // hundredth of an altitude, a third up to the cap.
            let cap = match k % 3 {
                0 => 0.0,
                1 => 0.01,
                _ => MAX_CRACK_REACH,
            };
            let reach = [0; 3].map(|_| F::from_f64(cap * rng.unit()));
            patch.set_reach(reach);
            patch.fit_box();
            bounded += usize::from(patch.band.hi < F::MAX);
            let unbounded = Patch {
                band: Band::UNBOUNDED,
                ..patch
            };
            let frame = patch64.frame;
            for _ in 0..200 {
                // Raw barycentrics up to the cap beyond each edge.
                let w1 = rng.unit() * 1.5 - 0.25;
                let w2 = rng.unit() * (1.5 - w1.max(0.0)) - 0.25;
                let x = [1.0 - w1 - w2, w1, w2];
                let clamped = x.map(|v| v.clamp(0.0, 1.0));
                let sum: f64 = clamped.iter().sum();
                let inside = clamped.map(|v| v / sum);
                // The surface point at the projected barycentrics, moved in the triangle's
                // plane to the raw ones.
                let flat = |x: [f64; 3]| {
                    let [p0, p1, p2] = patch64.shape.p;
                    let [a, b, c] = x;
                    p0 * a + p1 * b + p2 * c
                };
                let base = point_local(&patch64.shape, inside) + flat(x) - flat(inside);
                let spread = 10f64.powf(rng.unit() * 3.5 - 4.0) * size;
                let target = f64::to_glam(frame.local_to_world(base)) + rng.vec() * spread;
                let dir = rng.vec().normalize_or_zero();
                if dir == DVec3::ZERO {
                    continue;
                }
                let r = ray(target - dir * 3.0 * size, dir);
                let (h, st) = patch.closest_hit_stats::<DEFAULT_SAMPLES>(&r, F::ZERO, F::MAX, 8);
                let (hu, su) =
                    unbounded.closest_hit_stats::<DEFAULT_SAMPLES>(&r, F::ZERO, F::MAX, 8);
                assert_eq!(h, hu, "patch {k}: the band changed a result");
                if su.height_evals > 0 && hu.is_none() {
                    entered += 1;
                    culled += usize::from(st.height_evals == 0);
                }
            }
        }
        assert!(bounded > 200, "{bounded} patches with a bounded band");
        (entered, culled)
    }

    #[test]
    fn culling_changes_no_result_f64() {
        let (entered, culled) = culling_changes_nothing(|p| Some(*p), Ray::new);
        assert!(culled * 20 > entered, "{culled} of {entered} culled");
    }

    #[test]
    fn culling_changes_no_result_f32() {
        let (entered, culled) = culling_changes_nothing(
            |p| {
                let v = p.vertices().map(|v| v.as_vec3());
                let n = p.normals().map(|v| v.as_vec3());
                let field = if crate::surface::field::parallel(&p.shape) {
                    LineField::Face
                } else {
                    LineField::Vertex
                };
                Patch::<f32>::with_field(v, n, field).ok()
            },
            |o, d| Ray::new(o.as_vec3(), d.as_vec3()),
        );
        assert!(culled * 20 > entered, "{culled} of {entered} culled");
    }
}
