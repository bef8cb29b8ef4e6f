//! The kernels per instruction set (`smoothtri-isa`): each instruction set this CPU has returns
//! what the core's own queries return, bit for bit: hits (`t`, barycentrics, point, normal,
//! `t_error`, patch), the scene's triangle and seamless shading normal, shadow answers, and the
//! kernel's statistics, in `f32` and `f64`, at every budget from bracketing only to
//! `MAX_ITERATIONS`. The lane code is the same IEEE operations in the same order at every width,
//! with no fused multiply-add, so nothing may differ; every accuracy test of the core's queries
//! then holds for the dispatched ones too. CI also runs the suite's kernel, BVH and C API tests
//! with `SMOOTHTRI_ISA` set to each instruction set the machine has.

use crate::common::*;
use glam::DVec3;
use smoothtri::{BuildOptions, MAX_ITERATIONS, OwnedScene, Patch, Ray, Vertices};
use smoothtri_isa::{Isa, Kernels};
use smoothtri_testkit::Camera;
use smoothtri_testkit::{Mesh, scenes};

/// The budgets compared: bracketing only, the odd ones no table held, the defaults, the most.
const BUDGETS: [usize; 7] = [0, 1, 3, 4, 8, 16, MAX_ITERATIONS];

/// The kernels of every instruction set this CPU has, besides the baseline.
fn wider() -> Vec<Kernels> {
    Isa::ALL
        .into_iter()
        .filter(|&i| i != Isa::Baseline)
        .filter_map(|i| Kernels::new(i).ok())
        .collect()
}

/// Bit for bit: `Debug` prints the shortest string that reads back as the same float (and tells
/// `-0.0` from `0.0`).
fn same<T: std::fmt::Debug>(a: &T, b: &T) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

fn owned<F: P>(m: &Mesh, seams: bool) -> OwnedScene<F> {
    let flat = |v: &[DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
    let (p, n) = (flat(&m.positions), flat(&m.normals));
    let mut options = BuildOptions {
        seams,
        ..BuildOptions::default()
    };
    OwnedScene::<F>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        &mut options,
    )
    .expect("the scene builds")
}

/// Camera rays at `m` (40 × 30) in precision `F`.
fn rays<F: P>(m: &Mesh) -> Vec<Ray<F>> {
    let cam = Camera::for_mesh(m, 30.0, 20.0, 40, 30);
    (0..30)
        .flat_map(|y| (0..40).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = cam.pixel_ray(x, y);
            Ray::new(F::v(o), F::v(d))
        })
        .collect()
}

/// Every query of `k` on the scene of `m` equals the core's: returns the hits compared.
fn scene_queries<F: P>(k: Kernels, m: &Mesh, seams: bool) -> usize {
    let owned = owned::<F>(m, seams);
    let scene = owned.scene();
    let bvh = scene.bvh();
    let inf = F::from_f64(f64::INFINITY);
    let mut hits = 0;
    for ray in rays::<F>(m) {
        for n in BUDGETS {
            let (want, got) = (
                scene.closest_hit(&ray, F::ZERO, inf, n),
                k.scene_closest_hit(&scene, &ray, F::ZERO, inf, n),
            );
            assert!(
                same(&want, &got),
                "{} N = {n}: {want:?} != {got:?}",
                k.isa()
            );
            hits += usize::from(want.is_some());
            let (want, got) = (
                bvh.closest_hit(&ray, F::ZERO, inf, n),
                k.bvh_closest_hit(bvh, &ray, F::ZERO, inf, n),
            );
            assert!(
                same(&want, &got),
                "{} N = {n}: {want:?} != {got:?}",
                k.isa()
            );
            // Shadow rays up to half-way to the hit, or to the far side of the scene.
            let far = want.map_or(F::from_f64(10.0), |h| h.t * F::from_f64(0.5));
            assert_eq!(
                scene.any_hit(&ray, F::ZERO, far, n),
                k.scene_any_hit(&scene, &ray, F::ZERO, far, n),
            );
            assert_eq!(
                bvh.any_hit(&ray, F::ZERO, far, n),
                k.bvh_any_hit(bvh, &ray, F::ZERO, far, n),
            );
        }
    }
    hits
}

#[test]
fn every_instruction_set_gives_the_scene_queries_bit_for_bit() {
    for k in wider() {
        for (m, seams) in [
            (scenes::torus(8, 8, 1.0, 0.4), false),
            (scenes::tilted_normal_sphere(), true),
            (scenes::teapot(4), true),
        ] {
            // Most of the queries hit something (the camera frames the mesh).
            let queries = 40 * 30 * BUDGETS.len();
            let hits = [
                scene_queries::<f32>(k, &m, seams),
                scene_queries::<f64>(k, &m, seams),
            ];
            eprintln!("{}: {hits:?} hits of {queries} queries", k.isa());
            assert!(
                hits.iter().all(|&h| h > queries / 10),
                "{hits:?} of {queries}"
            );
        }
    }
}

