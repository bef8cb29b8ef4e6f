//! A construction-time certificate that a patch's surface does not jump: every sphere root of
//! the construction exists and stays on one branch over the whole triangle
//! (docs/METHOD.md §7, "Why folds are not detected").
//!
//! The surface height (docs/METHOD.md §5) is a weighted sum of the parameters where lines
//! `P(X) + s·D(X)` meet spheres, each the root nearest 0 of `a s² + 2 b s + c = 0`
//! (`s = c / (−b − sign(b)·√(b² − a c))`, [`crate::surface::sphere::nearest_root`]). That root is a
//! smooth function wherever the discriminant `b² − a c` is positive and `b` keeps its sign.
//! Where the discriminant reaches 0 the line misses the sphere (the root *goes missing*); where
//! `b` changes sign the nearest root moves to the other branch. The surface jumps or spikes
//! there (the domain study's `jump`), often over a spot narrower than any sampling grid.
//!
//! [`Patch::roots_certified`](crate::Patch::roots_certified) proves both absent for the twelve
//! spheres of a patch: the two of each edge curve (at edge parameter `t`) and the two of each
//! vertex `i`'s term, which depend on the opposite edge's point `C = c(t)` and normal
//! `N = n*(t)` and meet the line through `P = Pi + λ·(p(t) − Pi)` with direction
//! `∝ (1 − λ)·di + λ·g(t)` (`λ = 1 − Xi`: coordinates in which the term is regular up to the
//! vertex itself). Over a box of `(λ, t)` it encloses `b` and the discriminant by the mean-value
//! form `f(mid) + ∂f/∂λ(box)·(λ − λmid) + ∂f/∂t(box)·(t − tmid)`, in outward-rounded interval
//! arithmetic with dual numbers for the derivatives, and requires every `b` to exclude 0 and
//! every discriminant to be positive. A box that fails is split in four, down to
//! [`CERTIFY_MAX_DEPTH`] levels below a [`CERTIFY_GRID`]² start grid, within
//! [`CERTIFY_MAX_BOXES`] boxes per vertex: the work is bounded, and a patch that runs out of
//! depth or boxes is refused (a refusal, never a false certificate).
//!
//! The certificate is about the surface the patch's stored data define, in `f64` whatever the
//! patch's precision (`f32` data convert exactly); it does not cover the rounding of an `f32`
//! evaluation.
//!
//! Cost and sharpness (domain study, `f64`, docs/METHOD.md §7; its timings in
//! docs/MEASUREMENTS.md, "Notes moved from the code"): orders of magnitude above a construction;
//! it refuses every folded or jumping patch of the study, and also a fifth of the sound patches
//! at 45° (most at 55°), where interval enclosures stay too wide. It is therefore not part of
//! [`Patch::new_or_tilted`](crate::Patch::new_or_tilted): it is for offline validation of meshes
//! that must not spike.

use heapless::Vec as HVec;

use crate::geometry::Shape;
use crate::num::dual::{Dual, split};
use crate::num::interval::Iv;
use crate::num::real::{Float, Real};
use crate::num::vec::V3;

/// Start grid of the certificate: `CERTIFY_GRID × CERTIFY_GRID` boxes of `(λ, t)` per vertex.
/// Coarser boxes rarely pass (the enclosures of the edge normal's derivative are too wide).
pub const CERTIFY_GRID: usize = 8;

/// Subdivision levels below the start grid: boxes as small as `1 / (CERTIFY_GRID · 2^depth)`
/// = 1/128 of the unit square's side.
pub const CERTIFY_MAX_DEPTH: usize = 4;

/// Boxes evaluated per vertex at most, the start grid included: the work bound (three
/// vertices, so at most `3 · CERTIFY_MAX_BOXES` boxes per patch; a box's cost is in
/// docs/MEASUREMENTS.md, "Notes moved from the code").
pub const CERTIFY_MAX_BOXES: usize = 4096;

