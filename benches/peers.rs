//! smoothtri beside the other smooth surfaces built from a triangle and its vertex normals,
//! Phong tessellation (α = 3/4 and 1) and Nagata patches (`smoothtri-peers`), and beside flat
//! triangles, on the same meshes and the same rays:
//!
//! ```text
//! cargo bench --bench peers                      # accuracy, speed (+ instructions), terminator
//! cargo bench --features embree --bench peers    # the same with Embree's flat rows
//! cargo bench --bench peers -- accuracy          # one table: accuracy, speed or terminator
//! ```
//!
//! - **Accuracy**: each surface sampled at 45 barycentric points per triangle (a grid of step
//!   1/8) on the 8×8 torus, the octahedron's unit sphere (radial normals), Newell's teapot
//!   (992 triangles with the Bézier patches' exact normals) and the scanned WusonOBJ: the largest
//!   and 99th-percentile distance to the true surface (torus and sphere analytic; the teapot's
//!   Bézier patches by Newton projection), the geometric and shading normals' angle to the true
//!   normal, the normal jump across shared edges (every mesh, WusonOBJ included), and the
//!   coarsest flat tessellation of the same generator whose largest distance is no larger.
//! - **Speed**: one thread, f32, 640×480 camera rays (`render`'s default view of each mesh) and
//!   as many random rays through the mesh's box, on the torus and WusonOBJ: flat triangles
//!   (Möller–Trumbore in smoothtri's BVH over the triangles' boxes; Embree with `--features
//!   embree`), the peers (their exact solver in smoothtri's BVH over their boxes), smoothtri at
//!   N = 0, 4, 8; every hit with its normal. Mrays/s is the median of interleaved rounds;
//!   instructions per camera ray come from callgrind (160×120 rays) when valgrind is installed.
//! - **Terminator**: the torus under `render`'s light, one shadow ray per lit hit, each surface
//!   beside the analytic torus rendered the same way (`smoothtri_demo::peers`): pixels whose
//!   lit/shadowed state differs, and the shading error in the band `|n·l| ≤ 0.4` around the true
//!   terminator; the row of images goes to `target/peers/terminator.png`.

use std::hint::black_box;
use std::process::Command;
use std::time::Instant;

use glam::{DVec3, Vec3};
use smoothtri::{Aabb, BoxBvh, BvhNode, Hit, LineField, Ray, moller_trumbore};
use smoothtri_demo::Scene;
use smoothtri_demo::peers::{Analytic, FlatPhong, Peers, Pixel, Smooth, TerminatorFix};
use smoothtri_io::Mesh;
use smoothtri_io::load;
use smoothtri_peers::torus::Torus;
use smoothtri_peers::{Peer, PeerScene, QuadPatch};
use smoothtri_testkit::Camera;
use smoothtri_testkit::assimp_models;
use smoothtri_testkit::scenes::{teapot, torus};
use smoothtri_testkit::teapot_data::{TEAPOT_PATCHES, TEAPOT_POINTS};

mod common;
#[cfg(feature = "embree")]
#[path = "embree/ffi.rs"]
#[allow(dead_code)]
mod ffi;

use common::{cpu_name, flat_torus_matching};
use smoothtri_testkit::Rng;

const TORUS: Torus = Torus {
    major: 1.0,
    minor: 0.4,
};

/// The surfaces of the accuracy table.
#[derive(Clone, Copy, PartialEq)]
enum Method {
    Flat,
    Peer(Peer),
    Smooth,
}

impl Method {
    fn name(self) -> String {
        match self {
            Method::Flat => "flat triangles (Phong normals)".into(),
            Method::Peer(Peer::PhongTess { alpha }) => format!("Phong tessellation, α = {alpha}"),
            Method::Peer(Peer::Nagata) => "Nagata patches".into(),
            Method::Smooth => "smoothtri (seamless normal)".into(),
        }
    }
}

const METHODS: [Method; 5] = [
    Method::Flat,
    Method::Peer(Peer::PhongTess { alpha: 0.75 }),
    Method::Peer(Peer::PhongTess { alpha: 1.0 }),
    Method::Peer(Peer::Nagata),
    Method::Smooth,
];

