//! Shared helpers of the GPU tests: the device (or the skip), BVH storage and batches of random
//! rays. The scenes, the patches and the random rays of the CPU kernel's tests
//! (`tests/suite/kernel.rs`: the same generator, seeds and distributions) come from the test
//! kit.
#![allow(dead_code)]

use std::io::Write as _;
use std::sync::{Arc, OnceLock};

use glam::Vec3;
use smoothtri::{Bvh, BvhNode, Patch, Ray};
use smoothtri_gpu::{Gpu, GpuError};
use smoothtri_testkit::random::{Rng, random_ray};

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

/// Two unit vectors perpendicular to `d` and to each other.
pub fn perpendiculars(d: Vec3) -> (Vec3, Vec3) {
    let u = d.normalize().any_orthonormal_vector();
    (u, d.normalize().cross(u))
}

/// `count` of the test kit's random rays (`random_ray`, from the generator seeded with `seed`)
/// aimed within `target_radius` of the origin, in `f32`.
pub fn random_rays(seed: u64, count: usize, target_radius: f64) -> Vec<Ray> {
    let mut rng = Rng(seed);
    (0..count)
        .map(|_| {
            let (o, d) = random_ray(&mut rng, target_radius);
            Ray::new(o.as_vec3(), d.as_vec3())
        })
        .collect()
}

/// One output slot per ray of `rays`, each `slot` at first, filled by `query` (a batch query of
/// a GPU scene over those rays, writing into the slots it is given); panics on its error.
pub fn traced<T: Clone>(
    rays: &[Ray],
    slot: T,
    query: impl FnOnce(&mut [T]) -> Result<(), GpuError>,
) -> Vec<T> {
    let mut out = vec![slot; rays.len()];
    query(&mut out).expect("trace");
    out
}
