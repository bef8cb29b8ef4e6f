//! The quadratic triangular patch both peers are: a quadratic Bézier triangle given by its
//! three vertices and three edge control points, stored in monomial form for evaluation and for
//! the ray solver (the module `ray_quadratic`, which adds [`QuadPatch::closest_hit`]).
//!
//! With barycentrics `(w0, w1, w2)`, `w0 = 1 − w1 − w2`, the patch is
//!
//! ```text
//! x(w) = Σ_i w_i² P_i + 2 Σ_{i<j} w_i w_j B_ij
//! ```
//!
//! (`B_01`, `B_12`, `B_20` the edge controls). On edge `i → j` it is the quadratic Bézier curve
//! `P_i, B_ij, P_j`, so two patches that compute the same `B_ij` for a shared edge meet there.
//! In `u = w1`, `v = w2`:
//! `x = a + b_u·u + b_v·v + b_uu·u² + b_uv·uv + b_vv·v²`.

use smoothtri::Aabb;

use crate::real::{Real, V3};

/// Why a peer patch could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeerError {
    /// A position or normal is not finite.
    NonFinite,
    /// A vertex normal has zero length.
    ZeroNormal,
    /// The triangle has (numerically) zero area.
    Degenerate,
}

impl core::fmt::Display for PeerError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            PeerError::NonFinite => "a position or normal is not finite",
            PeerError::ZeroNormal => "a vertex normal has zero length",
            PeerError::Degenerate => "the triangle has zero area",
        })
    }
}

impl std::error::Error for PeerError {}

/// The inputs of a peer patch in `f64`: positions and unit normals, checked.
pub(crate) fn checked(
    p: [glam::DVec3; 3],
    n: [glam::DVec3; 3],
) -> Result<([glam::DVec3; 3], [glam::DVec3; 3]), PeerError> {
    if !p.iter().chain(&n).all(|v| v.is_finite()) {
        return Err(PeerError::NonFinite);
    }
    let mut unit = [glam::DVec3::ZERO; 3];
    for (u, v) in unit.iter_mut().zip(n) {
        *u = v.try_normalize().ok_or(PeerError::ZeroNormal)?;
    }
    let area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    let size = (p[1] - p[0])
        .length()
        .max((p[2] - p[1]).length())
        .max((p[0] - p[2]).length());
    if !(area > 1e-14 * size * size) {
        return Err(PeerError::Degenerate);
    }
    Ok((p, unit))
}

/// A quadratic triangular patch (see the module docs), with the unit vertex normals of the
/// triangle it was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadPatch<F: Real = f32> {
    pub(crate) a: V3<F>,
    pub(crate) bu: V3<F>,
    pub(crate) bv: V3<F>,
    pub(crate) buu: V3<F>,
    pub(crate) buv: V3<F>,
    pub(crate) bvv: V3<F>,
    normals: [V3<F>; 3],
    control: [V3<F>; 6],
    bbox: Aabb<F>,
    /// The largest coordinate magnitude of the control points plus the box's diagonal: the
    /// scale of the solver's tolerances.
    pub(crate) scale: F,
}