/// The unit sphere from an octahedron (radial normals).
fn octahedron(level: usize) -> Mesh {
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
struct Teapot {
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
    fn new() -> Self {
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
enum Truth {
    Torus,
    Sphere,
    Teapot(Box<Teapot>),
    None,
}

impl Truth {
    fn at(&self, x: DVec3) -> Option<(f64, DVec3)> {
        match self {
            Truth::Torus => Some((TORUS.distance(x), TORUS.normal_at(x))),
            Truth::Sphere => Some(((x.length() - 1.0).abs(), x.normalize())),
            Truth::Teapot(t) => Some(t.closest(x)),
            Truth::None => None,
        }
    }
}

/// A surface of the accuracy table on one mesh: per triangle, the point and the geometric and
/// shading normals at barycentrics `(w1, w2)`.
trait Sampled {
    fn eval(&self, tri: usize, w1: f64, w2: f64) -> Option<(DVec3, DVec3, DVec3)>;
}

struct FlatS<'a>(&'a Mesh);
impl Sampled for FlatS<'_> {
    fn eval(&self, tri: usize, w1: f64, w2: f64) -> Option<(DVec3, DVec3, DVec3)> {
        let (p, n) = self.0.triangle(tri);
        let w0 = 1.0 - w1 - w2;
        let x = p[0] * w0 + p[1] * w1 + p[2] * w2;
        let face = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize()?;
        let ns = (n[0].normalize() * w0 + n[1].normalize() * w1 + n[2].normalize() * w2)
            .try_normalize()?;
        Some((x, face, ns))
    }
}

struct PeerS(Vec<Option<QuadPatch<f64>>>, Peer);
impl Sampled for PeerS {
    fn eval(&self, tri: usize, w1: f64, w2: f64) -> Option<(DVec3, DVec3, DVec3)> {
        let q = self.0.get(tri)?.as_ref()?;
        Some((
            q.point(w1, w2),
            q.normal(w1, w2),
            self.1.shading_normal(q, w1, w2),
        ))
    }
}

struct SmoothS {
    scene: Scene<f64>,
    of_tri: Vec<Option<usize>>,
}
impl Sampled for SmoothS {
    fn eval(&self, tri: usize, w1: f64, w2: f64) -> Option<(DVec3, DVec3, DVec3)> {
        let k = (*self.of_tri.get(tri)?)?;
        let patch = self.scene.patches().get(k)?;
        let (x, n) = patch.point_normal(w1, w2);
        let s = self
            .scene
            .seams()
            .get(k)
            .map_or(n, |s| s.shading_normal(patch, w1, w2));
        Some((x, n, s))
    }
}

fn sampled<'a>(m: Method, mesh: &'a Mesh) -> Box<dyn Sampled + 'a> {
    match m {
        Method::Flat => Box::new(FlatS(mesh)),
        Method::Peer(peer) => Box::new(PeerS(
            (0..mesh.triangles.len())
                .map(|t| {
                    let (p, n) = mesh.triangle(t);
                    peer.patch::<f64>(p, n).ok()
                })
                .collect(),
            peer,
        )),
        Method::Smooth => {
            let scene = Scene::<f64>::build_with(mesh, LineField::Face, true).expect("builds");
            let mut of_tri = vec![None; mesh.triangles.len()];
            for (k, &t) in scene.tri_ids().iter().enumerate() {
                of_tri[t as usize] = Some(k);
            }
            Box::new(SmoothS { scene, of_tri })
        }
    }
}

