//! # smoothtri-capi
//!
//! The C API of [`smoothtri`]: C and C++ renderers build a scene of smooth patches from their
//! own vertex and index buffers into memory they own, and trace it with Embree-shaped rays. The
//! header `capi/include/smoothtri.h` is generated from this crate by cbindgen (checked in, and
//! checked against the sources by `tests/header.rs`); `capi/include/smoothtri_embree.h` puts
//! the patches into an Embree 3 scene as a user geometry.
//!
//! Shapes (after meshoptimizer and rustls-ffi):
//! - every fallible function returns an [`st_status`]; outputs are written only on [`ST_OK`];
//! - the build allocates nothing: [`st_scene_required_bytes`] says how many bytes
//!   [`st_scene_build`] needs, the caller provides them (any alignment), and the scene lives in
//!   them until the caller frees them (there is no destroy function);
//! - vertex input is strided in bytes, so interleaved vertex buffers need no copy;
//! - every query takes a `const` scene and is thread-safe; only [`st_scene_update`] changes
//!   a scene (one built with [`ST_BUILD_UPDATABLE`]), with no query running: many tracers,
//!   joined, then the update between frames ([`st_scene`] says what is not allowed); there is
//!   no global state;
//! - a NULL pointer or a short buffer is an error status (or, for the `void` queries, a miss),
//!   never a crash; panics never cross the boundary (the core does not panic; each entry point
//!   also catches one and returns [`ST_ERROR_INTERNAL`]).
//!
//! Every type and function has an `_f64` twin for scenes in double precision.
//!
//! This is the one crate of the workspace with `unsafe` code: each block says why it is sound.
#![allow(non_camel_case_types)]
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

mod query;
mod store;
mod types;

use core::ffi::{c_char, c_void};

use query::{guard, guard_status};
use store::Stored;
pub use types::*;

/// The name of a status code as a static, NUL-terminated string (`"ST_OK"`,
/// `"ST_ERROR_NULL_ARGUMENT"`, …; `"ST_ERROR_UNKNOWN"` for a value that is none of them).
/// Never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn st_status_str(status: st_status) -> *const c_char {
    let s: &'static core::ffi::CStr = match status {
        ST_OK => c"ST_OK",
        ST_ERROR_NULL_ARGUMENT => c"ST_ERROR_NULL_ARGUMENT",
        ST_ERROR_INVALID_ARGUMENT => c"ST_ERROR_INVALID_ARGUMENT",
        ST_ERROR_BUFFER_TOO_SMALL => c"ST_ERROR_BUFFER_TOO_SMALL",
        ST_ERROR_NO_USABLE_TRIANGLES => c"ST_ERROR_NO_USABLE_TRIANGLES",
        ST_ERROR_INDEX_OUT_OF_RANGE => c"ST_ERROR_INDEX_OUT_OF_RANGE",
        ST_ERROR_NON_FINITE => c"ST_ERROR_NON_FINITE",
        ST_ERROR_TOO_LARGE => c"ST_ERROR_TOO_LARGE",
        ST_ERROR_WRONG_SCENE => c"ST_ERROR_WRONG_SCENE",
        ST_ERROR_INTERNAL => c"ST_ERROR_INTERNAL",
        ST_ERROR_NOT_UPDATABLE => c"ST_ERROR_NOT_UPDATABLE",
        _ => c"ST_ERROR_UNKNOWN",
    };
    s.as_ptr()
}

/// The instruction set the queries run, as a static, NUL-terminated name: `"sse2"`, `"avx2"`
/// or `"avx512"` on x86-64 (`"neon"` on aarch64). The library's kernel is compiled for each
/// and the widest the CPU has is chosen once, at the first call of this function or of a
/// query; the environment variable `SMOOTHTRI_ISA` (one of those names) overrides the choice
/// when the CPU has the one it names. Every instruction set gives the same hits, bit for bit.
/// Never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn st_get_isa() -> *const c_char {
    smoothtri_isa::kernels().isa().c_name().as_ptr()
}