/// Random patches and rays through them: the hit and the kernel's statistics of
/// `intersect_stats::<K>`, for two bracketing sample counts.
fn patch_tests<F: P>(k: Kernels) {
    let mut rng = Rng(49);
    let inf = F::from_f64(f64::INFINITY);
    for _ in 0..200 {
        let (p, n) = random_patch(&mut rng, 35.0);
        let Ok(patch) = Patch::<F>::new(p.map(F::v), n.map(F::v)) else {
            continue;
        };
        for _ in 0..8 {
            let (o, d) = random_ray(&mut rng, 1.5);
            let ray = Ray::new(F::v(o), F::v(d));
            for n in BUDGETS {
                let want = patch.intersect_stats::<6>(&ray, F::ZERO, inf, n);
                let got = k.patch_intersect_stats::<F, 6>(&patch, &ray, F::ZERO, inf, n);
                assert!(
                    same(&want, &got),
                    "{} N = {n}: {want:?} != {got:?}",
                    k.isa()
                );
                let want = patch.intersect_stats::<14>(&ray, F::ZERO, inf, n);
                let got = k.patch_intersect_stats::<F, 14>(&patch, &ray, F::ZERO, inf, n);
                assert!(
                    same(&want, &got),
                    "{} N = {n}: {want:?} != {got:?}",
                    k.isa()
                );
                let want = patch.intersect(&ray, F::ZERO, inf, n);
                let got = k.patch_intersect(&patch, &ray, F::ZERO, inf, n);
                assert!(
                    same(&want, &got),
                    "{} N = {n}: {want:?} != {got:?}",
                    k.isa()
                );
            }
        }
    }
}

#[test]
fn every_instruction_set_gives_the_patch_tests_and_their_statistics_bit_for_bit() {
    for k in wider() {
        patch_tests::<f32>(k);
        patch_tests::<f64>(k);
    }
}

#[test]
fn a_budget_above_the_largest_runs_the_largest() {
    let m = scenes::torus(8, 8, 1.0, 0.4);
    let owned = owned::<f32>(&m, false);
    let scene = owned.scene();
    for ray in rays::<f32>(&m).iter().step_by(7) {
        let top = scene.closest_hit(ray, 0.0, f32::INFINITY, MAX_ITERATIONS);
        for n in [MAX_ITERATIONS + 1, usize::MAX] {
            let got = scene.closest_hit(ray, 0.0, f32::INFINITY, n);
            assert!(same(&top, &got), "N = {n}");
            for k in wider() {
                let got = k.scene_closest_hit(&scene, ray, 0.0, f32::INFINITY, n);
                assert!(same(&top, &got), "{} N = {n}", k.isa());
            }
        }
    }
}

/// The sixteen-lane probe of the lane call (two rays' eight samples in one call, the
/// measurement of `benches/kernel.rs`' "Lane call widths") gives, on every instruction set this
/// CPU has, the values of two eight-lane calls, and those the baseline's, bit for bit: the
/// comparison of the two widths times the same arithmetic.
#[test]
fn the_sixteen_lane_probe_equals_two_eight_lane_calls() {
    use smoothtri::internal::LaneProbe;
    let m = scenes::torus(8, 8, 1.0, 0.4);
    let mut checked = 0;
    for tri in m.triangles.iter().take(16) {
        let p = tri.map(|i| m.positions[i as usize].as_vec3());
        let n = tri.map(|i| m.normals[i as usize].as_vec3());
        let patch = Patch::<f32>::new(p, n).expect("torus patch");
        let probe = LaneProbe::new(&patch);
        let [p0, p1, p2] = patch.data().p;
        let ray = |u: f32, v: f32| {
            let x = [0, 1].map(|c| p0[c] + u * (p1[c] - p0[c]) + v * (p2[c] - p0[c]));
            ([x[0], x[1], 1.0], [0.1 * u - 0.03, 0.05 - 0.1 * v, -1.0])
        };
        let ((o0, r0), (o1, r1)) = (ray(0.2, 0.3), ray(0.5, 0.1));
        let taus: [[f32; 8]; 2] = [
            std::array::from_fn(|k| 0.6 + 0.1 * k as f32),
            std::array::from_fn(|k| 0.55 + 0.12 * k as f32),
        ];
        let base = Kernels::new(Isa::Baseline).expect("the baseline");
        let want = [
            base.probe_f8(&probe, o0, r0, taus[0]),
            base.probe_f8(&probe, o1, r1, taus[1]),
        ];
        assert!(want.iter().flatten().all(|f| f.is_finite()));
        for k in std::iter::once(base).chain(wider()) {
            let pair = k.probe_f16(&probe, [o0, o1], [r0, r1], taus);
            let eight = [
                k.probe_f8(&probe, o0, r0, taus[0]),
                k.probe_f8(&probe, o1, r1, taus[1]),
            ];
            assert!(
                same(&pair, &want),
                "{}: sixteen lanes {pair:?}, baseline {want:?}",
                k.isa()
            );
            assert!(
                same(&eight, &want),
                "{}: eight lanes {eight:?}, baseline {want:?}",
                k.isa()
            );
            checked += 1;
        }
    }
    assert!(checked >= 16);
}
