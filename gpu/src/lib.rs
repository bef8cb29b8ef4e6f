//! # smoothtri-gpu
//!
//! smoothtri's bounded-work ray kernel as a WGSL compute shader (wgpu, Vulkan backend): the
//! patches and the BVH of a scene go to the GPU as storage buffers, and a batch of rays is traced
//! with one invocation per ray, in `f32`, with the mathematics of the CPU kernel
//! (docs/METHOD.md §2–§8): box and shell clip, bracketing at 8 points, exactly `N` refinement
//! steps of 8 points each, the certified `t_error` (final bracket plus the rounding allowance
//! `16 ε L / |f′|`), and the exact surface normal once per ray (forward-mode derivatives written
//! out in the shader, no finite differences).
//!
//! Two ways in. **Batches**, mirroring the CPU API: [`GpuScene::closest_hit`] fills a slice of
//! [`Option<Hit>`](smoothtri::Hit) for a slice of [`Ray`]s (the CPU's
//! [`Bvh::closest_hit`](smoothtri::Bvh::closest_hit) per ray), [`GpuScene::any_hit`] a slice of
//! `bool` (shadow rays), with the iteration budget `N` a compile-time constant of the pipeline.
//! [`GpuScene::closest_shaded_with`] adds each hit's shading normal: the seamless normal of
//! smooth patches uploaded with their seams ([`GpuScene::smooth_seamless`], the CPU's
//! `Scene::shading_normal` in WGSL) or the Phong normal of flat triangles ([`GpuScene::phong`]).
//! **Frames**, for real-time use: [`GpuScene::render_frame`] makes the camera rays of a
//! [`FrameView`], traces them, shades each closest hit with the scene's normal and a shadow ray,
//! and writes the colours into a [`GpuFrame`], all in one compute pass; [`GpuSurface::present`]
//! draws the frame into a window's swap chain, so nothing comes back but the frame's counters
//! ([`GpuFrame::read`] reads the pixels for screenshots).
//!
//! Every failure is a [`GpuError`]: no adapter, buffers over the device's limits, a corrupt tree
//! (detected by the shader, which never reads outside a buffer), a lost device. Nothing here
//! panics on bad input.
//!
//! # Bounded work
//! Per patch test at most `8 + 8·N + 4` height evaluations ([`SAMPLES`]` + 2` bracketing
//! points, `N` steps of 8 and, for `N ≥ 1`, one estimate step of 4, as the CPU's
//! `smoothtri::max_height_evals`), every loop of the kernel with a constant trip count; per ray at most one
//! visit per BVH node, one test per index of the tree's order, and [`STACK`] pending nodes; per
//! pixel of a frame two such rays (the camera ray and at most one shadow ray) and at most four
//! exact normals (the hit's and, for the seamless normal, three edge points').
//!
//! ```no_run
//! use glam::Vec3;
//! use smoothtri::{Bvh, BvhNode, Patch, Ray};
//! use smoothtri_gpu::{Gpu, GpuScene};
//!
//! let p = [Vec3::X, Vec3::Y, Vec3::Z];
//! let patches = [Patch::<f32>::new(p, p).unwrap()];
//! let mut nodes = [BvhNode::default(); 1];
//! let mut order = [0u32; 1];
//! let bvh = Bvh::build(&patches, &mut nodes, &mut order).unwrap();
//! let gpu = Gpu::new()?; // GpuError::NoAdapter without a Vulkan device
//! let scene = GpuScene::smooth(&gpu, &bvh)?;
//! let rays = [Ray::new(Vec3::splat(2.0), -Vec3::ONE)];
//! let mut hits = [None; 1];
//! scene.closest_hit::<4>(&rays, 0.0, f32::INFINITY, &mut hits)?;
//! assert!((hits[0].unwrap().point.length() - 1.0).abs() < 1e-5);
//! # Ok::<(), smoothtri_gpu::GpuError>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

use std::collections::HashMap;
use std::fmt;
use std::sync::{Arc, Mutex};

use glam::Vec3;
use smoothtri::mesh::Seam;
use smoothtri::{Bvh, Hit, PatchData, Ray};
use wgpu::util::DeviceExt;

mod flat_tris;
mod frame;
pub use flat_tris::{FLAT_SHADER, FlatHit, FlatScene};
pub use frame::{FramePixel, FrameStats, FrameView, GpuFrame, GpuSurface};

/// The shader (WGSL), as compiled by [`Gpu::new`].
pub const SHADER: &str = include_str!("kernel.wgsl");

/// Interior bracketing samples `K` of the shader (the CPU's `DEFAULT_SAMPLES`): `K + 2 = 8`
/// points.
pub const SAMPLES: usize = 6;
/// Entries of the shader's traversal stack (the CPU's [`smoothtri::BVH_STACK`]).
pub const STACK: usize = smoothtri::BVH_STACK;
/// The refinement budget the demo uses by default on the GPU.
pub const DEFAULT_ITERATIONS: usize = 4;
/// Largest refinement budget a pipeline is built for.
pub const MAX_ITERATIONS: usize = 64;
/// `vec4<f32>` per smooth patch record: 432 bytes (the patch data of
/// [`PatchData`], the CPU kernel's per-patch precomputation and the culling band).
pub const PATCH_VEC4: usize = 27;
/// `vec4<f32>` per flat triangle record (the three world vertices).
pub const FLAT_VEC4: usize = 3;
/// Bytes per ray uploaded (`origin, t_min, dir, t_max`).
pub const RAY_BYTES: usize = 32;
/// Bytes per hit read back.
pub const HIT_BYTES: usize = 64;
/// `vec4<f32>` per seam record (the seamless normal's coefficients of one patch,
/// [`seam_record`]): 160 bytes.
pub const SEAM_VEC4: usize = 10;
/// Invocations per workgroup.
const WORKGROUP: u32 = 64;
/// Two resolved timestamp queries (begin and end of the compute pass), 8 bytes each.
const TIMESTAMP_BYTES: usize = 16;
/// Largest batch of rays per dispatch.
const MAX_CHUNK: usize = 1 << 20;

