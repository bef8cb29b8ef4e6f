//! Each peer against its own `f64` reference: the patch against its definition in the paper
//! (written out independently here), the box against dense sampling, and the ray solver
//! against dense sampling of the parametric surface plus Newton's method (no conic, no cubic).

use glam::{DVec3, Vec3};
use smoothtri::{DRay, Ray};
use smoothtri_peers::nagata::curvature_coefficient;
use smoothtri_peers::torus::Torus;
use smoothtri_peers::{Peer, PeerScene, QuadPatch, nagata, phong_tessellation};

/// Deterministic SplitMix64 in [0, 1).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.f(), self.f(), self.f()) * 2.0 - 1.0;
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// A random well-shaped triangle with normals within `max_deg` of its face normal.
fn random_triangle(rng: &mut Rng, max_deg: f64) -> ([DVec3; 3], [DVec3; 3]) {
    loop {
        let c = rng.unit() * 3.0 * rng.f();
        let p = [c + rng.unit(), c + rng.unit(), c + rng.unit()];
        let nf = (p[1] - p[0]).cross(p[2] - p[0]);
        let area = nf.length();
        let longest = (p[1] - p[0])
            .length()
            .max((p[2] - p[1]).length())
            .max((p[0] - p[2]).length());
        if area < 0.3 * longest * longest {
            continue;
        }
        let nf = nf / area;
        let tilt = |rng: &mut Rng| {
            let a = (max_deg * rng.f()).to_radians();
            let side = rng.unit().cross(nf).normalize();
            (nf * a.cos() + side * a.sin()).normalize()
        };
        return (p, [tilt(rng), tilt(rng), tilt(rng)]);
    }
}

/// `count` triangles of [`random_triangle`] (normals within `max_deg` of the face normal) from
/// the generator seeded with `seed`.
fn random_triangles(
    seed: u64,
    count: usize,
    max_deg: f64,
) -> impl Iterator<Item = ([DVec3; 3], [DVec3; 3])> {
    let mut rng = Rng(seed);
    (0..count).map(move |_| random_triangle(&mut rng, max_deg))
}

/// Phong tessellation straight from the paper's definition.
fn phong_reference(p: [DVec3; 3], n: [DVec3; 3], alpha: f64, w1: f64, w2: f64) -> DVec3 {
    let w = [1.0 - w1 - w2, w1, w2];
    let flat = p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
    let proj = |i: usize| flat - n[i] * (flat - p[i]).dot(n[i]);
    let star = proj(0) * w[0] + proj(1) * w[1] + proj(2) * w[2];
    flat * (1.0 - alpha) + star * alpha
}

/// Nagata's patch in his own parameters `0 ≤ ζ ≤ η ≤ 1` (x00, x10, x11 = P0, P1, P2).
fn nagata_reference(p: [DVec3; 3], n: [DVec3; 3], eta: f64, zeta: f64) -> DVec3 {
    let c1 = curvature_coefficient(p[1] - p[0], n[0], n[1]);
    let c2 = curvature_coefficient(p[2] - p[1], n[1], n[2]);
    let c3 = curvature_coefficient(p[2] - p[0], n[0], n[2]);
    let c00 = p[0];
    let c10 = p[1] - p[0] - c1;
    let c01 = p[2] - p[1] + c1 - c3;
    let c11 = c3 - c1 - c2;
    p[0] * 0.0 + c00 + c10 * eta + c01 * zeta + c11 * eta * zeta + c1 * eta * eta + c2 * zeta * zeta
}

fn patch64(peer: Peer, p: [DVec3; 3], n: [DVec3; 3]) -> QuadPatch<f64> {
    peer.patch::<f64>(p, n).unwrap()
}

/// The patch of `peer` in `f32`, on the triangle rounded to `f32`.
fn patch32(peer: Peer, p: [DVec3; 3], n: [DVec3; 3]) -> QuadPatch<f32> {
    peer.patch::<f32>(p.map(|v| v.as_vec3()), n.map(|v| v.as_vec3()))
        .unwrap()
}

const PEERS: [Peer; 3] = [
    Peer::PhongTess { alpha: 0.75 },
    Peer::PhongTess { alpha: 1.0 },
    Peer::Nagata,
];

