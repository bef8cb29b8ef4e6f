//! Workloads shared by the benchmarks (`kernel.rs`: criterion timings; `instructions.rs`:
//! callgrind instruction counts), so both measure the same rays on the same scenes.
#![allow(dead_code)]

use glam::{DVec3, Vec3};
use smoothtri::{Bvh, DPatch, DRay, LineField, OwnedScene, Patch, Ray, flat_hit};
use smoothtri_testkit::scenes::{torus, torus_distance};
use smoothtri_testkit::{Mesh, Rng, build_scene};

/// The triangles and vertex normals of `m`, rounded to f32.
pub fn triangles32(m: &Mesh) -> Vec<([Vec3; 3], [Vec3; 3])> {
    (0..m.triangles.len())
        .map(|t| {
            let (p, n) = m.triangle(t);
            (p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()))
        })
        .collect()
}

/// Rays aimed at random points of patch `k`'s triangle from random directions above it:
/// every ray hits the patch's box, most hit the patch (the per-test cost of a real traversal).
pub fn rays_at_patch(p: &DPatch, n: usize) -> Vec<DRay> {
    let mut rng = Rng(7);
    let v = p.vertices();
    let nf = p.face_normal();
    (0..n)
        .map(|_| {
            let (a, b) = (rng.f(), rng.f());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            let target = v[0] * (1.0 - a - b) + v[1] * a + v[2] * b;
            let dir =
                (nf + DVec3::new(rng.f() - 0.5, rng.f() - 0.5, rng.f() - 0.5) * 1.2).normalize();
            DRay::new(target + dir * 2.0, -dir)
        })
        .collect()
}

pub struct Setup {
    pub p64: DPatch,
    pub p32: Patch,
    pub tri32: [Vec3; 3],
    pub tri64: [DVec3; 3],
    pub rays64: Vec<DRay>,
    pub rays32: Vec<Ray>,
}

pub fn setup() -> Setup {
    let mesh = torus(8, 8, 1.0, 0.4);
    let (p, n) = mesh.triangle(21);
    let p64 = DPatch::new(p, n).unwrap();
    let p32 = Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap();
    let rays64 = rays_at_patch(&p64, 1024);
    let rays32 = rays64
        .iter()
        .map(|r| Ray::new(r.origin.as_vec3(), r.dir.as_vec3()))
        .collect();
    Setup {
        p64,
        p32,
        tri32: p.map(|x| x.as_vec3()),
        tri64: p,
        rays64,
        rays32,
    }
}

/// Smallest flat torus grid whose maximum distance to the true torus is at most `target`.
pub fn flat_torus_matching(target: f64) -> (usize, f64) {
    for n in 8..200 {
        let m = torus(n, n, 1.0, 0.4);
        let mut worst = 0.0f64;
        for t in 0..m.triangles.len() {
            let (p, _) = m.triangle(t);
            for i in 0..=8 {
                for j in 0..=(8 - i) {
                    let (a, b) = (i as f64 / 8.0, j as f64 / 8.0);
                    let x = p[0] * (1.0 - a - b) + p[1] * a + p[2] * b;
                    worst = worst.max(torus_distance(x, 1.0, 0.4));
                }
            }
        }
        if worst <= target {
            return (n, worst);
        }
    }
    (200, f64::NAN)
}

/// A scene built as the demo builds it (the core's builder: crack closure, no seams), `f32`.
pub struct Scene {
    built: OwnedScene<f32>,
}
impl Scene {
    pub fn new(m: &Mesh) -> Self {
        Self::new_on(m, LineField::Face)
    }
    pub fn new_on(m: &Mesh, field: LineField) -> Self {
        let built = build_scene(m, field, false).expect("the bench meshes build");
        Scene { built }
    }
    pub fn bvh(&self) -> Bvh<'_, f32> {
        *self.built.scene().bvh()
    }
    pub fn patches(&self) -> &[Patch] {
        self.built.scene().patches()
    }
}

/// The camera rays of the scene benchmarks (a view of the torus from above the side), `w × h`
/// pixels, row by row.
pub fn camera_rays(w: usize, h: usize) -> Vec<Ray> {
    let eye = Vec3::new(0.0, -3.2, 2.2);
    let fwd = (-eye).normalize();
    let right = fwd.cross(Vec3::Z).normalize();
    let up = right.cross(fwd);
    let mut rays = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let u = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
            let v = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
            rays.push(Ray::new(eye, fwd + right * u * 0.55 + up * v * 0.42));
        }
    }
    rays
}

/// Whether `r` hits the flat triangles of `bvh`, a BVH of a mesh's patches: the closest hit
/// with [`flat_hit`] on each patch's triangle in the leaves (no normal), as a flat renderer
/// traces the same BVH.
#[inline]
pub fn hits_flat(bvh: &Bvh<'_, f32>, r: &Ray) -> bool {
    bvh.closest_with(r, 0.0, f32::INFINITY, |_, p, a, t| {
        flat_hit(&p.vertices(), None, r, a, t)
    })
    .is_some()
}

/// The CPU's model name (`/proc/cpuinfo`), for the tables.
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// Our BVH over a mesh's flat triangles, as an Embree user geometry holds them: each triangle
/// as a flat patch (its three vertex normals set to the face normal, so the patch's box is the
/// triangle's box), a BVH over those boxes, and the triangles themselves for the leaf test.
pub struct FlatBvh {
    pub patches: Vec<Patch>,
    pub nodes: Vec<smoothtri::BvhNode<f32>>,
    pub order: Vec<u32>,
    pub triangles: Vec<[Vec3; 3]>,
}

impl FlatBvh {
    pub fn new(m: &Mesh) -> Self {
        let triangles = smoothtri_testkit::flat_triangles32(m);
        let patches: Vec<Patch> = triangles
            .iter()
            .map(|p| {
                let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                Patch::new(*p, [nf; 3]).expect("a flat patch")
            })
            .collect();
        let mut nodes =
            vec![smoothtri::BvhNode::default(); Bvh::<f32>::nodes_needed(patches.len())];
        let mut order = vec![0u32; patches.len()];
        let used = Bvh::build(&patches, &mut nodes, &mut order)
            .expect("the BVH builds")
            .node_count();
        nodes.truncate(used);
        FlatBvh {
            patches,
            nodes,
            order,
            triangles,
        }
    }

    pub fn bvh(&self) -> Bvh<'_, f32> {
        Bvh::from_parts(&self.patches, &self.nodes, &self.order).expect("a tree made by build")
    }

    /// The closest hit of `r` (Möller–Trumbore in the leaves; no normal).
    #[inline]
    pub fn closest_hit(&self, bvh: &Bvh<'_, f32>, r: &Ray) -> Option<smoothtri::Hit> {
        bvh.closest_with(r, 0.0, f32::MAX, |id, _, a, b| {
            let (t, w1, w2) =
                smoothtri::moller_trumbore(self.triangles.get(id as usize)?, r, a, b)?;
            Some(smoothtri::Hit {
                t,
                t_error: 0.0,
                point: Vec3::ZERO,
                normal: Vec3::ZERO,
                w1,
                w2,
                front_face: false,
                patch: id,
            })
        })
    }
}
