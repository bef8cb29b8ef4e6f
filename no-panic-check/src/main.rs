//! Freestanding `no_std`, `no_main` binary that calls the core's construction, evaluation,
//! ray kernels and BVH on opaque inputs.
//!
//! Its panic handler calls `smoothtri_panic_path_survived`, a symbol defined nowhere: if any
//! panic path of the core survives optimisation, the handler is referenced and the link fails
//! with "undefined reference to `smoothtri_panic_path_survived`". A successful link proves the
//! called code cannot panic.
#![no_std]
#![no_main]

use core::hint::black_box;

use glam::{DVec3, Vec3};
use smoothtri::{Bvh, BvhNode, DPatch, DRay, Patch, Ray, flat_hit};

unsafe extern "C" {
    fn smoothtri_panic_path_survived() -> !;
    fn exit(code: i32) -> !;
}

#[panic_handler]
fn on_panic(_: &core::panic::PanicInfo) -> ! {
    // SAFETY: never executed when the link succeeds; the symbol does not exist.
    unsafe { smoothtri_panic_path_survived() }
}

fn f32_paths() -> u32 {
    let p: [Vec3; 3] = black_box([Vec3::X, Vec3::Y, Vec3::Z]);
    let n: [Vec3; 3] = black_box(p);
    let mut acc = 0u32;
    if let Ok(patch) = Patch::<f32>::new(p, n) {
        let (x, nn) = patch.point_normal(black_box(0.2), black_box(0.3));
        let (c, cn) = patch.edge_point_normal(black_box(4), black_box(0.3));
        let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
        let h = patch.height(black_box(0.1), black_box(0.1));
        let (d1, d2) = patch.derivatives(black_box(0.4), black_box(0.4));
        let s = x + nn + c + cn + lo + hi + d1 + d2 + Vec3::splat(h);
        acc += (s.x > 0.0) as u32;
        let ray = Ray::new(black_box(Vec3::splat(2.0)), black_box(-Vec3::ONE));
        let (t0, t1) = (black_box(0.0f32), black_box(f32::INFINITY));
        let hit = patch.intersect::<8>(&ray, t0, t1);
        let (hit2, stats) = patch.intersect_stats::<3, 5>(&ray, t0, t1);
        let flat = flat_hit(&patch.vertices(), Some(&patch.normals()), &ray, t0, t1);
        acc += hit.is_some() as u32 + hit2.is_some() as u32 + flat.is_some() as u32;
        acc += stats.height_evals;
        // BVH over a few copies, in caller-provided storage.
        let patches = [patch; 8];
        let mut nodes = [BvhNode::<f32>::default(); 15];
        let mut order = [0u32; 8];
        if let Ok(bvh) = Bvh::build(black_box(&patches), &mut nodes, &mut order) {
            if let Ok(Some(h)) = bvh.closest_hit::<8>(&ray, t0, t1) {
                acc += h.patch;
            }
            if let Ok(true) = bvh.any_hit::<4>(&ray, t0, t1) {
                acc += 1;
            }
        }
    }
    acc
}

fn f64_paths() -> u32 {
    let p: [DVec3; 3] = black_box([DVec3::X, DVec3::Y, DVec3::Z]);
    let n: [DVec3; 3] = black_box(p);
    let mut acc = 0u32;
    if let Ok(patch) = DPatch::new(p, n) {
        let (x, nn) = patch.point_normal(black_box(0.2), black_box(0.3));
        let (c, cn) = patch.edge_point_normal(black_box(1), black_box(0.3));
        let s = x + nn + c + cn;
        acc += (s.x > 0.0) as u32;
        let ray = DRay::new(black_box(DVec3::splat(2.0)), black_box(-DVec3::ONE));
        if let Some(h) = patch.intersect::<16>(&ray, black_box(0.0), black_box(f64::INFINITY)) {
            acc += (h.t > 0.0) as u32;
        }
    }
    acc
}

/// Entry point: aligns the stack as the C ABI expects, then calls [`main`].
#[cfg(target_arch = "x86_64")]
#[unsafe(naked)]
#[unsafe(no_mangle)]
pub extern "C" fn _start() -> ! {
    core::arch::naked_asm!("xor ebp, ebp", "and rsp, -16", "call {main}", "ud2", main = sym main)
}

extern "C" fn main() -> ! {
    let r = f32_paths() + f64_paths();
    // SAFETY: libc's exit, linked from the C library (only the start files are left out).
    unsafe { exit(if black_box(r) >= 2 { 0 } else { 1 }) }
}