/// The grid of barycentrics (step 1/8: 45 points per triangle).
fn grid() -> Vec<(f64, f64)> {
    let k = 8;
    (0..=k)
        .flat_map(|i| (0..=(k - i)).map(move |j| (i as f64 / k as f64, j as f64 / k as f64)))
        .collect()
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize_or_zero()
        .dot(b.normalize_or_zero())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

/// The angles between the two sides' normals at the midpoints of shared edges (same vertex
/// indices): the geometric normals' 99th percentile and largest, the shading normals' largest.
fn edge_jumps(s: &dyn Sampled, mesh: &Mesh) -> (f64, f64, f64) {
    let mut edges: std::collections::HashMap<(u32, u32), (usize, usize)> = Default::default();
    let (mut g, mut sh) = (Vec::new(), 0.0f64);
    let bary = |e: usize, s: f64| match e {
        0 => (s, 0.0),
        1 => (1.0 - s, s),
        _ => (0.0, 1.0 - s),
    };
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            if let Some(&(t2, e2)) = edges.get(&key) {
                // The midpoint is s = 1/2 from either end.
                if let (Some(x), Some(y)) = (
                    s.eval(t, bary(e, 0.5).0, bary(e, 0.5).1),
                    s.eval(t2, bary(e2, 0.5).0, bary(e2, 0.5).1),
                ) {
                    g.push(angle(x.1, y.1).min(180.0 - angle(x.1, y.1)));
                    sh = sh.max(angle(x.2, y.2).min(180.0 - angle(x.2, y.2)));
                }
            } else {
                edges.insert(key, (t, e));
            }
        }
    }
    let max = g.iter().copied().fold(0.0, f64::max);
    (percentile(&mut g, 0.99), max, sh)
}

/// Largest distance of the flat triangles of `mesh` to `truth` (the grid of points).
fn flat_max(mesh: &Mesh, truth: &Truth, pts: &[(f64, f64)]) -> f64 {
    let s = FlatS(mesh);
    let s = &s;
    (0..mesh.triangles.len())
        .flat_map(|t| pts.iter().filter_map(move |&(a, b)| s.eval(t, a, b)))
        .filter_map(|(x, ..)| truth.at(x).map(|d| d.0))
        .fold(0.0, f64::max)
}

fn accuracy() {
    let grid = grid();
    let mut meshes: Vec<(String, Mesh, Truth)> = vec![
        (
            "torus 8×8 (128 triangles)".into(),
            torus(8, 8, 1.0, 0.4),
            Truth::Torus,
        ),
        (
            "sphere from an octahedron (8)".into(),
            octahedron(1),
            Truth::Sphere,
        ),
        (
            "teapot (992)".into(),
            teapot(4),
            Truth::Teapot(Box::new(Teapot::new())),
        ),
    ];
    if let Ok(Some(dir)) = assimp_models()
        && let Ok(l) = load(&dir.join("OBJ/WusonOBJ.obj").to_string_lossy())
    {
        let n = l.mesh.triangles.len();
        meshes.push((format!("WusonOBJ ({n}, scan)"), l.mesh, Truth::None));
    }
    println!(
        "\n## Accuracy: the surfaces against the true surface (f64, 45 points per triangle)\n"
    );
    println!(
        "| mesh | surface | max distance | 99th pct | geometric normal: max, mean ° | shading normal: max, mean ° | normal jump across shared edges °: geometric 99th pct, max / shading max | flat tessellation of equal max distance |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, mesh, truth) in &meshes {
        let diag = mesh.diagonal();
        for m in METHODS {
            let s = sampled(m, mesh);
            let (mut d, mut ag, mut ash) = (Vec::new(), Vec::new(), Vec::new());
            for t in 0..mesh.triangles.len() {
                for &(a, b) in &grid {
                    let Some((x, ng, ns)) = s.eval(t, a, b) else {
                        continue;
                    };
                    if let Some((dist, n)) = truth.at(x) {
                        d.push(dist);
                        // The teapot's nearest point can lie across a crease (rim, lid, spout
                        // and handle joins), where its normal is not the surface's there: no
                        // normal error for it.
                        if !matches!(truth, Truth::Teapot(_)) {
                            ag.push(angle(ng, n).min(180.0 - angle(ng, n)));
                            ash.push(angle(ns, n).min(180.0 - angle(ns, n)));
                        }
                    }
                }
            }
            let (jg99, jg, js) = edge_jumps(s.as_ref(), mesh);
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            let max = d.iter().copied().fold(0.0, f64::max);
            let equal = match truth {
                Truth::None => "—".to_string(),
                _ if max < 1e-12 * diag => "none (exact)".to_string(),
                Truth::Torus => {
                    let (n, _) = flat_torus_matching(max);
                    format!("{n}×{n} torus ({} triangles)", 2 * n * n)
                }
                Truth::Sphere => (1..400)
                    .find(|&l| flat_max(&octahedron(l), truth, &grid) <= max)
                    .map_or("> level 400".into(), |l| {
                        format!("octahedron level {l} ({} triangles)", 8 * l * l)
                    }),
                Truth::Teapot(_) => {
                    let few = [
                        (1.0 / 3.0, 1.0 / 3.0),
                        (0.5, 0.25),
                        (0.25, 0.5),
                        (0.25, 0.25),
                    ];
                    (4..=48)
                        .step_by(2)
                        .find(|&k| flat_max(&teapot(k), truth, &few) <= max)
                        .map_or("> 48×48 per patch".into(), |k| {
                            format!(
                                "{k}×{k} per patch ({} triangles)",
                                teapot(k).triangles.len()
                            )
                        })
                }
            };
            let p99 = percentile(&mut d, 0.99);
            let dist = |x: f64| {
                if d.is_empty() {
                    "—".into()
                } else {
                    format!("{x:.2e}")
                }
            };
            let ang = |v: &[f64]| {
                if v.is_empty() {
                    "—".into()
                } else {
                    format!(
                        "{:.2}, {:.2}",
                        v.iter().copied().fold(0.0, f64::max),
                        mean(v)
                    )
                }
            };
            println!(
                "| {name} | {} | {} | {} | {} | {} | {jg99:.2}, {jg:.2} / {js:.2} | {equal} |",
                m.name(),
                dist(max),
                dist(p99),
                ang(&ag),
                ang(&ash),
            );
        }
    }
    println!(
        "\nDistances in the mesh's units (torus R = 1, r = 0.4; unit sphere; the teapot is about 6 wide). \
         smoothtri: the patches of `Scene::build` (crack closure, seams); flat tessellations of the same generator (the torus grid, the octahedron subdivided, the teapot's patches at k×k)."
    );
}

