//! The batched queries of a scene, in one precision: closest hits, occlusion and surface
//! evaluation, each ray or point independent, written into caller-visible arrays from many
//! threads. Inputs are checked as they are read; the first bad one is reported after the
//! batch ([`BadInput`]).

use smoothtri::{Ray, Scene};

use crate::arrays::{PerRay, Rows, num};
use crate::batch::{FirstBad, Rows as Out, Split, Threads, split_fields};
use crate::budget::Budget;
use crate::precision::Prec;

/// A batch of rays: origins and directions `(R, 3)`, and the interval of `t`.
#[derive(Clone, Copy)]
pub struct RayBatch<'a> {
    /// Ray origins.
    pub origins: Rows<'a>,
    /// Ray directions (any non-zero length; `t` is in units of it).
    pub directions: Rows<'a>,
    /// The smallest `t` accepted.
    pub t_min: PerRay<'a>,
    /// The largest `t` accepted.
    pub t_max: PerRay<'a>,
}

/// Why an input of a batch was refused: its index and the words of the message.
#[derive(Clone, Debug, PartialEq)]
pub struct BadInput {
    /// The ray or point.
    pub index: usize,
    /// What is wrong with it (a sentence naming the argument).
    pub why: String,
}

impl RayBatch<'_> {
    /// The number of rays.
    pub fn len(&self) -> usize {
        self.origins.len()
    }

    /// Ray `i` in precision `F` with its interval, or `None` when it is not a ray: a
    /// non-finite origin or direction (after rounding to `F`), a zero direction, a NaN bound.
    /// An interval with `t_min > t_max` is a ray that hits nothing.
    #[inline]
    pub fn ray<F: Prec>(&self, i: usize) -> Option<(Ray<F>, F, F)> {
        let [ox, oy, oz] = self.origins.row3(i).map(F::from_f64);
        let [dx, dy, dz] = self.directions.row3(i).map(F::from_f64);
        // `&`, not `&&`: six comparisons without branches.
        let finite =
            ox.is_fin() & oy.is_fin() & oz.is_fin() & dx.is_fin() & dy.is_fin() & dz.is_fin();
        let zero = (dx == F::ZERO) & (dy == F::ZERO) & (dz == F::ZERO);
        let (t0, t1) = (self.t_min.at(i), self.t_max.at(i));
        if !finite || zero || t0.is_nan() || t1.is_nan() {
            return None;
        }
        Some((
            Ray::new(F::from_array3([ox, oy, oz]), F::from_array3([dx, dy, dz])),
            F::from_f64(t0),
            F::from_f64(t1),
        ))
    }

    /// Why ray `i` is refused by [`RayBatch::ray`] in precision `F`.
    pub fn why<F: Prec>(&self, i: usize) -> String {
        let o = self.origins.row3(i);
        let d = self.directions.row3(i);
        let show = |v: [f64; 3]| format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]));
        let finite = |v: [f64; 3]| v.map(F::from_f64).iter().all(|x| x.is_fin());
        if !finite(o) {
            return format!("origins[{i}] = {} is not finite in {}", show(o), F::DTYPE);
        }
        if !finite(d) {
            return format!(
                "directions[{i}] = {} is not finite in {}",
                show(d),
                F::DTYPE
            );
        }
        if d.map(F::from_f64).iter().all(|&x| x == F::ZERO) {
            return format!(
                "directions[{i}] = {} is zero in {}: a ray needs a direction",
                show(d),
                F::DTYPE
            );
        }
        if self.t_min.at(i).is_nan() {
            return format!("t_min[{i}] is nan");
        }
        format!("t_max[{i}] is nan")
    }
}

