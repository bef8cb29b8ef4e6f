//! The curved patch of one triangle and its three vertex normals: construction and storage.
//!
//! A [`Patch`] stores the triangle in a local orthonormal frame (origin `P0`, `x` along
//! `P1 − P0`, `z` along the face normal `Nf`), where the height of a point over the triangle's
//! plane is its `z` coordinate. All evaluation happens in that frame; results are mapped back to
//! world coordinates.

use crate::aabb::Aabb;
use crate::edge::{EdgeView, edge_point};
use crate::error::PatchError;
use crate::geometry::PatchData;
use crate::real::{Float, Real};
use crate::shell;
use crate::sphere::curvature;
use crate::vec::V3;

/// Relative area tolerance of [`PatchError::DegenerateTriangle`] for `f64`: a triangle is
/// degenerate when `2·area < ratio · longest_edge²`, with `ratio = √ε` of the precision
/// (this value for `f64`, [`DEGENERATE_RATIO_F32`] for `f32`). Below it barycentric coordinates
/// lose more than half their digits.
pub const DEGENERATE_RATIO_F64: f64 = 1.490_116_119_384_765_6e-8;
/// Relative area tolerance of [`PatchError::DegenerateTriangle`] for `f32` (`√ε`).
pub const DEGENERATE_RATIO_F32: f32 = 3.452_669_8e-4;

/// A vertex normal is accepted when the cosine of its angle to the face normal is at least
/// this (the angle is then below 89.94°). The method itself degrades well before that
/// (docs/METHOD.md §7); construction may still fail with [`PatchError::InvalidShell`].
pub const MIN_NORMAL_COS: f64 = 1.0e-3;

/// `√ε` of the precision: the relative area below which a triangle is degenerate.
#[inline(always)]
pub(crate) fn degenerate_ratio<F: Float>() -> F {
    F::EPSILON.sqrt()
}

/// A smooth triangular patch (the construction of Gusyatin & Sorokin, docs/METHOD.md §2–§5) in
/// precision `F` (`f32`, the default, or `f64`; see [`DPatch`]).
///
/// Built from a triangle `P0 P1 P2`, counter-clockwise seen from the side its normals point to,
/// and three vertex normals (any positive length). The surface interpolates the vertices with
/// the given normals, passes through the edge conjugation lines, and reproduces spheres exactly.
///
/// Memory: `size_of::<Patch<f32>>()` is 216 bytes, `Patch<f64>` 432 bytes (checked by a test).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch<F: Float = f32> {
    /// World position of `P0`: the local frame's origin.
    pub(crate) origin: V3<F>,
    /// Local frame axes in world coordinates: `x`, `y`, `z = Nf`.
    pub(crate) axes: [V3<F>; 3],
    /// Vertices in the local frame (`p[0] = 0`, `z = 0`).
    pub(crate) p: [V3<F>; 3],
    /// Unit vertex normals in the local frame.
    pub(crate) n: [V3<F>; 3],
    /// Direction field `di = ni / (ni·Nf)` in the local frame (`z = 1`).
    pub(crate) d: [V3<F>; 3],
    /// Curvatures of the edge spheres `S¹i`, `S²i`.
    pub(crate) k: [[F; 2]; 3],
    /// Conservative height range of the surface over the triangle.
    pub(crate) sigma: [F; 2],
    /// World bounding box of the shell (min, max), cached for the kernel and the BVH.
    pub(crate) bbox: Aabb<F>,
    /// Index + 1 into [`NORMAL_CLAMP_DEG`] of the clamp applied by [`Patch::new_or_tilted`]
    /// (0: the normals were used as given).
    pub(crate) remedy: u8,
}

/// Angle clamps (degrees from the face normal) tried in order by [`Patch::new_or_tilted`]
/// for patches whose normals the construction cannot represent. The last, 0°, is the flat
/// triangle, which is always valid.
pub const NORMAL_CLAMP_DEG: [f64; 6] = [75.0, 60.0, 45.0, 30.0, 15.0, 0.0];

/// A [`Patch`] in `f64`: the reference precision.
pub type DPatch = Patch<f64>;

