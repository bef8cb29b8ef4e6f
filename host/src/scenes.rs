//! Built-in scenes (the demo's `--scene`, the tests' and benchmarks' meshes): torus,
//! icosphere, cube with averaged normals (exactly a sphere for the method) and Newell's teapot,
//! with analytic vertex normals, and the exact surfaces they sample for measuring fidelity
//! ([`torus_distance`], [`exact_distance`], [`sphere_root`]).

use glam::DVec3;
use smoothtri_io::Mesh;

use crate::grid::grid_triangles;

/// Torus of major radius `big_r` and minor radius `r` around the z axis, on a `nu × nv` grid
/// split into two triangles per quad, with analytic normals.
pub fn torus(nu: usize, nv: usize, big_r: f64, r: f64) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..nu {
        for j in 0..nv {
            let u = i as f64 / nu as f64 * std::f64::consts::TAU;
            let v = j as f64 / nv as f64 * std::f64::consts::TAU;
            let n = DVec3::new(v.cos() * u.cos(), v.cos() * u.sin(), v.sin());
            m.positions
                .push(DVec3::new(big_r * u.cos(), big_r * u.sin(), 0.0) + n * r);
            m.normals.push(n);
        }
    }
    m.triangles = grid_triangles(nu, nv);
    m
}

/// Distance of `x` to the torus of [`torus`] (major radius `big_r`, minor `r`).
pub fn torus_distance(x: DVec3, big_r: f64, r: f64) -> f64 {
    let q = (x.x * x.x + x.y * x.y).sqrt() - big_r;
    ((q * q + x.z * x.z).sqrt() - r).abs()
}

/// The unit icosphere of level 3 with each vertex normal tilted from the radius by up to 20°
/// (a fixed pattern): on the shared line field (`smoothtri::LineField::Vertex`) its patches'
/// sections are tilted, so the kernels run the section's Newton steps and the ruled walls.
/// Used by the instruction-count bench, the GPU bench and the GPU parity test.
pub fn tilted_normal_sphere() -> Mesh {
    let mut m = icosphere(3, 1.0);
    for (i, n) in m.normals.iter_mut().enumerate() {
        let k = i as f64;
        let axis = DVec3::new((1.3 * k).sin(), (2.1 * k).cos(), (0.7 * k).sin());
        let a = (20.0 * (0.5 + 0.5 * (3.7 * k).sin())).to_radians();
        *n = *n * a.cos() + axis.cross(*n).normalize_or_zero() * a.sin();
    }
    m
}

/// Icosphere of radius `r` centred at the origin: the icosahedron subdivided `level` times,
/// vertices projected onto the sphere, radial normals. Level 1 has 80 triangles.
pub fn icosphere(level: u32, r: f64) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<DVec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *mid.entry(key).or_insert_with(|| {
                pos.push(((pos[a as usize] + pos[b as usize]) * 0.5).normalize());
                (pos.len() - 1) as u32
            })
        };
        for [a, b, c] in tris {
            let ab = midpoint(a, b, &mut pos);
            let bc = midpoint(b, c, &mut pos);
            let ca = midpoint(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    Mesh {
        normals: pos.clone(),
        positions: pos.iter().map(|p| *p * r).collect(),
        triangles: tris,
    }
}

/// The cube `[-1, 1]³` (12 triangles) with averaged normals `(±1, ±1, ±1)/√3`: its vertices lie
/// on the sphere of radius √3 with radial normals, so every patch is exactly that sphere,
/// although the normals are 54.7° from the faces.
pub fn cube() -> Mesh {
    let mut m = Mesh::default();
    for k in 0..8u32 {
        let p = DVec3::new(
            if k & 1 != 0 { 1.0 } else { -1.0 },
            if k & 2 != 0 { 1.0 } else { -1.0 },
            if k & 4 != 0 { 1.0 } else { -1.0 },
        );
        m.positions.push(p);
        m.normals.push(p.normalize());
    }
    // Faces as quads counter-clockwise from outside.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    for [a, b, c, d] in quads {
        m.triangles.push([a, b, c]);
        m.triangles.push([a, c, d]);
    }
    m
}

