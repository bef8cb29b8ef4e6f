//! Shared helpers of the integration tests: approximate assertions, random geometry, reference
//! data loading.
#![allow(dead_code)]

use std::collections::HashMap;

use glam::DVec3;
pub use smoothtri::Float;
use smoothtri_testkit::{Mesh, scenes};

pub mod pins;
pub use smoothtri_testkit::random::*;

/// Asserts `|a − b| ≤ tol`, printing both values (glam's `assert_approx_eq!` style).
#[macro_export]
macro_rules! assert_close {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).abs();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}", stringify!($a), a, stringify!($b), b, d, tol);
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).abs();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}: {}", stringify!($a), a, stringify!($b), b, d, tol, format!($($msg)+));
    }};
}

/// Asserts `|a − b| ≤ tol` for vectors (Euclidean distance), printing both.
#[macro_export]
macro_rules! assert_vec_close {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).length();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}", stringify!($a), a, stringify!($b), b, d, tol);
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).length();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}: {}", stringify!($a), a, stringify!($b), b, d, tol, format!($($msg)+));
    }};
}

/// Directory of the vendored reference data (`tests/data/`, see its README).
pub fn reference_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// Parses a CSV of floats with a header; returns (header, rows). Every field must parse as an
/// `f64` (`nan` is written explicitly where the reference has no value); anything else, or a
/// row whose width differs from the header's, fails the test with the file and line.
pub fn read_csv(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let path = reference_dir().join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut lines = text.lines().enumerate();
    let header: Vec<String> = lines
        .next()
        .map(|(_, l)| l.split(',').map(str::to_owned).collect())
        .unwrap_or_else(|| panic!("{}: empty file", path.display()));
    let rows = lines
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let row: Vec<f64> = l
                .split(',')
                .map(|x| {
                    x.trim().parse::<f64>().unwrap_or_else(|e| {
                        panic!("{}:{}: bad number {x:?}: {e}", path.display(), i + 1)
                    })
                })
                .collect();
            assert_eq!(
                row.len(),
                header.len(),
                "{}:{}: {} fields, header has {}",
                path.display(),
                i + 1,
                row.len(),
                header.len()
            );
            row
        })
        .collect();
    (header, rows)
}

/// Number of property-test cases: `SMOOTHTRI_CASES` from the environment when set to a positive
/// integer, `default` otherwise (for quick CI runs in debug mode).
pub fn env_cases(default: u32) -> u32 {
    std::env::var("SMOOTHTRI_CASES")
        .ok()
        .and_then(|s| s.trim().parse::<u32>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(default)
}

/// A random skinny triangle: longest side `size` along a random direction, the third vertex at
/// height `size / aspect` over it (aspect drawn log-uniformly in `[amin, amax]`) above a point
/// drawn uniformly along the side (so both needles and caps occur). Counter-clockwise about the
/// returned face normal, centred near `offset`.
pub fn skinny(
    rng: &mut Rng,
    size: f64,
    offset: DVec3,
    amin: f64,
    amax: f64,
) -> ([DVec3; 3], DVec3) {
    let nf = rng.unit();
    let u = nf.any_orthonormal_vector();
    let v = nf.cross(u);
    let rot = rng.range(0.0, std::f64::consts::TAU);
    let (eu, ev) = (
        u * rot.cos() + v * rot.sin(),
        -u * rot.sin() + v * rot.cos(),
    );
    let aspect = (rng.range(amin.ln(), amax.ln())).exp();
    let x = rng.f();
    let a = offset - eu * (0.5 * size);
    let b = offset + eu * (0.5 * size);
    let c = a + eu * (x * size) + ev * (size / aspect);
    ([a, b, c], nf)
}

/// Interior edges by vertex indices: (triangle A, its edge, triangle B, its edge), B
/// traversing the edge the other way.
pub fn interior_edges(mesh: &Mesh) -> Vec<(usize, usize, usize, usize)> {
    let mut map: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = (tri[j], tri[(j + 1) % 3]);
            map.entry((a.min(b), a.max(b))).or_default().push((t, j));
        }
    }
    let mut out: Vec<_> = map
        .values()
        .filter(|l| l.len() == 2)
        .map(|l| (l[0].0, l[0].1, l[1].0, l[1].1))
        .collect();
    out.sort_unstable();
    out
}

