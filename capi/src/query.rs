//! The queries behind the C functions, once for both precisions: rays in, hits out.

use core::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind};

use glam::DVec3;
use smoothtri::{Float, Ray, SceneHit};
use smoothtri_isa::kernels;

use crate::store::{Prec, Stored};
use crate::types::{
    ST_ERROR_INDEX_OUT_OF_RANGE, ST_ERROR_INTERNAL, ST_ERROR_INVALID_ARGUMENT, ST_INVALID_ID,
    ST_OK, st_hit, st_hit_f64, st_ray, st_ray_f64, st_rayhit, st_rayhit_f64, st_rayhit8,
    st_rayhit8_f64, st_status,
};

/// Runs `f`, swallowing a panic (none is expected: the core does not panic) so that it never
/// unwinds into C.
pub(crate) fn guard(f: impl FnOnce()) {
    let _ = catch_unwind(AssertUnwindSafe(f));
}

/// Runs `f`; a panic becomes [`ST_ERROR_INTERNAL`].
pub(crate) fn guard_status(f: impl FnOnce() -> st_status) -> st_status {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(ST_ERROR_INTERNAL)
}

/// Runs `f`; a panic becomes `false`.
pub(crate) fn guard_bool(f: impl FnOnce() -> bool) -> bool {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(false)
}

/// A ray of the C API in precision `F`: the core's ray and its `[tnear, tfar]`.
pub(crate) struct Query<F: Float> {
    ray: Ray<F>,
    tnear: F,
    tfar: F,
}

fn vec<F: Float>(x: F, y: F, z: F) -> F::Vec3 {
    F::from_dvec3(DVec3::new(x.to_f64(), y.to_f64(), z.to_f64()))
}

/// The components of a vector of precision `F` (exact: widened to `f64` and back).
fn xyz<F: Float>(v: F::Vec3) -> [F; 3] {
    let d = F::to_dvec3(v);
    [F::from_f64(d.x), F::from_f64(d.y), F::from_f64(d.z)]
}

/// A C ray struct of one precision.
pub(crate) trait CRay {
    /// Its precision.
    type F: Prec;
    /// The query it describes.
    fn query(&self) -> Query<Self::F>;
    /// Marks it occluded (Embree's `tfar = -∞`).
    fn occlude(&mut self);
}

/// A C ray-hit struct of one precision.
pub(crate) trait CRayHit {
    /// Its precision.
    type F: Prec;
    /// The query its ray describes.
    fn query(&self) -> Query<Self::F>;
    /// Writes a hit: `tfar` and every hit field.
    fn write_hit(&mut self, h: &SceneHit<Self::F>);
    /// Writes a miss: the ids invalid, nothing else.
    fn write_miss(&mut self);
}

macro_rules! c_structs {
    ($f:ty, $ray:ident, $hit:ident, $rayhit:ident, $rayhit8:ident) => {
        impl CRay for $ray {
            type F = $f;
            fn query(&self) -> Query<$f> {
                Query {
                    ray: Ray::new(
                        vec(self.org_x, self.org_y, self.org_z),
                        vec(self.dir_x, self.dir_y, self.dir_z),
                    ),
                    tnear: self.tnear,
                    tfar: self.tfar,
                }
            }
            fn occlude(&mut self) {
                self.tfar = <$f>::NEG_INFINITY;
            }
        }

        impl CRayHit for $rayhit {
            type F = $f;
            fn query(&self) -> Query<$f> {
                self.ray.query()
            }
            fn write_hit(&mut self, h: &SceneHit<$f>) {
                let [ng_x, ng_y, ng_z] = xyz::<$f>(h.hit.normal);
                let [ns_x, ns_y, ns_z] = xyz::<$f>(h.shading_normal);
                // Field by field: the caller's padding bytes stay as they were.
                self.ray.tfar = h.hit.t;
                let o = &mut self.hit;
                (o.ng_x, o.ng_y, o.ng_z) = (ng_x, ng_y, ng_z);
                (o.u, o.v) = (h.hit.w1, h.hit.w2);
                (o.prim_id, o.geom_id) = (h.triangle, 0);
                (o.ns_x, o.ns_y, o.ns_z) = (ns_x, ns_y, ns_z);
                o.t_error = h.hit.t_error;
            }
            fn write_miss(&mut self) {
                self.hit.prim_id = ST_INVALID_ID;
                self.hit.geom_id = ST_INVALID_ID;
            }
        }

        impl Lanes8 for $rayhit8 {
            type One = $rayhit;
            fn get(&self, i: usize) -> Option<$rayhit> {
                let (r, h) = (&self.ray, &self.hit);
                Some($rayhit {
                    ray: <$ray>::from_lane(r, i)?,
                    hit: $hit {
                        ng_x: *h.ng_x.get(i)?,
                        ng_y: *h.ng_y.get(i)?,
                        ng_z: *h.ng_z.get(i)?,
                        u: *h.u.get(i)?,
                        v: *h.v.get(i)?,
                        prim_id: *h.prim_id.get(i)?,
                        geom_id: *h.geom_id.get(i)?,
                        ns_x: *h.ns_x.get(i)?,
                        ns_y: *h.ns_y.get(i)?,
                        ns_z: *h.ns_z.get(i)?,
                        t_error: *h.t_error.get(i)?,
                    },
                })
            }
            fn set(&mut self, i: usize, one: &$rayhit) -> Option<()> {
                let (r, h) = (&mut self.ray, &mut self.hit);
                *r.tfar.get_mut(i)? = one.ray.tfar;
                let x = &one.hit;
                *h.ng_x.get_mut(i)? = x.ng_x;
                *h.ng_y.get_mut(i)? = x.ng_y;
                *h.ng_z.get_mut(i)? = x.ng_z;
                *h.u.get_mut(i)? = x.u;
                *h.v.get_mut(i)? = x.v;
                *h.prim_id.get_mut(i)? = x.prim_id;
                *h.geom_id.get_mut(i)? = x.geom_id;
                *h.ns_x.get_mut(i)? = x.ns_x;
                *h.ns_y.get_mut(i)? = x.ns_y;
                *h.ns_z.get_mut(i)? = x.ns_z;
                *h.t_error.get_mut(i)? = x.t_error;
                Some(())
            }
        }
    };
}