/// Writes to `*bytes` the size of the memory [`st_scene_build`] needs for a mesh of
/// `vertex_count` vertices and `triangle_count` triangles built with `flags`, whatever the
/// data and the memory's alignment (the padding to align inside it is counted).
///
/// Errors: [`ST_ERROR_NULL_ARGUMENT`] (`bytes`), [`ST_ERROR_INVALID_ARGUMENT`] (unknown
/// flags), [`ST_ERROR_TOO_LARGE`].
///
/// # Safety
/// `bytes` is NULL or valid for one write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_required_bytes(
    vertex_count: usize,
    triangle_count: usize,
    flags: u32,
    bytes: *mut usize,
) -> st_status {
    // SAFETY: forwarded contract: `bytes` is NULL or writable.
    guard_status(|| unsafe {
        store::required_bytes::<f32>(vertex_count, triangle_count, flags, bytes)
    })
}

/// [`st_scene_required_bytes`] for a scene in double precision.
///
/// # Safety
/// As [`st_scene_required_bytes`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_required_bytes_f64(
    vertex_count: usize,
    triangle_count: usize,
    flags: u32,
    bytes: *mut usize,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe {
        store::required_bytes::<f64>(vertex_count, triangle_count, flags, bytes)
    })
}

/// Builds the scene of a triangle mesh into `memory` and writes its address to `*scene`.
///
/// - `memory`, `bytes`: caller memory of at least [`st_scene_required_bytes`] bytes, any
///   alignment. The scene lives in it: keep it unchanged and in place while the scene is used,
///   then free it as it was allocated. Bytes from `memory + bytes_used` on
///   ([`st_scene_info::bytes_used`]) are free again after a successful build. After a failed
///   build its contents are unspecified.
/// - `positions`, `normals`: `vertex_count` × (x, y, z) floats, vertex `i`'s at byte
///   `i · stride` from the pointer (`stride` 0: tightly packed, 12 bytes). Strides are
///   multiples of 4 and at least 12; the pointers are 4-byte aligned. Normals of any non-zero
///   length, pointing to the side from which the triangles are counter-clockwise.
/// - `indices`: `triangle_count` × 3 vertex indices.
/// - `flags`: [`ST_BUILD_SEAMS`], [`ST_BUILD_SHARED_FIELD`], [`ST_BUILD_UPDATABLE`], or 0.
/// - `iterations`: the kernel's refinement steps `N`, any of 0 to [`ST_MAX_ITERATIONS`]
///   (64): the work per patch test is bounded by `N` plus a constant, and `t_error` shrinks at least five-fold
///   per step (8 is a good default in `f32`).
///
/// Triangles the core rejects (degenerate, non-finite, bad normals) are skipped and counted
/// ([`st_scene_get_info`]).
///
/// Errors: [`ST_ERROR_NULL_ARGUMENT`], [`ST_ERROR_INVALID_ARGUMENT`],
/// [`ST_ERROR_BUFFER_TOO_SMALL`], [`ST_ERROR_INDEX_OUT_OF_RANGE`],
/// [`ST_ERROR_NO_USABLE_TRIANGLES`] (no triangle, or all rejected), [`ST_ERROR_NON_FINITE`]
/// (all rejected, the first for a non-finite value), [`ST_ERROR_TOO_LARGE`].
///
/// Work: `O(n log n)`, single-threaded, no allocation.
///
/// # Safety
/// `memory` is NULL or valid for `bytes` bytes of writes; `positions` and `normals` are NULL
/// or readable for `vertex_count` vertices at their strides; `indices` is NULL or readable for
/// `3 · triangle_count` values; `scene` is NULL or writable. None of the input overlaps
/// `memory`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_build(
    memory: *mut c_void,
    bytes: usize,
    positions: *const f32,
    position_stride: usize,
    normals: *const f32,
    normal_stride: usize,
    vertex_count: usize,
    indices: *const u32,
    triangle_count: usize,
    flags: u32,
    iterations: u32,
    scene: *mut *mut st_scene,
) -> st_status {
    let vertices = store::VertexInput {
        positions,
        position_stride,
        normals,
        normal_stride,
        vertex_count,
    };
    let input = store::Input {
        vertices,
        indices,
        triangle_count,
        flags,
        iterations,
    };
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::build_into(memory, bytes, &input, scene.cast()) })
}