impl<F: Float> Patch<F> {
    /// Builds the patch of triangle `p` with vertex normals `n`.
    ///
    /// Preconditions: vertices counter-clockwise seen from the side the normals point to; normals
    /// of any positive length (they are normalised). Units: any consistent length unit.
    ///
    /// Returns a typed [`PatchError`] for: non-finite input ([`PatchError::NonFinite`]), a
    /// triangle whose doubled area is below `√ε · longest_edge²`
    /// ([`PatchError::DegenerateTriangle`]), a zero normal ([`PatchError::ZeroNormal`]), a
    /// normal whose cosine to the face normal is below [`MIN_NORMAL_COS`]
    /// ([`PatchError::BackFacingNormal`]), normals so divergent that the shell degenerates
    /// ([`PatchError::InvalidShell`]), and magnitudes that overflow the precision
    /// ([`PatchError::OutOfRange`]).
    ///
    /// # Accuracy
    /// The stored frame is orthonormal (its normals unit to
    /// [`UNIT_LENGTH_ULPS`](crate::accuracy::UNIT_LENGTH_ULPS) ulps); vertices are reproduced
    /// to [`F64_INTERPOLATION`](crate::accuracy::F64_INTERPOLATION) of the triangle's size
    /// (`f64`), [`F32_INTERPOLATION`](crate::accuracy::F32_INTERPOLATION) of its scale (`f32`).
    /// # Panics
    /// Never.
    pub fn new(p: [F::Vec3; 3], n: [F::Vec3; 3]) -> Result<Self, PatchError> {
        let [p0, p1, p2] = p.map(F::from_glam);
        let [n0, n1, n2] = n.map(F::from_glam);
        if ![p0, p1, p2, n0, n1, n2].iter().all(|v| v.all_finite()) {
            return Err(PatchError::NonFinite);
        }
        let e = p1 - p0;
        let f = p2 - p0;
        let c = e.cross(f);
        let lmax2 = e.length2().max(f.length2()).max((p2 - p1).length2());
        let c_len = c.length();
        if !lmax2.is_fin() || !c_len.is_fin() {
            return Err(PatchError::OutOfRange);
        }
        // The scale before the area: for triangles this small |e × f|² underflows and the area
        // test below would report a well-shaped triangle as degenerate. Exactly coincident
        // vertices stay `DegenerateTriangle`.
        let all_zero = |v: V3<F>| v.x == F::ZERO && v.y == F::ZERO && v.z == F::ZERO;
        if !(all_zero(e) && all_zero(f)) && lmax2 * lmax2 < F::MIN_POSITIVE / F::EPSILON {
            return Err(PatchError::OutOfRange);
        }
        if c_len <= degenerate_ratio::<F>() * lmax2 || c_len <= F::ZERO {
            return Err(PatchError::DegenerateTriangle);
        }
        // Squared areas near the subnormal range lose their digits: too small for this
        // precision (f32: edges below ~1e-15).
        if c.length2() < F::MIN_POSITIVE / F::EPSILON {
            return Err(PatchError::OutOfRange);
        }
        let nf = c * (F::ONE / c_len);
        let ex = match e.try_normalize() {
            Some(v) => v,
            None => return Err(PatchError::DegenerateTriangle),
        };
        // Re-orthogonalise: on skinny triangles the cross product's direction carries an error
        // of ε·|e||f|/|e×f| that would otherwise tilt the frame.
        let nf = match (nf - ex * nf.dot(ex)).try_normalize() {
            Some(v) => v,
            None => return Err(PatchError::DegenerateTriangle),
        };
        let ey = nf.cross(ex);
        let axes = [ex, ey, nf];
        let to_local = |v: V3<F>| V3::new(v.dot(ex), v.dot(ey), v.dot(nf));

        let mut nl = [V3::zero(); 3];
        let mut dl = [V3::zero(); 3];
        for (vi, (src, (ndst, ddst))) in [n0, n1, n2]
            .iter()
            .zip(nl.iter_mut().zip(dl.iter_mut()))
            .enumerate()
        {
            let vertex = vi as u8;
            let len2 = src.length2();
            if !len2.is_fin() {
                // Overflowing normal: rescale first.
                let m = src.x.abs().max(src.y.abs()).max(src.z.abs());
                let s = *src * (F::ONE / m);
                let Some(u) = s.try_normalize() else {
                    return Err(PatchError::ZeroNormal { vertex });
                };
                *ndst = to_local(u);
            } else if len2 < F::MIN_POSITIVE {
                return Err(PatchError::ZeroNormal { vertex });
            } else {
                let Some(u) = src.try_normalize() else {
                    return Err(PatchError::ZeroNormal { vertex });
                };
                *ndst = to_local(u);
            }
            let cos = ndst.z;
            if cos < F::from_f64(MIN_NORMAL_COS) || !cos.is_fin() {
                return Err(PatchError::BackFacingNormal { vertex });
            }
            *ddst = *ndst * (F::ONE / cos);
            ddst.z = F::ONE;
        }
        let mut pl = [V3::zero(), to_local(e), to_local(f)];
        // Exact zeros where the frame guarantees them.
        pl[1].y = F::ZERO;
        pl[1].z = F::ZERO;
        pl[2].z = F::ZERO;

        let mut patch = Patch {
            origin: p0,
            axes,
            p: pl,
            n: nl,
            d: dl,
            k: [[F::ZERO; 2]; 3],
            sigma: [F::ZERO; 2],
            bbox: Aabb::EMPTY,
            remedy: 0,
        };
        for j in 0..3 {
            let ev = patch.edge(j);
            let k1 = curvature(ev.a, ev.na, ev.b);
            let k2 = curvature(ev.b, ev.nb, ev.a);
            if let Some(slot) = patch.k.get_mut(j) {
                *slot = [k1, k2];
            }
        }
        patch.sigma = shell::height_bounds(&patch);
        if !shell::is_valid(&patch) {
            return Err(PatchError::InvalidShell);
        }
        patch.bbox = shell::aabb(&patch);
        if !patch.all_finite() {
            return Err(PatchError::OutOfRange);
        }
        Ok(patch)
    }