c_structs!(f32, st_ray, st_hit, st_rayhit, st_rayhit8);
c_structs!(f64, st_ray_f64, st_hit_f64, st_rayhit_f64, st_rayhit8_f64);

macro_rules! ray_from_lane {
    ($ray:ident, $ray8:ty) => {
        impl $ray {
            /// Lane `i` of eight SoA rays.
            fn from_lane(r: &$ray8, i: usize) -> Option<Self> {
                Some(Self {
                    org_x: *r.org_x.get(i)?,
                    org_y: *r.org_y.get(i)?,
                    org_z: *r.org_z.get(i)?,
                    tnear: *r.tnear.get(i)?,
                    dir_x: *r.dir_x.get(i)?,
                    dir_y: *r.dir_y.get(i)?,
                    dir_z: *r.dir_z.get(i)?,
                    time: *r.time.get(i)?,
                    tfar: *r.tfar.get(i)?,
                    mask: *r.mask.get(i)?,
                    id: *r.id.get(i)?,
                    flags: *r.flags.get(i)?,
                })
            }
        }
    };
}

ray_from_lane!(st_ray, crate::types::st_ray8);
ray_from_lane!(st_ray_f64, crate::types::st_ray8_f64);

/// Eight SoA ray-hits, lane by lane.
pub(crate) trait Lanes8 {
    /// One lane's ray-hit.
    type One: CRayHit;
    /// Lane `i` (`None` beyond 8).
    fn get(&self, i: usize) -> Option<Self::One>;
    /// Writes back lane `i`'s `tfar` and hit.
    fn set(&mut self, i: usize, one: &Self::One) -> Option<()>;
}

/// `st_intersect1` on one ray-hit.
pub(crate) fn trace_one<R: CRayHit>(scene: &Stored<R::F>, rh: &mut R) {
    let q = rh.query();
    let n = scene.iterations as usize;
    match kernels().scene_closest_hit(&scene.scene(), &q.ray, q.tnear, q.tfar, n) {
        Some(h) => rh.write_hit(&h),
        None => rh.write_miss(),
    }
}

/// `st_intersect1`.
///
/// # Safety
/// `rayhit` NULL or valid for reads and writes.
pub(crate) unsafe fn intersect1<R: CRayHit>(scene: Option<&Stored<R::F>>, rayhit: *mut R) {
    if rayhit.is_null() || !rayhit.is_aligned() {
        return;
    }
    // SAFETY: non-null, aligned, valid and not aliased during the call by the contract.
    let rh = unsafe { &mut *rayhit };
    match scene {
        Some(s) => trace_one(s, rh),
        None => rh.write_miss(),
    }
}

/// `st_occluded1`.
///
/// # Safety
/// `ray` NULL or valid for reads and writes.
pub(crate) unsafe fn occluded1<R: CRay>(scene: Option<&Stored<R::F>>, ray: *mut R) {
    let Some(s) = scene else { return };
    if ray.is_null() || !ray.is_aligned() {
        return;
    }
    // SAFETY: non-null, aligned, valid and not aliased during the call by the contract.
    let r = unsafe { &mut *ray };
    let q = r.query();
    let n = s.iterations as usize;
    if kernels().scene_any_hit(&s.scene(), &q.ray, q.tnear, q.tfar, n) {
        r.occlude();
    }
}