/// Why a GPU query could not run. Every failure of this crate is one of these.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GpuError {
    /// No Vulkan adapter (GPU, or a software one such as Mesa's lavapipe) was found.
    NoAdapter,
    /// The adapter refused to create a device.
    RequestDevice(String),
    /// The shader or a pipeline failed to compile or validate on this device.
    Shader(String),
    /// A buffer would exceed the device's limits.
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Bytes needed.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The output slice's length differs from the ray slice's.
    LengthMismatch {
        /// Rays given.
        rays: usize,
        /// Output slots given.
        out: usize,
    },
    /// An iteration budget above [`MAX_ITERATIONS`].
    Iterations(usize),
    /// The shader found a node or patch index outside the uploaded buffers, a node reached more
    /// often than the tree has nodes, or a leaf longer than the order (storage not made by
    /// [`Bvh::build`]). The affected rays were reported as misses.
    CorruptTree,
    /// The traversal stack would have overflowed (only possible with a tree deeper than
    /// [`STACK`], i.e. storage not made by [`Bvh::build`]).
    StackOverflow,
    /// A device error while tracing (validation, out of memory, lost device, mapping).
    Device(String),
    /// The device cannot present to the window (no surface for it, no format in common, a
    /// surface lost for good).
    Surface(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter => f.write_str(
                "no GPU adapter: no Vulkan device found (install a driver, or Mesa's software \
                 Vulkan, Debian package mesa-vulkan-drivers)",
            ),
            GpuError::RequestDevice(m) => write!(f, "the GPU adapter refused a device: {m}"),
            GpuError::Shader(m) => write!(f, "the GPU kernel failed to compile: {m}"),
            GpuError::TooLarge { what, bytes, limit } => write!(
                f,
                "the {what} buffer needs {bytes} bytes, over the device's limit of {limit}"
            ),
            GpuError::LengthMismatch { rays, out } => {
                write!(f, "{rays} rays but {out} output slots")
            }
            GpuError::Iterations(n) => write!(
                f,
                "iteration budget {n} is above the largest supported, {MAX_ITERATIONS}"
            ),
            GpuError::CorruptTree => f.write_str(
                "the BVH uploaded to the GPU is corrupt (an index outside the storage, or a \
                 node reached twice)",
            ),
            GpuError::StackOverflow => f.write_str("GPU BVH traversal stack overflow"),
            GpuError::Device(m) => write!(f, "GPU device error: {m}"),
            GpuError::Surface(m) => write!(f, "cannot present to the window on the GPU: {m}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// A GPU device with the kernel's shader compiled: create one per process with [`Gpu::new`]
/// and share it (`Arc`) between scenes.
pub struct Gpu {
    instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    limits: wgpu::Limits,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Group 1 of the frame pass: the view, the image, the pixels and the frame's counters.
    frame_layout: wgpu::BindGroupLayout,
    frame_pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    pipelines: Mutex<HashMap<PipelineKey, wgpu::ComputePipeline>>,
    uncaptured: Arc<Mutex<Option<String>>>,
    /// The device was created with timestamp queries (kernel timings for benchmarks).
    timestamps: bool,
}

impl fmt::Debug for Gpu {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.info.name)
            .field("backend", &self.info.backend)
            .finish()
    }
}

