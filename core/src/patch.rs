//! The curved patch of one triangle and its three vertex normals: construction, storage, and
//! the public API of one patch (evaluation delegates to `surface`, ray queries to [`kernel`]).
//!
//! A [`Patch`] stores the triangle in a local orthonormal frame (origin `P0`, `x` along
//! `P1 − P0`, `z` along the face normal `Nf`), where the height of a point over the triangle's
//! plane is its `z` coordinate. All evaluation happens in that frame; results are mapped back to
//! world coordinates.

use crate::aabb::Aabb;
use crate::error::PatchError;
pub use crate::geometry::Patch;
use crate::geometry::{Band, Frame, PatchData, Predictor, Shape};
use crate::kernel::{self, DEFAULT_SAMPLES, KernelStats};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::ray::{Hit, Ray};
use crate::surface::band;
use crate::surface::edge;
use crate::surface::field::LineField;
use crate::surface::lanes::Prepared;
use crate::surface::scalar::{self, project_bary};
use crate::surface::shell;

/// A vertex normal is accepted when the cosine of its angle to the face normal is at least
/// this (the angle is then below 89.94°). The method itself degrades well before that
/// (docs/METHOD.md §7); construction may still fail with [`PatchError::InvalidShell`].
pub const MIN_NORMAL_COS: f64 = 1.0e-3;

/// `√ε` of the precision: the relative area below which a triangle is degenerate.
#[inline(always)]
pub(crate) fn degenerate_ratio<F: Float>() -> F {
    F::EPSILON.sqrt()
}

/// Angle clamps (degrees from the face normal) tried in order by [`Patch::new_or_tilted`]
/// for patches whose normals the construction cannot represent. The last, 0°, is the flat
/// triangle, which is always valid.
pub const NORMAL_CLAMP_DEG: [f64; 6] = [75.0, 60.0, 45.0, 30.0, 15.0, 0.0];

/// A [`Patch`] in `f64`: the reference precision.
pub type DPatch = Patch<f64>;