/// The closest-hit outputs of a batch, one row per ray.
pub struct HitsOut<'a, F> {
    /// Whether the ray hit.
    pub hit: &'a mut [bool],
    /// `t` of the hit.
    pub t: &'a mut [F],
    /// The certified bound on `|t − t_true|`.
    pub t_error: &'a mut [F],
    /// The hit point, `(R, 3)`.
    pub point: Out<'a, F, 3>,
    /// The geometric normal, `(R, 3)`.
    pub normal: Out<'a, F, 3>,
    /// The shading normal, `(R, 3)`.
    pub shading_normal: Out<'a, F, 3>,
    /// The input triangle, `-1` on a miss.
    pub triangle: &'a mut [i64],
    /// `(w1, w2)`, `(R, 2)`.
    pub barycentric: Out<'a, F, 2>,
}

split_fields!(HitsOut: hit, t, t_error, point, normal, shading_normal, triangle, barycentric);

/// A batched ray query ([`closest_hit`], [`any_hit`]): the scene, the rays, the budget, the
/// outputs `O`, the threads.
pub type RayQueryFn<F, O> =
    fn(&Scene<'_, F>, &RayBatch<'_>, Budget, O, &Threads) -> Result<(), BadInput>;

/// Writes the closest hit of every ray of `rays` with `t` in its interval into `out`
/// (`Scene::closest_hit` at `budget`). A miss writes `hit = false`, `t = inf`, `t_error = 0`,
/// zero vectors, `triangle = -1`. Returns the first ray that is not a ray.
pub fn closest_hit<F: Prec>(
    scene: &Scene<'_, F>,
    rays: &RayBatch<'_>,
    budget: Budget,
    out: HitsOut<'_, F>,
    threads: &Threads,
) -> Result<(), BadInput> {
    let bad = FirstBad::new();
    threads.for_chunks(out, &|start, out: HitsOut<'_, F>| {
        // Every output cut to the chunk's length, so that the writes below need no checks.
        let n = out.hit.len();
        let (t, t_error, triangle) = (
            &mut out.t[..n],
            &mut out.t_error[..n],
            &mut out.triangle[..n],
        );
        let point = &mut out.point.0[..3 * n];
        let normal = &mut out.normal.0[..3 * n];
        let shading = &mut out.shading_normal.0[..3 * n];
        let bary = &mut out.barycentric.0[..2 * n];
        for (k, hit) in out.hit.iter_mut().enumerate() {
            let i = start + k;
            let found = match rays.ray::<F>(i) {
                Some((ray, t0, t1)) => budget.closest(scene, &ray, t0, t1),
                None => {
                    bad.report(i);
                    None
                }
            };
            let (p, nr, s) = (3 * k, 3 * k, 3 * k);
            match found {
                Some(h) => {
                    *hit = true;
                    t[k] = h.hit.t;
                    t_error[k] = h.hit.t_error;
                    point[p..p + 3].copy_from_slice(&F::to_array3(h.hit.point));
                    normal[nr..nr + 3].copy_from_slice(&F::to_array3(h.hit.normal));
                    shading[s..s + 3].copy_from_slice(&F::to_array3(h.shading_normal));
                    triangle[k] = i64::from(h.triangle);
                    bary[2 * k..2 * k + 2].copy_from_slice(&[h.hit.w1, h.hit.w2]);
                }
                None => {
                    *hit = false;
                    t[k] = F::from_f64(f64::INFINITY);
                    t_error[k] = F::ZERO;
                    point[p..p + 3].fill(F::ZERO);
                    normal[nr..nr + 3].fill(F::ZERO);
                    shading[s..s + 3].fill(F::ZERO);
                    triangle[k] = -1;
                    bary[2 * k..2 * k + 2].fill(F::ZERO);
                }
            }
        }
    });
    first_bad::<F>(rays, &bad)
}