/// The rays of the speed table: `render`'s default camera at `w`×`h`, and as many random rays
/// (from a sphere of twice the diagonal around the mesh to random points of its box).
fn rays_of(mesh: &Mesh, w: u32, h: u32) -> (Vec<Ray>, Vec<Ray>) {
    let cam = Camera::for_mesh(mesh, 30.0, 35.0, w, h);
    let camera: Vec<Ray> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = cam.pixel_ray(x, y);
            Ray::new(o.as_vec3(), d.as_vec3())
        })
        .collect();
    let (lo, hi) = mesh.bounds();
    let (c, diag) = ((lo + hi) * 0.5, (hi - lo).length());
    let mut rng = Rng(9);
    let random = (0..camera.len())
        .map(|_| {
            let o = c + rand_unit(&mut rng) * diag * 2.0;
            let t = lo + (hi - lo) * DVec3::new(rng.f(), rng.f(), rng.f());
            Ray::new(o.as_vec3(), (t - o).normalize().as_vec3())
        })
        .collect();
    (camera, random)
}

fn rand_unit(rng: &mut Rng) -> DVec3 {
    loop {
        let v = DVec3::new(rng.f(), rng.f(), rng.f()) * 2.0 - 1.0;
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Flat triangles in smoothtri's BVH over their own boxes (Möller–Trumbore in the leaves; the
/// Phong normal of the closest hit), as an Embree user geometry would hold them.
struct FlatTris {
    tris: Vec<[Vec3; 3]>,
    normals: Vec<[Vec3; 3]>,
    nodes: Vec<BvhNode<f32>>,
    order: Vec<u32>,
}

impl FlatTris {
    fn new(mesh: &Mesh) -> Self {
        let tris: Vec<[Vec3; 3]> = (0..mesh.triangles.len())
            .map(|t| mesh.triangle(t).0.map(|p| p.as_vec3()))
            .collect();
        let normals = (0..mesh.triangles.len())
            .map(|t| mesh.triangle(t).1.map(|p| p.normalize().as_vec3()))
            .collect();
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb::new(t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2])))
            .collect();
        let mut nodes = vec![BvhNode::default(); BoxBvh::<f32>::nodes_needed(boxes.len())];
        let mut order = vec![0; boxes.len()];
        let used = BoxBvh::build(&boxes, &mut nodes, &mut order)
            .expect("builds")
            .node_count();
        nodes.truncate(used);
        FlatTris {
            tris,
            normals,
            nodes,
            order,
        }
    }
    fn tree(&self) -> BoxBvh<'_, f32> {
        BoxBvh::from_parts(self.tris.len(), &self.nodes, &self.order).expect("built")
    }
    #[inline]
    fn closest_hit(&self, tree: &BoxBvh<'_, f32>, r: &Ray) -> Option<Hit> {
        let h = tree.closest_with(r, 0.0, f32::MAX, |i, a, b| {
            let (t, w1, w2) = moller_trumbore(self.tris.get(i as usize)?, r, a, b)?;
            Some(Hit {
                t,
                t_error: 0.0,
                point: Vec3::ZERO,
                normal: Vec3::ZERO,
                w1,
                w2,
                front_face: true,
                patch: 0,
            })
        })?;
        let [n0, n1, n2] = self.normals[h.patch as usize];
        let n = (n0 * (1.0 - h.w1 - h.w2) + n1 * h.w1 + n2 * h.w2).normalize();
        Some(Hit {
            normal: n,
            point: r.at(h.t),
            ..h
        })
    }
}

