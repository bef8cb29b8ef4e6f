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
use smoothtri::{DPatch, Patch};

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
        let (lo, hi) = patch.bounds();
        let h = patch.height(black_box(0.1), black_box(0.1));
        let (d1, d2) = patch.derivatives(black_box(0.4), black_box(0.4));
        let s = x + nn + c + cn + lo + hi + d1 + d2 + Vec3::splat(h);
        acc += (s.x > 0.0) as u32;
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
    unsafe { exit(if black_box(r) == 2 { 0 } else { 1 }) }
}
