//! Built-in test meshes with analytic vertex normals: torus, icosphere, cube with averaged
//! normals (exactly a sphere for the method), and their exact surfaces for measuring fidelity.

use glam::DVec3;

/// An indexed triangle mesh with per-vertex normals, in `f64`.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex normals (one per position, any positive length).
    pub normals: Vec<DVec3>,
    /// Triangles as indices into `positions`/`normals`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The three corners and normals of triangle `t`.
    pub fn triangle(&self, t: usize) -> ([DVec3; 3], [DVec3; 3]) {
        let [a, b, c] = self.triangles[t].map(|i| i as usize);
        (
            [self.positions[a], self.positions[b], self.positions[c]],
            [self.normals[a], self.normals[b], self.normals[c]],
        )
    }
    /// Axis-aligned bounds (min, max) of the vertices.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }
}

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
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

/// Distance of `x` to the torus of [`torus`] (major radius `big_r`, minor `r`).
pub fn torus_distance(x: DVec3, big_r: f64, r: f64) -> f64 {
    let q = (x.x * x.x + x.y * x.y).sqrt() - big_r;
    ((q * q + x.z * x.z).sqrt() - r).abs()
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