/// Newell's Utah teapot (32 bicubic Bézier patches, z up), each patch tessellated on a
/// `k × k` grid with the exact surface normals of the Bézier patches. Coincident vertices of
/// neighbouring patches are welded (their normals averaged); triangles collapsed at the poles
/// are left out.
pub fn teapot(k: usize) -> Mesh {
    use crate::teapot_data::{TEAPOT_PATCHES, TEAPOT_POINTS};
    let k = k.max(1);
    let bern = |t: f64| {
        let s = 1.0 - t;
        [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
    };
    let dbern = |t: f64| {
        let s = 1.0 - t;
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * s * t,
            6.0 * s * t - 3.0 * t * t,
            3.0 * t * t,
        ]
    };
    let eval = |cp: &[DVec3; 16], u: f64, v: f64| {
        let (bu, bv, du, dv) = (bern(u), bern(v), dbern(u), dbern(v));
        let mut p = DVec3::ZERO;
        let mut pu = DVec3::ZERO;
        let mut pv = DVec3::ZERO;
        for i in 0..4 {
            for j in 0..4 {
                let c = cp[i * 4 + j];
                p += c * bu[i] * bv[j];
                pu += c * du[i] * bv[j];
                pv += c * bu[i] * dv[j];
            }
        }
        (p, pv.cross(pu))
    };
    let mut m = Mesh::default();
    let mut sums: Vec<DVec3> = Vec::new();
    let mut weld: std::collections::HashMap<[i64; 3], u32> = std::collections::HashMap::new();
    for patch in TEAPOT_PATCHES.iter() {
        let cp: [DVec3; 16] =
            core::array::from_fn(|i| DVec3::from_array(TEAPOT_POINTS[patch[i] as usize]));
        let (ku, kv) = (k, k);
        let mut ids = vec![0u32; (ku + 1) * (kv + 1)];
        for i in 0..=ku {
            for j in 0..=kv {
                let (u, v) = (i as f64 / ku as f64, j as f64 / kv as f64);
                let (p, mut n) = eval(&cp, u, v);
                if n.length() < 1e-9 {
                    // A pole: take the normal just inside the patch.
                    let e = 1e-5;
                    let uu = if u < 0.5 { u + e } else { u - e };
                    let vv = if v < 0.5 { v + e } else { v - e };
                    n = eval(&cp, uu, vv).1;
                }
                let n = n.normalize_or_zero();
                let key = (p * 1e7).round().to_array().map(|x| x as i64);
                let id = *weld.entry(key).or_insert_with(|| {
                    m.positions.push(p);
                    sums.push(DVec3::ZERO);
                    (m.positions.len() - 1) as u32
                });
                sums[id as usize] += n;
                ids[i * (kv + 1) + j] = id;
            }
        }
        for i in 0..ku {
            for j in 0..kv {
                let a = ids[i * (kv + 1) + j];
                let b = ids[(i + 1) * (kv + 1) + j];
                let c = ids[(i + 1) * (kv + 1) + j + 1];
                let d = ids[i * (kv + 1) + j + 1];
                for t in [[a, b, c], [a, c, d]] {
                    if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                        m.triangles.push(t);
                    }
                }
            }
        }
    }
    m.normals = sums.iter().map(|n| n.normalize_or_zero()).collect();
    // Wind every triangle counter-clockwise seen from its normals' side.
    for t in m.triangles.iter_mut() {
        let [a, b, c] = t.map(|i| i as usize);
        let face = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
        let avg = m.normals[a] + m.normals[b] + m.normals[c];
        if face.dot(avg) < 0.0 {
            t.swap(1, 2);
        }
    }
    m
}

/// Analytic first intersection of the ray `o + t·d` (`t > 0`) with the sphere `|x| = r`, and the
/// ray's closest approach to the centre (the reference of the kernel's sphere tests).
pub fn sphere_root(o: DVec3, d: DVec3, r: f64) -> (Option<f64>, f64) {
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

/// A distance function to an exact surface.
pub type DistanceFn = fn(DVec3) -> f64;

/// The exact surface a built-in scene samples, as its name and distance function: the torus
/// (R = 1, r = 0.4), the unit sphere (`sphere`), the sphere of radius √3 through the cube's
/// corners (`cube`). `None` for the teapot and unknown names.
pub fn exact_distance(name: &str) -> Option<(&'static str, DistanceFn)> {
    match name {
        "torus" => Some(("torus", |x| torus_distance(x, 1.0, 0.4))),
        "sphere" => Some(("sphere", |x| (x.length() - 1.0).abs())),
        "cube" => Some(("sphere of radius √3", |x| {
            (x.length() - 3f64.sqrt()).abs()
        })),
        _ => None,
    }
}

/// The built-in scene names accepted by `--scene`.
pub const SCENE_NAMES: [&str; 5] = ["torus", "sphere", "cube", "teapot", "twist"];

/// A built-in scene by name: `torus` (8×8, R = 1, r = 0.4, 128 triangles), `sphere`
/// (icosphere level 1, radius 1), `cube` (averaged normals), `teapot` (Newell's, 4×4 per patch),
/// `twist` (the twisting torus at rest, 100 352 triangles; animated: [`crate::twist`]).
pub fn builtin(name: &str) -> Option<Mesh> {
    Some(match name {
        "torus" => torus(8, 8, 1.0, 0.4),
        "sphere" => icosphere(1, 1.0),
        "cube" => cube(),
        "teapot" => teapot(4),
        "twist" => crate::twist::twisting_torus(crate::twist::TWIST_DEMO_SIDE, 0.0),
        _ => return None,
    })
}