/// Ranks adapters: discrete GPUs first, software ones last.
fn rank(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

/// Runs `f` inside validation and out-of-memory error scopes; the first captured error is
/// returned as `wrap(message)`.
fn scoped<T>(
    device: &wgpu::Device,
    wrap: fn(String) -> GpuError,
    f: impl FnOnce() -> T,
) -> Result<T, GpuError> {
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let val = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    let v = pollster::block_on(val.pop());
    let o = pollster::block_on(oom.pop());
    match v.or(o) {
        Some(e) => Err(wrap(e.to_string())),
        None => Ok(out),
    }
}

impl Gpu {
    /// Opens the best Vulkan adapter (a discrete GPU before an integrated, virtual or software
    /// one), creates a device with the adapter's own limits and compiles the shader.
    ///
    /// Returns [`GpuError::NoAdapter`] when there is none (no driver, no Mesa), so callers can
    /// say so and stop.
    pub fn new() -> Result<Arc<Gpu>, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        desc.flags = wgpu::InstanceFlags::empty();
        let instance = wgpu::Instance::new(desc);
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        let adapter = adapters
            .into_iter()
            .min_by_key(|a| rank(a.get_info().device_type))
            .ok_or(GpuError::NoAdapter)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        // Timestamp queries only time the kernel for benchmarks ([`GpuScene::closest_hit_timed`]);
        // adapters without them work the same.
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let features = if timestamps {
            wgpu::Features::TIMESTAMP_QUERY
        } else {
            wgpu::Features::empty()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("smoothtri"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::RequestDevice(e.to_string()))?;
        // Errors outside a scope are recorded, never a panic (wgpu's default handler panics).
        let uncaptured = Arc::new(Mutex::new(None));
        let sink = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut slot) = sink.lock() {
                slot.get_or_insert_with(|| e.to_string());
            }
        }));
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
        let (layout, pipeline_layout, frame_layout, frame_pipeline_layout, module) =
            scoped(&device, GpuError::Shader, || {
                let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("smoothtri"),
                    entries: &[
                        entry(0, wgpu::BufferBindingType::Uniform),
                        entry(1, ro),
                        entry(2, ro),
                        entry(3, ro),
                        entry(4, ro),
                        entry(5, rw),
                        entry(6, rw),
                        entry(7, ro),
                    ],
                });
                let pipeline_layout =
                    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("smoothtri"),
                        bind_group_layouts: &[Some(&layout)],
                        immediate_size: 0,
                    });
                let frame_layout =
                    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: Some("smoothtri frame"),
                        entries: &[
                            entry(0, wgpu::BufferBindingType::Uniform),
                            entry(1, rw),
                            entry(2, rw),
                            entry(3, rw),
                        ],
                    });
                let frame_pipeline_layout =
                    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("smoothtri frame"),
                        bind_group_layouts: &[Some(&layout), Some(&frame_layout)],
                        immediate_size: 0,
                    });
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("smoothtri kernel"),
                    source: wgpu::ShaderSource::Wgsl(SHADER.into()),
                });
                (
                    layout,
                    pipeline_layout,
                    frame_layout,
                    frame_pipeline_layout,
                    module,
                )
            })?;
        Ok(Arc::new(Gpu {
            instance,
            adapter,
            device,
            queue,
            info,
            limits,
            layout,
            pipeline_layout,
            frame_layout,
            frame_pipeline_layout,
            module,
            pipelines: Mutex::new(HashMap::new()),
            uncaptured,
            timestamps,
        }))
    }

    /// The adapter's name and driver, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Mesa 22.3.6)`.
    pub fn adapter_name(&self) -> String {
        if self.info.driver_info.is_empty() {
            self.info.name.clone()
        } else {
            format!("{} ({})", self.info.name, self.info.driver_info)
        }
    }

    /// `true` for a software adapter (a CPU implementation of Vulkan, such as lavapipe): its
    /// timings say nothing about GPUs.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// The pipeline of `key` (compiled once).
    fn pipeline(&self, key: PipelineKey) -> Result<wgpu::ComputePipeline, GpuError> {
        if key.n > MAX_ITERATIONS {
            return Err(GpuError::Iterations(key.n));
        }
        let mut map = self
            .pipelines
            .lock()
            .map_err(|_| GpuError::Device("pipeline cache poisoned".into()))?;
        if let Some(p) = map.get(&key) {
            return Ok(p.clone());
        }
        let constants = [
            ("ITERATIONS", key.n as f64),
            ("FLAT", f64::from(u8::from(key.flat))),
            ("ANY_HIT", f64::from(u8::from(key.any))),
            ("TILTED", f64::from(u8::from(key.tilted))),
            ("SHADING", f64::from(key.shading as u8)),
        ];
        let (layout, entry) = if key.frame {
            (&self.frame_pipeline_layout, "frame")
        } else {
            (&self.pipeline_layout, "main")
        };
        let p = scoped(&self.device, GpuError::Shader, || {
            self.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("smoothtri kernel"),
                    layout: Some(layout),
                    module: &self.module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &constants,
                        zero_initialize_workgroup_memory: false,
                    },
                    cache: None,
                })
        })?;
        map.insert(key, p.clone());
        Ok(p)
    }

    /// A storage buffer with `bytes` (at least 16 bytes: an empty slice gets one zero record,
    /// ignored through the counts), checked against the device's limits.
    fn storage(&self, what: &'static str, mut bytes: Vec<u8>) -> Result<wgpu::Buffer, GpuError> {
        let limit = self.buffer_limit();
        if bytes.len() as u64 > limit {
            return Err(GpuError::TooLarge {
                what,
                bytes: bytes.len() as u64,
                limit,
            });
        }
        // Empty arrays are not bindable: at least one element of the largest (a node).
        if bytes.len() < size_of::<GpuNode>() {
            bytes.resize(size_of::<GpuNode>(), 0);
        }
        scoped(&self.device, GpuError::Device, || {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(what),
                    contents: &bytes,
                    usage: wgpu::BufferUsages::STORAGE,
                })
        })
    }

    /// Submits `enc`, waits for it, and returns `range` of `read_buf` (a `MAP_READ` buffer the
    /// commands copied into). Call inside [`scoped`].
    fn submit_and_read(
        &self,
        enc: wgpu::CommandEncoder,
        read_buf: &wgpu::Buffer,
        range: std::ops::Range<u64>,
    ) -> Result<Vec<u8>, GpuError> {
        self.queue.submit([enc.finish()]);
        let done = Arc::new(Mutex::new(None));
        let flag = Arc::clone(&done);
        read_buf.map_async(wgpu::MapMode::Read, range.clone(), move |r| {
            if let Ok(mut slot) = flag.lock() {
                *slot = Some(r);
            }
        });
        let polled = self.device.poll(wgpu::PollType::wait_indefinitely());
        let mapped = done.lock().ok().and_then(|mut s| s.take());
        let out = match (polled, mapped) {
            (Err(e), _) => Err(GpuError::Device(e.to_string())),
            (_, Some(Ok(()))) => {
                let view = read_buf
                    .get_mapped_range(range)
                    .map_err(|e| GpuError::Device(e.to_string()))?;
                let v = view.to_vec();
                drop(view);
                read_buf.unmap();
                Ok(v)
            }
            (_, Some(Err(e))) => Err(GpuError::Device(e.to_string())),
            (_, None) => Err(GpuError::Device("the readback was never mapped".into())),
        };
        if let Ok(mut slot) = self.uncaptured.lock()
            && let Some(msg) = slot.take()
        {
            return Err(GpuError::Device(msg));
        }
        out
    }

    /// The largest storage buffer the device binds, in bytes.
    fn buffer_limit(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    /// Rays per dispatch: bounded by the device's buffer and dispatch limits.
    fn chunk(&self) -> usize {
        let by_buffer = (self.buffer_limit() / HIT_BYTES as u64).min(usize::MAX as u64) as usize;
        let by_dispatch =
            self.limits.max_compute_workgroups_per_dimension as usize * WORKGROUP as usize;
        MAX_CHUNK.min(by_buffer).min(by_dispatch).max(1)
    }
}