/// Writes into `out` whether each ray of `rays` hits anything with `t` in its interval
/// (`Scene::any_hit` at `budget`). Returns the first ray that is not a ray.
pub fn any_hit<F: Prec>(
    scene: &Scene<'_, F>,
    rays: &RayBatch<'_>,
    budget: Budget,
    out: &mut [bool],
    threads: &Threads,
) -> Result<(), BadInput> {
    let bad = FirstBad::new();
    threads.for_chunks(out, &|start, out: &mut [bool]| {
        for (k, slot) in out.iter_mut().enumerate() {
            let i = start + k;
            *slot = match rays.ray::<F>(i) {
                Some((ray, t0, t1)) => budget.any(scene, &ray, t0, t1),
                None => {
                    bad.report(i);
                    false
                }
            };
        }
    });
    first_bad::<F>(rays, &bad)
}

fn first_bad<F: Prec>(rays: &RayBatch<'_>, bad: &FirstBad) -> Result<(), BadInput> {
    match bad.get() {
        None => Ok(()),
        Some(index) => Err(BadInput {
            index,
            why: rays.why::<F>(index),
        }),
    }
}

/// Points on the surface: a triangle and barycentrics `(w1, w2)` each.
#[derive(Clone, Copy)]
pub struct PointBatch<'a> {
    /// Input triangles (already checked to be triangles of the mesh).
    pub triangles: &'a [u32],
    /// `(w1, w2)` per point.
    pub barycentric: Rows<'a>,
}

/// The evaluation outputs, one row per point.
pub struct SurfaceOut<'a, F> {
    /// The surface point, `(M, 3)`.
    pub point: Out<'a, F, 3>,
    /// The geometric normal, `(M, 3)`.
    pub normal: Out<'a, F, 3>,
    /// The shading normal, `(M, 3)`.
    pub shading_normal: Out<'a, F, 3>,
}

split_fields!(SurfaceOut: point, normal, shading_normal);

/// Writes the surface point, geometric normal and shading normal of every point of `points`
/// into `out` (`Patch::point_normal`, then `Seam::correct` where the scene has seams).
/// Returns the first point whose triangle was rejected by the build or whose barycentrics
/// are not finite in `F`.
pub fn evaluate<F: Prec>(
    scene: &Scene<'_, F>,
    points: &PointBatch<'_>,
    out: SurfaceOut<'_, F>,
    threads: &Threads,
) -> Result<(), BadInput> {
    let bad = FirstBad::new();
    threads.for_chunks(out, &|start, mut out: SurfaceOut<'_, F>| {
        for k in 0..out.point.len() {
            let i = start + k;
            let w1 = F::from_f64(points.barycentric.at(i, 0));
            let w2 = F::from_f64(points.barycentric.at(i, 1));
            let patch = points
                .triangles
                .get(i)
                .and_then(|&t| scene.patch_index(t))
                .and_then(|p| Some((p, scene.patches().get(p)?)));
            let z = [F::ZERO; 3];
            match patch {
                Some((p, patch)) if w1.is_fin() && w2.is_fin() => {
                    let (x, n) = patch.point_normal(w1, w2);
                    let s = match scene.seams().get(p) {
                        Some(seam) => seam.correct(patch, w1, w2, n),
                        None => n,
                    };
                    out.point.set(k, F::to_array3(x));
                    out.normal.set(k, F::to_array3(n));
                    out.shading_normal.set(k, F::to_array3(s));
                }
                _ => {
                    bad.report(i);
                    out.point.set(k, z);
                    out.normal.set(k, z);
                    out.shading_normal.set(k, z);
                }
            }
        }
    });
    let Some(index) = bad.get() else {
        return Ok(());
    };
    let tri = points.triangles.get(index).copied().unwrap_or(u32::MAX);
    let why = if scene.patch_index(tri).is_none() {
        format!(
            "triangles[{index}] = {tri}: that triangle was rejected by the build (scene.report says why)"
        )
    } else {
        let w = [
            points.barycentric.at(index, 0),
            points.barycentric.at(index, 1),
        ];
        format!(
            "barycentrics[{index}] = ({}, {}) is not finite in {}",
            num(w[0]),
            num(w[1]),
            F::DTYPE
        )
    };
    Err(BadInput { index, why })
}
