//! Robustness properties of the core over hostile input, in `f32` ([`Patch`]) and `f64`
//! ([`DPatch`]): extreme magnitudes (1e-20 … 1e20), NaN, ±inf, zero vectors, collinear and
//! near-collinear vertices, normals near 90° and back-facing, degenerate rays and ray ranges
//! (generators in `robustness/strategies.rs`).
//!
//! What is checked (docs/METHOD.md §7, §8; the checks are in `robustness/checks.rs`), with no
//! case skipped and no tolerance relaxed for any input:
//! - construction returns a patch or the typed error that the input explains (`NonFinite`
//!   exactly for non-finite input, `ZeroNormal`/`BackFacingNormal` naming the first offending
//!   vertex, …), never panics;
//! - for every accepted patch, `point`, `point_normal`, `height`, `derivatives`,
//!   `edge_point_normal`, `bounds` and `height_range` are finite, and every unit vector is unit
//!   within [`smoothtri::accuracy::UNIT_LENGTH_ULPS`] ulps, at any barycentrics (outside the triangle, NaN, ±inf,
//!   subnormal sums);
//! - every `intersect(…, n)` / `closest_hit_stats::<K>(…, n)` result is `None` or fully finite, `t`
//!   inside `[t_min, t_max]` exactly, `t_error ≥ 0`, unit normal, barycentrics in the triangle,
//!   with at most `max_height_evals(K, N)` height evaluations (`max_lane_calls(K, N)` lane calls of eight and two steps of four) and at most one normal evaluation;
//! - BVH queries on storage made by `Bvh::build` never err and equal brute force exactly
//!   (`closest_hit` returns the brute-force closest hit bit for bit, `any_hit` its hit/miss);
//! - inside the method's domain (well-shaped triangles, normals ≤ 50°) the surface stays inside
//!   `height_range()` and `bounds()` on a dense grid.
//!
//! The bugs these properties found are reproduced, each asserting the fixed behaviour, in
//! `tests/suite/regressions.rs`.
//!
//! # Case count
//! The default is quick (the whole file runs in seconds in debug mode, as CI runs
//! `cargo test --workspace`). Set `SMOOTHTRI_CASES=<n>` to run `n` cases per property, e.g. a
//! run of more than 10^6 cases in total (6 properties):
//!
//! ```text
//! SMOOTHTRI_CASES=200000 cargo test --release --test suite robustness::
//! ```
//!
//! The quick run uses a fixed proptest seed, a long run a random one (printed on failure).
//! `in_domain_surface_stays_in_shell` fails about once in 4·10^5 cases on the one known limit
//! of the method (`surface_stays_in_shell_at_isolated_spikes` in `tests/suite/regressions.rs`).

mod checks;
pub(crate) mod strategies;
use crate::common::*;
use checks::*;
use glam::{DVec3, Vec3};
use proptest::prelude::*;
use smoothtri::accuracy::{F32_SPHERE_HIT, F64_SPHERE_HIT, F64_SPHERE_POINT};
use smoothtri::{DPatch, Patch, PatchError, Ray};
use strategies::*;

/// Default cases per property for CI (debug mode).
const QUICK_CASES: u32 = 256;

/// The quick default run's seed ([`proptest_config`]).
const SEED: u64 = 0x5EED_2026;

// ---------------------------------------------------------------------------------------------
// Properties

