//! Shared helpers of the integration tests: approximate assertions, random geometry, reference
//! data loading, the property tests' configuration, and what the builder's and the update's
//! tests share (an executor in reverse order, caller storage, the parts of a build compared).
#![allow(dead_code)]

use std::collections::HashMap;

use glam::DVec3;
use proptest::prop_assert_eq;
use proptest::test_runner::{Config, RngSeed, TestCaseError};
pub use smoothtri::Float;
use smoothtri::mesh::{Seam, SharedEdge, VertexClamp};
use smoothtri::{
    BuildError, BuildOptions, BvhNode, EdgeWork, Executor, OwnedScene, Patch, Scene, SceneSizes,
    SceneStorage, Vertices,
};
use smoothtri_testkit::{Mesh, scenes};

pub mod pins;
pub use smoothtri_testkit::random::*;

/// Asserts `|a − b| ≤ tol`, printing both values (glam's `assert_approx_eq!` style), then the
/// optional message (`format!` arguments).
#[macro_export]
macro_rules! assert_close {
    ($a:expr, $b:expr, $tol:expr $(, $($msg:tt)+)?) => {
        $crate::assert_within!(abs, $a, $b, $tol $(, $($msg)+)?)
    };
}

/// Asserts `|a − b| ≤ tol` for vectors (Euclidean distance), printing both, then the optional
/// message.
#[macro_export]
macro_rules! assert_vec_close {
    ($a:expr, $b:expr, $tol:expr $(, $($msg:tt)+)?) => {
        $crate::assert_within!(length, $a, $b, $tol $(, $($msg)+)?)
    };
}