/// What a compute pipeline is compiled for: the budget `n`, flat or smooth records, closest or
/// any hit, with or without the tilted-section branches, the shading normal, and the batch
/// entry point (`main`) or the frame pass (`frame`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PipelineKey {
    n: usize,
    flat: bool,
    any: bool,
    tilted: bool,
    shading: Shading,
    frame: bool,
}

/// The shading normal a scene's closest hits and frames carry (the shader's `SHADING`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    /// The geometric normal: the patch's exact normal, or the flat triangle's face normal.
    Geometric = 0,
    /// The seamless normal of smooth patches ([`smoothtri::mesh::Seam::correct`]).
    Seamless = 1,
    /// The flat triangles' interpolated vertex normals (Phong).
    Phong = 2,
}

/// One BVH node as the shader reads it (128 bytes), as [`smoothtri::BvhNode`]: the four
/// children's boxes by coordinate, and per slot a child node (count 0), a leaf of `count`
/// patches (`order[child..]`), or [`smoothtri::BVH_EMPTY_SLOT`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuNode {
    /// Minimum corners: `lo[axis][slot]`.
    pub lo: [[f32; 4]; 3],
    /// Maximum corners: `hi[axis][slot]`.
    pub hi: [[f32; 4]; 3],
    /// Per slot: the child node, the start of the leaf's range in the order, or
    /// [`smoothtri::BVH_EMPTY_SLOT`].
    pub child: [u32; 4],
    /// Per slot: patches of a leaf; 0 for a child node or an unused slot.
    pub count: [u32; 4],
}

impl GpuNode {
    /// The node of a CPU BVH.
    pub fn from_node(n: &smoothtri::BvhNode<f32>) -> Self {
        let b: [smoothtri::Aabb<f32>; 4] = std::array::from_fn(|k| n.bounds(k));
        GpuNode {
            lo: [0, 1, 2].map(|a| b.map(|b| b.min()[a])),
            hi: [0, 1, 2].map(|a| b.map(|b| b.max()[a])),
            child: std::array::from_fn(|k| n.child(k)),
            count: std::array::from_fn(|k| n.count(k)),
        }
    }
}

/// What a scene's records are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneKind {
    /// The smooth patches (the kernel).
    Smooth,
    /// The patches' flat triangles (Möller–Trumbore, the baseline), on the same traversal.
    Flat,
}

/// A scene uploaded to the GPU: patch records, BVH nodes and order.
pub struct GpuScene {
    gpu: Arc<Gpu>,
    kind: SceneKind,
    patches: wgpu::Buffer,
    nodes: wgpu::Buffer,
    order: wgpu::Buffer,
    counts: [u32; 3],
    bytes: u64,
    /// Some smooth patch has tilted sections (`smoothtri::LineField::Vertex`): traced by the
    /// pipeline with the tilted branches (`TILTED` in the shader), all others without them.
    tilted: bool,
    /// The shading normal of closest hits and frames, with its data (`shade_in`: seam records
    /// or vertex normals; one zero record for [`Shading::Geometric`]).
    shading: Shading,
    shade_in: wgpu::Buffer,
}

impl fmt::Debug for GpuScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuScene")
            .field("kind", &self.kind)
            .field("patches", &self.counts[2])
            .field("nodes", &self.counts[0])
            .finish()
    }
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The smooth record of one patch: its data and the CPU kernel's per-patch precomputation
/// (`core/src/height.rs`, `Prepared`), in `f32` with the CPU's arithmetic; layout in
/// `kernel.wgsl` (`load_patch`).
pub fn smooth_record(pd: &PatchData<f32>) -> [f32; PATCH_VEC4 * 4] {
    let [p0, p1, p2] = pd.p;
    let [n0, n1, n2] = pd.n;
    let [d0, d1, d2] = pd.d;
    let longest = dot(sub(p1, p0), sub(p1, p0))
        .max(dot(sub(p2, p1), sub(p2, p1)))
        .max(dot(sub(p0, p2), sub(p0, p2)))
        .sqrt();
    let scale = longest * 4.0 + dot(pd.origin, pd.origin).sqrt();
    let [ex, ey, ez] = pd.axes;
    let [s_lo, s_hi] = pd.sigma;
    let mut r = [0.0f32; PATCH_VEC4 * 4];
    let head: [[f32; 4]; 10] = [
        [pd.origin[0], pd.origin[1], pd.origin[2], scale],
        [ex[0], ex[1], ex[2], s_lo],
        [ey[0], ey[1], ey[2], s_hi],
        [ez[0], ez[1], ez[2], p1[0]],
        [pd.bbox_min[0], pd.bbox_min[1], pd.bbox_min[2], p2[0]],
        [pd.bbox_max[0], pd.bbox_max[1], pd.bbox_max[2], p2[1]],
        [n0[0], n0[1], n0[2], d0[0]],
        [n1[0], n1[1], n1[2], d0[1]],
        [n2[0], n2[1], n2[2], d1[0]],
        [d1[1], d2[0], d2[1], 0.0],
    ];
    let ends = [(0usize, 1usize), (1, 2), (2, 0)];
    let mut edges = [[[0.0f32; 4]; 5]; 3];
    for (j, (slot, (i, k))) in edges.iter_mut().zip(ends).enumerate() {
        let (a, b, da, db, na, nb) = (pd.p[i], pd.p[k], pd.d[i], pd.d[k], pd.n[i], pd.n[k]);
        let [k1, k2] = pd.k[j];
        let e = sub(b, a);
        let gd = sub(db, da);
        let gg = [dot(da, da), 2.0 * dot(da, gd), dot(gd, gd)];
        let eg = [dot(e, da), dot(e, gd)];
        let ee = dot(e, e);
        *slot = [
            [e[0], e[1], gd[0], gd[1]],
            [k1, k2, ee, eg[0]],
            [eg[1], gg[0], gg[1], gg[2]],
            // The reach of wall j (opposite vertex j) rides in edge j's spare slot.
            [dot(da, na), dot(gd, na), dot(e, na), pd.reach[j]],
            // d_j.z (1 for parallel sections) rides in the last spare slot.
            [dot(da, nb), dot(gd, nb), dot(e, nb), da[2]],
        ];
    }
    // The culling band (core/src/surface/band.rs), in the last two vec4s.
    let [c0, c1, c2] = pd.band_fit;
    let [lo, hi, per_reach] = pd.band;
    let band = [[c0, c1, c2, lo], [hi, per_reach, 0.0, 0.0]];
    let all = head.iter().chain(edges.iter().flatten()).chain(band.iter());
    for (dst, src) in r.chunks_exact_mut(4).zip(all) {
        dst.copy_from_slice(src);
    }
    r
}

