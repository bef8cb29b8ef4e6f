//! Fuzz target `capi`: the C API's `st_scene_build` and `st_scene_update` (and their `_f64`
//! twins) on arbitrary vertex buffers, strides, counts, index buffers, flags, iteration counts
//! and memory sizes, the way a C caller could misuse them within the documented contract.
//!
//! Every buffer handed over is a real allocation at least as long as the arguments say it is
//! (the contract), but the arguments themselves are arbitrary: strides below three scalars or
//! not multiples of the scalar size, vertex counts that differ from the build's, indices out of
//! range, NaN and infinite coordinates, unknown flags, memory shorter than
//! `st_scene_required_bytes`. Asserts: each call returns a documented status; after `ST_OK`
//! the scene's info is consistent and every hit of a few rays is finite (`t` in range,
//! `t_error ≥ 0`); after a failed update the scene answers those rays bit for bit as before.
//! Any panic, abort or sanitizer report is a bug.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use smoothtri_capi::*;

#[path = "structured.rs"]
mod structured;
use structured::structured;

#[derive(Arbitrary, Debug)]
struct Input {
    /// Bit 0: f64 (else f32); bit 1: memory one byte short; bit 2: structured vertices.
    mode: u8,
    flags: u32,
    iterations: u8,
    vertices: Vec<[f64; 6]>,
    indices: Vec<[u16; 3]>,
    strides: [u8; 2],
    updates: Vec<Update>,
    rays: Vec<[f32; 6]>,
}

#[derive(Arbitrary, Debug)]
struct Update {
    /// Vertices of the update (their count may differ from the build's).
    vertices: Vec<[f64; 6]>,
    /// Bit 0: use the build's vertex count, reading `vertices` cyclically.
    mode: u8,
    strides: [u8; 2],
}

/// The documented statuses.
const STATUSES: [st_status; 11] = [
    ST_OK,
    ST_ERROR_NULL_ARGUMENT,
    ST_ERROR_INVALID_ARGUMENT,
    ST_ERROR_BUFFER_TOO_SMALL,
    ST_ERROR_NO_USABLE_TRIANGLES,
    ST_ERROR_INDEX_OUT_OF_RANGE,
    ST_ERROR_NON_FINITE,
    ST_ERROR_TOO_LARGE,
    ST_ERROR_WRONG_SCENE,
    ST_ERROR_INTERNAL,
    ST_ERROR_NOT_UPDATABLE,
];

/// `st_scene_build`'s signature for scalars `T` and scenes `S`.
type BuildFn<T, S> = unsafe extern "C" fn(
    *mut core::ffi::c_void,
    usize,
    *const T,
    usize,
    *const T,
    usize,
    usize,
    *const u32,
    usize,
    u32,
    u32,
    *mut *mut S,
) -> st_status;

/// `st_scene_update`'s signature for scalars `T` and scenes `S`.
type UpdateFn<T, S> =
    unsafe extern "C" fn(*mut S, *const T, usize, *const T, usize, usize) -> st_status;

/// `st_scene_get_info`'s signature for scenes `S`.
type InfoFn<S> = unsafe extern "C" fn(*const S, *mut st_scene_info) -> st_status;

/// `st_scene_required_bytes`'s signature.
type RequiredFn = unsafe extern "C" fn(usize, usize, u32, *mut usize) -> st_status;

/// One precision's entry points.
trait Api: Copy + Default + PartialEq + core::fmt::Debug {
    type Scene;
    /// `st_scene_required_bytes` (or its twin).
    const REQUIRED: RequiredFn;
    /// `st_scene_build` (or its twin).
    const BUILD: BuildFn<Self, Self::Scene>;
    /// `st_scene_update` (or its twin).
    const UPDATE: UpdateFn<Self, Self::Scene>;
    /// `st_scene_get_info` (or its twin).
    const INFO: InfoFn<Self::Scene>;
    fn from_f64(x: f64) -> Self;
    fn finite(self) -> bool;
    /// `(tfar, t_error, prim_id)` of the ray's closest hit, `None` for a miss.
    unsafe fn trace(s: *const Self::Scene, ray: [f32; 6]) -> Option<(Self, Self, u32)>;
}

/// [`Api`] for one precision: its scene and ray-hit types and its `st_*` entry points.
macro_rules! api {
    ($f:ty, $scene:ty, $rayhit:ty, $required:ident, $build:ident, $update:ident, $info:ident, $intersect:ident) => {
        impl Api for $f {
            type Scene = $scene;
            const REQUIRED: RequiredFn = $required;
            const BUILD: BuildFn<$f, $scene> = $build;
            const UPDATE: UpdateFn<$f, $scene> = $update;
            const INFO: InfoFn<$scene> = $info;
            fn from_f64(x: f64) -> Self {
                x as $f
            }
            fn finite(self) -> bool {
                self.is_finite()
            }
            unsafe fn trace(s: *const $scene, r: [f32; 6]) -> Option<($f, $f, u32)> {
                let mut rh = <$rayhit>::default();
                rh.ray.org_x = r[0].into();
                rh.ray.org_y = r[1].into();
                rh.ray.org_z = r[2].into();
                rh.ray.dir_x = r[3].into();
                rh.ray.dir_y = r[4].into();
                rh.ray.dir_z = r[5].into();
                rh.ray.tfar = <$f>::INFINITY;
                unsafe { $intersect(s, &mut rh) };
                (rh.hit.geom_id != ST_INVALID_ID).then_some((
                    rh.ray.tfar,
                    rh.hit.t_error,
                    rh.hit.prim_id,
                ))
            }
        }
    };
}

