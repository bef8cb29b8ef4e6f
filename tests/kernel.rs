//! The bounded-iteration ray kernel against analytic spheres, the f64 reference, and its own
//! work bound.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::{DPatch, DRay, Patch, Ray};
use smoothtri_demo::scenes::{Mesh, cube, icosphere, torus};

fn patches64(m: &Mesh) -> Vec<DPatch> {
    (0..m.triangles.len())
        .map(|t| {
            let (p, n) = m.triangle(t);
            DPatch::new(p, n).unwrap()
        })
        .collect()
}
fn patches32(m: &Mesh) -> Vec<Patch> {
    (0..m.triangles.len())
        .map(|t| {
            let (p, n) = m.triangle(t);
            Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap()
        })
        .collect()
}

/// Closest hit over all patches (brute force).
fn closest64<const N: usize>(ps: &[DPatch], ray: &DRay) -> Option<smoothtri::DHit> {
    let mut best: Option<smoothtri::DHit> = None;
    for p in ps {
        // `t_max` is the best so far, so any hit is closer.
        if let Some(h) = p.intersect::<N>(ray, 0.0, best.map_or(f64::INFINITY, |b| b.t)) {
            best = Some(h);
        }
    }
    best
}
fn closest32<const N: usize>(ps: &[Patch], ray: &Ray) -> Option<smoothtri::Hit> {
    let mut best: Option<smoothtri::Hit> = None;
    for p in ps {
        // `t_max` is the best so far, so any hit is closer.
        if let Some(h) = p.intersect::<N>(ray, 0.0, best.map_or(f32::INFINITY, |b| b.t)) {
            best = Some(h);
        }
    }
    best
}