/// The flat record of one patch: its triangle's world vertices.
pub fn flat_record(pd: &PatchData<f32>) -> [f32; FLAT_VEC4 * 4] {
    let mut r = [0.0f32; FLAT_VEC4 * 4];
    let [ex, ey, ez] = pd.axes;
    for (dst, p) in r.chunks_exact_mut(4).zip(pd.p) {
        // The CPU's local_to_world: origin + ex·x + ey·y + ez·z.
        for (c, slot) in dst.iter_mut().take(3).enumerate() {
            *slot = pd.origin[c] + ex[c] * p[0] + ey[c] * p[1] + ez[c] * p[2];
        }
    }
    r
}

fn f32_bytes(v: impl IntoIterator<Item = f32>) -> Vec<u8> {
    v.into_iter().flat_map(f32::to_ne_bytes).collect()
}

/// One traced ray as the shader wrote it.
#[derive(Clone, Copy, Debug, Default)]
struct Raw {
    t: f32,
    t_error: f32,
    w1: f32,
    w2: f32,
    point: [f32; 3],
    patch: u32,
    normal: [f32; 3],
    flags: u32,
    shading: [f32; 3],
}

impl Raw {
    /// The hit of a closest-hit query, `None` on a miss.
    fn hit(&self) -> Option<Hit<f32>> {
        (self.flags & 1 != 0).then(|| Hit {
            t: self.t,
            t_error: self.t_error,
            point: Vec3::from_array(self.point),
            normal: Vec3::from_array(self.normal),
            w1: self.w1,
            w2: self.w2,
            front_face: self.flags & 2 != 0,
            patch: self.patch,
        })
    }
}

/// The shader's status word as a result: its `STATUS_CORRUPT` bit (1) is
/// [`GpuError::CorruptTree`], its `STATUS_STACK` bit (2) [`GpuError::StackOverflow`].
fn status_result(status: u32) -> Result<(), GpuError> {
    if status & 1 != 0 {
        return Err(GpuError::CorruptTree);
    }
    if status & 2 != 0 {
        return Err(GpuError::StackOverflow);
    }
    Ok(())
}

/// A buffer bound whole at `binding`.
fn bind_entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// The `k`-th 32-bit word of bytes read back (0 past the end).
fn word(b: &[u8], k: usize) -> u32 {
    let mut a = [0u8; 4];
    if let Some(s) = b.get(4 * k..4 * k + 4) {
        a.copy_from_slice(s);
    }
    u32::from_ne_bytes(a)
}

fn parse_hit(b: &[u8]) -> Raw {
    let f = |k: usize| f32::from_bits(word(b, k));
    let u = |k: usize| word(b, k);
    Raw {
        t: f(0),
        t_error: f(1),
        w1: f(2),
        w2: f(3),
        point: [f(4), f(5), f(6)],
        patch: u(7),
        normal: [f(8), f(9), f(10)],
        flags: u(11),
        shading: [f(12), f(13), f(14)],
    }
}

/// The seam record of one patch as the shader reads it ([`SEAM_VEC4`] vec4s): per edge `j` the
/// six coefficients of the common normal's tilt across the edge then the six along it; then
/// the three edges' `free` flags (1 or 0) and 1 for a non-zero seam (0: no correction).
pub fn seam_record(seam: &Seam<f32>) -> [f32; SEAM_VEC4 * 4] {
    let mut r = [0.0f32; SEAM_VEC4 * 4];
    let mut k = 0;
    for (common, along) in seam.common.iter().zip(&seam.common_along) {
        // The shader's TWIST_TERMS is 6: a change of smoothtri::mesh::TWIST_TERMS fails here.
        let (c, a): (&[f32; 6], &[f32; 6]) = (common, along);
        for (dst, src) in r.iter_mut().skip(k).zip(c.iter().chain(a)) {
            *dst = *src;
        }
        k += 12;
    }
    let flags = seam.free.map(|f| f32::from(u8::from(f)));
    let nonzero = f32::from(u8::from(!seam.is_zero()));
    for (dst, src) in r.iter_mut().skip(36).zip(flags.iter().chain([&nonzero])) {
        *dst = *src;
    }
    r
}