/// The surfaces of the speed table, built for one mesh.
struct Tracers {
    flat: Option<FlatTris>,
    phong_tess: Option<PeerScene<f32>>,
    nagata: Option<PeerScene<f32>>,
    smooth: Option<Scene<f32>>,
    /// Embree's scene of the same triangles and the vertex normals (the device is leaked: it
    /// lives as long as the bench).
    #[cfg(feature = "embree")]
    embree: Option<(ffi::Scene<'static>, Vec<Vec3>)>,
}

const SPEED_ROWS: [&str; 7] = [
    "flat (Embree)",
    "flat (smoothtri's BVH)",
    "Phong tessellation α = 0.75",
    "Nagata",
    "smoothtri N = 0",
    "smoothtri N = 4",
    "smoothtri N = 8",
];

impl Tracers {
    /// The surfaces of `mesh`: every row's, or row `only`'s (the callgrind runs).
    fn new(mesh: &Mesh, only: Option<usize>) -> Self {
        let want = |k: usize| only.is_none_or(|o| o == k);
        let peer = |p| {
            PeerScene::build(p, &mesh.positions, &mesh.normals, &mesh.triangles).expect("builds")
        };
        Tracers {
            flat: want(1).then(|| FlatTris::new(mesh)),
            phong_tess: want(2).then(|| peer(Peer::PhongTess { alpha: 0.75 })),
            nagata: want(3).then(|| peer(Peer::Nagata)),
            smooth: (4..7)
                .any(want)
                .then(|| Scene::<f32>::build(mesh).expect("builds")),
            #[cfg(feature = "embree")]
            embree: want(0).then(|| {
                let device: &'static ffi::Device =
                    Box::leak(Box::new(ffi::Device::new(c"threads=1")));
                let pos: Vec<[f32; 3]> = mesh
                    .positions
                    .iter()
                    .map(|p| p.as_vec3().to_array())
                    .collect();
                (
                    ffi::Scene::triangles(device, &pos, &mesh.triangles),
                    mesh.normals
                        .iter()
                        .map(|n| n.normalize().as_vec3())
                        .collect(),
                )
            }),
        }
    }

