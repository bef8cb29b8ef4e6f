//! Rays and hits (parry style: `Ray { origin, dir }`, hits with `t`, normal and the hit patch's
//! index).

use crate::num::real::Float;

/// A ray `origin + t·dir`. `dir` need not be unit length: `t` is measured in units of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<F: Float = f32> {
    /// Origin, world coordinates.
    pub origin: F::Vec3,
    /// Direction (any non-zero finite length).
    pub dir: F::Vec3,
}

/// A [`Ray`] in `f64`.
pub type DRay = Ray<f64>;

impl<F: Float> Ray<F> {
    /// A ray from `origin` along `dir`.
    ///
    /// # Panics
    /// Never (a zero or non-finite direction is accepted here and gives no hit in every query).
    pub fn new(origin: F::Vec3, dir: F::Vec3) -> Self {
        Ray { origin, dir }
    }

    /// The point `origin + t·dir`.
    ///
    /// # Accuracy
    /// One rounding per component operation.
    /// # Panics
    /// Never.
    pub fn at(&self, t: F) -> F::Vec3 {
        let o = F::from_glam(self.origin);
        let d = F::from_glam(self.dir);
        F::to_glam(o + d * t)
    }
}

/// A ray–surface intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<F: Float = f32> {
    /// Ray parameter of the hit, in units of the ray's `dir`.
    pub t: F,
    /// Error bound on `t`: the width of the final bracket (which certainly contains a sign
    /// change of the floating-point height difference `f`) plus a rounding allowance
    /// `16·ε·L / |f′|` (L = 4 × the longest edge + the patch's distance from the world origin,
    /// f′ = the final bracket's slope) for the uncertainty of `f`'s sign near the root. In
    /// units of the ray's `dir`. Tests check it against analytic spheres and the f64 kernel at
    /// N = 40; in f32 against the true surface it can still be exceeded on grazing rays, where
    /// the allowance's slope estimate is poor.
    ///
    /// A ray whose clipped interval starts or ends within that rounding of the surface counts
    /// the surface as hit there (what makes shared edges watertight, docs/METHOD.md §8): start
    /// secondary rays more than a few `t_error` (or a fixed fraction of the scene) away from
    /// the surface they leave.
    pub t_error: F,
    /// Hit point `ray.at(t)`, world coordinates.
    pub point: F::Vec3,
    /// Unit surface normal at the hit (exact derivatives of the patch), oriented like the vertex
    /// normals (not flipped toward the ray: see `front_face`).
    pub normal: F::Vec3,
    /// Barycentric coordinate `w1` of the hit on the patch (`w0 = 1 − w1 − w2`).
    pub w1: F,
    /// Barycentric coordinate `w2` of the hit on the patch.
    pub w2: F,
    /// `true` when the ray arrives from the side the normals point to.
    pub front_face: bool,
    /// Index of the hit patch in the slice given to [`crate::Bvh::build`] (0 for a query on
    /// a lone patch).
    pub patch: u32,
}

/// A [`Hit`] in `f64`.
pub type DHit = Hit<f64>;