impl GpuScene {
    /// Uploads the smooth patches and the BVH of `bvh`.
    pub fn smooth(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        let data: Vec<PatchData<f32>> = bvh.patches().iter().map(|p| p.data()).collect();
        let nodes: Vec<GpuNode> = bvh.nodes().iter().map(GpuNode::from_node).collect();
        Self::from_parts(gpu, SceneKind::Smooth, &data, &nodes, bvh.order())
    }

    /// Uploads the smooth patches and the BVH of `bvh` with the patches' seams (`seams[i]` the
    /// seam of `bvh.patches()[i]`, as `smoothtri::Scene::seams`): closest hits and frames then
    /// carry the seamless shading normal ([`Shading::Seamless`], the CPU's
    /// `Scene::shading_normal`). Returns [`GpuError::LengthMismatch`] when the lengths differ.
    pub fn smooth_seamless(
        gpu: &Arc<Gpu>,
        bvh: &Bvh<'_, f32>,
        seams: &[Seam<f32>],
    ) -> Result<GpuScene, GpuError> {
        if seams.len() != bvh.patches().len() {
            return Err(GpuError::LengthMismatch {
                rays: bvh.patches().len(),
                out: seams.len(),
            });
        }
        let data = f32_bytes(seams.iter().flat_map(seam_record));
        Self::smooth(gpu, bvh)?.with_shading(Shading::Seamless, data)
    }

    /// Uploads the flat triangles of `bvh`'s patches with their world vertex normals: closest
    /// hits and frames carry the Phong normal ([`Shading::Phong`]: the vertex normals
    /// interpolated at the hit's barycentrics, normalised; the face normal where that vanishes).
    pub fn phong(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        let data = f32_bytes(
            bvh.patches()
                .iter()
                .flat_map(|p| p.normals().into_iter().flat_map(|n| [n.x, n.y, n.z, 0.0])),
        );
        Self::flat(gpu, bvh)?.with_shading(Shading::Phong, data)
    }

    fn with_shading(mut self, shading: Shading, data: Vec<u8>) -> Result<GpuScene, GpuError> {
        self.bytes += data.len() as u64;
        self.shade_in = self.gpu.storage("shading", data)?;
        self.shading = shading;
        Ok(self)
    }

    /// The shading normal of the scene's closest hits and frames.
    pub fn shading(&self) -> Shading {
        self.shading
    }

    /// Uploads the flat triangles of `bvh`'s patches (their world vertices) with the same BVH:
    /// the baseline on the same traversal code.
    pub fn flat(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        let data: Vec<PatchData<f32>> = bvh.patches().iter().map(|p| p.data()).collect();
        let nodes: Vec<GpuNode> = bvh.nodes().iter().map(GpuNode::from_node).collect();
        Self::from_parts(gpu, SceneKind::Flat, &data, &nodes, bvh.order())
    }

