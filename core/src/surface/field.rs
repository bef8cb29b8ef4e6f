//! The line field of a patch (docs/METHOD.md §2, "Line fields"): the surface lies on the lines
//! `P(X) + λ·V(X)`, `V(X) = Σ Xi di`, one line per barycentric point `X`, and its height over
//! the triangle's plane is `z = λ·Vz(X)`.
//!
//! Two fields, chosen at construction ([`LineField`]):
//! - [`LineField::Face`], the paper's: `di = ni / (ni·Nf)`, so every `di.z = 1`, `Vz = 1`, `λ`
//!   is the height and the cross-section at height `z` is the triangle `Pi + z·di` (parallel
//!   sections): a point's barycentrics follow linearly.
//! - [`LineField::Vertex`], shared: `di = ni / max_j(nj·Nf)`, along the vertex normals with one
//!   scale per patch. The lines over an edge, `p(t) + λ·lerp(na, nb, t)`, then depend only on
//!   the edge's two vertices and their normals, so both neighbours of an edge sweep the same
//!   wall and their edge curves coincide (eq. (2) only uses the line). Spheres stay exact (every
//!   line passes through the centre) and on meshes whose faces see their vertex normals at equal
//!   angles (spheres, surfaces of revolution sampled on a regular grid such as the torus) the
//!   field equals the face field. Elsewhere the sections at constant `λ` are tilted planes: the
//!   point `x` lies in the section of `λ` where the cubic
//!   `g(λ) = det[A1(λ) − A0(λ), A2(λ) − A0(λ), x − A0(λ)]` (`Ai(λ) = Pi + λ·di`) vanishes,
//!   solved by [`SECTION_NEWTON_STEPS`] Newton steps (`Section::param`).

use crate::geometry::Shape;
use crate::num::real::Float;
use crate::num::vec::V3;

/// The direction field a patch is built with ([`Patch::with_field`](crate::Patch::with_field)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LineField {
    /// The paper's field `di = ni / (ni·Nf)` (unit height at every vertex): the reference
    /// construction of the seed paper and its figures. Neighbours' edge curves part where an
    /// edge's two faces see its vertex normals at different angles (irregular meshes).
    #[default]
    Face,
    /// The shared field `di ∝ ni` (one scale per patch): neighbours sweep the same lines over
    /// their common edge, so their edge curves and surfaces meet (to rounding). Equal to
    /// [`LineField::Face`] on faces whose vertex normals make equal angles with the face.
    Vertex,
}

/// Newton steps that locate a point's section `λ` in a [`LineField::Vertex`] patch whose
/// sections are tilted (`Section::param`): a fixed count, so the work per point is bounded.
///
/// Derivation. The start `λ0 = z / mean(di.z)` errs by at most the spread of `di.z` over their
/// mean, a relative `ρ`; Newton on the cubic (its derivative `≈ −2·area·Vz` stays away from 0
/// in a valid shell) squares the relative error each step, `ρ^(2^k)`. Vertex normals within 60°
/// of their face and of each other keep `ρ ≤ 0.5`, reaching `f64`'s ε (`2^-52`) in 6 steps; the
/// irregular test meshes (normals tilted 20°) need 3–4.
pub const SECTION_NEWTON_STEPS: usize = 6;

/// Whether the sections of `shape`'s line field are parallel to the triangle (every `di.z` is
/// exactly 1: the face field, or a vertex field on a face whose normals make equal angles).
#[inline(always)]
pub(crate) fn parallel<F: Float>(shape: &Shape<F>) -> bool {
    shape.d.iter().all(|d| d.z == F::ONE)
}

/// The point-to-section map of a patch: the cubic `g(λ)` of the module docs as coefficients
/// affine in the point, built once per patch test (about 40 flops).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Section<F> {
    /// `K0 = P1 × P2`, `K1 = P1 × c2 + c1 × P2`, `K2 = c1 × c2` (`ci = di − d0`, local frame,
    /// `P0 = 0`): `(A1 − A0) × (A2 − A0) = K0 + λ·K1 + λ²·K2`.
    pub(crate) k: [V3<F>; 3],
    /// `Kj · d0`.
    pub(crate) kd: [F; 3],
    /// `1 / mean(di.z)`: the start `λ0 = z / mean(di.z)`.
    pub(crate) inv_mean: F,
    /// Parallel sections ([`parallel`]): `λ = z`, no iteration.
    pub(crate) parallel: bool,
}

