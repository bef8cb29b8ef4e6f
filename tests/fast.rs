//! `FastF32` (feature `micromath`): how far the fast square root moves the surface and hits.
//! Run with `cargo test --features micromath --test fast -- --nocapture`.
#![cfg(feature = "micromath")]

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::{DPatch, FastF32, Patch, Ray};

#[test]
fn micromath_sqrt_error_is_bounded() {
    let mut worst = 0.0f64;
    let mut x = 1e-6f32;
    while x < 1e6 {
        let p: Patch<FastF32> =
            Patch::new([Vec3::ZERO, Vec3::X * x, Vec3::Y * x], [Vec3::Z; 3]).unwrap();
        // The flat patch's height range is ±1e-4 of the size: exercise sqrt through the frame.
        let (lo, hi) = p.height_range();
        assert!(lo.0 <= 0.0 && hi.0 >= 0.0);
        let y0 = micromath::F32Ext::sqrt(x);
        let y = (0.5 * (y0 + x / y0)) as f64;
        worst = worst.max((y - (x as f64).sqrt()).abs() / (x as f64).sqrt());
        x *= 1.37;
    }
    eprintln!("micromath sqrt: worst relative error {worst:.2e}");
    assert!(worst < 2e-3, "{worst}");
}

#[test]
fn fast_patches_stay_close_and_kernel_is_finite() {
    let mut rng = Rng(31);
    let (mut worst_p, mut hits) = (0.0f64, 0);
    for _ in 0..300 {
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0]).length();
        let (p32, n32) = (p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()));
        let Ok(fast) = Patch::<FastF32>::new(p32, n32) else {
            continue;
        };
        let exact = DPatch::new(p32.map(Vec3::as_dvec3), n32.map(Vec3::as_dvec3)).unwrap();
        for (w1, w2) in bary_grid(4) {
            let a = fast
                .point(FastF32(w1 as f32), FastF32(w2 as f32))
                .as_dvec3();
            let b = exact.point(w1, w2);
            worst_p = worst_p.max((a - b).length() / size);
        }
        let nf = exact.face_normal();
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let ray = Ray::new((c + nf * size).as_vec3(), (-nf).as_vec3());
        if let Some(h) = fast.intersect::<8>(&ray, FastF32(0.0), FastF32(f32::INFINITY)) {
            hits += 1;
            assert!(h.t.0.is_finite() && h.point.is_finite() && h.normal.is_finite());
            let want = exact
                .intersect::<16>(
                    &smoothtri::DRay::new(ray.origin.as_dvec3(), ray.dir.as_dvec3()),
                    0.0,
                    f64::INFINITY,
                )
                .unwrap();
            assert!(((h.t.0 as f64) - want.t).abs() < 2e-2 * size / DVec3::ONE.length().min(1.0));
        }
    }
    eprintln!("FastF32 vs f64 surface: worst {worst_p:.2e} of the size; {hits} central hits");
    assert!(worst_p < 1e-2, "{worst_p}");
    assert!(hits > 250);
}