/// The patches equal their papers' definitions (Phong: the projections; Nagata: his
/// monomial form in (η, ζ)), at random points of random triangles. Fails on a wrong edge
/// control or a wrong monomial conversion.
#[test]
fn patches_equal_their_definitions() {
    let mut rng = Rng(1);
    for _ in 0..300 {
        let (p, n) = random_triangle(&mut rng, 50.0);
        for alpha in [0.0, 0.75, 1.0] {
            let q = phong_tessellation::<f64>(p, n, alpha).unwrap();
            for _ in 0..5 {
                let (a, b) = (rng.f(), rng.f());
                let (w1, w2) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                let want = phong_reference(p, n, alpha, w1, w2);
                assert!((q.point(w1, w2) - want).length() < 1e-13, "alpha {alpha}");
            }
        }
        let q = nagata::<f64>(p, n).unwrap();
        for _ in 0..5 {
            let (a, b) = (rng.f(), rng.f());
            let (eta, zeta) = (a.max(b), a.min(b));
            let want = nagata_reference(p, n, eta, zeta);
            assert!((q.point(eta - zeta, zeta) - want).length() < 1e-12);
        }
    }
}

/// The interpolation and tangency properties: each patch passes through its vertices; a
/// Nagata edge leaves each vertex perpendicular to that vertex's normal; with all normals
/// equal to the face normal both peers are the flat triangle.
#[test]
fn vertices_tangents_and_flat_triangles() {
    for (p, n) in random_triangles(2, 200, 40.0) {
        for peer in PEERS {
            let q = patch64(peer, p, n);
            for (k, (w1, w2)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
                assert!((q.point(w1, w2) - p[k]).length() < 1e-14);
            }
        }
        let q = nagata::<f64>(p, n).unwrap();
        // Edge 0 → 1 is w2 = 0, parameter w1: tangent ∂x/∂w1 − 0 at w1 = 0 (w0 falls).
        let (du, _) = q.derivatives(0.0, 0.0);
        assert!(du.dot(n[0]).abs() < 1e-12 * du.length());
        let (du1, _) = q.derivatives(1.0, 0.0);
        assert!(du1.dot(n[1]).abs() < 1e-12 * du1.length());
        let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        for peer in PEERS {
            let flat = patch64(peer, p, [nf; 3]);
            let x = flat.point(0.3, 0.2);
            assert!((x - (p[0] * 0.5 + p[1] * 0.3 + p[2] * 0.2)).length() < 1e-13);
        }
    }
}

/// Nagata's fallback for degenerate normal pairs: parallel or opposite normals give a straight
/// edge (c = 0); normals just past the tolerance give the formula's value, which satisfies both
/// tangency conditions.
#[test]
fn nagata_degenerate_normal_pairs() {
    let d = DVec3::new(1.0, 0.0, 0.2);
    let n = DVec3::new(0.0, 0.0, 1.0);
    assert_eq!(curvature_coefficient(d, n, n), DVec3::ZERO);
    assert_eq!(curvature_coefficient(d, n, -n), DVec3::ZERO);
    // A tilt of 1e-7 rad: κ ≈ 2.5e-15, below the tolerance: the fallback.
    let tiny = DVec3::new(1e-7, 0.0, 1.0).normalize();
    assert_eq!(curvature_coefficient(d, n, tiny), DVec3::ZERO);
    // 10°: the formula; both tangency conditions hold.
    let n1 = DVec3::new(10f64.to_radians().sin(), 0.0, 10f64.to_radians().cos());
    let c = curvature_coefficient(d, n, n1);
    assert!(((d - c).dot(n)).abs() < 1e-14);
    assert!(((d + c).dot(n1)).abs() < 1e-14);
    // A whole patch with two equal normals and an edge off their tangent plane stays finite.
    let p = [DVec3::ZERO, d, DVec3::new(0.0, 1.0, 0.0)];
    let q = nagata::<f32>(p.map(|v| v.as_vec3()), [n, n, n1].map(|v| v.as_vec3())).unwrap();
    assert!(q.point(0.5, 0.0).is_finite());
}

/// The analytic box contains the patch: dense sampling (f32 and f64 evaluation).
#[test]
fn bounds_contain_dense_samples() {
    for (p, n) in random_triangles(3, 150, 60.0) {
        for peer in PEERS {
            let q64 = patch64(peer, p, n);
            let q32 = patch32(peer, p, n);
            let (b64, b32) = (q64.bounds(), q32.bounds());
            let k = 40;
            for i in 0..=k {
                for j in 0..=(k - i) {
                    let (u, v) = (i as f64 / k as f64, j as f64 / k as f64);
                    let x = q64.point(u, v);
                    assert!(x.cmpge(b64.min()).all() && x.cmple(b64.max()).all());
                    let y = q32.point(u as f32, v as f32);
                    assert!(y.cmpge(b32.min()).all() && y.cmple(b32.max()).all());
                }
            }
        }
    }
}

