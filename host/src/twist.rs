//! The twisting torus: a procedural deforming mesh for timing animated scenes (the demo's
//! `--scene twist`, the update benchmarks), with the exact surface's normals at any time.
//!
//! A torus (major radius 1, minor 0.4) on an `n × n` grid, `2n²` triangles with the index
//! buffer of `scenes::torus`, whose surface moves with period
//! [`TWIST_PERIOD`]: with `s = sin(ωt)`, `ω = 2π / TWIST_PERIOD`,
//!
//! - the tube's radius waves, `ρ = 0.4 + 0.03 · sin(7u − ωt) · sin(5v + 1.5 · sin u · s)`: the
//!   ripples travel around the ring and twist around the tube;
//! - the ring bends out of its plane, `z = 0.25 · sin 2u · s` (a saddle that breathes);
//!
//! so the point at `(u, v)` is `c(u) + ρ(u, v) · (cos v · e_r(u) + sin v · z)`, with the
//! ring's centre line `c(u) = (cos u, sin u, 0.25 · sin 2u · s)` and `e_r(u) = (cos u, sin u,
//! 0)`. Vertex normals are the surface's (`∂u × ∂v` from the analytic derivatives), so they
//! are exact to rounding at every time. At `t = 0` (and every whole period) the mesh is the
//! wavy torus of the GPU benchmark (`gpu/examples/bench.rs`) with analytic normals.

use std::f64::consts::TAU;

use glam::DVec3;
use rayon::prelude::*;
use smoothtri_io::Mesh;

use crate::grid::grid_triangles;

/// The period of the twisting torus's motion, seconds: every pose repeats after it.
pub const TWIST_PERIOD: f64 = 4.0;

/// Grid sides `n` of the benchmarks' twisting tori and their triangle counts `2n²`: about 10k
/// (10 082), 100k (100 352, the timing mesh) and 1M (1 002 528) triangles.
pub const TWIST_SIDES: [usize; 3] = [71, 224, 708];

/// The grid side of the demo's `--scene twist` (100 352 triangles).
pub const TWIST_DEMO_SIDE: usize = 224;

const BIG_R: f64 = 1.0;
const SMALL_R: f64 = 0.4;
const WAVE: f64 = 0.03;
const WAVE_U: f64 = 7.0;
const WAVE_V: f64 = 5.0;
const TWIST: f64 = 1.5;
const BEND: f64 = 0.25;

/// The point at grid angles `(u, v)` (radians) at time `t` (seconds), and the unit outward
/// normal there (the normalised cross product of the analytic derivatives in `u` and `v`).
pub fn twist_point(u: f64, v: f64, t: f64) -> (DVec3, DVec3) {
    let w = TAU / TWIST_PERIOD;
    let s = (w * t).sin();
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let (s2u, c2u) = (2.0 * u).sin_cos();
    let chi = WAVE_U * u - w * t;
    let psi = WAVE_V * v + TWIST * su * s;
    let (schi, cchi) = chi.sin_cos();
    let (spsi, cpsi) = psi.sin_cos();
    let rho = SMALL_R + WAVE * schi * spsi;
    let rho_u = WAVE * (WAVE_U * cchi * spsi + schi * cpsi * TWIST * cu * s);
    let rho_v = WAVE * schi * cpsi * WAVE_V;
    let e_r = DVec3::new(cu, su, 0.0);
    let e_r_u = DVec3::new(-su, cu, 0.0);
    let radial = e_r * cv + DVec3::Z * sv;
    let centre = DVec3::new(BIG_R * cu, BIG_R * su, BEND * s2u * s);
    let centre_u = DVec3::new(-BIG_R * su, BIG_R * cu, 2.0 * BEND * c2u * s);
    let p = centre + radial * rho;
    let d_u = centre_u + radial * rho_u + e_r_u * (rho * cv);
    let d_v = radial * rho_v + (DVec3::Z * cv - e_r * sv) * rho;
    (p, d_u.cross(d_v).normalize())
}

/// The twisting torus on an `n × n` grid at time `t` (seconds): `n²` vertices, `2n²`
/// triangles counter-clockwise seen from outside (the index buffer of
/// `scenes::torus``(n, n, …)`).
pub fn twisting_torus(n: usize, t: f64) -> Mesh {
    let mut m = Mesh {
        positions: vec![DVec3::ZERO; n * n],
        normals: vec![DVec3::ZERO; n * n],
        triangles: grid_triangles(n, n),
    };
    twist_pose(n, t, &mut m.positions, &mut m.normals);
    m
}