    /// Traces `rays` with row `k` of [`SPEED_ROWS`]; the hit count (`None`: not available).
    fn run(&self, k: usize, mesh: &Mesh, rays: &[Ray]) -> Option<usize> {
        let mut hits = 0usize;
        match k {
            0 => {
                #[cfg(feature = "embree")]
                {
                    let (scene, nrm) = self.embree.as_ref()?;
                    let mut ctx = ffi::RTCIntersectContext::new();
                    for r in rays {
                        if let Some(h) =
                            ffi::embree_hit(scene, &mut ctx, &mesh.triangles, nrm, black_box(r))
                        {
                            black_box(h);
                            hits += 1;
                        }
                    }
                    return Some(hits);
                }
                #[cfg(not(feature = "embree"))]
                {
                    let _ = mesh;
                    return None;
                }
            }
            1 => {
                let flat = self.flat.as_ref()?;
                let tree = flat.tree();
                for r in rays {
                    hits += black_box(flat.closest_hit(&tree, black_box(r))).is_some() as usize;
                }
            }
            2 | 3 => {
                let s = if k == 2 {
                    &self.phong_tess
                } else {
                    &self.nagata
                };
                let tr = s.as_ref()?.tracer().expect("built");
                for r in rays {
                    hits +=
                        black_box(tr.closest_hit(black_box(r), 0.0, f32::MAX)).is_some() as usize;
                }
            }
            _ => {
                let bvh = self.smooth.as_ref()?.bvh();
                for r in rays {
                    let h = match k {
                        4 => bvh.closest_hit(black_box(r), 0.0, f32::MAX, 0),
                        5 => bvh.closest_hit(black_box(r), 0.0, f32::MAX, 4),
                        _ => bvh.closest_hit(black_box(r), 0.0, f32::MAX, 8),
                    };
                    hits += black_box(h).is_some() as usize;
                }
            }
        }
        Some(hits)
    }
}

fn speed_meshes() -> Vec<(String, Mesh)> {
    let mut v = vec![("torus 8×8".to_string(), torus(8, 8, 1.0, 0.4))];
    if let Ok(Some(dir)) = assimp_models()
        && let Ok(l) = load(&dir.join("OBJ/WusonOBJ.obj").to_string_lossy())
    {
        v.push(("WusonOBJ".to_string(), l.mesh));
    }
    v
}

/// Instructions per camera ray of row `k` on mesh `m` (callgrind, 160×120 rays), or `None`.
fn instructions(m: usize, k: usize) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let count = |reps: usize| -> Option<u64> {
        let out = Command::new("valgrind")
            .args(["--tool=callgrind", "--callgrind-out-file=/dev/null"])
            .arg(&exe)
            .args(["--case", &format!("{m}:{k}:{reps}")])
            .output()
            .ok()?;
        let text = String::from_utf8_lossy(&out.stderr);
        text.lines()
            .find(|l| l.contains("Collected :"))?
            .rsplit(':')
            .next()?
            .trim()
            .parse()
            .ok()
    };
    let (a, b) = (count(1)?, count(0)?);
    Some(a.saturating_sub(b) as f64 / (160.0 * 120.0))
}

