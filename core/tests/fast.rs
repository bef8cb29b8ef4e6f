//! `FastF32` (feature `micromath`): the error of the crate's fast square root, and how far it
//! moves the surface and the hits, within the named bounds of [`smoothtri::accuracy`].
//! Run with `cargo test -p smoothtri --features micromath --test fast -- --nocapture` (prints
//! the measured worst values). It lives in the core package, whose only dev-dependency is
//! proptest, so the feature rebuilds the core alone; the random patches are the test kit's
//! (`testkit/src/random.rs`, included by path).
#![cfg(feature = "micromath")]
// Test code: indexing and unwrapping are how a test fails; not every shared helper is used.
#![allow(
    dead_code,
    clippy::indexing_slicing,
    clippy::unwrap_used,
    clippy::expect_used
)]

#[path = "../../testkit/src/random.rs"]
mod random;
use glam::Vec3;
use random::*;
use smoothtri::accuracy::{FASTF32_HIT, FASTF32_SQRT_REL, FASTF32_SURFACE};
use smoothtri::{DPatch, FastF32, Float, Patch, Ray};

/// The crate's `FastF32` square root (`Float::sqrt`, the one every `FastF32` computation uses)
/// against the correctly rounded one, relative: 4096 points in each pair of binades (the
/// approximation's pattern repeats every factor 4) from 2^-120 to 2^120, within
/// [`FASTF32_SQRT_REL`]; 0 and negative input give 0.
#[test]
fn fast_sqrt_error_is_bounded() {
    let (mut worst, mut at) = (0.0f64, 0.0f32);
    for e in (-120..120).step_by(2) {
        for k in 0..4096 {
            let x = 2f32.powi(e) * (1.0 + 3.0 * k as f32 / 4096.0);
            let y = Float::sqrt(FastF32(x)).0 as f64;
            let want = (x as f64).sqrt();
            let rel = (y - want).abs() / want;
            if rel.is_nan() || rel > worst {
                (worst, at) = (rel, x);
            }
        }
    }
    eprintln!("FastF32 sqrt: worst relative error {worst:.2e} at {at:e}");
    assert!(worst <= FASTF32_SQRT_REL, "{worst:e} at {at:e}");
    assert_eq!(Float::sqrt(FastF32(0.0)).0, 0.0);
    assert_eq!(Float::sqrt(FastF32(-4.0)).0, 0.0);
    // The construction goes through it: flat patches at every scale keep a valid shell.
    let mut x = 1e-6f32;
    while x < 1e6 {
        let p: Patch<FastF32> =
            Patch::new([Vec3::ZERO, Vec3::X * x, Vec3::Y * x], [Vec3::Z; 3]).unwrap();
        let (lo, hi) = p.height_range();
        assert!(lo.0 <= 0.0 && hi.0 >= 0.0, "scale {x:e}: [{lo:?}, {hi:?}]");
        x *= 1.37;
    }
}

/// Random patches (normals ≤ 40°) built in `FastF32` against `f64` on the same input: surface
/// points within [`FASTF32_SURFACE`] of the triangle's size; a ray along the face normal at the
/// centroid hits both, at distances within [`FASTF32_HIT`] of the size.
#[test]
fn fast_patches_stay_close_and_kernel_is_finite() {
    let mut rng = Rng(31);
    let (mut worst_p, mut worst_t, mut hits) = (0.0f64, 0.0f64, 0);
    for _ in 0..300 {
        let (p, n) = random_patch(&mut rng, 40.0);
        let size = (p[1] - p[0]).length();
        let (p32, n32) = (p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()));
        let fast = Patch::<FastF32>::new(p32, n32).expect("FastF32 accepts what f64 accepts");
        let exact = DPatch::new(p32.map(Vec3::as_dvec3), n32.map(Vec3::as_dvec3)).unwrap();
        for (w1, w2) in bary_grid(4) {
            let a = fast
                .point(FastF32(w1 as f32), FastF32(w2 as f32))
                .as_dvec3();
            let b = exact.point(w1 as f32 as f64, w2 as f32 as f64);
            worst_p = worst_p.max((a - b).length() / size);
        }
        let nf = exact.face_normal();
        let c = (p[0] + p[1] + p[2]) / 3.0;
        // Unit direction: `t` is a distance.
        let ray = Ray::new((c + nf * size).as_vec3(), (-nf).as_vec3());
        let h = fast
            .closest_hit(&ray, FastF32(0.0), FastF32(f32::INFINITY), 8)
            .expect("FastF32 misses a central ray");
        hits += 1;
        assert!(h.t.0.is_finite() && h.point.is_finite() && h.normal.is_finite());
        let want = exact
            .closest_hit(
                &smoothtri::DRay::new(ray.origin.as_dvec3(), ray.dir.as_dvec3()),
                0.0,
                f64::INFINITY,
                16,
            )
            .expect("f64 misses a central ray");
        let et = ((h.t.0 as f64) - want.t).abs() * ray.dir.as_dvec3().length() / size;
        worst_t = worst_t.max(et);
        assert!(
            et <= FASTF32_HIT,
            "hit {} vs {}: {et:e} of the size",
            h.t.0,
            want.t
        );
    }
    eprintln!(
        "FastF32 vs f64: surface worst {worst_p:.2e} of the size (bound {FASTF32_SURFACE:e}); \
         central hits worst {worst_t:.2e} of the size (bound {FASTF32_HIT:e}); {hits} hits"
    );
    assert!(worst_p <= FASTF32_SURFACE, "{worst_p:e}");
    assert_eq!(hits, 300);
}

/// The BVH over `FastF32` patches, whose four-wide slab test runs one slot at a time (its lane
/// type carries one value): closest and any hit equal brute force over the same patches.
#[test]
fn fast_bvh_equals_brute_force() {
    use smoothtri::{Bvh, BvhNode};
    let mut rng = Rng(32);
    let patches: Vec<Patch<FastF32>> = (0..60)
        .map(|_| {
            let (p, n) = random_patch(&mut rng, 30.0);
            let off = rng.unit() * 6.0;
            Patch::<FastF32>::new(p.map(|x| (x + off).as_vec3()), n.map(|x| x.as_vec3())).unwrap()
        })
        .collect();
    let mut nodes = vec![BvhNode::default(); Bvh::<FastF32>::nodes_needed(patches.len())];
    let mut order = vec![0u32; patches.len()];
    let bvh = Bvh::build(&patches, &mut nodes, &mut order).unwrap();
    let (zero, inf) = (FastF32(0.0), FastF32(f32::INFINITY));
    let mut hits = 0;
    for _ in 0..2000 {
        let o = rng.unit() * 12.0;
        let aim = rng.unit() * 6.0 * rng.f();
        let ray = Ray::<FastF32>::new(o.as_vec3(), (aim - o).as_vec3());
        let got = bvh.closest_hit(&ray, zero, inf, 4).map(|h| h.t.0);
        let want = patches
            .iter()
            .filter_map(|p| p.closest_hit(&ray, zero, inf, 4))
            .map(|h| h.t.0)
            .reduce(f32::min);
        assert_eq!(got, want);
        assert_eq!(bvh.any_hit(&ray, zero, inf, 4), want.is_some());
        hits += want.is_some() as usize;
    }
    assert!(hits > 200, "{hits} hits");
}