/// The scalars the certificate is evaluated in: an interval, or dual numbers over one (for the
/// derivatives of the mean-value form). `sqrt_pos` is the square root of a quantity known to be
/// positive: its derivative divides by the root's enclosure, so it is the whole line (never a
/// wrong, narrow enclosure) where that enclosure reaches 0.
trait Cert: Real<F = f64> {
    /// Square root of a quantity known to be positive.
    fn sqrt_pos(self) -> Self;
}
impl Cert for Iv {
    #[inline]
    fn sqrt_pos(self) -> Iv {
        self.sqrt0()
    }
}
impl<T: Cert> Cert for Dual<T> {
    #[inline]
    fn sqrt_pos(self) -> Self {
        let r = self.re.sqrt_pos();
        Dual {
            re: r,
            du: self.du / (r + r),
        }
    }
}

#[inline]
fn lift<S: Cert>(v: V3<f64>) -> V3<S> {
    V3::<S>::lift(v)
}

/// `b` and the discriminant `b² − a c` of the line `A + w + s·g` against the sphere (anchor `A`,
/// unit axis `m`, curvature `kappa`), and the root nearest 0 on the branch `b < 0` (`neg`) or
/// `b > 0`.
#[inline]
fn sphere<S: Cert>(w: V3<S>, g: V3<S>, m: V3<S>, kappa: S, neg: bool) -> (S, S, S) {
    let a = kappa * g.length2();
    let b = kappa * w.dot(g) - g.dot(m);
    let c = kappa * w.length2() - S::lit(2.0) * w.dot(m);
    let disc = b * b - a * c;
    let sq = disc.sqrt_pos();
    let q = if neg { sq - b } else { -b - sq };
    (b, disc, c / q)
}

/// `[b, disc]` of edge `j`'s two spheres at `t` (`S¹j` then `S²j`), and the two roots on the
/// branches `neg`.
#[inline]
fn edge_terms<S: Cert>(shape: &Shape<f64>, j: usize, t: S, neg: [bool; 2]) -> ([S; 4], [S; 2]) {
    let e = shape.edge(j);
    let (a, b) = (lift::<S>(e.a), lift::<S>(e.b));
    let p = a.lerp(b, t);
    let g = lift::<S>(e.da).lerp(lift(e.db), t);
    let [n1, n2] = neg;
    let (b1, d1, s1) = sphere(p - a, g, lift(e.na), S::cst(e.k1), n1);
    let (b2, d2, s2) = sphere(p - b, g, lift(e.nb), S::cst(e.k2), n2);
    ([b1, d1, b2, d2], [s1, s2])
}

/// `[b, disc]` of vertex `i`'s spheres `Ŝ¹`, `Ŝ²` at `(λ, t)` (module docs), the opposite
/// edge's roots on the branches `edge_neg`, and the two roots' branches `neg`.
#[inline]
fn term_terms<S: Cert>(shape: &Shape<f64>, i: usize, lam: S, t: S, edge_neg: [bool; 2]) -> [S; 4] {
    let j = (i + 1) % 3;
    let ([p0, p1, p2], [n0, n1, n2], [d0, d1, d2]) = (shape.p, shape.n, shape.d);
    let (pi, ni, di) = match i {
        0 => (p0, n0, d0),
        1 => (p1, n1, d1),
        _ => (p2, n2, d2),
    };
    // The opposite edge's point and tangent at `t`.
    let e = shape.edge(j);
    let td = Dual::var(t);
    let (_, [s1, s2]) = edge_terms::<Dual<S>>(shape, j, td, edge_neg);
    let (a, b) = (lift::<Dual<S>>(e.a), lift::<Dual<S>>(e.b));
    let p = a.lerp(b, td);
    let g = lift::<Dual<S>>(e.da).lerp(lift(e.db), td);
    let s = (Dual::<S>::one() - td) * s1 + td * s2;
    let (c, tan) = split(p + g * s);
    let (pv, gv) = (split(p).0, split(g).0);
    let nraw = gv - tan * (tan.dot(gv) / tan.length2());
    let nc = nraw * (S::one() / nraw.length2().sqrt_pos());
    // The line of the point, its direction up to a positive factor.
    let (piv, niv) = (lift::<S>(pi), lift::<S>(ni));
    let dir = lift::<S>(di) * (S::one() - lam) + gv * lam;
    let w1 = (pv - piv) * lam;
    let wc = c - piv;
    let l2 = wc.length2();
    let two = S::lit(2.0);
    let k1 = two * wc.dot(niv) / l2;
    let k2 = -(two * wc.dot(nc)) / l2;
    let (b1, d1, _) = sphere(w1, dir, niv, k1, true);
    let (b2, d2, _) = sphere(w1 - wc, dir, nc, k2, true);
    [b1, d1, b2, d2]
}