/// `st_intersect8`.
///
/// # Safety
/// `valid` NULL or readable for 8 values; `rayhit` NULL or valid.
pub(crate) unsafe fn intersect8<L: Lanes8>(
    valid: *const i32,
    scene: Option<&Stored<<L::One as CRayHit>::F>>,
    rayhit: *mut L,
) {
    if valid.is_null() || !valid.is_aligned() || rayhit.is_null() || !rayhit.is_aligned() {
        return;
    }
    // SAFETY: non-null, aligned and readable for 8 values by the contract.
    let valid = unsafe { &*valid.cast::<[i32; 8]>() };
    // SAFETY: non-null, aligned, valid and not aliased during the call by the contract.
    let rh = unsafe { &mut *rayhit };
    for (i, &v) in valid.iter().enumerate() {
        if v == 0 {
            continue;
        }
        let Some(mut one) = rh.get(i) else { continue };
        match scene {
            Some(s) => trace_one(s, &mut one),
            None => one.write_miss(),
        }
        let _ = rh.set(i, &one);
    }
}

/// `st_intersect1M`.
///
/// # Safety
/// `rayhits` NULL or valid for `count` ray-hits at `byte_stride`.
pub(crate) unsafe fn intersect1m<R: CRayHit>(
    scene: Option<&Stored<R::F>>,
    rayhits: *mut R,
    count: usize,
    byte_stride: usize,
) {
    let stride = if byte_stride == 0 {
        size_of::<R>()
    } else {
        byte_stride
    };
    if rayhits.is_null()
        || !rayhits.is_aligned()
        || stride < size_of::<R>()
        || stride % align_of::<R>() != 0
    {
        return;
    }
    for k in 0..count {
        let Some(offset) = k.checked_mul(stride) else {
            return;
        };
        // SAFETY: by the contract the stream holds `count` ray-hits at `stride` bytes, so the
        // `k`-th starts at `offset` inside it; `stride` is a multiple of the alignment and the
        // base is aligned, so it is aligned; no two overlap (stride ≥ size).
        let rh = unsafe { &mut *rayhits.cast::<u8>().add(offset).cast::<R>() };
        match scene {
            Some(s) => trace_one(s, rh),
            None => rh.write_miss(),
        }
    }
}

/// `st_patch_bounds`.
///
/// # Safety
/// `scene` NULL or a scene; `out` NULL or writable for 6 values.
pub(crate) unsafe fn patch_bounds<F: Prec>(
    scene: *const c_void,
    prim: u32,
    out: *mut F,
) -> st_status {
    let s = match Stored::<F>::with_output(scene, out) {
        Ok(s) => s,
        Err(e) => return e,
    };
    let Some(patch) = s.scene().patches().get(prim as usize) else {
        return ST_ERROR_INDEX_OUT_OF_RANGE;
    };
    if !out.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    let b = patch.bounds();
    let [x0, y0, z0] = xyz::<F>(b.min());
    let [x1, y1, z1] = xyz::<F>(b.max());
    // SAFETY: non-null, aligned and writable for 6 values by the contract.
    unsafe { out.cast::<[F; 6]>().write([x0, y0, z0, x1, y1, z1]) };
    ST_OK
}

/// `st_patch_intersect`.
///
/// # Safety
/// `rayhit` NULL or valid for reads and writes.
pub(crate) unsafe fn patch_closest_hit<R: CRayHit>(
    scene: Option<&Stored<R::F>>,
    prim: u32,
    rayhit: *mut R,
) -> bool {
    let Some(s) = scene else { return false };
    let Some(patch) = s.scene().patches().get(prim as usize) else {
        return false;
    };
    if rayhit.is_null() || !rayhit.is_aligned() {
        return false;
    }
    // SAFETY: non-null, aligned, valid and not aliased during the call by the contract.
    let rh = unsafe { &mut *rayhit };
    let q = rh.query();
    let n = s.iterations as usize;
    match kernels().patch_closest_hit(patch, &q.ray, q.tnear, q.tfar, n) {
        Some(mut h) => {
            h.patch = prim;
            rh.write_hit(&s.scene().scene_hit(h));
            true
        }
        None => false,
    }
}

/// `st_patch_of_triangle`.
///
/// # Safety
/// `scene` NULL or a scene; `prim` NULL or writable.
pub(crate) unsafe fn patch_of_triangle<F: Prec>(
    scene: *const c_void,
    triangle: u32,
    prim: *mut u32,
) -> st_status {
    let s = match Stored::<F>::with_output(scene, prim) {
        Ok(s) => s,
        Err(e) => return e,
    };
    let Some(index) = s.scene().patch_index(triangle) else {
        return ST_ERROR_INDEX_OUT_OF_RANGE;
    };
    if !prim.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    // SAFETY: non-null, aligned and writable by the contract; patch indices fit in `u32`
    // (the build refuses more than `u32::MAX` triangles).
    unsafe { prim.write(index as u32) };
    ST_OK
}
