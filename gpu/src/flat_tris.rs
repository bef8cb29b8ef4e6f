//! Flat triangles in a pipeline of their own ([`FlatScene`]): the GPU baseline the smooth
//! kernel is measured against. Its shader (`flat_tris.wgsl`) holds no smooth code: smoothtri's
//! four-wide BVH over the triangles' own boxes ([`smoothtri::BoxBvh`]), nearest child first
//! with a fixed stack (a pending child is dropped when the best hit lies in front of it),
//! Möller–Trumbore in the leaves, one invocation per ray.

use std::sync::Arc;

use glam::Vec3;
use smoothtri::{Aabb, BoxBvh, BvhNode, Ray};

use crate::device::{
    TRACE_BINDINGS, buffer_layout, compute_pipeline, pipeline_layout, scoped, wgsl_module,
};
use crate::dispatch::{Batch, Tracer, word};
use crate::records::packed_bytes;
use crate::{Gpu, GpuError, GpuNode};

/// The shader of [`FlatScene`] (WGSL).
pub const FLAT_SHADER: &str = include_str!("flat_tris.wgsl");

/// Bytes per hit read back: `t, w1, w2, triangle`.
const FLAT_HIT_BYTES: usize = 16;

/// The label of the pipeline's objects.
const LABEL: &str = "flat triangles";

/// A closest hit of [`FlatScene::closest_hit`]: the CPU's
/// [`moller_trumbore`](smoothtri::moller_trumbore) result and the triangle's index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatHit {
    /// Ray parameter.
    pub t: f32,
    /// Barycentric `w1` on the triangle.
    pub w1: f32,
    /// Barycentric `w2`.
    pub w2: f32,
    /// The triangle's index in the slice given to [`FlatScene::new`].
    pub triangle: u32,
}

/// Flat triangles and their BVH on the GPU, with their own pipeline.
pub struct FlatScene {
    gpu: Arc<Gpu>,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    tris: wgpu::Buffer,
    nodes: wgpu::Buffer,
    order: wgpu::Buffer,
    counts: [u32; 3],
    bytes: u64,
}

impl FlatScene {
    /// Builds smoothtri's BVH over the triangles' boxes ([`BoxBvh::build`]), uploads the
    /// triangles (a vertex and two edges each) and the tree, and compiles the pipeline.
    ///
    /// Returns [`GpuError::Shader`] or [`GpuError::Device`] when the device refuses, and
    /// [`GpuError::Device`] for an empty slice.
    pub fn new(gpu: &Arc<Gpu>, triangles: &[[Vec3; 3]]) -> Result<FlatScene, GpuError> {
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| Aabb::new(t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2])))
            .collect();
        let mut nodes = vec![BvhNode::default(); BoxBvh::<f32>::nodes_needed(boxes.len())];
        let mut order = vec![0u32; boxes.len()];
        let tree = BoxBvh::build(&boxes, &mut nodes, &mut order)
            .map_err(|e| GpuError::Device(format!("flat triangles: {e}")))?;
        let node_bytes = packed_bytes(tree.nodes().iter().map(GpuNode::from_node));
        let order_bytes = packed_bytes(tree.order().iter().copied());
        let tri_bytes = packed_bytes(triangles.iter().map(|t| {
            let [a, b, c] = [t[0], t[1] - t[0], t[2] - t[0]];
            [a.x, a.y, a.z, 0.0, b.x, b.y, b.z, 0.0, c.x, c.y, c.z, 0.0]
        }));
        let bytes = (node_bytes.len() + order_bytes.len() + tri_bytes.len()) as u64;
        let counts = [
            tree.node_count() as u32,
            tree.order().len() as u32,
            triangles.len() as u32,
        ];
        let (tris, nodes, order) = (
            gpu.storage("flat triangles", tri_bytes)?,
            gpu.storage("flat nodes", node_bytes)?,
            gpu.storage("flat order", order_bytes)?,
        );
        let device = &gpu.device;
        let (layout, pipeline) = scoped(device, GpuError::Shader, || {
            // The kernel's group 0 without its shading data.
            let layout = buffer_layout(device, LABEL, &TRACE_BINDINGS[..7]);
            let pl = pipeline_layout(device, LABEL, &[&layout]);
            let module = wgsl_module(device, LABEL, FLAT_SHADER);
            let pipeline = compute_pipeline(device, LABEL, Some(&pl), &module, "main", &[]);
            (layout, pipeline)
        })?;
        Ok(FlatScene {
            gpu: Arc::clone(gpu),
            pipeline,
            layout,
            tris,
            nodes,
            order,
            counts,
            bytes,
        })
    }

    /// Bytes on the GPU (triangles, nodes, order).
    pub fn memory_bytes(&self) -> u64 {
        self.bytes
    }

    /// The closest hit of each ray with `t` in `[t_min, t_max]` (either face), into `hits`
    /// (as long as `rays`): the CPU's Möller–Trumbore through smoothtri's BVH, in `f32` on the
    /// GPU (the same arithmetic; the parity test allows rounding).
    pub fn closest_hit(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<FlatHit>],
    ) -> Result<(), GpuError> {
        self.run(Batch::new(rays, t_min, t_max), hits, None)
    }

    /// [`FlatScene::closest_hit`], also returning the GPU's execution time of the compute
    /// passes in seconds (timestamp queries), or `None` without timestamp queries.
    pub fn closest_hit_timed(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<FlatHit>],
    ) -> Result<Option<f64>, GpuError> {
        let mut s = 0.0;
        self.run(Batch::new(rays, t_min, t_max), hits, Some(&mut s))?;
        Ok(self.gpu.timestamps.then_some(s))
    }

    /// Traces `batch` into `out` through the shared dispatch ([`Tracer`]), adding the passes'
    /// GPU time to `seconds` when asked.
    fn run(
        &self,
        batch: Batch<'_>,
        out: &mut [Option<FlatHit>],
        seconds: Option<&mut f64>,
    ) -> Result<(), GpuError> {
        batch.check(out)?;
        let tracer = Tracer {
            gpu: &self.gpu,
            label: LABEL,
            pipeline: &self.pipeline,
            layout: &self.layout,
            scene: [&self.tris, &self.nodes, &self.order],
            shading: None,
            counts: self.counts,
            hit_bytes: FLAT_HIT_BYTES,
        };
        match tracer.trace(batch, seconds, out, parse_flat_hit)? {
            0 => Ok(()),
            s if s & 1 != 0 => Err(GpuError::Device("flat traversal stack overflow".into())),
            _ => Err(GpuError::Device("flat BVH storage is corrupt".into())),
        }
    }
}

/// One hit as the flat shader wrote it (`t, w1, w2, triangle`), `None` on a miss.
fn parse_flat_hit(b: &[u8]) -> Option<FlatHit> {
    let triangle = word(b, 3);
    (triangle != u32::MAX).then(|| FlatHit {
        t: f32::from_bits(word(b, 0)),
        w1: f32::from_bits(word(b, 1)),
        w2: f32::from_bits(word(b, 2)),
        triangle,
    })
}

impl std::fmt::Debug for FlatScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FlatScene")
            .field("triangles", &self.counts[2])
            .field("nodes", &self.counts[0])
            .finish()
    }
}
