//! Shared helpers of the GPU tests: the device (or the skip), scenes, and the ray sets of the
//! CPU kernel's tests (`tests/suite/kernel.rs`: the same generator, seeds and distributions).
#![allow(dead_code)]

use std::io::Write as _;
use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};
use smoothtri::{Bvh, BvhNode, Patch};
use smoothtri_demo::scenes::Mesh;
use smoothtri_gpu::{Gpu, GpuError};

/// Set (to anything but `0`) to make a missing adapter a test failure instead of a skip
/// (`.ci/run` sets it).
pub const REQUIRE: &str = "SMOOTHTRI_REQUIRE_GPU";

/// The device shared by the tests of one binary, or `None` (after one line on stderr) when
/// this machine has no Vulkan adapter and [`REQUIRE`] is not set.
pub fn gpu() -> Option<Arc<Gpu>> {
    static GPU: OnceLock<Result<Arc<Gpu>, GpuError>> = OnceLock::new();
    match GPU.get_or_init(Gpu::new) {
        Ok(g) => Some(Arc::clone(g)),
        Err(GpuError::NoAdapter) => {
            let required = std::env::var(REQUIRE).is_ok_and(|v| !v.is_empty() && v != "0");
            assert!(
                !required,
                "{REQUIRE} is set but there is no Vulkan adapter (install mesa-vulkan-drivers)"
            );
            // Once per test binary, straight to stderr (the harness does not capture it).
            static SAID: std::sync::Once = std::sync::Once::new();
            SAID.call_once(|| {
                let _ = writeln!(
                    std::io::stderr(),
                    "skipped: no Vulkan adapter on this machine (set {REQUIRE}=1 to fail instead)"
                );
            });
            None
        }
        Err(e) => panic!("GPU setup failed: {e}"),
    }
}

/// The f32 patches of a mesh (every triangle must be accepted, as in `tests/suite/kernel.rs`).
pub fn patches32(m: &Mesh) -> Vec<Patch> {
    (0..m.triangles.len())
        .map(|t| {
            let (p, n) = m.triangle(t);
            Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).expect("patch")
        })
        .collect()
}

/// BVH storage over `patches`.
pub struct Tree {
    pub nodes: Vec<BvhNode<f32>>,
    pub order: Vec<u32>,
}

impl Tree {
    pub fn new(patches: &[Patch]) -> Tree {
        let mut nodes = vec![BvhNode::default(); Bvh::<f32>::nodes_needed(patches.len())];
        let mut order = vec![0u32; patches.len()];
        let used = Bvh::build(patches, &mut nodes, &mut order)
            .expect("bvh")
            .node_count();
        nodes.truncate(used);
        Tree { nodes, order }
    }
    pub fn bvh<'a>(&'a self, patches: &'a [Patch]) -> Bvh<'a, f32> {
        Bvh::from_parts(patches, &self.nodes, &self.order).expect("a tree made by Bvh::build")
    }
}

// The suite's PRNG and random geometry (SplitMix64 `Rng`), shared by file.
#[path = "../../../tests/suite/common/random.rs"]
mod random;
pub use random::Rng;

/// The random rays of `tests/suite/kernel.rs`: from 4–8 away, aimed within `target_radius` of the
/// origin, directions not of unit length.
pub fn random_ray(rng: &mut Rng, target_radius: f64) -> (DVec3, DVec3) {
    let o = rng.unit() * rng.range(4.0, 8.0);
    let aim = rng.unit() * target_radius * rng.f().cbrt();
    let d = (aim - o) * rng.range(0.3, 3.0);
    (o, d)
}

/// Analytic first intersection with the sphere |x| = r, and the ray's closest approach.
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

/// Two unit vectors perpendicular to `d` and to each other.
pub fn perpendiculars(d: Vec3) -> (Vec3, Vec3) {
    let u = d.normalize().any_orthonormal_vector();
    (u, d.normalize().cross(u))
}