/// The reference intersection: the nearest `(t, u, v)` found by Newton's method on
/// `x(u, v) − o − t·d = 0` from every sample of a dense grid that lies near the ray.
fn reference_hit(q: &QuadPatch<f64>, o: DVec3, d: DVec3) -> Option<(f64, f64, f64)> {
    let k = 48;
    let mut best: Option<(f64, f64, f64)> = None;
    let size = (q.bounds().max() - q.bounds().min()).length();
    for i in 0..=k {
        for j in 0..=(k - i) {
            let (mut u, mut v) = (i as f64 / k as f64, j as f64 / k as f64);
            let x = q.point(u, v);
            let mut t = d.dot(x - o) / d.dot(d);
            let off = (x - o - d * t).length();
            if off > 0.08 * size {
                continue;
            }
            for _ in 0..40 {
                let r = q.point(u, v) - o - d * t;
                let (xu, xv) = q.derivatives(u, v);
                let m = glam::DMat3::from_cols(xu, xv, -d);
                let det = m.determinant();
                if det.abs() < 1e-300 {
                    break;
                }
                let delta = m.inverse() * -r;
                u += delta.x;
                v += delta.y;
                t += delta.z;
            }
            let r = (q.point(u, v) - o - d * t).length();
            if r < 1e-10 * size
                && u >= -1e-9
                && v >= -1e-9
                && u + v <= 1.0 + 1e-9
                && t >= 0.0
                && best.is_none_or(|b| t < b.0)
            {
                best = Some((t, u, v));
            }
        }
    }
    best
}

/// Random rays at random patches: the solver's nearest hit (f64 and f32) against the
/// reference. A disagreement in hit or miss is allowed only within rounding of the patch's
/// rim (where the reference's domain test and the solver's may differ). Fails on a lost
/// root, a wrong root (not the nearest) or an inaccurate `t`.
#[test]
fn solver_equals_reference() {
    const TRIANGLES: usize = 60;
    const RAYS_PER_PATCH: usize = 12;
    let mut rng = Rng(4);
    let mut hits = 0;
    for _ in 0..TRIANGLES {
        let (p, n) = random_triangle(&mut rng, 45.0);
        for peer in PEERS {
            let q = patch64(peer, p, n);
            let q32 = patch32(peer, p, n);
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let size = (q.bounds().max() - q.bounds().min()).length();
            for _ in 0..RAYS_PER_PATCH {
                let target = c + rng.unit() * size * 0.6 * rng.f();
                let o = target + rng.unit() * 3.0 * size;
                let d = (target - o) * (0.5 + rng.f());
                let want = reference_hit(&q, o, d);
                let got = q.closest_hit(&DRay::new(o, d), 0.0, f64::INFINITY);
                let got32 = q32.closest_hit(&Ray::new(o.as_vec3(), d.as_vec3()), 0.0, f32::MAX);
                match (got, want) {
                    (Some(g), Some((t, u, v))) => {
                        hits += 1;
                        let scale = d.length();
                        assert!(
                            (g.t - t).abs() * scale < 1e-9 * size,
                            "{peer:?} t {} vs {t}",
                            g.t
                        );
                        assert!((g.w1 - u).abs() < 1e-7 && (g.w2 - v).abs() < 1e-7);
                        let g32 = got32.expect("f32 hit where f64 hits");
                        assert!(
                            (f64::from(g32.t) - t).abs() * scale < 2e-4 * size,
                            "{peer:?} f32 t {} vs {t}",
                            g32.t
                        );
                    }
                    (None, None) => assert!(got32.is_none() || rim(&q, o, d)),
                    (Some(g), None) => {
                        let (u, v) = (g.w1, g.w2);
                        assert!(
                            u.min(v).min(1.0 - u - v) < 1e-6,
                            "{peer:?} extra hit inside"
                        )
                    }
                    (None, Some(_)) => assert!(rim(&q, o, d), "{peer:?} lost a hit"),
                }
            }
        }
    }
    let rays = TRIANGLES * PEERS.len() * RAYS_PER_PATCH;
    assert!(hits > rays / 5, "{hits} of {rays}");
}

/// Whether the ray passes within rounding of the patch's rim (its three edge curves).
fn rim(q: &QuadPatch<f64>, o: DVec3, d: DVec3) -> bool {
    let dn = d.normalize();
    let size = (q.bounds().max() - q.bounds().min()).length();
    (0..=2000).any(|k| {
        let s = k as f64 / 2000.0;
        [(s, 0.0), (0.0, s), (1.0 - s, s)].iter().any(|&(u, v)| {
            let x = q.point(u, v) - o;
            (x - dn * x.dot(dn)).length() < 2e-3 * size
        })
    })
}

