//! Baselines for side-by-side comparison: the flat triangle (Möller–Trumbore) and the flat
//! triangle with interpolated vertex normals (Phong shading).

use crate::num::real::Float;
use crate::ray::{Hit, Ray};

/// Möller–Trumbore ray–triangle test: `Some((t, w1, w2))` for the hit with `t` in
/// `[t_min, t_max]` (either face), `None` otherwise (also for degenerate triangles or rays).
///
/// # Accuracy
/// The standard single-precision-friendly formulation; no error bound is returned.
/// # Panics
/// Never.
#[inline]
pub fn moller_trumbore<F: Float>(
    tri: &[F::Vec3; 3],
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
) -> Option<(F, F, F)> {
    let [p0, p1, p2] = tri.map(F::from_glam);
    let o = F::from_glam(ray.origin);
    let d = F::from_glam(ray.dir);
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det == F::ZERO || !det.is_fin() {
        return None;
    }
    let inv = F::ONE / det;
    let tv = o - p0;
    let u = tv.dot(pv) * inv;
    if !(u >= F::ZERO && u <= F::ONE) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if !(v >= F::ZERO && u + v <= F::ONE) {
        return None;
    }
    let t = e2.dot(qv) * inv;
    if t >= t_min && t <= t_max && t.is_fin() {
        Some((t, u, v))
    } else {
        None
    }
}

/// Flat hit (Möller–Trumbore) with a shading normal: the face normal when `normals` is `None`
/// (flat shading), the normalised barycentric interpolation of the vertex normals otherwise
/// (Phong shading). `t_error` is 0 (the flat triangle is exact), `feature` 0.
///
/// # Accuracy
/// As [`moller_trumbore`].
/// # Panics
/// Never.
#[inline]
pub fn flat_hit<F: Float>(
    tri: &[F::Vec3; 3],
    normals: Option<&[F::Vec3; 3]>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
) -> Option<Hit<F>> {
    let (t, w1, w2) = moller_trumbore(tri, ray, t_min, t_max)?;
    let [p0, p1, p2] = tri.map(F::from_glam);
    let face = (p1 - p0).cross(p2 - p0).try_normalize()?;
    let n = match normals {
        None => face,
        Some(ns) => {
            let [n0, n1, n2] = ns.map(F::from_glam);
            let w0 = F::ONE - w1 - w2;
            (n0 * w0 + n1 * w1 + n2 * w2)
                .try_normalize()
                .unwrap_or(face)
        }
    };
    let d = F::from_glam(ray.dir);
    Some(Hit {
        t,
        t_error: F::ZERO,
        point: ray.at(t),
        normal: F::to_glam(n),
        w1,
        w2,
        front_face: face.dot(d) < F::ZERO,
        patch: 0,
    })
}