    /// Builds the patch like [`Patch::new`], and where the normals are outside the method's
    /// domain (a zero, back-facing or near-perpendicular normal, or a shell that degenerates)
    /// applies the documented remedy instead of failing: each normal steeper than a clamp angle
    /// is rotated toward the face normal down to that angle, trying the clamps of
    /// [`NORMAL_CLAMP_DEG`] in order (75°, 60°, 45°, 30°, 15°, then 0° = the flat triangle);
    /// zero normals become the face normal. The clamp used is reported by
    /// [`Patch::normal_clamp`]. Only non-finite input, degenerate triangles and overflow are
    /// still errors.
    ///
    /// Work is bounded: at most 7 constructions.
    /// # Accuracy
    /// As [`Patch::new`] for the (possibly clamped) normals.
    /// # Panics
    /// Never.
    pub fn new_or_tilted(p: [F::Vec3; 3], n: [F::Vec3; 3]) -> Result<Self, PatchError> {
        let first = match Self::new(p, n) {
            Ok(patch) => return Ok(patch),
            Err(
                e @ (PatchError::NonFinite
                | PatchError::DegenerateTriangle
                | PatchError::OutOfRange),
            ) => {
                return Err(e);
            }
            Err(e) => e,
        };
        let [p0, p1, p2] = p.map(F::from_glam);
        let Some(nf) = (p1 - p0).cross(p2 - p0).try_normalize() else {
            return Err(first);
        };
        let units = n.map(|v| F::from_glam(v).try_normalize().unwrap_or(nf));
        for (k, deg) in NORMAL_CLAMP_DEG.iter().enumerate() {
            let (s, c) = libm::sincos(deg.to_radians());
            let (sin_max, cos_max) = (F::from_f64(s), F::from_f64(c));
            let clamped = units.map(|u| {
                let cos = u.dot(nf);
                if cos >= cos_max {
                    return F::to_glam(u);
                }
                // Rotate toward nf in the plane of (nf, u) down to the clamp angle.
                match (u - nf * cos).try_normalize() {
                    Some(w) => F::to_glam(nf * cos_max + w * sin_max),
                    None => F::to_glam(nf),
                }
            });
            if let Ok(mut patch) = Self::new(p, clamped) {
                patch.remedy = (k + 1) as u8;
                return Ok(patch);
            }
        }
        Err(first)
    }

    /// The clamp angle (degrees from the face normal) that [`Patch::new_or_tilted`] applied to
    /// this patch's normals, or `None` when they were used as given.
    ///
    /// # Panics
    /// Never.
    pub fn normal_clamp(&self) -> Option<f64> {
        NORMAL_CLAMP_DEG
            .get(usize::from(self.remedy).checked_sub(1)?)
            .copied()
    }

    /// The data of edge `j` (from `Pj` to `Pj+1`); `j` is 0, 1 or 2 (anything else means 2).
    #[inline(always)]
    pub(crate) fn edge(&self, j: usize) -> EdgeView<F> {
        let [p0, p1, p2] = self.p;
        let [n0, n1, n2] = self.n;
        let [d0, d1, d2] = self.d;
        let [k0, k1, k2] = self.k;
        let (a, b, da, db, na, nb, k) = match j {
            0 => (p0, p1, d0, d1, n0, n1, k0),
            1 => (p1, p2, d1, d2, n1, n2, k1),
            _ => (p2, p0, d2, d0, n2, n0, k2),
        };
        let [k1, k2] = k;
        EdgeView {
            a,
            b,
            da,
            db,
            na,
            nb,
            k1,
            k2,
        }
    }

    /// Edge conjugation-line point in the local frame (no normal).
    #[inline(always)]
    pub(crate) fn edge_point_local(&self, j: usize, t: F) -> V3<F> {
        edge_point::<F>(&self.edge(j), t).0
    }