/// The bit of `Patch::remedy` that marks a placeholder ([`Patch::rejected`]); the low bits then
/// hold the reason.
const REJECTED: u8 = 0x80;

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
        Self::with_field(p, n, LineField::Face)
    }

    /// Builds the patch of triangle `p` with vertex normals `n` like [`Patch::new`], on the
    /// line field `field` ([`LineField`]): [`LineField::Face`] is [`Patch::new`] (the paper's
    /// construction); [`LineField::Vertex`] sweeps the same lines over an edge as the patch on
    /// the other side of it, so neighbours built from the same vertices and normals meet
    /// (their edge curves coincide to rounding) while spheres stay exact.
    ///
    /// Preconditions, errors and accuracy as [`Patch::new`].
    /// # Panics
    /// Never.
    pub fn with_field(
        p: [F::Vec3; 3],
        n: [F::Vec3; 3],
        field: LineField,
    ) -> Result<Self, PatchError> {
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
        if field == LineField::Vertex {
            // One scale for the three normals (the largest height, so `di.z ≤ 1`), unless
            // they make equal angles with the face to rounding: then the face field is the
            // same field, with parallel sections (kept exactly, `di.z = 1`).
            let [w0, w1, w2] = nl.map(|v| v.z);
            let (lo, hi) = (w0.min(w1).min(w2), w0.max(w1).max(w2));
            if hi - lo > F::from_f64(4.0) * F::EPSILON * hi {
                let inv = F::ONE / hi;
                dl = nl.map(|v| v * inv);
            }
        }
        let mut pl = [V3::zero(), to_local(e), to_local(f)];
        // Exact zeros where the frame guarantees them.
        pl[1].y = F::ZERO;
        pl[1].z = F::ZERO;
        pl[2].z = F::ZERO;

        let shape = Shape {
            p: pl,
            n: nl,
            d: dl,
            k: edge::sphere_curvatures(pl, nl),
        };
        let prep = Prepared::new(&shape);
        let (heights, inner) = shell::samples(&shape, &prep, Predictor::interior_nodes());
        let sigma = shell::bounds_of(&shape, &heights);
        if !shell::is_valid(&shape, sigma) {
            return Err(PatchError::InvalidShell);
        }
        let frame = Frame { origin: p0, axes };
        let reach = [F::ZERO; 3];
        let bbox = shell::aabb(&shape, sigma, &frame, reach);
        let mut patch = Patch {
            frame,
            shape,
            sigma,
            bbox,
            remedy: 0,
            reach,
            band: Band::UNBOUNDED,
            predictor: Predictor::NONE,
        };
        let snap = kernel::budget::end_snap(kernel::budget::rounding_scale(&patch));
        patch.band = band::fit(
            &shape,
            &heights,
            sigma,
            snap,
            F::from_f64(kernel::MAX_CRACK_REACH),
        );
        patch.predictor = Predictor::build(&shape, &prep, &heights, inner);
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
        Self::new_or_tilted_with(p, n, LineField::Face)
    }

    /// [`Patch::new_or_tilted`] on the line field `field` ([`Patch::with_field`]). The clamp
    /// acts on this patch's normals only, so a clamped patch no longer shares its edges'
    /// lines with its neighbours ([`crate::mesh::close_cracks`] closes what parts).
    ///
    /// Work is bounded: at most 7 constructions.
    /// # Accuracy
    /// As [`Patch::new`] for the (possibly clamped) normals.
    /// # Panics
    /// Never.
    pub fn new_or_tilted_with(
        p: [F::Vec3; 3],
        n: [F::Vec3; 3],
        field: LineField,
    ) -> Result<Self, PatchError> {
        let first = match Self::with_field(p, n, field) {
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
            if let Ok(mut patch) = Self::with_field(p, clamped, field) {
                patch.remedy = (k + 1) as u8;
                // Clamped patches keep the kernel's bracketing (surface::predictor, "Domain").
                patch.predictor = Predictor::NONE;
                return Ok(patch);
            }
        }
        Err(first)
    }

    /// How far each side wall reaches beyond the edge (barycentric units; wall `k` is
    /// opposite vertex `k`): 0 unless crack closure widened it.
    pub(crate) fn reach(&self) -> [F; 3] {
        self.reach
    }

    /// Sets the walls' reach ([`Patch::reach`]), leaving the box as it was until
    /// [`Patch::fit_box`]: the edge pass sets each patch's three reaches one shared edge at a
    /// time and fits each box once at its end. A placeholder ([`Patch::rejected`]) keeps its
    /// reach of 0.
    pub(crate) fn set_reach(&mut self, reach: [F; 3]) {
        if self.remedy & REJECTED == 0 {
            self.reach = reach;
        }
    }

    /// Fits the bounding box to the shell as widened by the reach, so that the box holds every
    /// point the kernel may hit. A placeholder keeps its empty box.
    pub(crate) fn fit_box(&mut self) {
        if self.remedy & REJECTED == 0 {
            self.bbox = shell::aabb(&self.shape, self.sigma, &self.frame, self.reach);
        }
    }

    /// Whether this patch's surface is proven not to jump: `true` when every sphere root of its
    /// construction is certified, over the whole triangle, to exist and to stay on one branch
    /// (interval arithmetic with outward rounding, mean-value form over `(λ, t)` boxes). `false` means "not
    /// proven": a patch that jumps or spikes, or one whose enclosures stay too wide (about a
    /// fifth of sound patches with normals 45° off the face, most at 55°).
    ///
    /// Not part of [`Patch::new_or_tilted`]: it is for offline validation. Work is bounded
    /// (at most 3 · 4096 boxes) but large, and grows with the normals' angle to the face
    /// (docs/MEASUREMENTS.md, "Notes moved from the code").
    ///
    /// # Accuracy
    /// Sound for the surface the stored data define in `f64` (for `f32` patches, their data
    /// widened exactly): a certified patch has no missing or switched root anywhere, not only
    /// at samples. In the domain study it refused every patch that folds or jumps.
    /// # Panics
    /// Never.
    pub fn roots_certified(&self) -> bool {
        crate::surface::certify::roots_certified(&self.shape)
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
        F::to_glam(
            self.frame
                .local_to_world(scalar::point_local(&self.shape, x)),
        )
    }

    /// Height of the surface over the triangle's plane at `(w1, w2)` (signed, along the face
    /// normal, in the input's length unit): the paper's construction as a height field.
    ///
    /// # Accuracy
    /// As [`Patch::point`].
    /// # Panics
    /// Never.
    pub fn height(&self, w1: F, w2: F) -> F {
        scalar::height(&self.shape, project_bary(w1, w2))
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
        let (p, n) = scalar::point_normal_local(&self.shape, project_bary(w1, w2));
        (
            F::to_glam(self.frame.local_to_world(p)),
            F::to_glam(self.frame.local_dir_to_world(n)),
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
        let [du1, du2] = scalar::derivatives_local(&self.shape, project_bary(w1, w2));
        (
            F::to_glam(self.frame.local_dir_to_world(du1)),
            F::to_glam(self.frame.local_dir_to_world(du2)),
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
        let (c, n) = edge::clamped_point_normal(&self.shape, edge, t);
        (
            F::to_glam(self.frame.local_to_world(c)),
            F::to_glam(self.frame.local_dir_to_world(n)),
        )
    }

    /// Closest intersection of `ray` with the patch for `t` in `[t_min, t_max]`, with a
    /// refinement budget of `n` steps (any `n`; it runs [`iterations`](kernel::iterations)`(n)`,
    /// at most [`MAX_ITERATIONS`](kernel::MAX_ITERATIONS)) and [`DEFAULT_SAMPLES`] bracketing
    /// samples. The lane code is compiled for the build's target; [`crate::isa`] has the same
    /// test with a kernel chosen at run time (the same hit, bit for bit).
    ///
    /// Returns `None` when the ray misses (including degenerate rays: zero or non-finite
    /// direction, non-finite origin, `t_max < t_min`, NaN bounds). `t_max` may be infinite.
    ///
    /// # Accuracy
    /// `|t − t_true| ≤ hit.t_error` where `t_true` is the crossing inside the final bracket.
    /// `t_error` is the final bracket's width plus a rounding allowance
    /// ([`KernelStats::rounding`]: `16 · ε · L / |f′|`
    /// for the patch's extent `L = 4 · longest_edge + |P0|`), and the bracket is at most `(tb − ta) / ((K + 1)·5^n)` for the shell interval
    /// `[ta, tb]` ([`KernelStats::shell_width`]): one sampling step, divided by at least
    /// `WORST_SHRINK` = 5 by every refinement step (tested on
    /// every patch test of random rays in `tests/suite/kernel.rs`). Convergence is usually far
    /// faster: from n = 4, `f64` hits on the torus are at rounding
    /// (the table of docs/MEASUREMENTS.md); at n = 8 `f64`
    /// hits on spheres are on the sphere to [`F64_SPHERE_HIT`](crate::accuracy::F64_SPHERE_HIT).
    /// Rays that cross the surface twice within one sampling step `(tb − ta)/(K + 1)` may be
    /// reported as misses.
    /// # Panics
    /// Never. Work is bounded: at most [`max_lane_calls`](kernel::max_lane_calls)`(K, n)` lane
    /// calls (eight height evaluations each), one call of four and one normal evaluation
    /// ([`max_height_evals`](kernel::max_height_evals)), whatever `n`.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> Option<Hit<F>> {
        self.closest_hit_stats::<DEFAULT_SAMPLES>(ray, t_min, t_max, n)
            .0
    }

    /// [`Patch::closest_hit`] with `K` bracketing samples chosen by the caller, also returning
    /// the [`KernelStats`] of the call (evaluation counts, the shell interval's width and the
    /// rounding allowance).
    ///
    /// # Accuracy
    /// As [`Patch::closest_hit`].
    /// # Panics
    /// Never.
    pub fn closest_hit_stats<const K: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        n: usize,
    ) -> (Option<Hit<F>>, KernelStats) {
        kernel::closest_hit_stats::<F, K>(self, ray, [t_min, t_max], n, &kernel::heights::target())
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
        self.shape
            .p
            .map(|v| F::to_glam(self.frame.local_to_world(v)))
    }

    /// The unit vertex normals in world coordinates.
    ///
    /// # Accuracy
    /// Unit length to [`UNIT_LENGTH_ULPS`](crate::accuracy::UNIT_LENGTH_ULPS) ulps.
    /// # Panics
    /// Never.
    pub fn normals(&self) -> [F::Vec3; 3] {
        self.shape
            .n
            .map(|v| F::to_glam(self.frame.local_dir_to_world(v)))
    }

    /// The unit face normal `Nf` (right-handed with the vertex order) in world coordinates.
    ///
    /// # Panics
    /// Never.
    pub fn face_normal(&self) -> F::Vec3 {
        let [_, _, nf] = self.frame.axes;
        F::to_glam(nf)
    }

    /// Conservative range `[σmin, σmax]` of the surface's height over the triangle's plane
    /// (signed distance along the face normal, in the input's length unit).
    ///
    /// # Accuracy
    /// Conservative: every surface point's height lies inside, with a safety margin (docs/METHOD.md, "The shell", says how it is computed and tested).
    /// # Panics
    /// Never.
    pub fn height_range(&self) -> (F, F) {
        let [lo, hi] = self.sigma;
        (lo, hi)
    }

    /// Axis-aligned bounding box of the patch's shell in world coordinates: the box
    /// of its six corners `Pi + σmin·di`, `Pi + σmax·di` (with the side walls moved out by the
    /// reach that [`close_cracks`](crate::mesh::close_cracks) set, if any). Every surface
    /// point lies inside.
    ///
    /// # Accuracy
    /// Conservative up to a few ulps of the box's size.
    /// # Panics
    /// Never.
    pub fn bounds(&self) -> Aabb<F> {
        self.bbox
    }

    /// The placeholder a scene keeps in the slot of a triangle it rejected for `why` (so that
    /// a mesh's layout does not depend on its data, for updates): an empty box that no ray
    /// enters, no surface, and the reason, [`Patch::rejected`].
    pub(crate) fn placeholder(why: PatchError) -> Self {
        let code = match why {
            PatchError::NonFinite => 1,
            PatchError::DegenerateTriangle => 2,
            PatchError::ZeroNormal { vertex } => 3 + vertex.min(2),
            PatchError::BackFacingNormal { vertex } => 6 + vertex.min(2),
            PatchError::InvalidShell => 9,
            PatchError::OutOfRange => 10,
        };
        Patch {
            remedy: REJECTED | code,
            ..Patch::default()
        }
    }

    /// Why the scene builder left this slot empty: `Some` for the placeholder of a rejected
    /// triangle (an empty box, no surface: no ray reaches it, and its evaluations are
    /// meaningless), `None` for a patch.
    ///
    /// # Panics
    /// Never.
    pub fn rejected(&self) -> Option<PatchError> {
        if self.remedy & REJECTED == 0 {
            return None;
        }
        Some(match self.remedy & !REJECTED {
            1 => PatchError::NonFinite,
            2 => PatchError::DegenerateTriangle,
            c @ 3..=5 => PatchError::ZeroNormal { vertex: c - 3 },
            c @ 6..=8 => PatchError::BackFacingNormal { vertex: c - 6 },
            9 => PatchError::InvalidShell,
            _ => PatchError::OutOfRange,
        })
    }

    /// The stored geometry as plain arrays (see [`PatchData`] for each field's meaning and
    /// invariants): what a GPU port of the kernel uploads.
    ///
    /// # Panics
    /// Never.
    pub fn data(&self) -> PatchData<F> {
        let a = |v: V3<F>| [v.x, v.y, v.z];
        PatchData {
            origin: a(self.frame.origin),
            axes: self.frame.axes.map(a),
            p: self.shape.p.map(a),
            n: self.shape.n.map(a),
            d: self.shape.d.map(a),
            k: self.shape.k,
            sigma: self.sigma,
            bbox_min: a(self.bbox.lo),
            bbox_max: a(self.bbox.hi),
            reach: self.reach,
            band_fit: self.band.c,
            band: [self.band.lo, self.band.hi, self.band.per_reach],
        }
    }

    /// Whether every stored value is finite. Mostly branch-free: `v·0` is ±0 for a finite `v` and
    /// NaN otherwise, so the sum of those products is 0 exactly when all are finite.
    fn all_finite(&self) -> bool {
        let z = |v: V3<F>| (v.x * F::ZERO) + (v.y * F::ZERO) + (v.z * F::ZERO);
        let zs = |v: &[V3<F>; 3]| z(v[0]) + z(v[1]) + z(v[2]);
        let [ex, ey, ez] = self.frame.axes;
        let [[k0, k1], [k2, k3], [k4, k5]] = self.shape.k;
        let [s0, s1] = self.sigma;
        let k = V3::new(k0 + k1, k2 + k3, k4 + k5) + V3::new(s0, s1, F::ZERO);
        let a = z(self.frame.origin) + z(ex) + z(ey) + z(ez) + z(k);
        let b = zs(&self.shape.p) + zs(&self.shape.n) + zs(&self.shape.d);
        a + b == F::ZERO
            && self.bbox.is_finite()
            && self.band.is_finite()
            && self.predictor.is_finite()
    }
}