/// Writes the vertices and normals of [`twisting_torus`]`(n, t)` into `positions` and
/// `normals` (on rayon's pool, allocation-free): a frame of the animation.
///
/// # Panics
/// When a buffer does not hold `n²` elements.
pub fn twist_pose(n: usize, t: f64, positions: &mut [DVec3], normals: &mut [DVec3]) {
    assert!(
        positions.len() == n * n && normals.len() == n * n,
        "twist_pose: buffers of {} and {} for {n}² vertices",
        positions.len(),
        normals.len()
    );
    positions
        .par_iter_mut()
        .zip(normals.par_iter_mut())
        .enumerate()
        .for_each(|(k, (p, nrm))| {
            let (i, j) = (k / n, k % n);
            let u = i as f64 / n as f64 * TAU;
            let v = j as f64 / n as f64 * TAU;
            (*p, *nrm) = twist_point(u, v, t);
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::torus;

    #[test]
    fn normals_are_the_surface_s_by_finite_differences() {
        let h = 1e-5;
        // 500 points of the additive recurrence of the plastic-number family (a low-discrepancy
        // cover of the (u, v, t) box), so the points spread evenly without a random generator.
        let (a1, a2, a3) = (
            0.819_172_513_396_164_4,
            0.671_043_606_703_789_2,
            0.549_700_477_901_970_2,
        );
        for k in 0..500 {
            let k = f64::from(k) + 0.5;
            let (u, v, t) = (
                (k * a1).fract() * TAU,
                (k * a2).fract() * TAU,
                -3.0 + 12.0 * (k * a3).fract(),
            );
            let (p, n) = twist_point(u, v, t);
            let du = (twist_point(u + h, v, t).0 - twist_point(u - h, v, t).0) / (2.0 * h);
            let dv = (twist_point(u, v + h, t).0 - twist_point(u, v - h, t).0) / (2.0 * h);
            let fd = du.cross(dv).normalize();
            assert!((n - fd).length() < 1e-8, "({u}, {v}, {t}): {n} vs {fd}");
            assert!((n.length() - 1.0).abs() < 1e-14);
            // Outward: away from the tube's centre line c(u).
            let s = (TAU * t / TWIST_PERIOD).sin();
            let c = DVec3::new(u.cos(), u.sin(), 0.25 * (2.0 * u).sin() * s);
            assert!(n.dot(p - c) > 0.0);
        }
    }

    #[test]
    fn at_rest_it_is_the_wavy_torus_and_it_repeats_every_period() {
        let n = 12;
        let m = twisting_torus(n, 0.0);
        let flat = torus(n, n, 1.0, 0.4);
        assert_eq!(m.triangles, flat.triangles);
        for i in 0..n {
            for j in 0..n {
                let (u, v) = (i as f64 / n as f64 * TAU, j as f64 / n as f64 * TAU);
                let r = 0.4 + 0.03 * (7.0 * u).sin() * (5.0 * v).sin();
                let radial = DVec3::new(v.cos() * u.cos(), v.cos() * u.sin(), v.sin());
                let want = DVec3::new(u.cos(), u.sin(), 0.0) + radial * r;
                assert!((m.positions[i * n + j] - want).length() < 1e-15);
            }
        }
        for t in [0.3, 1.1, 2.9] {
            let a = twisting_torus(n, t);
            let b = twisting_torus(n, t + 2.0 * TWIST_PERIOD);
            for (p, q) in a.positions.iter().zip(&b.positions) {
                assert!((*p - *q).length() < 1e-12);
            }
            // It moves: the bend lifts the ring's top (at rest 0.4 ± 0.03) by up to 0.25·|sin ωt|
            // (0.22·|sin ωt| at the grid's u = 30°, 120°, …).
            let s = (TAU * t / TWIST_PERIOD).sin().abs();
            let top = a.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
            assert!(top > 0.37 + 0.21 * s, "{t}: {top}");
        }
    }

    #[test]
    fn the_benchmark_sizes_have_the_advertised_triangle_counts() {
        let counts: Vec<usize> = TWIST_SIDES.iter().map(|n| 2 * n * n).collect();
        assert_eq!(counts, [10_082, 100_352, 1_002_528]);
        assert_eq!(twisting_torus(TWIST_SIDES[0], 1.0).triangles.len(), 10_082);
    }
}
