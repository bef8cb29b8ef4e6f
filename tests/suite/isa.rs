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
use smoothtri_isa::{Isa, Kernels, Precision};
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

fn owned<F: Float>(m: &Mesh, seams: bool) -> OwnedScene<F> {
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
fn rays<F: Float>(m: &Mesh) -> Vec<Ray<F>> {
    let cam = Camera::for_mesh(m, 30.0, 20.0, 40, 30);
    (0..30)
        .flat_map(|y| (0..40).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = cam.pixel_ray(x, y);
            Ray::new(F::from_dvec3(o), F::from_dvec3(d))
        })
        .collect()
}

/// One comparison per entry of the core's list of queries (`smoothtri::for_each_query!`):
/// `q::NAME(k, args…)` runs the core's query and `k`'s of that name, asserts they are the same
/// bits and returns the core's answer. A query the tests below never call is a dead-code
/// warning, an error in CI's lints: each entry of the list is compared.
mod q {
    use super::same;
    use smoothtri_isa::{Kernels, Precision};

    macro_rules! comparisons {
        (
            ()
            $({ name: $name:ident, doc: $doc:literal, same: $same:literal, generics: [$($k:ident)?],
                params: ($($p:ident: $t:ty),* $(,)?), returns: $ret:ty, lanes: ($l:ident) $lanes:expr,
                core: $core:expr $(,)? })*
        ) => {
            $(
                #[doc = concat!("`", $doc, "` on `k` against the core's: ", $same, ".")]
                pub fn $name<F: Precision $(, const $k: usize)?>(k: Kernels, $($p: $t),*) -> $ret {
                    let want = $core;
                    let got = k.$name $(::<F, $k>)? ($($p),*);
                    assert!(
                        same(&want, &got),
                        "{} {}: {want:?} != {got:?}",
                        k.isa(),
                        stringify!($name)
                    );
                    want
                }
            )*
        };
    }
    smoothtri::for_each_query!(comparisons);
}

/// Every query of `k` on the scene of `m` equals the core's: returns the hits compared.
fn scene_queries<F: Precision>(k: Kernels, m: &Mesh, seams: bool) -> usize {
    let owned = owned::<F>(m, seams);
    let scene = owned.scene();
    let bvh = scene.bvh();
    let inf = F::from_f64(f64::INFINITY);
    let mut hits = 0;
    for ray in rays::<F>(m) {
        for n in BUDGETS {
            let hit = q::scene_closest_hit(k, &scene, &ray, F::ZERO, inf, n);
            hits += usize::from(hit.is_some());
            let hit = q::bvh_closest_hit(k, bvh, &ray, F::ZERO, inf, n);
            // Shadow rays up to half-way to the hit, or to the far side of the scene.
            let far = hit.map_or(F::from_f64(10.0), |h| h.t * F::from_f64(0.5));
            q::scene_any_hit(k, &scene, &ray, F::ZERO, far, n);
            q::bvh_any_hit(k, bvh, &ray, F::ZERO, far, n);
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
/// `closest_hit_stats::<K>`, for two bracketing sample counts.
fn patch_tests<F: Precision>(k: Kernels) {
    let mut rng = Rng(49);
    let inf = F::from_f64(f64::INFINITY);
    for _ in 0..200 {
        let (p, n) = random_patch(&mut rng, 35.0);
        let Ok(patch) = Patch::<F>::new(p.map(F::from_dvec3), n.map(F::from_dvec3)) else {
            continue;
        };
        for _ in 0..8 {
            let (o, d) = random_ray(&mut rng, 1.5);
            let ray = Ray::new(F::from_dvec3(o), F::from_dvec3(d));
            for n in BUDGETS {
                q::patch_closest_hit_stats::<F, 6>(k, &patch, &ray, F::ZERO, inf, n);
                q::patch_closest_hit_stats::<F, 14>(k, &patch, &ray, F::ZERO, inf, n);
                q::patch_closest_hit(k, &patch, &ray, F::ZERO, inf, n);
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