impl<F: Float> Section<F> {
    /// The map of `shape`.
    #[inline(always)]
    pub(crate) fn new(shape: &Shape<F>) -> Self {
        if parallel(shape) {
            // `param` returns `x.z` without the cubic: skip its coefficients.
            return Section {
                k: [V3::zero(); 3],
                kd: [F::ZERO; 3],
                inv_mean: F::ONE,
                parallel: true,
            };
        }
        let [_, p1, p2] = shape.p;
        let [d0, d1, d2] = shape.d;
        let (c1, c2) = (d1 - d0, d2 - d0);
        let k = [p1.cross(p2), p1.cross(c2) + c1.cross(p2), c1.cross(c2)];
        Section {
            k,
            kd: k.map(|v| v.dot(d0)),
            inv_mean: F::from_f64(3.0) / (d0.z + d1.z + d2.z),
            parallel: false,
        }
    }

    /// The coefficients `[c0, c1, c2, c3]` of `g(λ) = c0 + c1·λ + c2·λ² + c3·λ³` for the
    /// local point `x`.
    #[inline(always)]
    pub(crate) fn cubic(&self, x: V3<F>) -> [F; 4] {
        let [k0, k1, k2] = self.k;
        let [a0, a1, a2] = self.kd;
        [k0.dot(x), k1.dot(x) - a0, k2.dot(x) - a1, -a2]
    }

    /// The line parameter `λ` of the section through the local point `x`: `x.z` for parallel
    /// sections; otherwise the root of `g` reached by [`SECTION_NEWTON_STEPS`] Newton steps from
    /// `x.z / mean(di.z)` (a step that is not finite is skipped).
    ///
    /// # Accuracy
    /// Within a few ulps of the section's `λ` for points of a valid shell (the Newton
    /// iteration has converged; `tests/suite/linefield.rs` checks the recovered barycentrics against
    /// the points they were built from).
    #[inline(always)]
    pub(crate) fn param(&self, x: V3<F>) -> F {
        if self.parallel {
            return x.z;
        }
        let [c0, c1, c2, c3] = self.cubic(x);
        let (two, three) = (F::from_f64(2.0), F::from_f64(3.0));
        let mut l = x.z * self.inv_mean;
        for _ in 0..SECTION_NEWTON_STEPS {
            let g = c0 + l * (c1 + l * (c2 + l * c3));
            let dg = c1 + l * (two * c2 + three * l * c3);
            let next = l - g / dg;
            if next.is_fin() {
                l = next;
            }
        }
        l
    }
    /// The three barycentric numerators of the local point `x` of `shape` (this map's) in its
    /// cross-section `A(λ)` (`λ` from [`Section::param`]; `x.z` for parallel sections) and
    /// their sum (twice the cross-section's projected area).
    #[inline(always)]
    pub(crate) fn bary_numerators(&self, shape: &Shape<F>, x: V3<F>) -> ([F; 3], F) {
        let [p0, p1, p2] = shape.p;
        let [d0, d1, d2] = shape.d;
        let s = self.param(x);
        let a0 = p0 + d0 * s - x;
        let a1 = p1 + d1 * s - x;
        let a2 = p2 + d2 * s - x;
        let c = |u: V3<F>, v: V3<F>| u.x * v.y - u.y * v.x;
        let n = [c(a1, a2), c(a2, a0), c(a0, a1)];
        let [n0, n1, n2] = n;
        (n, n0 + n1 + n2)
    }
}

/// The line direction at barycentrics `x` with unit height: `D(X) = V(X) / Vz(X)`, or `V(X)`
/// itself for parallel sections (where `Vz = Σ Xi`, 1 up to rounding, as the face field has
/// always used it).
#[inline(always)]
pub(crate) fn unit_height_dir<S: crate::num::real::Real>(shape: &Shape<S::F>, x: [S; 3]) -> V3<S> {
    let [x0, x1, x2] = x;
    let [d0, d1, d2] = shape.d.map(V3::<S>::lift);
    let v = d0 * x0 + d1 * x1 + d2 * x2;
    if parallel(shape) {
        v
    } else {
        v * (S::one() / v.z)
    }
}