/// [`st_scene_build`] in double precision: `double` positions and normals (strides multiples
/// of 8, at least 24; 0 for packed), a scene for the `_f64` queries.
///
/// # Safety
/// As [`st_scene_build`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_build_f64(
    memory: *mut c_void,
    bytes: usize,
    positions: *const f64,
    position_stride: usize,
    normals: *const f64,
    normal_stride: usize,
    vertex_count: usize,
    indices: *const u32,
    triangle_count: usize,
    flags: u32,
    iterations: u32,
    scene: *mut *mut st_scene_f64,
) -> st_status {
    let vertices = store::VertexInput {
        positions,
        position_stride,
        normals,
        normal_stride,
        vertex_count,
    };
    let input = store::Input {
        vertices,
        indices,
        triangle_count,
        flags,
        iterations,
    };
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::build_into(memory, bytes, &input, scene.cast()) })
}

/// Moves an updatable scene (built with [`ST_BUILD_UPDATABLE`]) to new vertex positions and
/// normals, in place, for animated meshes: same index buffer, same memory, no allocation.
///
/// - `positions`, `normals`, strides: as for [`st_scene_build`], `vertex_count` of each (the
///   build's count).
///
/// The scene afterwards equals a fresh [`st_scene_build`] of the same vertices: the same
/// patches, crack closure and seams bit for bit; the BVH's boxes are refitted (or the tree is
/// built anew where a refit's cost passes the core's `REBUILD_COST_RATIO` times a fresh
/// tree's; [`st_scene_info::bvh_refitted`] says which), so hits agree with a fresh build's
/// within their `t_error`. A triangle that degenerates becomes an empty placeholder that no
/// ray reaches, counted in [`st_scene_info`]; `patch_count` and the patch indices do not
/// change. An update that leaves no usable triangle succeeds with a scene every ray misses.
///
/// Errors, each leaving the scene as it was (the last good one): [`ST_ERROR_NULL_ARGUMENT`],
/// [`ST_ERROR_WRONG_SCENE`], [`ST_ERROR_NOT_UPDATABLE`], [`ST_ERROR_INVALID_ARGUMENT`] (a
/// stride or alignment as in [`st_scene_build`], or `vertex_count` not the build's),
/// [`ST_ERROR_NON_FINITE`] (a NaN or infinite coordinate), [`ST_ERROR_TOO_LARGE`].
///
/// Work: that of a build without the pairing of shared edges and, when it refits, without
/// the BVH's build; single-threaded, no allocation. An Embree user geometry over the patches
/// (`smoothtri_embree.h`) must be committed again, as its bounds moved.
///
/// Threads: only between frames, with no query of this scene running on any thread (see
/// [`st_scene`]): tracers joined, update, then trace again.
///
/// # Safety
/// `scene` is NULL or a scene from [`st_scene_build`] whose memory is still valid, and no
/// other thread uses it during the call; `positions` and `normals` are NULL or readable for
/// `vertex_count` vertices at their strides and do not overlap the scene's memory.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_update(
    scene: *mut st_scene,
    positions: *const f32,
    position_stride: usize,
    normals: *const f32,
    normal_stride: usize,
    vertex_count: usize,
) -> st_status {
    let moved = store::VertexInput {
        positions,
        position_stride,
        normals,
        normal_stride,
        vertex_count,
    };
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::update::<f32>(scene.cast(), &moved) })
}

/// [`st_scene_update`] for a scene of [`st_scene_build_f64`]: `double` positions and normals.
///
/// # Safety
/// As [`st_scene_update`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_update_f64(
    scene: *mut st_scene_f64,
    positions: *const f64,
    position_stride: usize,
    normals: *const f64,
    normal_stride: usize,
    vertex_count: usize,
) -> st_status {
    let moved = store::VertexInput {
        positions,
        position_stride,
        normals,
        normal_stride,
        vertex_count,
    };
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::update::<f64>(scene.cast(), &moved) })
}

/// Fills `*info` with what the build of `scene` did.
///
/// Errors: [`ST_ERROR_NULL_ARGUMENT`], [`ST_ERROR_WRONG_SCENE`].
///
/// # Safety
/// `scene` is NULL or a scene from [`st_scene_build`] whose memory is still valid; `info` is
/// NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_get_info(
    scene: *const st_scene,
    info: *mut st_scene_info,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::info::<f32>(scene.cast(), info) })
}

/// [`st_scene_get_info`] of a scene in double precision.
///
/// # Safety
/// As [`st_scene_get_info`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_scene_get_info_f64(
    scene: *const st_scene_f64,
    info: *mut st_scene_info,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { store::info::<f64>(scene.cast(), info) })
}