/// Rays through the vertices and along the normals of the edge midpoints: hit, at the right
/// barycentrics; rays from the far side of a patch pointing away: miss.
#[test]
fn vertices_edges_and_misses() {
    for (p, n) in random_triangles(5, 100, 35.0) {
        for peer in PEERS {
            let q = patch64(peer, p, n);
            for (k, (w1, w2)) in [
                (0.0, 0.0),
                (1.0, 0.0),
                (0.0, 1.0),
                (0.5, 0.0),
                (0.5, 0.5),
                (0.0, 0.5),
            ]
            .into_iter()
            .enumerate()
            {
                let x = q.point(w1, w2);
                let nn = q.normal(w1, w2);
                let o = x + nn * 2.0;
                let h = q.closest_hit(&DRay::new(o, -nn), 0.0, f64::INFINITY);
                let h = h.unwrap_or_else(|| panic!("{peer:?} point {k} missed"));
                // A strongly curved patch can fold over the point: the reference says which
                // crossing is the nearest.
                let (t, ..) = reference_hit(&q, o, -nn).expect("the reference hits");
                assert!(t <= 2.0 + 1e-9);
                assert!(
                    (h.t - t).abs() < 1e-9,
                    "{peer:?} point {k}: t {} vs {t}",
                    h.t
                );
                if t > 2.0 - 1e-9 {
                    assert!((h.w1 - w1).abs() < 1e-6 && (h.w2 - w2).abs() < 1e-6);
                    assert!(h.front_face);
                }
                // From just beyond it, from the point's side: the crossing at t = 2.
                let h2 = q.closest_hit(&DRay::new(o, -nn), 2.0 - 1e-6, f64::INFINITY);
                assert!(
                    h2.is_some_and(|h| (h.t - 2.0).abs() < 1e-9),
                    "{peer:?} point {k}"
                );
                // Away from the patch: no hit.
                assert!(
                    q.closest_hit(&DRay::new(o, nn), 0.0, f64::INFINITY)
                        .is_none()
                );
                // Stopped short of it: no hit.
                assert!(q.closest_hit(&DRay::new(o, -nn), 0.0, t * 0.9).is_none());
            }
        }
    }
}

/// Grazing rays and double roots: a ray tangent to a convex patch at an interior point (a
/// double root of the pencil's quadratics) is found at the tangent point; moved off the surface
/// by 1e-6 of the size it misses, moved into it it hits twice and the nearer is returned.
#[test]
fn grazing_rays_and_double_roots() {
    // An octant of the unit sphere, radial normals: both peers bulge outward (convex).
    let p = [DVec3::X, DVec3::Y, DVec3::Z];
    for peer in PEERS {
        let q = patch64(peer, p, p);
        let mut tested = 0;
        for (w1, w2) in [(0.3, 0.3), (0.2, 0.5), (0.5, 0.25), (1.0 / 3.0, 1.0 / 3.0)] {
            let x = q.point(w1, w2);
            let nn = q.normal(w1, w2);
            let (du, dv) = q.derivatives(w1, w2);
            for tan in [du.normalize(), dv.normalize(), (du - dv).normalize()] {
                let o = x - tan * 0.5;
                // Exactly tangent: hit at the tangent point, to the square root of rounding.
                let h = q.closest_hit(&DRay::new(o, tan), 0.0, f64::INFINITY);
                let h = h.unwrap_or_else(|| panic!("{peer:?} tangent ray missed"));
                assert!(
                    (h.point - x).length() < 1e-5,
                    "{peer:?}: {}",
                    (h.point - x).length()
                );
                // Outside (the convex side): miss.
                let out = q.closest_hit(&DRay::new(o + nn * 1e-6, tan), 0.0, f64::INFINITY);
                assert!(out.is_none(), "{peer:?} hit from outside");
                // Inside: two crossings about ±sqrt(2δ/κ) around the tangent point; the nearer.
                let inside = q.closest_hit(&DRay::new(o - nn * 1e-6, tan), 0.0, f64::INFINITY);
                let h = inside.unwrap_or_else(|| panic!("{peer:?} missed from inside"));
                assert!(h.t < 0.5 && h.t > 0.49, "{peer:?} t {}", h.t);
                tested += 1;
            }
        }
        assert_eq!(tested, 12);
    }
}