/// What [`assert_close!`] and [`assert_vec_close!`] expand to: asserts that the distance
/// `(a − b).$norm()` is at most `tol`, printing both values, the distance and `tol`, then the
/// message after `": "` when there is one.
#[macro_export]
macro_rules! assert_within {
    ($norm:ident, $a:expr, $b:expr, $tol:expr) => {
        $crate::assert_within!($norm, $a, $b, $tol; "", "")
    };
    ($norm:ident, $a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {
        $crate::assert_within!($norm, $a, $b, $tol; ": ", format!($($msg)+))
    };
    ($norm:ident, $a:expr, $b:expr, $tol:expr; $sep:expr, $msg:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).$norm();
        assert!(
            d <= tol,
            "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}{}{}",
            stringify!($a),
            a,
            stringify!($b),
            b,
            d,
            tol,
            $sep,
            $msg
        );
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

/// A box of sides `sx`, `sy`, `sz` centred at the origin, with averaged vertex normals.
pub fn box_mesh(sx: f64, sy: f64, sz: f64) -> M {
    // The built-in cube (corners ±1, the same corner order and triangles), scaled.
    let cube = scenes::cube();
    let half = DVec3::new(sx, sy, sz) * 0.5;
    let p = cube.positions.iter().map(|&c| c * half).collect();
    let t = cube
        .triangles
        .iter()
        .map(|t| t.map(|i| i as usize))
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

/// An executor that runs chunks of one element, last first: the most different order from a
/// single call a thread pool could produce.
pub struct Backwards;

impl Executor for Backwards {
    fn run_chunks<T: Send>(
        &self,
        items: &mut [T],
        _grain: usize,
        work: &(dyn Fn(usize, &mut [T]) + Sync),
    ) {
        for k in (0..items.len()).rev() {
            work(k, &mut items[k..k + 1]);
        }
    }
}

/// The property tests' configuration: `default` cases (more with `SMOOTHTRI_CASES`, see
/// [`env_cases`]), no regression files (reproducers are written by hand in
/// `tests/suite/regressions.rs`); the quick default run uses the fixed `seed` (CI is
/// deterministic), a run with `SMOOTHTRI_CASES` set a random seed (printed by proptest on
/// failure).
pub fn proptest_config(default: u32, seed: u64) -> Config {
    let long = std::env::var_os("SMOOTHTRI_CASES").is_some();
    Config {
        cases: env_cases(default),
        failure_persistence: None,
        rng_seed: if long {
            RngSeed::Random
        } else {
            RngSeed::Fixed(seed)
        },
        ..Config::default()
    }
}

/// Owned storage of the sizes `n` (slice `short`, counted in `SceneStorage`'s field order, one
/// slot short), lent out as a `SceneStorage`.
pub struct Store<F: Float> {
    patches: Vec<Patch<F>>,
    ids: Vec<u32>,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
    seams: Vec<Seam<F>>,
    tris: Vec<[u32; 3]>,
    edges: Vec<SharedEdge>,
    vertex: [Vec<F::Vec3>; 3],
    clamps: Vec<VertexClamp<F>>,
    work: Vec<EdgeWork<F>>,
}

impl<F: Float> Store<F> {
    /// Storage of the sizes `n`; slice number `short` (in `SceneStorage`'s field order) one
    /// slot short.
    pub fn new(n: &SceneSizes, short: Option<usize>) -> Self {
        let len = |k: usize, want: usize| if short == Some(k) { want - 1 } else { want };
        let z = F::from_dvec3(DVec3::ZERO);
        Store {
            patches: vec![Patch::default(); len(0, n.patches)],
            ids: vec![0; len(1, n.patches)],
            nodes: vec![BvhNode::default(); len(2, n.nodes)],
            order: vec![0; len(3, n.patches)],
            seams: vec![Seam::default(); len(4, n.seams)],
            tris: vec![[0; 3]; len(5, n.patches)],
            edges: vec![SharedEdge::default(); len(6, n.edges)],
            vertex: [7, 8, 9].map(|k| vec![z; len(k, n.vertices)]),
            clamps: vec![VertexClamp::default(); len(10, n.vertices)],
            work: vec![EdgeWork::default(); len(11, n.edge_work)],
        }
    }

    /// The whole storage, lent out.
    pub fn storage(&mut self) -> SceneStorage<'_, F> {
        let [vp, vn, vc] = &mut self.vertex;
        SceneStorage {
            patches: &mut self.patches,
            triangle_ids: &mut self.ids,
            nodes: &mut self.nodes,
            order: &mut self.order,
            seams: &mut self.seams,
            triangles: &mut self.tris,
            edges: &mut self.edges,
            edge_work: &mut self.work,
            vertex_positions: vp,
            vertex_normals: vn,
            clamped_normals: vc,
            vertex_clamps: &mut self.clamps,
        }
    }
}

/// What an updated scene shares with a fresh build of the same vertices, bit for bit: the
/// patches, their triangles' slots, the seams, the counts the build reported (triangles,
/// patches, rejected, remedied) and the seam edges fitted. Returns the first that differs,
/// both values shown, its name after `prefix`.
pub fn same_parts<F: Float>(
    prefix: &str,
    a: &Scene<'_, F>,
    b: &Scene<'_, F>,
) -> Result<(), TestCaseError> {
    prop_assert_eq!(a.patches(), b.patches(), "{}patches", prefix);
    prop_assert_eq!(a.triangle_ids(), b.triangle_ids(), "{}slots", prefix);
    prop_assert_eq!(a.seams(), b.seams(), "{}seams", prefix);
    let (ra, rb) = (a.report(), b.report());
    prop_assert_eq!(
        (ra.triangles, ra.patches, ra.rejected, ra.remedied),
        (rb.triangles, rb.patches, rb.rejected, rb.remedied),
        "{}report",
        prefix
    );
    prop_assert_eq!(ra.seam_edges, rb.seam_edges, "{}seams fitted", prefix);
    Ok(())
}

/// The coordinates of `v` packed `x, y, z, x, …`: the builder's packed `f64` input.
pub fn packed(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// The positions and the normals of `m`, each [`packed`].
pub fn buffers(m: &Mesh) -> (Vec<f64>, Vec<f64>) {
    (packed(&m.positions), packed(&m.normals))
}

/// `OwnedScene::build` of `m` from its [`buffers`] with `options`: the scene, or the
/// builder's error.
pub fn build_owned<F: Float>(
    m: &Mesh,
    options: &mut BuildOptions<(), impl Executor>,
) -> Result<OwnedScene<F>, BuildError> {
    let (p, n) = buffers(m);
    OwnedScene::<F>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        options,
    )
}