impl<F: Real> QuadPatch<F> {
    /// The patch with vertices `p`, edge controls `e = [B_01, B_12, B_20]` and unit vertex
    /// normals `n` (all `f64`; rounded once to `F`; the monomial coefficients are formed in
    /// `f64` first).
    pub(crate) fn from_control(
        p: [glam::DVec3; 3],
        e: [glam::DVec3; 3],
        n: [glam::DVec3; 3],
    ) -> Self {
        let [b0, b1, b2] = p;
        let [b01, b12, b20] = e;
        let a = b0;
        let bu = (b01 - b0) * 2.0;
        let bv = (b20 - b0) * 2.0;
        let buu = b0 + b1 - b01 * 2.0;
        let buv = (b0 - b01 + b12 - b20) * 2.0;
        let bvv = b0 + b2 - b20 * 2.0;
        let pts = [b0, b1, b2, b01, b12, b20];
        let (lo, hi) = pts.iter().fold(
            (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
            |(l, h), q| (l.min(*q), h.max(*q)),
        );
        let mag = lo.abs().max(hi.abs()).max_element();
        let diag = (hi - lo).length();
        // The patch in `F` is the rounded monomial form, evaluated with rounding: its points
        // leave the exact Bézier hull by a few roundings of the terms (each at most 4× the
        // largest control point). 64 ε of the magnitude covers that with room.
        let pad = 64.0 * F::EPSILON.to_f64() * (mag + diag);
        let rd = |v: glam::DVec3| V3::<F>::from_d(v);
        let lo = rd(lo - glam::DVec3::splat(pad));
        let hi = rd(hi + glam::DVec3::splat(pad));
        // Rounding the padded corners to `F` may move them inward by half an ulp, which the
        // pad (64 ε) exceeds.
        QuadPatch {
            a: rd(a),
            bu: rd(bu),
            bv: rd(bv),
            buu: rd(buu),
            buv: rd(buv),
            bvv: rd(bvv),
            normals: n.map(rd),
            control: pts.map(rd),
            bbox: Aabb::new(F::glam(lo), F::glam(hi)),
            scale: F::from_f64(mag + diag),
        }
    }

    #[inline(always)]
    pub(crate) fn point_v(&self, u: F, v: F) -> V3<F> {
        self.a + (self.bu + self.buu * u + self.buv * v) * u + (self.bv + self.bvv * v) * v
    }

    #[inline(always)]
    pub(crate) fn derivs_v(&self, u: F, v: F) -> (V3<F>, V3<F>) {
        let two = F::ONE + F::ONE;
        (
            self.bu + self.buu * (two * u) + self.buv * v,
            self.bv + self.bvv * (two * v) + self.buv * u,
        )
    }

    #[inline(always)]
    pub(crate) fn interpolated_v(&self, u: F, v: F) -> V3<F> {
        let [n0, n1, n2] = self.normals;
        n0 * (F::ONE - u - v) + n1 * u + n2 * v
    }

    /// The geometric normal at `(w1, w2)` oriented to the side of the interpolated vertex
    /// normals; that interpolated normal where the derivatives are parallel.
    #[inline(always)]
    pub(crate) fn normal_v(&self, u: F, v: F) -> V3<F> {
        let (du, dv) = self.derivs_v(u, v);
        let s = self.interpolated_v(u, v);
        match du.cross(dv).try_normalize() {
            Some(n) if n.dot(s) < F::ZERO => -n,
            Some(n) => n,
            None => s.try_normalize().unwrap_or(self.normals[0]),
        }
    }

    /// The surface point at barycentrics `(w1, w2)` (`w0 = 1 − w1 − w2`; not clamped).
    ///
    /// # Accuracy
    /// A few roundings of the largest term (the monomial coefficients were rounded once from
    /// `f64`).
    /// # Panics
    /// Never.
    pub fn point(&self, w1: F, w2: F) -> F::Vec3 {
        F::glam(self.point_v(w1, w2))
    }

    /// The derivatives `∂x/∂w1`, `∂x/∂w2` at `(w1, w2)` (exact up to rounding: the patch is a
    /// polynomial).
    ///
    /// # Panics
    /// Never.
    pub fn derivatives(&self, w1: F, w2: F) -> (F::Vec3, F::Vec3) {
        let (a, b) = self.derivs_v(w1, w2);
        (F::glam(a), F::glam(b))
    }

    /// The unit geometric normal `∂x/∂w1 × ∂x/∂w2` at `(w1, w2)`, oriented to the side of the
    /// vertex normals (the interpolated one where the derivatives are parallel).
    ///
    /// # Panics
    /// Never.
    pub fn normal(&self, w1: F, w2: F) -> F::Vec3 {
        F::glam(self.normal_v(w1, w2))
    }

    /// The Phong normal at `(w1, w2)`: the vertex normals interpolated with the barycentrics,
    /// normalised (the first vertex normal where that sum vanishes).
    ///
    /// # Panics
    /// Never.
    pub fn interpolated_normal(&self, w1: F, w2: F) -> F::Vec3 {
        F::glam(
            self.interpolated_v(w1, w2)
                .try_normalize()
                .unwrap_or(self.normals[0]),
        )
    }

    /// The six Bézier control points: `P_0, P_1, P_2, B_01, B_12, B_20`.
    ///
    /// # Panics
    /// Never.
    pub fn control_points(&self) -> [F::Vec3; 6] {
        self.control.map(F::glam)
    }

    /// The unit vertex normals.
    ///
    /// # Panics
    /// Never.
    pub fn vertex_normals(&self) -> [F::Vec3; 3] {
        self.normals.map(F::glam)
    }

    /// A box that contains the patch: the box of the six control points (a Bézier triangle
    /// lies in their convex hull, its Bernstein weights being non-negative and summing to 1
    /// inside the triangle), widened by 64 ε of the control points' magnitude plus the box's
    /// diagonal for the rounding of the `F` evaluation. Tested by dense sampling.
    ///
    /// # Panics
    /// Never.
    pub fn bounds(&self) -> Aabb<F> {
        self.bbox
    }
}
