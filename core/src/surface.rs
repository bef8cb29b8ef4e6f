//! The surface point and normal (docs/METHOD.md §5, the paper's eqs. (4)–(5), with the ½ that makes
//! the weights sum to one).
//!
//! For barycentrics `X`, `P = Σ Xi Pi` and `D = Σ Xi di`. For each vertex `i`, the edge opposite
//! it (edge `i+1`) gives `Ci = c(ti)`, `Ni = n*(ti)` with `ti = Xi+2 / (Xi+1 + Xi+2)`; the spheres
//! `Ŝ¹` (anchor `Pi`, axis `ni`, through `Ci`) and `Ŝ²` (anchor `Ci`, axis `Ni`, through `Pi`)
//! meet the line `P + s·D` at `s¹`, `s²`. The surface is the height field
//! `σS(X) = ½ Σ [Xi·s¹ + ((1 − Xi)/2)·s²]` and `pS = P + σS·D`.

use crate::dual::{Dual, split};
use crate::edge::edge_point_normal;
use crate::patch::Patch;
use crate::real::{Float, Real};
use crate::sphere::{curvature, nearest_root};
use crate::vec::V3;

/// Barycentrics projected onto the triangle: non-finite components become 0, negative ones are
/// clamped to 0, and the three are renormalised to sum to one (the centroid if all vanish).
#[inline(always)]
pub(crate) fn project_bary<F: Float>(w1: F, w2: F) -> [F; 3] {
    let clean = |x: F| {
        if x.is_fin() && x > F::ZERO {
            x
        } else {
            F::ZERO
        }
    };
    let w0r = F::ONE - w1 - w2;
    let (a, b, c) = (clean(w0r), clean(w1), clean(w2));
    // Divide by the largest first, so subnormal sums cannot overflow `1 / sum`.
    let m = a.max(b).max(c);
    if m > F::ZERO && m.is_fin() {
        let (a, b, c) = (a / m, b / m, c / m);
        let inv = F::ONE / (a + b + c);
        [a * inv, b * inv, c * inv]
    } else {
        let third = F::from_f64(1.0 / 3.0);
        [third, third, third]
    }
}

/// The local-frame line `P(X) + s·D(X)` of barycentrics `x`.
#[inline(always)]
fn base_line<S: Real>(patch: &Patch<S::F>, x: [S; 3]) -> (V3<S>, V3<S>) {
    let [x0, x1, x2] = x;
    let [p0, p1, p2] = patch.p.map(V3::<S>::lift);
    let [d0, d1, d2] = patch.d.map(V3::<S>::lift);
    (p0 * x0 + p1 * x1 + p2 * x2, d0 * x0 + d1 * x1 + d2 * x2)
}

/// The term of vertex `i` in eq. (5): `½ (Xi·s¹ + ((1 − Xi)/2)·s²)`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn vertex_term<S: Real>(
    patch: &Patch<S::F>,
    opposite_edge: usize,
    pi: V3<S::F>,
    ni: V3<S::F>,
    xi: S,
    xa: S,
    xb: S,
    base: V3<S>,
    dir: V3<S>,
) -> S {
    let den = xa + xb;
    let t = if den.re() > <S::F as Float>::EPSILON {
        xb / den
    } else {
        S::lit(0.5)
    };
    let (c, nc) = edge_point_normal(&patch.edge(opposite_edge), t);
    let pi = V3::<S>::lift(pi);
    let ni = V3::<S>::lift(ni);
    let k1 = curvature(pi, ni, c);
    let s1 = nearest_root(base, dir, pi, ni, k1);
    let k2 = curvature(c, nc, pi);
    let s2 = nearest_root(base, dir, c, nc, k2);
    S::lit(0.5) * xi * s1 + S::lit(0.25) * (S::one() - xi) * s2
}

/// Height `σS(X)` of the surface over the triangle's plane at barycentrics `x` (summing to one,
/// inside the triangle), with the line `P + s·D` it lies on.
#[inline(always)]
pub(crate) fn height_line<S: Real>(patch: &Patch<S::F>, x: [S; 3]) -> (S, V3<S>, V3<S>) {
    let (base, dir) = base_line(patch, x);
    let [x0, x1, x2] = x;
    let [p0, p1, p2] = patch.p;
    let [n0, n1, n2] = patch.n;
    let h = vertex_term(patch, 1, p0, n0, x0, x1, x2, base, dir)
        + vertex_term(patch, 2, p1, n1, x1, x2, x0, base, dir)
        + vertex_term(patch, 0, p2, n2, x2, x0, x1, base, dir);
    (h, base, dir)
}