/// Analytic first intersection of a ray with the sphere |x| = r, and the ray's closest approach.
fn sphere_root(o: DVec3, d: DVec3, r: f64) -> (Option<f64>, f64) {
    let a = d.dot(d);
    let b = o.dot(d);
    let c = o.dot(o) - r * r;
    let closest = (o - d * (b / a)).length();
    let disc = b * b - a * c;
    if disc < 0.0 {
        return (None, closest);
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (t1, t2) = (q / a, c / q);
    let t = t1.min(t2);
    (if t > 0.0 { Some(t) } else { None }, closest)
}

fn random_ray(rng: &mut Rng, target_radius: f64) -> (DVec3, DVec3) {
    let o = rng.unit() * rng.range(4.0, 8.0);
    let aim = rng.unit() * target_radius * rng.f().cbrt();
    let d = (aim - o) * rng.range(0.3, 3.0); // not unit length on purpose
    (o, d)
}

fn check_sphere_scene(name: &str, mesh: &Mesh, r: f64) {
    let ps64 = patches64(mesh);
    let ps32 = patches32(mesh);
    let mut rng = Rng(42);
    let (mut hits, mut worst64, mut worst32, mut worst_t) = (0, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..3000 {
        let (o, d) = random_ray(&mut rng, 1.3 * r);
        let (root, closest) = sphere_root(o, d, r);
        let h64 = closest64::<8>(&ps64, &DRay::new(o, d));
        let h32 = closest32::<8>(&ps32, &Ray::new(o.as_vec3(), d.as_vec3()));
        let margin = 0.01 * r;
        if closest < r - margin {
            let t = root.unwrap();
            let h = h64.unwrap_or_else(|| {
                panic!("{name}: f64 missed a ray through the sphere (closest {closest})")
            });
            let g = h32.unwrap_or_else(|| panic!("{name}: f32 missed a ray through the sphere"));
            hits += 1;
            // On the sphere, to 1e-12 (f64) / 1e-5 (f32) relative.
            let e64 = (h.point.length() - r).abs() / r;
            let e32 = (g.point.as_dvec3().length() - r).abs() / r;
            worst64 = worst64.max(e64);
            worst32 = worst32.max(e32);
            assert!(e64 <= 1e-12, "{name}: f64 hit off the sphere by {e64:e}");
            assert!(e32 <= 1e-5, "{name}: f32 hit off the sphere by {e32:e}");
            // t within t_error (+ rounding slack) of the analytic root.
            let slack = 64.0 * f64::EPSILON * (o.length() / d.length() + t);
            worst_t = worst_t.max((h.t - t).abs());
            assert!(
                (h.t - t).abs() <= h.t_error + slack,
                "{name}: t {} vs {t}, t_error {}",
                h.t,
                h.t_error
            );
            // Radial normal, facing the ray.
            assert_vec_close!(h.normal, h.point / r, 1e-9);
            assert!(g.normal.as_dvec3().dot(g.point.as_dvec3() / r) > 1.0 - 1e-5);
            assert!(h.front_face && g.front_face);
        } else if closest > r + margin {
            assert!(
                h64.is_none() && h32.is_none(),
                "{name}: hit on a ray that misses the sphere"
            );
        }
    }
    eprintln!(
        "{name}: {hits} hits; worst distance to the sphere f64 {worst64:.1e}, f32 {worst32:.1e}; worst |t − t_true| f64 {worst_t:.1e}"
    );
    assert!(hits > 1000);
}

#[test]
fn icosphere_hits_are_on_the_analytic_sphere() {
    check_sphere_scene("icosphere(1)", &icosphere(1, 2.0), 2.0);
}

#[test]
fn cube_with_averaged_normals_is_a_sphere() {
    check_sphere_scene("cube", &cube(), 3f64.sqrt());
}

macro_rules! per_n {
    ($f:ident, $($n:literal),*) => { [$( (($n) as usize, $f::<$n> as fn(&[DPatch], &DRay) -> Option<smoothtri::DHit>) ),*] };
}

/// For every budget N the true error is within `t_error`, and `t_error` is within bisection's
/// guarantee on the shell interval.
#[test]
fn precision_versus_iterations_is_certified() {
    let mesh = torus(8, 8, 1.0, 0.4);
    let ps = patches64(&mesh);
    let table = per_n!(closest64, 0, 1, 2, 4, 8, 16, 24);
    let mut rng = Rng(5);
    let rays: Vec<(DVec3, DVec3)> = (0..1500).map(|_| random_ray(&mut rng, 1.4)).collect();
    let reference: Vec<_> = rays
        .iter()
        .map(|&(o, d)| closest64::<40>(&ps, &DRay::new(o, d)))
        .collect();
    let mut prev_max = f64::INFINITY;
    for (n, f) in table {
        let (mut max_err, mut max_bound, mut disagree) = (0.0f64, 0.0f64, 0);
        let mut errs = Vec::new();
        for (&(o, d), want) in rays.iter().zip(&reference) {
            let got = f(&ps, &DRay::new(o, d));
            match (got, want) {
                (Some(g), Some(w)) => {
                    if g.patch != w.patch && (g.t - w.t).abs() > 1e-9 {
                        continue;
                    }
                    let err = (g.t - w.t).abs();
                    let slack = 1e-12 * (1.0 + w.t);
                    assert!(
                        err <= g.t_error + slack,
                        "N={n}: error {err:e} > t_error {:e}",
                        g.t_error
                    );
                    max_err = max_err.max(err * d.length());
                    errs.push(err * d.length());
                    max_bound = max_bound.max(g.t_error * d.length());
                }
                (None, None) => {}
                _ => disagree += 1,
            }
        }
        errs.sort_by(f64::total_cmp);
        let p99 = errs[errs.len() * 99 / 100];
        eprintln!(
            "torus 8x8, N = {n:2}: max hit error {max_err:.2e}, 99th pct {p99:.2e}, max t_error {max_bound:.2e}, hit/miss disagreements {disagree}, hits {}",
            errs.len()
        );
        assert!(
            disagree <= 2,
            "N={n}: {disagree} rays changed between hit and miss"
        );
        assert!(max_bound <= prev_max * 1.000001 || n == 0);
        prev_max = max_bound;
    }
}

/// The work bound: at most K + 2 + N height evaluations per patch test, hits and misses alike.
#[test]
fn work_per_ray_is_bounded() {
    let mesh = torus(8, 8, 1.0, 0.4);
    let ps = patches32(&mesh);
    let mut rng = Rng(77);
    let (mut max_evals, mut tests) = (0u32, 0u64);
    for _ in 0..2000 {
        let (o, d) = random_ray(&mut rng, 1.5);
        let ray = Ray::new(o.as_vec3(), d.as_vec3());
        for p in &ps {
            let (_, s) = p.intersect_stats::<4, 8>(&ray, 0.0, f32::INFINITY);
            assert!(
                s.height_evals <= 4 + 2 + 8,
                "{} evaluations",
                s.height_evals
            );
            assert!(s.normal_evals <= 1);
            max_evals = max_evals.max(s.height_evals);
            tests += 1;
            let (_, s) = p.intersect_stats::<2, 3>(&ray, 0.0, f32::INFINITY);
            assert!(s.height_evals <= 2 + 2 + 3);
        }
    }
    eprintln!("{tests} patch tests, at most {max_evals} height evaluations (bound 14)");
    assert_eq!(
        max_evals, 14,
        "the bound should be reached by some ray, or the test is too easy"
    );
}

#[test]
fn t_error_shrinks_like_bisection() {
    // On a sphere patch, the reported bound after N iterations never exceeds the shell
    // interval's length / 2^N.
    let mesh = icosphere(1, 2.0);
    let ps = patches64(&mesh);
    let mut rng = Rng(9);
    for _ in 0..500 {
        let (o, d) = random_ray(&mut rng, 2.2);
        let ray = DRay::new(o, d);
        for p in &ps {
            let h0 = p.intersect::<0>(&ray, 0.0, f64::INFINITY);
            if let Some(h0) = h0 {
                // t_error at N = 0 is one sampling step: (tb − ta)/(K + 1).
                let w = h0.t_error * 5.0;
                for (n, h) in [
                    (1, p.intersect::<1>(&ray, 0.0, f64::INFINITY)),
                    (4, p.intersect::<4>(&ray, 0.0, f64::INFINITY)),
                    (8, p.intersect::<8>(&ray, 0.0, f64::INFINITY)),
                ] {
                    let h = h.unwrap();
                    assert!(
                        h.t_error <= w / 2f64.powi(n) * (1.0 + 1e-9),
                        "N={n}: {} > {}",
                        h.t_error,
                        w / 2f64.powi(n)
                    );
                }
            }
        }
    }
}

#[test]
fn degenerate_rays_give_no_hit_and_no_nan() {
    let p: Patch = Patch::new([Vec3::X, Vec3::Y, Vec3::Z], [Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
    let o = Vec3::splat(2.0);
    let toward = -Vec3::ONE;
    assert!(
        p.intersect::<8>(&Ray::new(o, toward), 0.0, f32::INFINITY)
            .is_some()
    );
    for (ray, a, b) in [
        (Ray::new(o, Vec3::ZERO), 0.0, f32::INFINITY),
        (Ray::new(o, Vec3::NAN), 0.0, f32::INFINITY),
        (
            Ray::new(Vec3::new(f32::NAN, 0.0, 0.0), toward),
            0.0,
            f32::INFINITY,
        ),
        (
            Ray::new(o, Vec3::new(f32::INFINITY, -1.0, -1.0)),
            0.0,
            f32::INFINITY,
        ),
        (Ray::new(o, toward), 5.0, 1.0),
        (Ray::new(o, toward), f32::NAN, 1.0),
        (Ray::new(o, toward), 0.0, f32::NAN),
        (Ray::new(o, -toward), 0.0, f32::INFINITY),
    ] {
        assert!(p.intersect::<8>(&ray, a, b).is_none(), "{ray:?} [{a}, {b}]");
    }
    // Starting inside the shell, below the surface: hits it from behind.
    let inside = Vec3::splat(0.5);
    let h = p
        .intersect::<8>(&Ray::new(inside, Vec3::ONE), 0.0, f32::INFINITY)
        .unwrap();
    assert!(!h.front_face && (h.point.length() - 1.0).abs() < 1e-5);
    // Parallel to the face, through the middle of the bulge.
    let nf = p.face_normal();
    let c = Vec3::ONE / 3.0 + nf * 0.05;
    let par = (Vec3::X - Vec3::Y) * 1.0;
    let h = p.intersect::<8>(&Ray::new(c - par * 2.0, par), 0.0, f32::INFINITY);
    assert!(h.is_none_or(|h| h.t.is_finite() && h.point.is_finite()));
    // Grazing the edge region: only finite answers.
    let mut rng = Rng(3);
    for _ in 0..20000 {
        let o = rng.unit().as_vec3() * 3.0;
        let d = (rng.unit() * 0.3 + DVec3::ONE / 3.0f64.sqrt()).as_vec3() - o;
        if let Some(h) = p.intersect::<8>(&Ray::new(o, d), 0.0, f32::INFINITY) {
            assert!(
                h.t.is_finite()
                    && h.point.is_finite()
                    && h.normal.is_finite()
                    && h.t_error.is_finite()
            );
            assert!((h.normal.length() - 1.0).abs() < 1e-5);
        }
    }
}