/// The icosphere of level 3 with vertices moved tangentially by up to 0.3 of an edge and
/// radially by ±2 %, and normals tilted from the radial direction by up to 20° (deterministic):
/// an irregular closed mesh whose neighbouring patches' edge curves part (cracks).
pub fn irregular() -> Mesh {
    let mut m = scenes::icosphere(3, 1.0);
    let mut rng = Rng(12);
    let t0 = m.triangles[0];
    let edge = (m.positions[t0[0] as usize] - m.positions[t0[1] as usize]).length();
    for i in 0..m.positions.len() {
        let p = m.positions[i];
        let u = rng.unit();
        let tang = (u - p * u.dot(p)).normalize_or_zero();
        let q = (p + tang * (0.3 * edge * rng.f())).normalize() * rng.range(0.98, 1.02);
        m.positions[i] = q;
        let nr = q.normalize();
        let w = rng.unit();
        let ax = (w - nr * w.dot(nr)).normalize_or_zero();
        let ang = rng.range(0.0, 20.0).to_radians();
        m.normals[i] = nr * ang.cos() + ax * ang.sin();
    }
    m
}

/// Indexed mesh with per-vertex normals: the stress meshes (`tests/suite/stress_meshes.rs`,
/// `tests/suite/watertight.rs`).
pub struct M {
    pub p: Vec<DVec3>,
    pub n: Vec<DVec3>,
    pub t: Vec<[usize; 3]>,
}

impl M {
    /// The same mesh as the demo's [`Mesh`].
    pub fn to_mesh(&self) -> Mesh {
        Mesh {
            positions: self.p.clone(),
            normals: self.n.clone(),
            triangles: self.t.iter().map(|t| t.map(|i| i as u32)).collect(),
        }
    }
}

/// Area-weighted averaged vertex normals of an indexed mesh.
pub fn averaged(p: Vec<DVec3>, t: Vec<[usize; 3]>) -> M {
    let mut n = vec![DVec3::ZERO; p.len()];
    for &[a, b, c] in &t {
        let f = (p[b] - p[a]).cross(p[c] - p[a]);
        for i in [a, b, c] {
            n[i] += f;
        }
    }
    M {
        n: n.iter().map(|v| v.normalize()).collect(),
        p,
        t,
    }
}

pub fn box_mesh(sx: f64, sy: f64, sz: f64) -> M {
    let p: Vec<DVec3> = (0..8)
        .map(|k| {
            DVec3::new(
                if k & 1 != 0 { sx } else { -sx },
                if k & 2 != 0 { sy } else { -sy },
                if k & 4 != 0 { sz } else { -sz },
            ) * 0.5
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    averaged(p, t)
}

/// Low-poly closed cylinder (radius 1, height 2) with averaged (not split) cap normals.
pub fn cylinder(k: usize) -> M {
    let mut p = vec![DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 1.0)];
    for i in 0..k {
        let a = i as f64 / k as f64 * std::f64::consts::TAU;
        p.push(DVec3::new(a.cos(), a.sin(), -1.0));
        p.push(DVec3::new(a.cos(), a.sin(), 1.0));
    }
    let mut t = Vec::new();
    for i in 0..k {
        let (b0, t0) = (2 + 2 * i, 3 + 2 * i);
        let (b1, t1) = (2 + 2 * ((i + 1) % k), 3 + 2 * ((i + 1) % k));
        t.push([b0, b1, t1]);
        t.push([b0, t1, t0]);
        t.push([0, b1, b0]);
        t.push([1, t0, t1]);
    }
    averaged(p, t)
}

pub fn noisy_sphere(rng: &mut Rng, noise_deg: f64) -> M {
    let ico = smoothtri_testkit::scenes::icosphere(2, 1.0);
    let n = ico
        .normals
        .iter()
        .map(|&v| tilted(rng, v.normalize(), noise_deg))
        .collect();
    M {
        p: ico.positions,
        n,
        t: ico
            .triangles
            .iter()
            .map(|t| t.map(|i| i as usize))
            .collect(),
    }
}