/// Height `σS(X)` only.
#[inline(always)]
pub(crate) fn height<F: Float>(patch: &Patch<F>, x: [F; 3]) -> F {
    height_line(patch, x).0
}

/// Local-frame surface point `pS = P + σS·D`.
#[inline(always)]
pub(crate) fn point_local<S: Real>(patch: &Patch<S::F>, x: [S; 3]) -> V3<S> {
    let (h, base, dir) = height_line(patch, x);
    base + dir * h
}

/// Local-frame surface point and the exact partial derivatives `∂pS/∂X1`, `∂pS/∂X2`
/// (with `X0 = 1 − X1 − X2`).
#[inline(always)]
pub(crate) fn point_derivs_local<F: Float>(patch: &Patch<F>, x: [F; 3]) -> [V3<F>; 3] {
    let [x0, x1, x2] = x;
    let one = Dual::<F>::var(x1);
    let d1 = point_local(
        patch,
        [
            Dual {
                re: x0,
                du: -F::ONE,
            },
            one,
            Dual::constant(x2),
        ],
    );
    let d2 = point_local(
        patch,
        [
            Dual {
                re: x0,
                du: -F::ONE,
            },
            Dual::constant(x1),
            Dual::var(x2),
        ],
    );
    let (p, du1) = split(d1);
    let (_, du2) = split(d2);
    [p, du1, du2]
}

/// Local-frame unit normal at barycentrics `x` (projected), oriented like the vertex normals.
/// Falls back to the normalised interpolated vertex normal where the derivatives degenerate
/// (exactly at a vertex, it is that vertex's normal).
#[inline(always)]
pub(crate) fn normal_local<F: Float>(patch: &Patch<F>, x: [F; 3], du1: V3<F>, du2: V3<F>) -> V3<F> {
    let [x0, x1, x2] = x;
    let [n0, n1, n2] = patch.n;
    let phong = n0 * x0 + n1 * x1 + n2 * x2;
    let fallback = phong
        .try_normalize()
        .unwrap_or(V3::new(F::ZERO, F::ZERO, F::ONE));
    let cr = du1.cross(du2);
    match cr.try_normalize() {
        Some(n) => {
            if n.dot(phong) < F::ZERO {
                -n
            } else {
                n
            }
        }
        None => fallback,
    }
}

impl<F: Float> Patch<F> {
    /// Surface point at barycentrics `(w1, w2)` (`w0 = 1 − w1 − w2`), in world coordinates.
    ///
    /// Barycentrics outside the triangle are projected onto it (negative components clamped to
    /// zero, then renormalised); non-finite ones count as zero.
    ///
    /// # Accuracy
    /// `f64`: vertices and edge curves reproduced to [`F64_INTERPOLATION`] of the triangle's
    /// size, points of a sphere's patch on the sphere to [`F64_SPHERE_POINT`] of the radius,
    /// general points within [`F64_SURFACE_VS_REFERENCE`] of the coordinates' scale of an
    /// independent implementation. `f32`: [`F32_INTERPOLATION`] and [`F32_SPHERE_POINT`], and
    /// within [`F32_VS_F64_POINT`] of the scale of `f64`.
    ///
    /// [`F64_INTERPOLATION`]: crate::accuracy::F64_INTERPOLATION
    /// [`F64_SPHERE_POINT`]: crate::accuracy::F64_SPHERE_POINT
    /// [`F64_SURFACE_VS_REFERENCE`]: crate::accuracy::F64_SURFACE_VS_REFERENCE
    /// [`F32_INTERPOLATION`]: crate::accuracy::F32_INTERPOLATION
    /// [`F32_SPHERE_POINT`]: crate::accuracy::F32_SPHERE_POINT
    /// [`F32_VS_F64_POINT`]: crate::accuracy::F32_VS_F64_POINT
    /// # Panics
    /// Never; the result is finite for every accepted patch.
    pub fn point(&self, w1: F, w2: F) -> F::Vec3 {
        let x = project_bary(w1, w2);
        F::to_glam(self.local_to_world(point_local(self, x)))
    }

    /// Height of the surface over the triangle's plane at `(w1, w2)` (signed, along the face
    /// normal, in the input's length unit): the paper's construction as a height field.
    ///
    /// # Accuracy
    /// As [`Patch::point`].
    /// # Panics
    /// Never.
    pub fn height(&self, w1: F, w2: F) -> F {
        height(self, project_bary(w1, w2))
    }

