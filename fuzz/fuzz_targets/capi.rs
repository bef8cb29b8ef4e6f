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

/// Maps a fuzzed vertex onto a small sphere-like cloud: finite positions, normals pointing
/// outwards, so most triangles are accepted.
fn structured(v: [f64; 6]) -> [f64; 6] {
    let f = |x: f64| {
        if x.is_finite() {
            (x.abs().fract() - 0.5) * 2.0
        } else {
            0.25
        }
    };
    let p = [f(v[0]), f(v[1]), f(v[2])];
    let n = [
        p[0] + 0.1 * f(v[3]),
        p[1] + 0.1 * f(v[4]),
        p[2] + 0.1 * f(v[5]) + 1e-3,
    ];
    [p[0], p[1], p[2], n[0], n[1], n[2]]
}

/// One precision's entry points.
trait Api: Copy + Default + PartialEq + core::fmt::Debug {
    type Scene;
    fn from_f64(x: f64) -> Self;
    fn finite(self) -> bool;
    fn required(vc: usize, tc: usize, flags: u32, bytes: &mut usize) -> st_status;
    #[allow(clippy::too_many_arguments)]
    unsafe fn build(
        memory: *mut u8,
        bytes: usize,
        p: *const Self,
        ps: usize,
        n: *const Self,
        ns: usize,
        vc: usize,
        idx: *const u32,
        tc: usize,
        flags: u32,
        it: u32,
        out: *mut *mut Self::Scene,
    ) -> st_status;
    unsafe fn update(
        s: *mut Self::Scene,
        p: *const Self,
        ps: usize,
        n: *const Self,
        ns: usize,
        vc: usize,
    ) -> st_status;
    unsafe fn info(s: *const Self::Scene, info: *mut st_scene_info) -> st_status;
    /// `(tfar, t_error, prim_id)` of the ray's closest hit, `None` for a miss.
    unsafe fn trace(s: *const Self::Scene, ray: [f32; 6]) -> Option<(Self, Self, u32)>;
}

impl Api for f32 {
    type Scene = st_scene;
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn finite(self) -> bool {
        self.is_finite()
    }
    fn required(vc: usize, tc: usize, flags: u32, bytes: &mut usize) -> st_status {
        unsafe { st_scene_required_bytes(vc, tc, flags, bytes) }
    }
    unsafe fn build(
        memory: *mut u8,
        bytes: usize,
        p: *const f32,
        ps: usize,
        n: *const f32,
        ns: usize,
        vc: usize,
        idx: *const u32,
        tc: usize,
        flags: u32,
        it: u32,
        out: *mut *mut st_scene,
    ) -> st_status {
        unsafe {
            st_scene_build(
                memory.cast(),
                bytes,
                p,
                ps,
                n,
                ns,
                vc,
                idx,
                tc,
                flags,
                it,
                out,
            )
        }
    }
    unsafe fn update(
        s: *mut st_scene,
        p: *const f32,
        ps: usize,
        n: *const f32,
        ns: usize,
        vc: usize,
    ) -> st_status {
        unsafe { st_scene_update(s, p, ps, n, ns, vc) }
    }
    unsafe fn info(s: *const st_scene, info: *mut st_scene_info) -> st_status {
        unsafe { st_scene_get_info(s, info) }
    }
    unsafe fn trace(s: *const st_scene, r: [f32; 6]) -> Option<(f32, f32, u32)> {
        let mut rh = st_rayhit::default();
        rh.ray.org_x = r[0];
        rh.ray.org_y = r[1];
        rh.ray.org_z = r[2];
        rh.ray.dir_x = r[3];
        rh.ray.dir_y = r[4];
        rh.ray.dir_z = r[5];
        rh.ray.tfar = f32::INFINITY;
        unsafe { st_intersect1(s, &mut rh) };
        (rh.hit.geom_id != ST_INVALID_ID).then_some((rh.ray.tfar, rh.hit.t_error, rh.hit.prim_id))
    }
}

impl Api for f64 {
    type Scene = st_scene_f64;
    fn from_f64(x: f64) -> Self {
        x
    }
    fn finite(self) -> bool {
        self.is_finite()
    }
    fn required(vc: usize, tc: usize, flags: u32, bytes: &mut usize) -> st_status {
        unsafe { st_scene_required_bytes_f64(vc, tc, flags, bytes) }
    }
    unsafe fn build(
        memory: *mut u8,
        bytes: usize,
        p: *const f64,
        ps: usize,
        n: *const f64,
        ns: usize,
        vc: usize,
        idx: *const u32,
        tc: usize,
        flags: u32,
        it: u32,
        out: *mut *mut st_scene_f64,
    ) -> st_status {
        unsafe {
            st_scene_build_f64(
                memory.cast(),
                bytes,
                p,
                ps,
                n,
                ns,
                vc,
                idx,
                tc,
                flags,
                it,
                out,
            )
        }
    }
    unsafe fn update(
        s: *mut st_scene_f64,
        p: *const f64,
        ps: usize,
        n: *const f64,
        ns: usize,
        vc: usize,
    ) -> st_status {
        unsafe { st_scene_update_f64(s, p, ps, n, ns, vc) }
    }
    unsafe fn info(s: *const st_scene_f64, info: *mut st_scene_info) -> st_status {
        unsafe { st_scene_get_info_f64(s, info) }
    }
    unsafe fn trace(s: *const st_scene_f64, r: [f32; 6]) -> Option<(f64, f64, u32)> {
        let mut rh = st_rayhit_f64::default();
        rh.ray.org_x = r[0].into();
        rh.ray.org_y = r[1].into();
        rh.ray.org_z = r[2].into();
        rh.ray.dir_x = r[3].into();
        rh.ray.dir_y = r[4].into();
        rh.ray.dir_z = r[5].into();
        rh.ray.tfar = f64::INFINITY;
        unsafe { st_intersect1_f64(s, &mut rh) };
        (rh.hit.geom_id != ST_INVALID_ID).then_some((rh.ray.tfar, rh.hit.t_error, rh.hit.prim_id))
    }
}

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
    check_status(T::required(vc, tc, flags, &mut bytes));
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
        T::build(
            memory.as_mut_ptr(),
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
    assert_eq!(unsafe { T::info(scene, &mut info) }, ST_OK);
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
            T::update(
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
            assert_eq!(unsafe { T::info(scene, &mut info) }, ST_OK);
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