    fn all_finite(&self) -> bool {
        let vs = [self.origin, self.axes[0], self.axes[1], self.axes[2]];
        vs.iter()
            .chain(self.p.iter())
            .chain(self.n.iter())
            .chain(self.d.iter())
            .all(|v| v.all_finite())
            && self.k.iter().flatten().all(|k| k.is_fin())
            && self.sigma.iter().all(|s| s.is_fin())
            && self.bbox.is_finite()
    }

    /// World coordinates of a local-frame point.
    #[inline(always)]
    pub(crate) fn local_to_world<S: Real<F = F>>(&self, v: V3<S>) -> V3<S> {
        let [ex, ey, ez] = self.axes;
        V3::lift(self.origin) + V3::lift(ex) * v.x + V3::lift(ey) * v.y + V3::lift(ez) * v.z
    }

    /// World direction of a local-frame direction.
    #[inline(always)]
    pub(crate) fn local_dir_to_world<S: Real<F = F>>(&self, v: V3<S>) -> V3<S> {
        let [ex, ey, ez] = self.axes;
        V3::lift(ex) * v.x + V3::lift(ey) * v.y + V3::lift(ez) * v.z
    }

    /// Local-frame coordinates of a world point.
    #[inline(always)]
    pub(crate) fn world_to_local(&self, v: V3<F>) -> V3<F> {
        let [ex, ey, ez] = self.axes;
        let w = v - self.origin;
        V3::new(w.dot(ex), w.dot(ey), w.dot(ez))
    }

    /// Local-frame components of a world direction.
    #[inline(always)]
    pub(crate) fn world_dir_to_local(&self, v: V3<F>) -> V3<F> {
        let [ex, ey, ez] = self.axes;
        V3::new(v.dot(ex), v.dot(ey), v.dot(ez))
    }

    /// The triangle's vertices in world coordinates, as given (up to rounding of the frame).
    ///
    /// # Accuracy
    /// The input vertices to [`F64_INTERPOLATION`](crate::accuracy::F64_INTERPOLATION) of the
    /// triangle's size (`f64`), [`F32_INTERPOLATION`](crate::accuracy::F32_INTERPOLATION) of its
    /// scale (`f32`).
    /// # Panics
    /// Never.
    pub fn vertices(&self) -> [F::Vec3; 3] {
        self.p.map(|v| F::to_glam(self.local_to_world(v)))
    }

    /// The unit vertex normals in world coordinates.
    ///
    /// # Accuracy
    /// Unit length to [`UNIT_LENGTH_ULPS`](crate::accuracy::UNIT_LENGTH_ULPS) ulps.
    /// # Panics
    /// Never.
    pub fn normals(&self) -> [F::Vec3; 3] {
        self.n.map(|v| F::to_glam(self.local_dir_to_world(v)))
    }

    /// The unit face normal `Nf` (right-handed with the vertex order) in world coordinates.
    ///
    /// # Panics
    /// Never.
    pub fn face_normal(&self) -> F::Vec3 {
        F::to_glam(self.axes[2])
    }

    /// Conservative range `[σmin, σmax]` of the surface's height over the triangle's plane
    /// (signed distance along the face normal, in the input's length unit).
    ///
    /// # Accuracy
    /// Conservative: every surface point's height lies inside, with a safety margin (see
    /// [`crate::shell`] for how it is computed and tested).
    /// # Panics
    /// Never.
    pub fn height_range(&self) -> (F, F) {
        let [lo, hi] = self.sigma;
        (lo, hi)
    }

    /// Axis-aligned bounding box of the patch's shell in world coordinates: the box
    /// of its six corners `Pi + σmin·di`, `Pi + σmax·di`. Every surface point lies inside.
    ///
    /// # Accuracy
    /// Conservative up to a few ulps of the box's size.
    /// # Panics
    /// Never.
    pub fn bounds(&self) -> Aabb<F> {
        self.bbox
    }

    /// The stored geometry as plain arrays (see [`PatchData`] for each field's meaning and
    /// invariants): what a GPU port of the kernel uploads.
    ///
    /// # Panics
    /// Never.
    pub fn data(&self) -> PatchData<F> {
        let a = |v: V3<F>| [v.x, v.y, v.z];
        PatchData {
            origin: a(self.origin),
            axes: self.axes.map(a),
            p: self.p.map(a),
            n: self.n.map(a),
            d: self.d.map(a),
            k: self.k,
            sigma: self.sigma,
            bbox_min: a(self.bbox.lo),
            bbox_max: a(self.bbox.hi),
        }
    }
}