api!(
    f32,
    st_scene,
    st_rayhit,
    st_scene_required_bytes,
    st_scene_build,
    st_scene_update,
    st_scene_get_info,
    st_intersect1
);
api!(
    f64,
    st_scene_f64,
    st_rayhit_f64,
    st_scene_required_bytes_f64,
    st_scene_build_f64,
    st_scene_update_f64,
    st_scene_get_info_f64,
    st_intersect1_f64
);

/// A vertex buffer laid out at byte strides `strides` (each rounded up to hold a vertex), as
/// long as `count` vertices at those strides need: `(buffer, position stride, normal stride)`
/// in bytes, with the normals at an offset of three scalars inside each record. The strides
/// given to the C API are the fuzzed ones, so they may be invalid; the buffer is long enough
/// for the valid ones the C API reads.
fn layout<T: Api>(
    vertices: &[[f64; 6]],
    count: usize,
    strides: [u8; 2],
    structured_input: bool,
) -> (Vec<T>, usize, usize) {
    let size = core::mem::size_of::<T>();
    let stride_of = |s: u8| usize::from(s) * 4;
    // Scalars per record: six (position then normal) or as much as the largest stride asks.
    let record = 6usize.max(stride_of(strides[0].max(strides[1])).div_ceil(size) + 3);
    let mut buf = vec![T::default(); count * record + 6];
    for i in 0..count {
        let v = if vertices.is_empty() {
            [0.0; 6]
        } else {
            vertices[i % vertices.len()]
        };
        let v = if structured_input { structured(v) } else { v };
        for k in 0..6 {
            buf[i * record + k] = T::from_f64(v[k]);
        }
    }
    // A stride of 0 means packed: three scalars, which reads this buffer's records wrongly but
    // within bounds (the buffer has `record ≥ 6` scalars per vertex).
    (buf, stride_of(strides[0]), stride_of(strides[1]))
}

fn check_status(s: st_status) {
    assert!(STATUSES.contains(&s), "undocumented status {s}");
}

/// Rays' answers, checked finite.
fn answers<T: Api>(scene: *const T::Scene, rays: &[[f32; 6]]) -> Vec<Option<(T, T, u32)>> {
    rays.iter()
        .map(|&r| {
            let a = unsafe { T::trace(scene, r) };
            if let Some((t, e, _)) = a {
                assert!(t.finite() && e.finite(), "non-finite hit {a:?}");
            }
            a
        })
        .collect()
}

fn run<T: Api>(inp: &Input) {
    let structured_input = inp.mode & 4 != 0;
    let vc = inp.vertices.len().min(64);
    let tc = inp.indices.len().min(64);
    let indices: Vec<u32> = inp.indices[..tc]
        .iter()
        .flat_map(|t| t.map(|i| u32::from(i) % (vc as u32 + 2)))
        .collect();
    let flags = inp.flags & 0xF;
    let iterations = [0, 1, 2, 4, 8, 16, 3, 32][usize::from(inp.iterations % 8)];
    let mut bytes = 0usize;
    check_status(unsafe { (T::REQUIRED)(vc, tc, flags, &mut bytes) });
    if bytes == 0 || bytes > 1 << 24 {
        return;
    }
    let short = inp.mode & 2 != 0;
    let len = if short { bytes - 1 } else { bytes };
    let mut memory = vec![0u8; len.max(1)];
    let (buf, ps, ns) = layout::<T>(&inp.vertices, vc, inp.strides, structured_input);
    let normals = buf.as_ptr().wrapping_add(3);
    let mut scene: *mut T::Scene = core::ptr::null_mut();
    let s = unsafe {
        (T::BUILD)(
            memory.as_mut_ptr().cast(),
            len,
            buf.as_ptr(),
            ps,
            normals,
            ns,
            vc,
            indices.as_ptr(),
            tc,
            flags,
            iterations,
            &mut scene,
        )
    };
    check_status(s);
    if s != ST_OK {
        assert!(scene.is_null(), "output written on failure");
        return;
    }
    let mut info = st_scene_info::default();
    assert_eq!(unsafe { (T::INFO)(scene, &mut info) }, ST_OK);
    assert_eq!(info.triangle_count, tc);
    assert!(info.bytes_used <= len);
    let rays = &inp.rays[..inp.rays.len().min(8)];
    let mut before = answers::<T>(scene, rays);
    for u in inp.updates.iter().take(4) {
        let count = if u.mode & 1 != 0 {
            vc
        } else {
            u.vertices.len().min(64)
        };
        let (ubuf, ups, uns) = layout::<T>(&u.vertices, count, u.strides, structured_input);
        let s = unsafe {
            (T::UPDATE)(
                scene,
                ubuf.as_ptr(),
                ups,
                ubuf.as_ptr().wrapping_add(3),
                uns,
                count,
            )
        };
        check_status(s);
        if flags & ST_BUILD_UPDATABLE == 0 {
            assert_eq!(s, ST_ERROR_NOT_UPDATABLE);
        }
        let after = answers::<T>(scene, rays);
        if s == ST_OK {
            let mut info = st_scene_info::default();
            assert_eq!(unsafe { (T::INFO)(scene, &mut info) }, ST_OK);
            assert_eq!(info.triangle_count, tc);
            before = after;
        } else {
            assert_eq!(before, after, "a failed update changed the scene");
        }
    }
}

fuzz_target!(|inp: Input| {
    if inp.mode & 1 != 0 {
        run::<f64>(&inp);
    } else {
        run::<f32>(&inp);
    }
});
