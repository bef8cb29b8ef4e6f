//! Ray packets ([`Bvh::closest_hit_packet`]) against the single-ray kernel
//! ([`Bvh::closest_hit`]) on coherent camera tiles and on scattered rays: the same rays hit and
//! miss, hits agree within their `t_error`s and carry finite unit normals, f32 and f64.

use glam::{DVec3, Vec3};
use smoothtri::internal::LANES;
use smoothtri::{Bvh, BvhNode, Float, Patch, Ray};
use smoothtri_demo::camera::Camera;
use smoothtri_demo::scenes::{Mesh, icosphere, teapot, torus};

fn patches<F: Float>(m: &Mesh, conv: fn(DVec3) -> F::Vec3) -> Vec<Patch<F>> {
    m.triangles
        .iter()
        .filter_map(|t| {
            let p = t.map(|i| conv(m.positions[i as usize]));
            let n = t.map(|i| conv(m.normals[i as usize]));
            Patch::<F>::new_or_tilted(p, n).ok()
        })
        .collect()
}

/// Rays of 2×4 pixel tiles of a camera framing the mesh, plus tiles of scattered rays.
fn packets(m: &Mesh, w: u32, h: u32) -> Vec<[(DVec3, DVec3); LANES]> {
    let cam = Camera::for_mesh(m, 30.0, 35.0, w, h);
    let mut out = Vec::new();
    for ty in (0..h).step_by(2) {
        for tx in (0..w).step_by(4) {
            out.push(core::array::from_fn(|i| {
                cam.pixel_ray(tx + (i % 4) as u32, ty + (i / 4) as u32)
            }));
        }
    }
    // Incoherent packets: each lane from a different tile.
    let n = out.len();
    for k in 0..n / 8 {
        out.push(core::array::from_fn(|i| out[(k * 8 + i * 97) % n][i]));
    }
    out
}

fn check<F: Float>(name: &str, m: &Mesh, conv: fn(DVec3) -> F::Vec3) {
    let ps = patches::<F>(m, conv);
    let mut nodes = vec![BvhNode::<F>::default(); Bvh::<F>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let (mut hits, mut worst) = (0usize, 0.0f64);
    let inf = F::from_f64(f64::INFINITY);
    for pk in packets(m, 64, 48) {
        let rays: [Ray<F>; LANES] = pk.map(|(o, d)| Ray::new(conv(o), conv(d)));
        let got = bvh.closest_hit_packet::<8>(&rays, F::ZERO, inf);
        for (ray, g) in rays.iter().zip(got) {
            let want = bvh.closest_hit::<8>(ray, F::ZERO, inf);
            match (g, want) {
                (Some(g), Some(w)) => {
                    hits += 1;
                    let (gt, wt) = (g.t.to_f64(), w.t.to_f64());
                    let slack = 8.0 * F::EPSILON.to_f64() * wt.abs();
                    let err = (gt - wt).abs();
                    let allowed = g.t_error.to_f64() + w.t_error.to_f64() + slack;
                    assert!(err <= allowed, "{name}: |{gt} − {wt}| > {allowed:e}");
                    worst = worst.max(err / allowed);
                    let n = F::from_glam(g.normal);
                    assert!((n.length().to_f64() - 1.0).abs() < 1e-5, "{name}: normal");
                }
                (None, None) => {}
                (g, w) => panic!("{name}: packet {g:?} vs single {w:?}"),
            }
        }
    }
    eprintln!("{name}: {hits} hits; largest |Δt| / (t_errors) {worst:.3}");
    assert!(hits > 400, "{name}: {hits}");
}

#[test]
fn packets_agree_with_single_rays() {
    let f32v = |v: DVec3| v.as_vec3();
    let f64v = |v: DVec3| v;
    for (name, m) in [
        ("torus 8x8", torus(8, 8, 1.0, 0.4)),
        ("icosphere", icosphere(1, 1.0)),
        ("teapot", teapot(4)),
    ] {
        check::<f32>(name, &m, f32v);
        check::<f64>(name, &m, f64v);
    }
}

#[test]
fn packets_with_bad_rays_are_finite_or_none() {
    let m = torus(8, 8, 1.0, 0.4);
    let ps = patches::<f32>(&m, |v| v.as_vec3());
    let mut nodes = vec![BvhNode::<f32>::default(); Bvh::<f32>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let good = Ray::new(Vec3::new(0.0, -3.0, 0.2), Vec3::Y);
    let bad = [
        Ray::new(Vec3::NAN, Vec3::Y),
        Ray::new(Vec3::ZERO, Vec3::ZERO),
        Ray::new(Vec3::splat(f32::INFINITY), Vec3::X),
        Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 0.0)),
    ];
    let rays = [good, bad[0], bad[1], good, bad[2], bad[3], good, good];
    let got = bvh.closest_hit_packet::<4>(&rays, 0.0, f32::INFINITY);
    for (r, g) in rays.iter().zip(got) {
        let want = bvh.closest_hit::<4>(r, 0.0, f32::INFINITY);
        assert_eq!(g.is_some(), want.is_some());
        if let Some(g) = g {
            assert!(g.t.is_finite() && g.t_error.is_finite() && g.normal.is_finite());
        }
    }
    assert!(got[0].is_some());
    // NaN range: no hits.
    let none = bvh.closest_hit_packet::<4>(&rays, f32::NAN, 1.0);
    assert!(none.iter().all(Option::is_none));
}