/// The closest hit of `rayhit->ray` with `t` in `[tnear, tfar]`, through the scene's BVH. On a
/// hit: `ray.tfar` = `t` and every field of `hit` written (`prim_id` the input triangle, `u, v`
/// its barycentrics of vertices 1 and 2, `geom_id` 0). On a miss: `hit.prim_id` and
/// `hit.geom_id` = [`ST_INVALID_ID`], nothing else changes. A NULL or wrong scene is a miss; a
/// NULL `rayhit` does nothing. Rays with a zero or non-finite direction miss.
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `rayhit` NULL or valid for reads and writes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect1(scene: *const st_scene, rayhit: *mut st_rayhit) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect1(Stored::<f32>::from_ptr(scene.cast()), rayhit) })
}

/// [`st_intersect1`] in double precision.
///
/// # Safety
/// As [`st_intersect1`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect1_f64(scene: *const st_scene_f64, rayhit: *mut st_rayhit_f64) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect1(Stored::<f64>::from_ptr(scene.cast()), rayhit) })
}

/// Whether anything blocks `ray` with `t` in `[tnear, tfar]` (shadow rays): sets
/// `ray->tfar = -INFINITY` when occluded (Embree's rule), changes nothing otherwise. Stops at
/// the first crossing found; evaluates no normal. A NULL or wrong scene occludes nothing.
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `ray` NULL or valid for reads and writes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_occluded1(scene: *const st_scene, ray: *mut st_ray) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::occluded1(Stored::<f32>::from_ptr(scene.cast()), ray) })
}

/// [`st_occluded1`] in double precision.
///
/// # Safety
/// As [`st_occluded1`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_occluded1_f64(scene: *const st_scene_f64, ray: *mut st_ray_f64) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::occluded1(Stored::<f64>::from_ptr(scene.cast()), ray) })
}

/// [`st_intersect1`] for each lane `i` of eight SoA rays with `valid[i]` non-zero (Embree
/// passes −1 for active lanes and 0 for inactive ones); inactive lanes are not touched. The
/// lanes are traced one after the other: each lane's result equals [`st_intersect1`]'s for
/// its ray, bit for bit.
///
/// # Safety
/// `valid` NULL (nothing is traced) or readable for 8 values; `scene` as in
/// [`st_scene_get_info`]; `rayhit` NULL or valid and 32-byte aligned.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect8(
    valid: *const i32,
    scene: *const st_scene,
    rayhit: *mut st_rayhit8,
) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect8(valid, Stored::<f32>::from_ptr(scene.cast()), rayhit) })
}

/// [`st_intersect8`] in double precision.
///
/// # Safety
/// As [`st_intersect8`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect8_f64(
    valid: *const i32,
    scene: *const st_scene_f64,
    rayhit: *mut st_rayhit8_f64,
) {
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect8(valid, Stored::<f64>::from_ptr(scene.cast()), rayhit) })
}

/// [`st_intersect1`] over a stream of `count` ray-hits, the `k`-th at byte `k · byte_stride`
/// from `rayhits` (`byte_stride` 0: `sizeof(st_rayhit)`). Nothing is traced when the stride is
/// smaller than `sizeof(st_rayhit)` or not a multiple of 16, or `rayhits` is NULL or not
/// 16-byte aligned.
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `rayhits` NULL or valid for `count` ray-hits at the
/// stride.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect1M(
    scene: *const st_scene,
    rayhits: *mut st_rayhit,
    count: usize,
    byte_stride: usize,
) {
    let scene = Stored::<f32>::from_ptr(scene.cast());
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect1m(scene, rayhits, count, byte_stride) })
}

/// [`st_intersect1M`] in double precision.
///
/// # Safety
/// As [`st_intersect1M`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_intersect1M_f64(
    scene: *const st_scene_f64,
    rayhits: *mut st_rayhit_f64,
    count: usize,
    byte_stride: usize,
) {
    let scene = Stored::<f64>::from_ptr(scene.cast());
    // SAFETY: forwarded contract.
    guard(|| unsafe { query::intersect1m(scene, rayhits, count, byte_stride) })
}