fn speed() {
    let reps: usize = std::env::var("SMOOTHTRI_PEERS_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let has_valgrind = Command::new("valgrind").arg("--version").output().is_ok();
    println!(
        "\n## Speed, one thread, f32 ({}; 640×480 camera rays of `render`'s view and as many random rays; median of {reps} interleaved rounds; instructions: callgrind, 160×120 camera rays)\n",
        cpu_name()
    );
    println!(
        "| mesh | surface | camera Mrays/s | random Mrays/s | instructions per camera ray | camera ÷ Embree flat (time per ray) | hits (camera) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (mi, (name, mesh)) in speed_meshes().iter().enumerate() {
        let tr = Tracers::new(mesh, None);
        let (cam, rnd) = rays_of(mesh, 640, 480);
        let mut times = vec![[Vec::new(), Vec::new()]; SPEED_ROWS.len()];
        let hits: Vec<_> = (0..SPEED_ROWS.len())
            .map(|k| tr.run(k, mesh, &cam))
            .collect();
        for _ in 0..reps {
            for (k, t) in times.iter_mut().enumerate() {
                for (j, rays) in [&cam, &rnd].into_iter().enumerate() {
                    let s = Instant::now();
                    if tr.run(k, mesh, rays).is_some() {
                        t[j].push(s.elapsed().as_secs_f64());
                    }
                }
            }
        }
        let med = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        let rates: Vec<[Option<f64>; 2]> = times
            .iter_mut()
            .map(|[a, b]| {
                [
                    med(a).map(|s| cam.len() as f64 / s / 1e6),
                    med(b).map(|s| rnd.len() as f64 / s / 1e6),
                ]
            })
            .collect();
        let anchor = rates[0][0];
        for (k, row) in SPEED_ROWS.iter().enumerate() {
            let [c, r] = rates[k];
            let Some(c) = c else { continue };
            let ins = if has_valgrind && k > 0 {
                instructions(mi, k).map_or("—".into(), |x| format!("{x:.0}"))
            } else {
                "—".into()
            };
            let ratio = anchor.map_or("—".into(), |a| format!("{:.1}×", a / c));
            println!(
                "| {name} | {row} | {c:.2} | {:.2} | {ins} | {ratio} | {} |",
                r.unwrap_or(0.0),
                hits[k].unwrap_or(0)
            );
        }
    }
    if !cfg!(feature = "embree") {
        println!("\n(Embree's rows need `--features embree`.)");
    }
}

/// One workload under callgrind: `m:k:reps` (mesh, row, repetitions) on 160×120 camera rays.
fn run_case(spec: &str) -> usize {
    let v: Vec<usize> = spec.split(':').filter_map(|s| s.parse().ok()).collect();
    let (m, k, reps) = (v[0], v[1], v[2]);
    let meshes = speed_meshes();
    let mesh = &meshes[m].1;
    let tr = Tracers::new(mesh, Some(k));
    let (cam, _) = rays_of(mesh, 160, 120);
    let mut hits = 0;
    for _ in 0..reps {
        hits += tr.run(k, mesh, &cam).unwrap_or(0);
    }
    hits
}

/// Pixels of a study against the analytic torus's: (both hit, lit/shadowed differs, in band,
/// differs in band, mean |ΔI| in band, max |ΔI| in band).
fn compare(p: &[Pixel], truth: &[Pixel], light: DVec3) -> (usize, usize, usize, usize, f64, f64) {
    let (mut both, mut diff, mut band, mut bdiff, mut sum, mut max) = (0, 0, 0, 0, 0.0, 0.0f64);
    for (a, t) in p.iter().zip(truth) {
        if !(a.hit && t.hit) {
            continue;
        }
        both += 1;
        diff += usize::from(a.lit != t.lit);
        if t.normal.dot(light).abs() <= 0.4 {
            band += 1;
            bdiff += usize::from(a.lit != t.lit);
            let e = (a.intensity - t.intensity).abs();
            sum += e;
            max = max.max(e);
        }
    }
    (both, diff, band, bdiff, sum / band.max(1) as f64, max)
}

fn terminator() {
    let mesh = torus(8, 8, 1.0, 0.4);
    let (w, h) = (640, 480);
    let cam = Camera::for_mesh(&mesh, 30.0, 35.0, w, h);
    let eps = smoothtri_demo::peers::shadow_eps(mesh.diagonal(), smoothtri_demo::Precision::F32);
    let light = cam.light_dir();
    let truth = smoothtri_demo::peers::render_study(&Analytic(TORUS), &mesh, &cam, None, eps);
    let flat = Scene::<f32>::build_with(&mesh, LineField::Face, false).expect("builds");
    let seams = Scene::<f32>::build_with(&mesh, LineField::Face, true).expect("builds");
    let pt = Peers::<f32>::build(Peer::PhongTess { alpha: 0.75 }, &mesh).expect("builds");
    let ng = Peers::<f32>::build(Peer::Nagata, &mesh).expect("builds");
    let fp = FlatPhong { scene: &flat };
    let sm = Smooth {
        scene: &seams,
        n: 4,
    };
    let rows: [(
        &str,
        &dyn smoothtri_demo::peers::Surface,
        Option<TerminatorFix>,
    ); 6] = [
        ("flat, Phong normals", &fp, None),
        (
            "flat, Phong normals, Hanika's offset",
            &fp,
            Some(TerminatorFix::Hanika),
        ),
        (
            "flat, Phong normals, Chiang et al.'s term",
            &fp,
            Some(TerminatorFix::Chiang),
        ),
        ("Phong tessellation α = 0.75 (Phong normals)", &pt, None),
        ("Nagata (its normal)", &ng, None),
        ("smoothtri N = 4 (seamless normal)", &sm, None),
    ];
    println!(
        "\n## The shadow terminator: the 8×8 torus, {w}×{h}, `render`'s light and view, one shadow ray per lit hit (f32), against the analytic torus rendered the same way (f64)\n"
    );
    println!(
        "| surface | pixels both hit | lit/shadowed differs | band pixels (\\|n·l\\| ≤ 0.4) | differs in band | mean \\|ΔI\\| in band | max \\|ΔI\\| in band |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut images = vec![(truth.image.clone(), "ANALYTIC".to_string())];
    for (name, s, fix) in rows {
        let st = smoothtri_demo::peers::render_study(s, &mesh, &cam, fix, eps);
        let (both, diff, band, bdiff, mean, max) = compare(&st.pixels, &truth.pixels, light);
        println!(
            "| {name} | {both} | {diff} ({:.2} %) | {band} | {bdiff} ({:.2} %) | {mean:.4} | {max:.3} |",
            100.0 * diff as f64 / both.max(1) as f64,
            100.0 * bdiff as f64 / band.max(1) as f64
        );
        let label = match (name, fix) {
            (_, Some(TerminatorFix::Hanika)) => "HANIKA",
            (_, Some(TerminatorFix::Chiang)) => "CHIANG",
            (n, _) if n.starts_with("flat") => "PHONG",
            (n, _) if n.starts_with("Phong tess") => "PHONG TESS",
            (n, _) if n.starts_with("Nagata") => "NAGATA",
            _ => "SMOOTHTRI",
        };
        images.push((st.image, label.to_string()));
    }
    println!(
        "\nIntensity I = ambient + (1 − ambient)·(n·l)·visibility (·G for Chiang et al.), ambient 0.12; the band is where the analytic torus's own normal has |n·l| ≤ 0.4."
    );
    // The row of images, each frame halved (2×2 pixels averaged).
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("..")
        .join("peers");
    let _ = std::fs::create_dir_all(&dir);
    let crop = |img: &smoothtri_demo::image::Image| {
        let (cw, ch) = (img.width / 2, img.height / 2);
        let mut c = smoothtri_demo::image::Image::new(cw, ch, [0, 0, 0]);
        for y in 0..ch {
            for x in 0..cw {
                let px =
                    [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| img.get(2 * x + i, 2 * y + j));
                let avg: [u8; 3] = core::array::from_fn(|k| {
                    (px.iter().map(|p| u32::from(p[k])).sum::<u32>() / 4) as u8
                });
                c.put(x as i64, y as i64, avg);
            }
        }
        c
    };
    let crops: Vec<(smoothtri_demo::image::Image, String)> =
        images.iter().map(|(i, l)| (crop(i), l.clone())).collect();
    let refs: Vec<(&smoothtri_demo::image::Image, String)> =
        crops.iter().map(|(i, l)| (i, l.clone())).collect();
    let row = smoothtri_demo::commands::render::side_by_side(&refs);
    let path = dir.join("terminator.png");
    if row.write_png(&path.to_string_lossy()).is_ok() {
        println!("\nImages: {}", path.display());
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--case") {
        println!("{}", black_box(run_case(&args[i + 1])));
        return;
    }
    if !args.iter().any(|a| a == "--bench") {
        eprintln!("run with `cargo bench --bench peers`");
        return;
    }
    let only: Vec<&str> = args
        .iter()
        .skip(1)
        .map(String::as_str)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let want = |s: &str| only.is_empty() || only.contains(&s);
    if want("accuracy") {
        accuracy();
    }
    if want("speed") {
        speed();
    }
    if want("terminator") {
        terminator();
    }
}