proptest! {
    #![proptest_config(proptest_config(QUICK_CASES, SEED))]

    /// Construction never panics; it rejects with the error the input explains, and when it
    /// accepts, every evaluation and ray query is finite (f32 and f64 from the same input).
    #[test]
    fn accepted_patches_evaluate_and_intersect_finitely(
        inp in input(),
        extra in prop::collection::vec((wild(), wild()), 0..3),
        rays in prop::collection::vec(ray_param(), 1..4),
    ) {
        let (p, n) = inp.build();
        check_input::<f64>(p, n, &extra, &rays)?;
        check_input::<f32>(p, n, &extra, &rays)?;
    }

    /// Fully wild rays (any origin, direction and range, including non-finite) against accepted
    /// patches.
    #[test]
    fn wild_rays_are_finite_or_none(
        s in structured(),
        rays in prop::collection::vec((wild_vec(), wild_vec(), wild(), wild()), 1..6),
    ) {
        let (p, n) = s.build();
        if let Ok(patch) = DPatch::new(p, n) {
            for &(o, d, a, b) in &rays {
                check_ray(&patch, &Ray::new(o, d), a, b)?;
            }
        }
        if let Ok(patch) = Patch::<f32>::new(p.map(|v| v.as_vec3()), n.map(|v| v.as_vec3())) {
            for &(o, d, a, b) in &rays {
                check_ray(&patch, &Ray::new(o.as_vec3(), d.as_vec3()), a as f32, b as f32)?;
            }
        }
    }

    /// Construction errors: a special value injected into any coordinate; non-finite input is
    /// always `NonFinite`, every rejection is the one the input explains, a collinear triangle
    /// is never accepted, and a zero normal is reported as `ZeroNormal` unless the triangle or
    /// an earlier vertex is rejected first.
    #[test]
    fn construction_errors_are_typed(s in structured(), k in 0..18usize, bad in special()) {
        let (p, n) = s.build();
        let mut flat = [p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| v.to_array());
        flat[k / 3][k % 3] = bad;
        let v = flat.map(DVec3::from_array);
        let (p2, n2) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let (p32, n32) = (p2.map(|x| x.as_vec3()), n2.map(|x| x.as_vec3()));
        let r64 = DPatch::new(p2, n2);
        let r32 = Patch::<f32>::new(p32, n32);
        if !bad.is_finite() {
            prop_assert_eq!(r64.err(), Some(PatchError::NonFinite));
            prop_assert_eq!(r32.err(), Some(PatchError::NonFinite));
        }
        if let Err(e) = r64 {
            check_rejection::<f64>(p2, n2, e)?;
        }
        if let Err(e) = r32 {
            check_rejection::<f32>(p32, n32, e)?;
        }
        // Collinear (the apex on the base line, no injection) is never accepted, unless an
        // offset far larger than the triangle quantises the vertices off the line.
        let near = s.offset.is_none_or(|(_, e)| e <= s.scale + 3.0);
        if s.apex.1 == 0.0 && s.inject.is_none() && near {
            prop_assert!(DPatch::new(p, n).is_err());
        }
        // A zero normal is reported as such unless the triangle, or a vertex before it, is
        // rejected first.
        for (k, par) in s.normals.iter().enumerate() {
            if par.is_none() && s.inject.is_none() {
                let e = DPatch::new(p, n).err();
                let earlier = |v: u8| usize::from(v) < k;
                prop_assert!(
                    matches!(
                        e,
                        Some(PatchError::DegenerateTriangle | PatchError::OutOfRange)
                    ) || matches!(e, Some(PatchError::ZeroNormal { vertex }) if usize::from(vertex) <= k)
                        || matches!(e, Some(PatchError::BackFacingNormal { vertex }) if earlier(vertex)),
                    "zero normal at vertex {}: {:?}",
                    k,
                    e
                );
            }
        }
    }

    /// In the method's domain (well-shaped triangles, normals ≤ 50°, any scale from 1e-6 to
    /// 1e6, offsets up to 1e3 sizes) the surface stays inside `height_range()` and `bounds()`.
    #[test]
    fn in_domain_surface_stays_in_shell(seed in any::<u64>(), deg in 0.0..50.0f64, scale in -6.0..6.0f64) {
        let mut rng = Rng(seed);
        let size = 10f64.powf(scale);
        let off = rng.unit() * size * rng.range(0.0, 1e3);
        let (p, nf) = well_shaped(&mut rng, size, off);
        let n = [tilted(&mut rng, nf, deg), tilted(&mut rng, nf, deg), tilted(&mut rng, nf, deg)];
        let patch = DPatch::new(p, n);
        prop_assert!(patch.is_ok(), "in-domain patch rejected: {patch:?}");
        if let Ok(patch) = patch {
            let (lo, hi) = patch.height_range();
            let (bmin, bmax) = (patch.bounds().min(), patch.bounds().max());
            for (w1, w2) in bary_grid(20) {
                let h = patch.height(w1, w2);
                prop_assert!(h >= lo && h <= hi, "height {h} outside [{lo}, {hi}] at ({w1}, {w2})");
                let x = patch.point(w1, w2);
                prop_assert!(x.cmpge(bmin).all() && x.cmple(bmax).all(), "{x} outside {bmin} {bmax}");
            }
        }
    }

    /// BVH over random patches equals brute force exactly, in f64 and in f32 (the same inputs:
    /// with the fixed seed these are the cases the two precisions' tests drew apart).
    #[test]
    fn bvh_agrees_with_brute_force(
        inputs in prop::collection::vec(structured(), 1..24),
        spread in -20.0..20.0f64,
        rays in prop::collection::vec(ray_param(), 1..6),
    ) {
        check_bvh(&scene::<f64>(&inputs, spread), &rays)?;
        check_bvh(&scene::<f32>(&inputs, spread), &rays)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Plain tests of specific extremes

/// The octant of the unit sphere at scales 1e-20 … 1e20: f64 accepts every scale, f32 the
/// scales 1e-7 … 1e9 (`OutOfRange` beyond); the f64 surface is on the sphere to
/// [`F64_SPHERE_POINT`], and the ray from the outside hits the sphere in both precisions,
/// within the certified bound plus [`F64_SPHERE_HIT`] / [`F32_SPHERE_HIT`] of the radius.
#[test]
fn tiny_and_huge_patches() {
    let base = [DVec3::X, DVec3::Y, DVec3::Z];
    let mut accepted32 = Vec::new();
    for e in -20..=20 {
        let s = 10f64.powi(e);
        let p = base.map(|v| v * s);
        let patch = DPatch::new(p, base).expect("f64 octant");
        for (w1, w2) in bary_grid(4) {
            let x = patch.point(w1, w2);
            assert!(
                (x.length() / s - 1.0).abs() <= F64_SPHERE_POINT,
                "scale {s:e}: {x}"
            );
        }
        let ray = smoothtri::DRay::new(DVec3::splat(2.0 * s), -DVec3::ONE);
        let h = patch
            .closest_hit(&ray, 0.0, f64::INFINITY, 8)
            .unwrap_or_else(|| panic!("f64 scale {s:e}: the ray misses"));
        // Within the certified bound (|dir| = √3) plus rounding.
        let bound = h.t_error * 3f64.sqrt() / s + F64_SPHERE_HIT;
        let err = (h.point.length() / s - 1.0).abs();
        assert!(
            err <= bound,
            "f64 scale {s:e}: {err:e}, t_error {:e}",
            h.t_error
        );
        let p32 = p.map(|v| v.as_vec3());
        match Patch::<f32>::new(p32, base.map(|v| v.as_vec3())) {
            Ok(patch) => {
                accepted32.push(e);
                let ray = Ray::new(Vec3::splat(2.0 * s as f32), -Vec3::ONE);
                let h = patch
                    .closest_hit(&ray, 0.0, f32::INFINITY, 8)
                    .unwrap_or_else(|| panic!("f32 scale {s:e}: the ray misses"));
                let r = h.point.as_dvec3().length() / s;
                let bound = h.t_error as f64 * 3f64.sqrt() / s + F32_SPHERE_HIT;
                assert!(
                    (r - 1.0).abs() <= bound,
                    "f32 scale {s:e}: |point| − 1 = {:e}, t_error {:e}",
                    r - 1.0,
                    h.t_error
                );
            }
            Err(err) => assert_eq!(err, PatchError::OutOfRange, "f32 scale {s:e}"),
        }
    }
    assert_eq!(
        accepted32,
        (-7..=9).collect::<Vec<_>>(),
        "scales (powers of ten) accepted in f32"
    );
}

/// Coverage of the generators (not a check): how many inputs are accepted, by error variant,
/// and how many rays hit. `cargo test --release --test suite robustness::generator_coverage -- --ignored
/// --nocapture`.
#[test]
#[ignore = "statistics of the generators, not a check"]
fn generator_coverage() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;
    let mut runner = TestRunner::deterministic();
    let strat = (input(), prop::collection::vec(ray_param(), 3..4));
    let total = env_cases(20_000);
    let mut outcome: [BTreeMap<String, u32>; 2] = [BTreeMap::new(), BTreeMap::new()];
    let (mut rays, mut hits) = ([0u32; 2], [0u32; 2]);
    for _ in 0..total {
        let Ok(tree) = strat.new_tree(&mut runner) else {
            continue;
        };
        let (inp, rps) = tree.current();
        let (p, n) = inp.build();
        let kind = match inp {
            Input::Structured(_) => "structured",
            Input::Wild(..) => "wild",
        };
        let r64 = DPatch::new(p, n);
        let r32 = Patch::<f32>::new(p.map(|v| v.as_vec3()), n.map(|v| v.as_vec3()));
        let key = |e: Option<PatchError>| match e {
            None => format!("{kind}: accepted"),
            Some(e) => format!("{kind}: {e:?}"),
        };
        *outcome[0].entry(key(r64.err())).or_default() += 1;
        *outcome[1].entry(key(r32.err())).or_default() += 1;
        if let Ok(patch) = r64 {
            let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
            for r in &rps {
                let target = patch.point(r.aim.0, r.aim.1);
                let (o, d, a, b) = r.build(lo, hi, patch.face_normal(), target);
                rays[0] += 1;
                hits[0] += patch.closest_hit(&Ray::new(o, d), a, b, 8).is_some() as u32;
            }
        }
        if let Ok(patch) = r32 {
            let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
            for r in &rps {
                let target = patch.point(r.aim.0 as f32, r.aim.1 as f32).as_dvec3();
                let (o, d, a, b) = r.build(
                    lo.as_dvec3(),
                    hi.as_dvec3(),
                    patch.face_normal().as_dvec3(),
                    target,
                );
                rays[1] += 1;
                let ray = Ray::new(o.as_vec3(), d.as_vec3());
                hits[1] += patch.closest_hit(&ray, a as f32, b as f32, 8).is_some() as u32;
            }
        }
    }
    for (name, o) in ["f64", "f32"].iter().zip(&outcome) {
        eprintln!("{name}: {total} inputs");
        for (k, v) in o {
            eprintln!(
                "  {k:<40} {v:>7} ({:.1}%)",
                100.0 * *v as f64 / total as f64
            );
        }
    }
    eprintln!(
        "rays: f64 {} hits of {}, f32 {} of {}",
        hits[0], rays[0], hits[1], rays[1]
    );
}