/// Meshes of peer patches are watertight: rays aimed at the shared edges of a torus mesh never
/// slip between two patches (their edge curves are the same), f32 and f64, and every hit's
/// point lies on its patch.
#[test]
fn shared_edges_are_watertight() {
    // The 8 × 8 torus of major radius 1 and minor radius 0.4 of the built-in scenes.
    let torus = smoothtri_host::scenes::torus(8, 8, 1.0, 0.4);
    let (pos, nrm, tris) = (&torus.positions, &torus.normals, &torus.triangles);
    for peer in PEERS {
        let s64 = PeerScene::<f64>::build(peer, pos, nrm, tris).unwrap();
        let s32 = PeerScene::<f32>::build(peer, pos, nrm, tris).unwrap();
        let (t64, t32) = (s64.tracer().unwrap(), s32.tracer().unwrap());
        let mut rng = Rng(6);
        for (k, tri) in tris.iter().enumerate() {
            let q = &s64.patches()[k];
            for e in 0..3 {
                let s = rng.f();
                let (w1, w2) = match e {
                    0 => (s, 0.0),
                    1 => (1.0 - s, s),
                    _ => (0.0, s),
                };
                let x = q.point(w1, w2);
                // From outside the torus, along the surface normal.
                let nn = q.interpolated_normal(w1, w2);
                let o = x + nn * 0.5;
                let h = t64.closest_hit(&DRay::new(o, -nn), 0.0, f64::INFINITY);
                let h = h.unwrap_or_else(|| panic!("{peer:?} f64 slipped at triangle {k} {tri:?}"));
                assert!((h.t - 0.5).abs() < 1e-9);
                let h = t32.closest_hit(&Ray::new(o.as_vec3(), -nn.as_vec3()), 0.0, f32::MAX);
                let h = h.unwrap_or_else(|| panic!("{peer:?} f32 slipped at triangle {k}"));
                let on = s32.patches()[h.patch as usize].point(h.w1, h.w2);
                assert!((on - h.point).length() < 1e-5);
                assert!((h.t - 0.5).abs() < 1e-5);
                // Shadow query agrees.
                assert!(t32.any_hit(&Ray::new(o.as_vec3(), -nn.as_vec3()), 0.0, f32::MAX));
            }
        }
    }
}

/// The analytic torus: every hit lies on it to rounding, tangent rays are found, and a
/// dense march along random rays finds no crossing before the returned one.
#[test]
fn torus_reference() {
    let torus = Torus {
        major: 1.0,
        minor: 0.4,
    };
    let mut rng = Rng(7);
    let mut hits = 0;
    for _ in 0..2000 {
        let o = rng.unit() * (2.0 + 3.0 * rng.f());
        let d = (rng.unit() * 1.2 * rng.f() - o) * (0.3 + rng.f());
        let h = torus.closest_hit(o, d, 0.0, f64::INFINITY);
        // March: the first sign change of (distance to the tube's circle − r).
        let f = |t: f64| {
            let x = o + d * t;
            let q = (x.x * x.x + x.y * x.y).sqrt() - 1.0;
            (q * q + x.z * x.z).sqrt() - 0.4
        };
        let steps = 4000;
        let tmax = 2.0 * (o.length() + 2.0) / d.length();
        let first = (0..steps)
            .map(|k| k as f64 * tmax / steps as f64)
            .find(|&t| f(t) < 0.0);
        match (h, first) {
            (Some((t, n)), Some(tm)) => {
                hits += 1;
                assert!(torus.distance(o + d * t) < 1e-12 * o.length().max(1.0));
                assert!(t <= tm + 1e-12 && tm - t <= tmax / steps as f64 + 1e-9);
                assert!((n.length() - 1.0).abs() < 1e-12);
            }
            (None, Some(tm)) => panic!("missed a crossing at {tm}"),
            (Some((t, _)), None) => assert!(torus.distance(o + d * t) < 1e-12),
            (None, None) => {}
        }
    }
    assert!(hits > 300, "{hits}");
    // Tangent: the ray z = r over the ring touches the top circle at (0, ±1, 0.4)... it
    // grazes along a circle: the ray x = t, y = 1, z = 0.4 touches at (0, 1, 0.4).
    let h = torus.closest_hit(DVec3::new(-3.0, 1.0, 0.4), DVec3::X, 0.0, f64::INFINITY);
    let (t, _) = h.expect("the tangent ray");
    assert!((t - 3.0).abs() < 1e-6, "{t}");
    let _ = Vec3::ZERO;
}
