//! The surfaces of the speed table built for one mesh ([`Tracers`]), flat triangles in
//! smoothtri's BVH among them ([`FlatTris`]), and the table's rays ([`rays_of`]).

use std::hint::black_box;

use glam::{DVec3, Vec3};
use smoothtri::{BoxBvh, BvhNode, Hit, Ray, moller_trumbore};
use smoothtri_demo::Scene;
use smoothtri_io::Mesh;
use smoothtri_peers::{Peer, PeerScene};
use smoothtri_testkit::{Camera, Rng, flat_triangles32, triangle_boxes};

#[cfg(feature = "embree")]
use crate::ffi;

/// The rays of the speed table: `render`'s default camera at `w`×`h`, and as many random rays
/// (from a sphere of twice the diagonal around the mesh to random points of its box).
pub(crate) fn rays_of(mesh: &Mesh, w: u32, h: u32) -> (Vec<Ray>, Vec<Ray>) {
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
        let tris = flat_triangles32(mesh);
        let normals = (0..mesh.triangles.len())
            .map(|t| mesh.triangle(t).1.map(|p| p.normalize().as_vec3()))
            .collect();
        let boxes = triangle_boxes(&tris);
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
pub(crate) struct Tracers {
    flat: Option<FlatTris>,
    phong_tess: Option<PeerScene<f32>>,
    nagata: Option<PeerScene<f32>>,
    smooth: Option<Scene<f32>>,
    /// Embree's scene of the same triangles and the vertex normals (the device is leaked: it
    /// lives as long as the bench).
    #[cfg(feature = "embree")]
    embree: Option<(ffi::Scene<'static>, Vec<Vec3>)>,
}

pub(crate) const SPEED_ROWS: [&str; 7] = [
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
    pub(crate) fn new(mesh: &Mesh, only: Option<usize>) -> Self {
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
                (
                    ffi::Scene::of_mesh(device, mesh),
                    mesh.normals
                        .iter()
                        .map(|n| n.normalize().as_vec3())
                        .collect(),
                )
            }),
        }
    }

    /// Traces `rays` with row `k` of [`SPEED_ROWS`]; the hit count (`None`: not available).
    pub(crate) fn run(&self, k: usize, mesh: &Mesh, rays: &[Ray]) -> Option<usize> {
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
