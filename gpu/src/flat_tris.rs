//! Flat triangles in a pipeline of their own ([`FlatScene`]): the GPU baseline the smooth
//! kernel is measured against. Its shader (`flat_tris.wgsl`) holds no smooth code: smoothtri's
//! four-wide BVH over the triangles' own boxes ([`smoothtri::BoxBvh`]), nearest child first
//! with a fixed stack (a pending child is dropped when the best hit lies in front of it),
//! Möller–Trumbore in the leaves, one invocation per ray.

use std::sync::Arc;

use glam::Vec3;
use smoothtri::{Aabb, BoxBvh, BvhNode, Ray};

use crate::device::{bind_entry, scoped};
use crate::dispatch::{upload_ray, word};
use crate::shader::WORKGROUP;
use crate::{Gpu, GpuError, GpuNode};

/// The shader of [`FlatScene`] (WGSL).
pub const FLAT_SHADER: &str = include_str!("flat_tris.wgsl");

/// Bytes per hit read back: `t, w1, w2, triangle`.
const FLAT_HIT_BYTES: usize = 16;

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
        let node_bytes: Vec<u8> = tree
            .nodes()
            .iter()
            .flat_map(|n| {
                let g = GpuNode::from_node(n);
                let mut b = Vec::with_capacity(128);
                for r in g.lo.iter().chain(&g.hi) {
                    r.iter().for_each(|x| b.extend_from_slice(&x.to_ne_bytes()));
                }
                for x in g.child.iter().chain(&g.count) {
                    b.extend_from_slice(&x.to_ne_bytes());
                }
                b
            })
            .collect();
        let order_bytes: Vec<u8> = tree.order().iter().flat_map(|x| x.to_ne_bytes()).collect();
        let tri_bytes: Vec<u8> = triangles
            .iter()
            .flat_map(|t| [t[0], t[1] - t[0], t[2] - t[0]])
            .flat_map(|v| [v.x, v.y, v.z, 0.0])
            .flat_map(f32::to_ne_bytes)
            .collect();
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
            let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let ro = wgpu::BufferBindingType::Storage { read_only: true };
            let rw = wgpu::BufferBindingType::Storage { read_only: false };
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("flat triangles"),
                entries: &[
                    entry(0, wgpu::BufferBindingType::Uniform),
                    entry(1, ro),
                    entry(2, ro),
                    entry(3, ro),
                    entry(4, ro),
                    entry(5, rw),
                    entry(6, rw),
                ],
            });
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("flat triangles"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("flat triangles"),
                source: wgpu::ShaderSource::Wgsl(FLAT_SHADER.into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("flat triangles"),
                layout: Some(&pl),
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
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
        self.run(rays, t_min, t_max, hits, None)
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
        self.run(rays, t_min, t_max, hits, Some(&mut s))?;
        Ok(self.gpu.timestamps.then_some(s))
    }

    fn run(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        out: &mut [Option<FlatHit>],
        mut seconds: Option<&mut f64>,
    ) -> Result<(), GpuError> {
        if rays.len() != out.len() {
            return Err(GpuError::LengthMismatch {
                rays: rays.len(),
                out: out.len(),
            });
        }
        if rays.is_empty() {
            return Ok(());
        }
        let gpu = &self.gpu;
        let device = &gpu.device;
        let chunk = gpu.chunk().min(rays.len());
        use wgpu::BufferUsages as U;
        let buf = |label, size: usize, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage,
                mapped_at_creation: false,
            })
        };
        let (ray_buf, hit_buf, status_buf, params_buf, read_buf, timing) =
            scoped(device, GpuError::Device, || {
                let timing = (seconds.is_some() && gpu.timestamps).then(|| {
                    (
                        device.create_query_set(&wgpu::QuerySetDescriptor {
                            label: Some("flat time"),
                            ty: wgpu::QueryType::Timestamp,
                            count: 2,
                        }),
                        buf("flat timestamps", 16, U::QUERY_RESOLVE | U::COPY_SRC),
                    )
                });
                (
                    buf("flat rays", chunk * 32, U::STORAGE | U::COPY_DST),
                    buf(
                        "flat hits",
                        chunk * FLAT_HIT_BYTES,
                        U::STORAGE | U::COPY_SRC,
                    ),
                    buf("flat status", 16, U::STORAGE | U::COPY_SRC | U::COPY_DST),
                    buf("flat params", 16, U::UNIFORM | U::COPY_DST),
                    buf(
                        "flat readback",
                        chunk * FLAT_HIT_BYTES + 32,
                        U::MAP_READ | U::COPY_DST,
                    ),
                    timing,
                )
            })?;
        let bind = scoped(device, GpuError::Device, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("flat triangles"),
                layout: &self.layout,
                entries: &[
                    bind_entry(0, &params_buf),
                    bind_entry(1, &self.tris),
                    bind_entry(2, &self.nodes),
                    bind_entry(3, &self.order),
                    bind_entry(4, &ray_buf),
                    bind_entry(5, &hit_buf),
                    bind_entry(6, &status_buf),
                ],
            })
        })?;
        let mut status = 0u32;
        for (c, part) in rays.chunks(chunk).enumerate() {
            let n = part.len();
            let bytes: Vec<u8> = part
                .iter()
                .flat_map(|r| upload_ray(r, t_min, t_max))
                .flat_map(f32::to_ne_bytes)
                .collect();
            let [nodes, order, tris] = self.counts;
            let params: Vec<u8> = [n as u32, nodes, order, tris]
                .iter()
                .flat_map(|x| x.to_ne_bytes())
                .collect();
            let data = scoped(device, GpuError::Device, || {
                gpu.queue.write_buffer(&ray_buf, 0, &bytes);
                gpu.queue.write_buffer(&params_buf, 0, &params);
                gpu.queue.write_buffer(&status_buf, 0, &[0u8; 16]);
                let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("flat triangles"),
                });
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("flat triangles"),
                        timestamp_writes: timing.as_ref().map(|(set, _)| {
                            wgpu::ComputePassTimestampWrites {
                                query_set: set,
                                beginning_of_pass_write_index: Some(0),
                                end_of_pass_write_index: Some(1),
                            }
                        }),
                    });
                    pass.set_pipeline(&self.pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    pass.dispatch_workgroups((n as u32).div_ceil(WORKGROUP), 1, 1);
                }
                let hb = (n * FLAT_HIT_BYTES) as u64;
                enc.copy_buffer_to_buffer(&hit_buf, 0, &read_buf, 0, hb);
                enc.copy_buffer_to_buffer(&status_buf, 0, &read_buf, hb, 16);
                let mut range = 0..hb + 16;
                if let Some((set, resolve)) = &timing {
                    enc.resolve_query_set(set, 0..2, resolve, 0);
                    enc.copy_buffer_to_buffer(resolve, 0, &read_buf, range.end, 16);
                    range.end += 16;
                }
                gpu.submit_and_read(enc, &read_buf, range)
            })??;
            let word = |k: usize| word(&data, k);
            status |= word(n * 4);
            if let (Some(total), Some(_)) = (seconds.as_deref_mut(), &timing) {
                let tick = |k: usize| {
                    u64::from(word(n * 4 + 4 + 2 * k)) | (u64::from(word(n * 4 + 5 + 2 * k)) << 32)
                };
                let period = f64::from(gpu.queue.get_timestamp_period());
                *total += tick(1).saturating_sub(tick(0)) as f64 * period * 1e-9;
            }
            for k in 0..n {
                let triangle = word(4 * k + 3);
                if let Some(slot) = out.get_mut(c * chunk + k) {
                    *slot = (triangle != u32::MAX).then(|| FlatHit {
                        t: f32::from_bits(word(4 * k)),
                        w1: f32::from_bits(word(4 * k + 1)),
                        w2: f32::from_bits(word(4 * k + 2)),
                        triangle,
                    });
                }
            }
        }
        match status {
            0 => Ok(()),
            s if s & 1 != 0 => Err(GpuError::Device("flat traversal stack overflow".into())),
            _ => Err(GpuError::Device("flat BVH storage is corrupt".into())),
        }
    }
}

impl std::fmt::Debug for FlatScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FlatScene")
            .field("triangles", &self.counts[2])
            .field("nodes", &self.counts[0])
            .finish()
    }
}
