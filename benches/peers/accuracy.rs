//! The accuracy table: each surface sampled on every triangle of each mesh against the true
//! surface (distance, normals, the normal jump across shared edges, the flat tessellation of
//! equal error).

use glam::DVec3;
use smoothtri::LineField;
use smoothtri_demo::Scene;
use smoothtri_io::{Mesh, load};
use smoothtri_peers::{Peer, QuadPatch};
use smoothtri_testkit::assimp_models;
use smoothtri_testkit::random::bary_grid;
use smoothtri_testkit::scenes::{teapot, torus};

use crate::common::flat_torus_matching;
use crate::truth::{Teapot, Truth, octahedron};

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

/// Prints the accuracy table.
pub(crate) fn accuracy() {
    // The grid of barycentrics (step 1/8: 45 points per triangle).
    let grid = bary_grid(8);
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