    /// Surface point and unit surface normal `normalize(∂pS/∂X1 × ∂pS/∂X2)` at `(w1, w2)`,
    /// world coordinates, the normal oriented like the vertex normals.
    ///
    /// The derivatives are exact (dual numbers, no finite differences). At the vertices the
    /// normal is the vertex normal.
    ///
    /// # Accuracy
    /// Point as [`Patch::point`]. Normal (differences of unit vectors ≈ angles in radians):
    /// radial on a sphere's patch to [`F64_SPHERE_NORMAL`] (`f64`) and [`F32_SPHERE_NORMAL`]
    /// (`f32`); `f32` within [`F32_VS_F64_NORMAL`] of `f64`; unit length to
    /// [`UNIT_LENGTH_ULPS`] ulps.
    ///
    /// [`F64_SPHERE_NORMAL`]: crate::accuracy::F64_SPHERE_NORMAL
    /// [`F32_SPHERE_NORMAL`]: crate::accuracy::F32_SPHERE_NORMAL
    /// [`F32_VS_F64_NORMAL`]: crate::accuracy::F32_VS_F64_NORMAL
    /// [`UNIT_LENGTH_ULPS`]: crate::accuracy::UNIT_LENGTH_ULPS
    /// # Panics
    /// Never; both results are finite for every accepted patch.
    pub fn point_normal(&self, w1: F, w2: F) -> (F::Vec3, F::Vec3) {
        let x = project_bary(w1, w2);
        let [p, du1, du2] = point_derivs_local(self, x);
        let n = normal_local(self, x, du1, du2);
        (
            F::to_glam(self.local_to_world(p)),
            F::to_glam(self.local_dir_to_world(n)),
        )
    }

    /// Exact partial derivatives `(∂pS/∂w1, ∂pS/∂w2)` at `(w1, w2)` (with `w0 = 1 − w1 − w2`),
    /// world coordinates, in length units per unit of barycentric coordinate.
    ///
    /// # Accuracy
    /// Exact derivatives of the computed surface up to rounding (dual numbers; central
    /// differences agree to [`DERIVATIVES_VS_CENTRAL_DIFFERENCES`] of the size). Where they
    /// overflow (f32 coordinates near 1e9 within ~1e-30 of a vertex) the flat triangle's edge
    /// vectors are returned instead.
    ///
    /// [`DERIVATIVES_VS_CENTRAL_DIFFERENCES`]: crate::accuracy::DERIVATIVES_VS_CENTRAL_DIFFERENCES
    /// # Panics
    /// Never; always finite.
    pub fn derivatives(&self, w1: F, w2: F) -> (F::Vec3, F::Vec3) {
        let [_, du1, du2] = point_derivs_local(self, project_bary(w1, w2));
        let (du1, du2) = if du1.all_finite() && du2.all_finite() {
            (du1, du2)
        } else {
            // Overflow of the dual parts (extreme f32 magnitudes within ~1e-30 of a vertex):
            // the flat triangle's edge vectors, finite.
            let [p0, p1, p2] = self.p;
            (p1 - p0, p2 - p0)
        };
        (
            F::to_glam(self.local_dir_to_world(du1)),
            F::to_glam(self.local_dir_to_world(du2)),
        )
    }

    /// Point of edge `edge`'s conjugation line (eq. (2)) at `t ∈ [0, 1]` (`t` is clamped), with
    /// its unit normal (eq. (3)). Edge `i` runs from vertex `i` to vertex `i+1 mod 3`; indices
    /// above 2 are taken mod 3.
    ///
    /// # Accuracy
    /// Points within [`F64_EDGE_VS_REFERENCE`] of the size of an independent implementation
    /// (`f64`); normals from the exact tangent, within [`F64_EDGE_NORMAL_VS_REFERENCE`] of it,
    /// equal to the vertex normals at the ends to [`F64_INTERPOLATION`] (`f64`) and
    /// [`F32_INTERPOLATION`] (`f32`).
    ///
    /// [`F64_EDGE_VS_REFERENCE`]: crate::accuracy::F64_EDGE_VS_REFERENCE
    /// [`F64_EDGE_NORMAL_VS_REFERENCE`]: crate::accuracy::F64_EDGE_NORMAL_VS_REFERENCE
    /// [`F64_INTERPOLATION`]: crate::accuracy::F64_INTERPOLATION
    /// [`F32_INTERPOLATION`]: crate::accuracy::F32_INTERPOLATION
    /// # Panics
    /// Never.
    pub fn edge_point_normal(&self, edge: usize, t: F) -> (F::Vec3, F::Vec3) {
        let t = if t.is_fin() {
            t.max(F::ZERO).min(F::ONE)
        } else {
            F::ZERO
        };
        let (c, n) = edge_point_normal::<F>(&self.edge(edge % 3), t);
        (
            F::to_glam(self.local_to_world(c)),
            F::to_glam(self.local_dir_to_world(n)),
        )
    }
}