/// Writes to `out` a conservative box of patch `prim` (`0 .. patch_count`, see
/// [`st_scene_info::patch_count`]): min x, y, z then max x, y, z. Every point of the patch's
/// curved shell lies inside, so a BVH of the caller's over these boxes finds every hit of
/// [`st_patch_intersect`].
///
/// Errors: [`ST_ERROR_NULL_ARGUMENT`], [`ST_ERROR_WRONG_SCENE`],
/// [`ST_ERROR_INDEX_OUT_OF_RANGE`] (`prim ≥ patch_count`).
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `out` NULL or writable for 6 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_bounds(
    scene: *const st_scene,
    prim: u32,
    out: *mut f32,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { query::patch_bounds::<f32>(scene.cast(), prim, out) })
}

/// [`st_patch_bounds`] in double precision.
///
/// # Safety
/// As [`st_patch_bounds`] (`out` writable for 6 doubles).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_bounds_f64(
    scene: *const st_scene_f64,
    prim: u32,
    out: *mut f64,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { query::patch_bounds::<f64>(scene.cast(), prim, out) })
}

/// The closest hit of `rayhit->ray` on patch `prim` alone (`0 .. patch_count`) with `t` in
/// `[tnear, tfar]`: returns `true` and writes `ray.tfar` and `hit` as [`st_intersect1`] does
/// (`prim_id` the patch's input triangle); returns `false` and changes nothing otherwise (so
/// a caller's traversal keeps its closest hit so far). `false` for a NULL or wrong scene, a
/// NULL `rayhit` or `prim ≥ patch_count`.
///
/// The kernel samples the part of the patch's shell inside `[tnear, tfar]`, so the same ray
/// tested with another `tfar` (a traversal that found a nearer hit elsewhere first) may give
/// a hit that differs in its last bits: `t` within `t_error`, `u, v` and the normals to
/// rounding.
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `rayhit` NULL or valid for reads and writes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_intersect(
    scene: *const st_scene,
    prim: u32,
    rayhit: *mut st_rayhit,
) -> bool {
    let scene = Stored::<f32>::from_ptr(scene.cast());
    // SAFETY: forwarded contract.
    query::guard_bool(|| unsafe { query::patch_closest_hit(scene, prim, rayhit) })
}

/// [`st_patch_intersect`] in double precision.
///
/// # Safety
/// As [`st_patch_intersect`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_intersect_f64(
    scene: *const st_scene_f64,
    prim: u32,
    rayhit: *mut st_rayhit_f64,
) -> bool {
    let scene = Stored::<f64>::from_ptr(scene.cast());
    // SAFETY: forwarded contract.
    query::guard_bool(|| unsafe { query::patch_closest_hit(scene, prim, rayhit) })
}

/// Writes to `*prim` the patch index (`0 .. patch_count`) of input triangle `triangle`, for
/// [`st_patch_bounds`] and [`st_patch_intersect`] (`O(log n)`).
///
/// Errors: [`ST_ERROR_NULL_ARGUMENT`], [`ST_ERROR_WRONG_SCENE`],
/// [`ST_ERROR_INDEX_OUT_OF_RANGE`] (the triangle was rejected, or is not one of the scene's).
///
/// # Safety
/// `scene` as in [`st_scene_get_info`]; `prim` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_of_triangle(
    scene: *const st_scene,
    triangle: u32,
    prim: *mut u32,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { query::patch_of_triangle::<f32>(scene.cast(), triangle, prim) })
}

/// [`st_patch_of_triangle`] in double precision.
///
/// # Safety
/// As [`st_patch_of_triangle`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn st_patch_of_triangle_f64(
    scene: *const st_scene_f64,
    triangle: u32,
    prim: *mut u32,
) -> st_status {
    // SAFETY: forwarded contract.
    guard_status(|| unsafe { query::patch_of_triangle::<f64>(scene.cast(), triangle, prim) })
}

// The layouts C compilers give the header's structs (checked again from C in tests/c/).
const _: () = {
    use core::mem::{align_of, offset_of, size_of};
    assert!(size_of::<st_ray>() == 48 && align_of::<st_ray>() == 16);
    assert!(size_of::<st_hit>() == 48 && align_of::<st_hit>() == 16);
    assert!(size_of::<st_rayhit>() == 96 && offset_of!(st_rayhit, hit) == 48);
    assert!(size_of::<st_rayhit8>() == 736 && align_of::<st_rayhit8>() == 32);
    assert!(offset_of!(st_rayhit8, hit) == 384);
    assert!(size_of::<st_ray_f64>() == 96 && size_of::<st_rayhit_f64>() == 176);
};