/// Mean-value enclosures `f(m) + f_λ(B)·(B_λ − m_λ) + f_t(B)·(B_t − m_t)` of four quantities.
#[inline]
fn mean_value(center: [Iv; 4], dl: [Dual<Iv>; 4], rl: f64, dt: [Dual<Iv>; 4], rt: f64) -> [Iv; 4] {
    let (bl, bt) = (Iv::new(-rl, rl), Iv::new(-rt, rt));
    let mut out = center;
    for ((o, l), t) in out.iter_mut().zip(dl).zip(dt) {
        *o = *o + l.du * bl + t.du * bt;
    }
    out
}

/// `Some(branches)` when both spheres' `b` exclude 0 and their discriminants are positive.
#[inline]
fn certified([b1, d1, b2, d2]: [Iv; 4]) -> Option<[bool; 2]> {
    (b1.excludes_zero() && b2.excludes_zero() && d1.positive() && d2.positive())
        .then(|| [b1.hi() < 0.0, b2.hi() < 0.0])
}

/// Whether every root of vertex `i`'s term and of its opposite edge is certified over the box
/// `λ ∈ [l0, l1]`, `t ∈ [t0, t1]`.
fn term_box(shape: &Shape<f64>, i: usize, (l0, l1): (f64, f64), (t0, t1): (f64, f64)) -> bool {
    let j = (i + 1) % 3;
    let (lm, tm) = (0.5 * (l0 + l1), 0.5 * (t0 + t1));
    let (rl, rt) = (0.5 * (l1 - l0), 0.5 * (t1 - t0));
    let (lb, tb) = (Iv::new(l0, l1), Iv::new(t0, t1));
    // The edge's roots over [t0, t1]; their branches are those at the middle.
    let any = [true, true];
    let (ec, _) = edge_terms::<Iv>(shape, j, Iv::cst(tm), any);
    let (et, _) = edge_terms::<Dual<Iv>>(shape, j, Dual::var(tb), any);
    let zero = Dual::constant(Iv::cst(0.0));
    let Some(edge_neg) = certified(mean_value(ec, [zero; 4], 0.0, et, rt)) else {
        return false;
    };
    // The interior spheres over the box.
    let c = term_terms::<Iv>(shape, i, Iv::cst(lm), Iv::cst(tm), edge_neg);
    let dl = term_terms::<Dual<Iv>>(shape, i, Dual::var(lb), Dual::constant(tb), edge_neg);
    // The λ part alone is inside the whole enclosure: if it fails, so does the whole.
    if certified(mean_value(c, dl, rl, [zero; 4], 0.0)).is_none() {
        return false;
    }
    let dt = term_terms::<Dual<Iv>>(shape, i, Dual::constant(lb), Dual::var(tb), edge_neg);
    certified(mean_value(c, dl, rl, dt, rt)).is_some()
}