    /// Uploads arbitrary parts: patch data, nodes and order (node 0 the root). Storage not
    /// made by [`Bvh::build`] is traced without any read outside the buffers: queries then
    /// return [`GpuError::CorruptTree`] or [`GpuError::StackOverflow`] where the shader notices,
    /// misses or wrong answers otherwise, never a panic or a device loss.
    pub fn from_parts(
        gpu: &Arc<Gpu>,
        kind: SceneKind,
        patches: &[PatchData<f32>],
        nodes: &[GpuNode],
        order: &[u32],
    ) -> Result<GpuScene, GpuError> {
        let too_many = |what: &'static str, n: usize| GpuError::TooLarge {
            what,
            bytes: n as u64,
            limit: u32::MAX as u64,
        };
        let count = |what, n: usize| u32::try_from(n).map_err(|_| too_many(what, n));
        let counts = [
            count("node", nodes.len())?,
            count("order", order.len())?,
            count("patch", patches.len())?,
        ];
        let records = match kind {
            SceneKind::Smooth => f32_bytes(patches.iter().flat_map(smooth_record)),
            SceneKind::Flat => f32_bytes(patches.iter().flat_map(flat_record)),
        };
        let node_bytes: Vec<u8> = nodes
            .iter()
            .flat_map(|n| {
                // The shader's `Node`: lo[3], hi[3], child, count (vec4 each).
                let mut b = Vec::with_capacity(128);
                for x in n.lo.iter().chain(&n.hi).flatten() {
                    b.extend_from_slice(&x.to_ne_bytes());
                }
                for x in n.child.iter().chain(&n.count) {
                    b.extend_from_slice(&x.to_ne_bytes());
                }
                b
            })
            .collect();
        let order_bytes: Vec<u8> = order.iter().flat_map(|i| i.to_ne_bytes()).collect();
        let bytes = (records.len() + node_bytes.len() + order_bytes.len()) as u64;
        Ok(GpuScene {
            gpu: Arc::clone(gpu),
            kind,
            patches: gpu.storage("patch", records)?,
            nodes: gpu.storage("node", node_bytes)?,
            order: gpu.storage("order", order_bytes)?,
            counts,
            bytes,
            tilted: kind == SceneKind::Smooth
                && patches.iter().any(|pd| pd.d.iter().any(|d| d[2] != 1.0)),
            shading: Shading::Geometric,
            shade_in: gpu.storage("shading", Vec::new())?,
        })
    }

    /// The shader's group 0 for this scene with the query's own buffers (the frame pass binds
    /// unused ones for `rays` and `hits`). Call inside [`scoped`].
    fn bind_group(
        &self,
        params: &wgpu::Buffer,
        rays: &wgpu::Buffer,
        hits: &wgpu::Buffer,
        status: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("smoothtri"),
                layout: &self.gpu.layout,
                entries: &[
                    bind_entry(0, params),
                    bind_entry(1, &self.patches),
                    bind_entry(2, &self.nodes),
                    bind_entry(3, &self.order),
                    bind_entry(4, rays),
                    bind_entry(5, hits),
                    bind_entry(6, status),
                    bind_entry(7, &self.shade_in),
                ],
            })
    }

    /// The pipeline key of this scene's queries.
    fn key(&self, n: usize, any: bool, frame: bool) -> PipelineKey {
        PipelineKey {
            n,
            flat: self.kind == SceneKind::Flat,
            any,
            tilted: self.tilted,
            shading: self.shading,
            frame,
        }
    }

    /// Whether the records are smooth patches or flat triangles.
    pub fn kind(&self) -> SceneKind {
        self.kind
    }

    /// Bytes uploaded (records, nodes, order).
    pub fn memory_bytes(&self) -> u64 {
        self.bytes
    }

    /// The device.
    pub fn gpu(&self) -> &Arc<Gpu> {
        &self.gpu
    }

    /// Closest hits of `rays` in `[t_min, t_max]` with `N` refinement steps, one per slot of
    /// `hits` (`hit.patch` is the index of the patch in the uploaded order of patches, as
    /// the CPU's [`Bvh::closest_hit`]). Rays that the CPU rejects (non-finite, zero direction,
    /// NaN or reversed range) are misses; `t_max` may be infinite.
    ///
    /// # Accuracy
    /// As the CPU kernel's in `f32`: `|t − t_true| ≤ hit.t_error` for the crossing inside the
    /// final bracket (tested against analytic spheres and the CPU kernel: `gpu/tests/`).
    pub fn closest_hit<const N: usize>(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<(), GpuError> {
        self.closest_hit_with(N, rays, t_min, t_max, hits)
    }

    /// [`GpuScene::closest_hit`] with the budget chosen at run time (at most
    /// [`MAX_ITERATIONS`]; each budget is its own pipeline, compiled once).
    pub fn closest_hit_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<(), GpuError> {
        self.closest_hit_impl(iterations, rays, t_min, t_max, hits, None)
    }

    /// [`GpuScene::closest_hit_with`], also returning the GPU's own execution time of the
    /// kernel's compute passes in seconds (timestamp queries, summed over the dispatches:
    /// without the ray upload and the readback), or `None` when the adapter has no timestamp
    /// queries. For benchmarks; the hits are the same as [`GpuScene::closest_hit_with`]'s.
    pub fn closest_hit_timed(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
    ) -> Result<Option<f64>, GpuError> {
        let mut seconds = 0.0;
        self.closest_hit_impl(iterations, rays, t_min, t_max, hits, Some(&mut seconds))?;
        Ok(self.gpu.timestamps.then_some(seconds))
    }

    fn closest_hit_impl(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<Hit<f32>>],
        seconds: Option<&mut f64>,
    ) -> Result<(), GpuError> {
        self.run(
            iterations,
            false,
            rays,
            t_min,
            t_max,
            seconds,
            hits,
            Raw::hit,
        )
    }

    /// [`GpuScene::closest_hit_with`] with each hit's shading normal (world, unit, oriented like
    /// [`Hit::normal`]): the scene's [`Shading`], i.e. the seamless normal (the CPU's
    /// `Scene::shading_normal`, the same formula in `f32`: within 1e-5 of it for the same hit
    /// in the parity tests), the Phong normal, or the hit's own normal.
    pub fn closest_shaded_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        out: &mut [Option<(Hit<f32>, Vec3)>],
    ) -> Result<(), GpuError> {
        self.run(iterations, false, rays, t_min, t_max, None, out, |raw| {
            raw.hit().map(|h| (h, Vec3::from_array(raw.shading)))
        })
    }

    /// Whether anything is hit in `[t_min, t_max]` along each ray (shadow rays), with `N`
    /// refinement steps; the traversal stops at the first hit.
    pub fn any_hit<const N: usize>(
        &self,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        occluded: &mut [bool],
    ) -> Result<(), GpuError> {
        self.any_hit_with(N, rays, t_min, t_max, occluded)
    }

    /// [`GpuScene::any_hit`] with the budget chosen at run time.
    pub fn any_hit_with(
        &self,
        iterations: usize,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        occluded: &mut [bool],
    ) -> Result<(), GpuError> {
        self.run(
            iterations,
            true,
            rays,
            t_min,
            t_max,
            None,
            occluded,
            |raw| raw.flags & 1 != 0,
        )
    }

    /// Traces `rays` in chunks into `out` (`out[i] = map(hit of rays[i])`; `LengthMismatch`
    /// unless the lengths agree); adds the kernel's GPU time to `seconds` when asked and the
    /// device has timestamp queries.
    #[allow(clippy::too_many_arguments)] // one private worker behind the public entry points
    fn run<T>(
        &self,
        iterations: usize,
        any: bool,
        rays: &[Ray<f32>],
        t_min: f32,
        t_max: f32,
        mut seconds: Option<&mut f64>,
        out: &mut [T],
        map: impl Fn(&Raw) -> T,
    ) -> Result<(), GpuError> {
        if rays.len() != out.len() {
            return Err(GpuError::LengthMismatch {
                rays: rays.len(),
                out: out.len(),
            });
        }
        let gpu = &self.gpu;
        let pipeline = gpu.pipeline(self.key(iterations, any, false))?;
        if rays.is_empty() {
            return Ok(());
        }
        let chunk = gpu.chunk().min(rays.len());
        let device = &gpu.device;
        let (ray_buf, hit_buf, status_buf, params_buf, read_buf) =
            scoped(device, GpuError::Device, || {
                let buf = |label, size: usize, usage| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: size as u64,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                use wgpu::BufferUsages as U;
                (
                    buf("rays", chunk * RAY_BYTES, U::STORAGE | U::COPY_DST),
                    buf("hits", chunk * HIT_BYTES, U::STORAGE | U::COPY_SRC),
                    buf("status", 16, U::STORAGE | U::COPY_SRC | U::COPY_DST),
                    buf("params", 16, U::UNIFORM | U::COPY_DST),
                    buf(
                        "readback",
                        chunk * HIT_BYTES + 16 + TIMESTAMP_BYTES,
                        U::MAP_READ | U::COPY_DST,
                    ),
                )
            })?;
        let timing = match (&seconds, gpu.timestamps) {
            (Some(_), true) => Some(scoped(device, GpuError::Device, || {
                let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("smoothtri kernel time"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                });
                let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps"),
                    size: TIMESTAMP_BYTES as u64,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                (set, resolve)
            })?),
            _ => None,
        };
        let bind = scoped(device, GpuError::Device, || {
            self.bind_group(&params_buf, &ray_buf, &hit_buf, &status_buf)
        })?;
        let mut status = 0u32;
        for (c, part) in rays.chunks(chunk).enumerate() {
            let n = part.len();
            let mut bytes = Vec::with_capacity(n * RAY_BYTES);
            for r in part {
                for x in upload_ray(r, t_min, t_max) {
                    bytes.extend_from_slice(&x.to_ne_bytes());
                }
            }
            let [nodes, order, patches] = self.counts;
            let params: Vec<u8> = [n as u32, nodes, order, patches]
                .iter()
                .flat_map(|x| x.to_ne_bytes())
                .collect();
            let data = scoped(device, GpuError::Device, || {
                gpu.queue.write_buffer(&ray_buf, 0, &bytes);
                gpu.queue.write_buffer(&params_buf, 0, &params);
                gpu.queue.write_buffer(&status_buf, 0, &[0u8; 16]);
                let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("smoothtri"),
                });
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("smoothtri"),
                        timestamp_writes: timing.as_ref().map(|(set, _)| {
                            wgpu::ComputePassTimestampWrites {
                                query_set: set,
                                beginning_of_pass_write_index: Some(0),
                                end_of_pass_write_index: Some(1),
                            }
                        }),
                    });
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    pass.dispatch_workgroups((n as u32).div_ceil(WORKGROUP), 1, 1);
                }
                let hit_bytes = (n * HIT_BYTES) as u64;
                enc.copy_buffer_to_buffer(&hit_buf, 0, &read_buf, 0, hit_bytes);
                enc.copy_buffer_to_buffer(&status_buf, 0, &read_buf, hit_bytes, 16);
                let mut range = 0..hit_bytes + 16;
                if let Some((set, resolve)) = &timing {
                    enc.resolve_query_set(set, 0..2, resolve, 0);
                    enc.copy_buffer_to_buffer(
                        resolve,
                        0,
                        &read_buf,
                        range.end,
                        TIMESTAMP_BYTES as u64,
                    );
                    range.end += TIMESTAMP_BYTES as u64;
                }
                gpu.submit_and_read(enc, &read_buf, range)
            })??;
            let (Some(hits), Some(tail)) = (
                data.get(..n * HIT_BYTES),
                data.get(n * HIT_BYTES..n * HIT_BYTES + 4),
            ) else {
                return Err(GpuError::Device("short readback".into()));
            };
            let mut s = [0u8; 4];
            s.copy_from_slice(tail);
            status |= u32::from_ne_bytes(s);
            if let (Some(total), Some(_)) = (seconds.as_deref_mut(), &timing) {
                let at = n * HIT_BYTES + 16;
                let tick = |k: usize| {
                    data.get(at + 8 * k..at + 8 * k + 8).map(|b| {
                        let mut t = [0u8; 8];
                        t.copy_from_slice(b);
                        u64::from_ne_bytes(t)
                    })
                };
                if let (Some(begin), Some(end)) = (tick(0), tick(1)) {
                    let period = f64::from(gpu.queue.get_timestamp_period());
                    *total += end.saturating_sub(begin) as f64 * period * 1e-9;
                }
            }
            for (k, h) in hits.chunks_exact(HIT_BYTES).enumerate() {
                if let Some(slot) = out.get_mut(c * chunk + k) {
                    *slot = map(&parse_hit(h));
                }
            }
        }
        status_result(status)
    }
}

/// The 8 floats of one ray as the shader reads them: `origin, t_min, dir, t_max`. Rays the CPU
/// rejects are marked with `t_min > t_max` (and zeroed); infinite bounds become ±`f32::MAX`
/// (the same intervals: every box is finite).
fn upload_ray(r: &Ray<f32>, t_min: f32, t_max: f32) -> [f32; 8] {
    let (o, d) = (r.origin, r.dir);
    let valid = o.is_finite()
        && d.is_finite()
        && d.length_squared() != 0.0
        && !t_min.is_nan()
        && !t_max.is_nan()
        && t_max >= t_min;
    if !valid {
        return [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    }
    let lo = t_min.clamp(-f32::MAX, f32::MAX);
    let hi = t_max.clamp(-f32::MAX, f32::MAX);
    [o.x, o.y, o.z, lo, d.x, d.y, d.z, hi]
}
