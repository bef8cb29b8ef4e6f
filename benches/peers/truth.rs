//! The true surfaces of the accuracy table's meshes: the analytic torus and unit sphere, and
//! Newell's teapot as its Bézier patches; and the octahedron's subdivisions (the sphere's
//! meshes).

use glam::DVec3;
use smoothtri_io::Mesh;
use smoothtri_testkit::teapot_data::{TEAPOT_PATCHES, TEAPOT_POINTS};

use crate::TORUS;

/// The unit sphere from an octahedron (radial normals).
pub(crate) fn octahedron(level: usize) -> Mesh {
    let c = [
        DVec3::X,
        DVec3::Y,
        -DVec3::X,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ];
    let faces = [
        [0, 1, 4],
        [1, 2, 4],
        [2, 3, 4],
        [3, 0, 4],
        [1, 0, 5],
        [2, 1, 5],
        [3, 2, 5],
        [0, 3, 5],
    ];
    let l = level.max(1);
    let mut m = Mesh::default();
    let mut weld = std::collections::HashMap::new();
    let mut id = |p: DVec3, m: &mut Mesh| {
        let p = p.normalize();
        let key = (p * 1e9).round().to_array().map(|x| x as i64);
        *weld.entry(key).or_insert_with(|| {
            m.positions.push(p);
            m.normals.push(p);
            (m.positions.len() - 1) as u32
        })
    };
    for f in faces {
        let [a, b, cc] = f.map(|i| c[i]);
        let at = |i: usize, j: usize| {
            a + (b - a) * (i as f64 / l as f64) + (cc - a) * (j as f64 / l as f64)
        };
        for i in 0..l {
            for j in 0..(l - i) {
                let (p, q, r) = (at(i, j), at(i + 1, j), at(i, j + 1));
                let t = [id(p, &mut m), id(q, &mut m), id(r, &mut m)];
                m.triangles.push(t);
                if i + j + 1 < l {
                    let s = at(i + 1, j + 1);
                    let u = [id(q, &mut m), id(s, &mut m), id(r, &mut m)];
                    m.triangles.push(u);
                }
            }
        }
    }
    m
}

/// Newell's teapot as its 32 bicubic Bézier patches: closest points by Newton projection from
/// the nearest of a dense set of samples (a uniform grid of cells).
pub(crate) struct Teapot {
    patches: Vec<[DVec3; 16]>,
    samples: Vec<(DVec3, usize, f64, f64)>,
    cells: std::collections::HashMap<[i64; 3], Vec<u32>>,
    cell: f64,
}

fn bern(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * s * t,
            6.0 * s * t - 3.0 * t * t,
            3.0 * t * t,
        ],
        [6.0 * s, -12.0 * s + 6.0 * t, 6.0 * s - 12.0 * t, 6.0 * t],
    )
}

impl Teapot {
    pub(crate) fn new() -> Self {
        let patches: Vec<[DVec3; 16]> = TEAPOT_PATCHES
            .iter()
            .map(|p| core::array::from_fn(|i| DVec3::from_array(TEAPOT_POINTS[p[i] as usize])))
            .collect();
        let mut samples = Vec::new();
        let k = 48;
        for (pi, cp) in patches.iter().enumerate() {
            for i in 0..=k {
                for j in 0..=k {
                    let (u, v) = (i as f64 / k as f64, j as f64 / k as f64);
                    samples.push((Self::eval(cp, u, v).0, pi, u, v));
                }
            }
        }
        let cell = 0.15;
        let mut cells: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
        for (i, s) in samples.iter().enumerate() {
            cells
                .entry(Self::key(s.0, cell))
                .or_default()
                .push(i as u32);
        }
        Teapot {
            patches,
            samples,
            cells,
            cell,
        }
    }
    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        (p / cell).floor().to_array().map(|x| x as i64)
    }
    /// Point, ∂u, ∂v, ∂uu, ∂uv, ∂vv.
    fn eval(cp: &[DVec3; 16], u: f64, v: f64) -> (DVec3, DVec3, DVec3, DVec3, DVec3, DVec3) {
        let ((bu, du, ddu), (bv, dv, ddv)) = (bern(u), bern(v));
        let mut r = [DVec3::ZERO; 6];
        for i in 0..4 {
            for j in 0..4 {
                let c = cp[i * 4 + j];
                r[0] += c * bu[i] * bv[j];
                r[1] += c * du[i] * bv[j];
                r[2] += c * bu[i] * dv[j];
                r[3] += c * ddu[i] * bv[j];
                r[4] += c * du[i] * dv[j];
                r[5] += c * bu[i] * ddv[j];
            }
        }
        (r[0], r[1], r[2], r[3], r[4], r[5])
    }
    /// Distance from `x` to the teapot and the unit normal there (unoriented).
    fn closest(&self, x: DVec3) -> (f64, DVec3) {
        let k = Self::key(x, self.cell);
        let mut cands: Vec<(f64, u32)> = Vec::new();
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(ids) = self.cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        cands.extend(
                            ids.iter()
                                .map(|&i| ((self.samples[i as usize].0 - x).length(), i)),
                        );
                    }
                }
            }
        }
        cands.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = (f64::MAX, DVec3::Z);
        for &(_, i) in cands.iter().take(6) {
            let (_, pi, mut u, mut v) = self.samples[i as usize];
            let cp = &self.patches[pi];
            for _ in 0..30 {
                let (p, pu, pv, puu, puv, pvv) = Self::eval(cp, u, v);
                let r = p - x;
                let (gu, gv) = (r.dot(pu), r.dot(pv));
                let (huu, huv, hvv) = (
                    pu.dot(pu) + r.dot(puu),
                    pu.dot(pv) + r.dot(puv),
                    pv.dot(pv) + r.dot(pvv),
                );
                let det = huu * hvv - huv * huv;
                if det.abs() < 1e-300 {
                    break;
                }
                u = (u - (hvv * gu - huv * gv) / det).clamp(0.0, 1.0);
                v = (v - (huu * gv - huv * gu) / det).clamp(0.0, 1.0);
            }
            let (p, pu, pv, ..) = Self::eval(cp, u, v);
            let dist = (p - x).length();
            if dist < best.0 {
                let n = pv
                    .cross(pu)
                    .try_normalize()
                    .unwrap_or((x - p).normalize_or_zero());
                best = (dist, n);
            }
        }
        best
    }
}

/// The true surface of a mesh of the table: distance and unit normal (unoriented for the
/// teapot), or nothing (a scan).
pub(crate) enum Truth {
    Torus,
    Sphere,
    Teapot(Box<Teapot>),
    None,
}

impl Truth {
    pub(crate) fn at(&self, x: DVec3) -> Option<(f64, DVec3)> {
        match self {
            Truth::Torus => Some((TORUS.distance(x), TORUS.normal_at(x))),
            Truth::Sphere => Some(((x.length() - 1.0).abs(), x.normalize())),
            Truth::Teapot(t) => Some(t.closest(x)),
            Truth::None => None,
        }
    }
}