/// Whether vertex `i`'s term is certified over `[0, 1]²`, adaptively.
fn term_certified(shape: &Shape<f64>, i: usize) -> bool {
    let mut stack: HVec<(f64, f64, f64, usize), { 4 * CERTIFY_MAX_DEPTH + 4 }> = HVec::new();
    let mut boxes = 0usize;
    let h0 = 1.0 / CERTIFY_GRID as f64;
    for a in 0..CERTIFY_GRID {
        for b in 0..CERTIFY_GRID {
            if stack.push((a as f64 * h0, b as f64 * h0, h0, 0)).is_err() {
                return false;
            }
            while let Some((l0, t0, h, depth)) = stack.pop() {
                boxes += 1;
                if boxes > CERTIFY_MAX_BOXES {
                    return false;
                }
                if term_box(shape, i, (l0, (l0 + h).min(1.0)), (t0, (t0 + h).min(1.0))) {
                    continue;
                }
                if depth >= CERTIFY_MAX_DEPTH {
                    return false;
                }
                let hh = 0.5 * h;
                for (dl, dt) in [(0.0, 0.0), (hh, 0.0), (0.0, hh), (hh, hh)] {
                    if stack.push((l0 + dl, t0 + dt, hh, depth + 1)).is_err() {
                        return false;
                    }
                }
            }
        }
    }
    true
}

/// Whether every sphere root of `shape`'s construction is certified to exist and stay on one
/// branch over the whole triangle (the module docs).
pub(crate) fn roots_certified<F: Float>(shape: &Shape<F>) -> bool {
    let wide = shape.widen();
    (0..3).all(|i| term_certified(&wide, i))
}

#[cfg(test)]
mod tests {
    use crate::{DPatch, Patch};
    use glam::DVec3;

    #[test]
    fn spheres_and_flat_triangles_are_certified() {
        // A triangle of the unit sphere with radial normals about 20° off its face (every
        // sphere of the construction is the sphere itself), in both precisions. (The octant,
        // at 54.7°, is refused: the enclosures stay too wide at 1/128.)
        let p = [
            DVec3::new(1.0, 0.0, 3.0).normalize(),
            DVec3::new(0.0, 1.0, 3.0).normalize(),
            DVec3::new(-1.0, -1.0, 3.0).normalize(),
        ];
        assert!(DPatch::new(p, p).is_ok_and(|x| x.roots_certified()));
        let p32 = p.map(|v| v.as_vec3());
        assert!(Patch::<f32>::new(p32, p32).is_ok_and(|x| x.roots_certified()));
        // A flat triangle (all spheres are planes), far from the origin.
        let q = [
            DVec3::new(1e3, 2e3, 0.0),
            DVec3::new(1e3 + 1.0, 2e3, 0.0),
            DVec3::new(1e3 + 0.3, 2e3 + 0.8, 0.0),
        ];
        assert!(DPatch::new(q, [DVec3::Z; 3]).is_ok_and(|x| x.roots_certified()));
        // A gentle patch: normals 10° off the face.
        let t = 10f64.to_radians();
        let n = [
            DVec3::new(-t.sin(), 0.0, t.cos()),
            DVec3::new(t.sin(), 0.0, t.cos()),
            DVec3::new(0.0, t.sin(), t.cos()),
        ];
        let r = [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.8, 0.0)];
        assert!(DPatch::new(r, n).is_ok_and(|x| x.roots_certified()));
    }

    #[test]
    fn a_jump_is_refused() {
        // A well-shaped triangle with normals up to 75° off its face, from the domain study
        // (`tests/suite/domain.rs`): accepted by `new`, but its surface jumps (a step of the
        // study's dense grid is over ten times the median).
        let p = [
            DVec3::new(
                -0.2550730694943111,
                0.37230136317356516,
                -0.2955933590641072,
            ),
            DVec3::new(-0.06404516753895564, 0.08179243824022224, 0.498349093302454),
            DVec3::new(
                0.2460969284818547,
                -0.3484076987043927,
                -0.24353648865989014,
            ),
        ];
        let n = [
            DVec3::new(
                0.3875983963560769,
                -0.10731688677529203,
                -0.8639334441154906,
            ),
            DVec3::new(0.16025951293941076, 0.9302521141732544, 0.37679773746780537),
            DVec3::new(0.6641242726030434, 0.7647099537618912, 0.10106762058362803),
        ];
        assert!(DPatch::new(p, n).is_ok_and(|x| !x.roots_certified()));
    }
}
