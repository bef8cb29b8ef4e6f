//! The device: [`Gpu`] opens a Vulkan adapter, compiles the shader and its pipelines (one per
//! [`PipelineKey`], cached), makes storage buffers within the device's limits, and submits work
//! and reads results back; every device error is caught in an error scope ([`scoped`]). The
//! set-up every pipeline shares (the kernel's, the flat triangles', the update's, the
//! presentation's) is here too: the kernel's group 0 ([`TRACE_BINDINGS`]), layouts of buffers
//! ([`buffer_layout`]), shader modules ([`wgsl_module`]) and compute pipelines
//! ([`compute_pipeline`]).

use std::collections::HashMap;
use std::fmt;
use std::sync::{Arc, Mutex};

use wgpu::util::DeviceExt;

use crate::error::GpuError;
use crate::records::{GpuNode, Packed, packed_bytes};
use crate::shader::{HIT_BYTES, MAX_ITERATIONS, SHADER, Shading, WORKGROUP};
use crate::update::pipelines::UpdatePipelines;

/// Largest batch of rays per dispatch.
const MAX_CHUNK: usize = 1 << 20;

/// A GPU device with the kernel's shader compiled: create one per process with [`Gpu::new`]
/// and share it (`Arc`) between scenes.
pub struct Gpu {
    pub(crate) instance: wgpu::Instance,
    pub(crate) adapter: wgpu::Adapter,
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) info: wgpu::AdapterInfo,
    pub(crate) limits: wgpu::Limits,
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) pipeline_layout: wgpu::PipelineLayout,
    /// Group 1 of the frame pass: the view, the image, the pixels and the frame's counters.
    pub(crate) frame_layout: wgpu::BindGroupLayout,
    pub(crate) frame_pipeline_layout: wgpu::PipelineLayout,
    pub(crate) module: wgpu::ShaderModule,
    pub(crate) pipelines: Mutex<HashMap<PipelineKey, wgpu::ComputePipeline>>,
    pub(crate) uncaptured: Arc<Mutex<Option<String>>>,
    /// The device was created with timestamp queries (kernel timings for benchmarks).
    pub(crate) timestamps: bool,
    /// The scene update's pipelines ([`crate::GpuUpdate`]), compiled on first use.
    pub(crate) update: Mutex<Option<Arc<UpdatePipelines>>>,
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

/// How long a readback waits for its mapping once the device has finished the work.
const MAP_WAIT: std::time::Duration = std::time::Duration::from_secs(30);

/// Bytes packed at a time by [`Gpu::rewrite`] before they are copied into the staging view.
const WRITE_CHUNK: usize = 64 * 1024;

/// Runs `f` inside validation and out-of-memory error scopes; the first captured error is
/// returned as `wrap(message)`.
pub(crate) fn scoped<T>(
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
        let (pipeline_layout, frame_pipeline_layout, layout, frame_layout, module) =
            scoped(&device, GpuError::Shader, || {
                let layout = buffer_layout(&device, "smoothtri", &TRACE_BINDINGS);
                let frame_layout = buffer_layout(&device, "smoothtri frame", &FRAME_BINDINGS);
                (
                    pipeline_layout(&device, "smoothtri", &[&layout]),
                    pipeline_layout(&device, "smoothtri frame", &[&layout, &frame_layout]),
                    layout,
                    frame_layout,
                    wgsl_module(&device, "smoothtri kernel", SHADER),
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
            update: Mutex::new(None),
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
    pub(crate) fn pipeline(&self, key: PipelineKey) -> Result<wgpu::ComputePipeline, GpuError> {
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
            compute_pipeline(
                &self.device,
                "smoothtri kernel",
                Some(layout),
                &self.module,
                entry,
                &constants,
            )
        })?;
        map.insert(key, p.clone());
        Ok(p)
    }

    /// A storage buffer with `bytes` (at least 16 bytes: an empty slice gets one zero record,
    /// ignored through the counts), checked against the device's limits.
    pub(crate) fn storage(
        &self,
        what: &'static str,
        mut bytes: Vec<u8>,
    ) -> Result<wgpu::Buffer, GpuError> {
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
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                })
        })
    }

    /// Writes `records` (back to back, as [`Packed`] packs them) into `buffer`
    /// through the queue's staging memory when their length is the buffer's (no allocation on
    /// the device, no copy of the whole on the host: records are packed in chunks of
    /// [`WRITE_CHUNK`] bytes straight into the staging view), else replaces `buffer` by a new
    /// [`Gpu::storage`] buffer of them. Empty contents keep the one-node minimum of
    /// [`Gpu::storage`]. Returns the records' bytes.
    pub(crate) fn rewrite<R: Packed>(
        &self,
        buffer: &mut wgpu::Buffer,
        what: &'static str,
        records: impl ExactSizeIterator<Item = R>,
    ) -> Result<u64, GpuError> {
        let len = records.len() * R::BYTES;
        let size = len.max(size_of::<GpuNode>()) as u64;
        let staged = match wgpu::BufferSize::new(size) {
            Some(s) if size == buffer.size() && len > 0 => s,
            _ => {
                *buffer = self.storage(what, packed_bytes(records))?;
                return Ok(len as u64);
            }
        };
        scoped(&self.device, GpuError::Device, || {
            let Some(mut view) = self.queue.write_buffer_with(buffer, 0, staged) else {
                return Err(GpuError::Device(format!(
                    "no staging memory for {size} bytes of {what} records"
                )));
            };
            let mut chunk: Vec<u8> = Vec::with_capacity(WRITE_CHUNK + R::BYTES);
            let mut at = 0usize;
            let mut flush = |chunk: &mut Vec<u8>, at: &mut usize| {
                view.slice(*at..*at + chunk.len()).copy_from_slice(chunk);
                *at += chunk.len();
                chunk.clear();
            };
            for r in records {
                r.pack(&mut chunk);
                if chunk.len() >= WRITE_CHUNK {
                    flush(&mut chunk, &mut at);
                }
            }
            flush(&mut chunk, &mut at);
            Ok(len as u64)
        })?
    }

    /// Submits `enc`, waits for it, and returns `range` of `read_buf` (a `MAP_READ` buffer the
    /// commands copied into). Call inside [`scoped`].
    pub(crate) fn submit_and_read(
        &self,
        enc: wgpu::CommandEncoder,
        read_buf: &wgpu::Buffer,
        range: std::ops::Range<u64>,
    ) -> Result<Vec<u8>, GpuError> {
        self.queue.submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        read_buf.map_async(wgpu::MapMode::Read, range.clone(), move |r| {
            let _ = tx.send(r);
        });
        let polled = self.device.poll(wgpu::PollType::wait_indefinitely());
        // The poll returns once the work is done, but the callback may run a moment later: a
        // poll on another thread sharing the device can have taken it from the queue first.
        let mapped = match polled {
            Ok(_) => rx.recv_timeout(MAP_WAIT).ok(),
            Err(_) => None,
        };
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

    /// The scene update's pipelines, compiled once per device.
    pub(crate) fn update_pipelines(&self) -> Result<Arc<UpdatePipelines>, GpuError> {
        let mut slot = self
            .update
            .lock()
            .map_err(|_| GpuError::Device("pipeline cache poisoned".into()))?;
        if let Some(p) = slot.as_ref() {
            return Ok(Arc::clone(p));
        }
        let p = Arc::new(scoped(&self.device, GpuError::Shader, || {
            UpdatePipelines::new(&self.device)
        })?);
        *slot = Some(Arc::clone(&p));
        Ok(p)
    }

    /// The first `bytes` of `buffer` (a `COPY_SRC` buffer), copied out and read back.
    pub(crate) fn read_buffer(
        &self,
        buffer: &wgpu::Buffer,
        bytes: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let bytes = bytes.min(buffer.size()) & !3;
        if bytes == 0 {
            return Ok(Vec::new());
        }
        scoped(&self.device, GpuError::Device, || {
            let read_buf = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut enc = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("readback"),
                });
            enc.copy_buffer_to_buffer(buffer, 0, &read_buf, 0, bytes);
            self.submit_and_read(enc, &read_buf, 0..bytes)
        })?
    }

    /// The first `bytes` of `buffer` read back ([`Gpu::read_buffer`]) as 32-bit words, each
    /// made a value by `from` (`f32::from_ne_bytes`, `u32::from_ne_bytes`).
    pub(crate) fn read_words<T>(
        &self,
        buffer: &wgpu::Buffer,
        bytes: u64,
        from: fn([u8; 4]) -> T,
    ) -> Result<Vec<T>, GpuError> {
        let raw = self.read_buffer(buffer, bytes)?;
        Ok(raw
            .chunks_exact(4)
            .map(|c| from([c[0], c[1], c[2], c[3]]))
            .collect())
    }

    /// The largest storage buffer the device binds, in bytes.
    pub(crate) fn buffer_limit(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    /// Rays per dispatch: bounded by the device's buffer and dispatch limits.
    pub(crate) fn chunk(&self) -> usize {
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
pub(crate) struct PipelineKey {
    pub(crate) n: usize,
    pub(crate) flat: bool,
    pub(crate) any: bool,
    pub(crate) tilted: bool,
    pub(crate) shading: Shading,
    pub(crate) frame: bool,
}

/// A buffer bound whole at `binding`.
pub(crate) fn bind_entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// The kernel's group 0, binding by binding (binding `k` of type `TRACE_BINDINGS[k]`): the
/// parameters; the scene's records, nodes and order; the rays; the hits and the status word
/// (written); the shading data. The flat triangles' own pipeline
/// ([`FlatScene`](crate::FlatScene)) binds the first seven ([`crate::dispatch::Tracer`]).
pub(crate) const TRACE_BINDINGS: [wgpu::BufferBindingType; 8] = {
    use wgpu::BufferBindingType::{Storage, Uniform};
    let (ro, rw) = (Storage { read_only: true }, Storage { read_only: false });
    [Uniform, ro, ro, ro, ro, rw, rw, ro]
};

/// The frame pass's group 1: the view (uniform), then the image, the pixels and the frame's
/// counters (written).
const FRAME_BINDINGS: [wgpu::BufferBindingType; 4] = {
    use wgpu::BufferBindingType::{Storage, Uniform};
    let rw = Storage { read_only: false };
    [Uniform, rw, rw, rw]
};

/// The layout entry of a buffer at `binding` of type `ty`, seen by the shader `stage`.
pub(crate) fn buffer_entry(
    binding: u32,
    stage: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stage,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A compute shader's bind group layout of buffers: binding `k` of type `types[k]`. Call inside
/// [`scoped`].
pub(crate) fn buffer_layout(
    device: &wgpu::Device,
    label: &str,
    types: &[wgpu::BufferBindingType],
) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = (0..)
        .zip(types)
        .map(|(k, &ty)| buffer_entry(k, wgpu::ShaderStages::COMPUTE, ty))
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// The pipeline layout of `groups` (group `k` is `groups[k]`). Call inside [`scoped`].
pub(crate) fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<_> = groups.iter().copied().map(Some).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}

/// The shader module of the WGSL `source`. Call inside [`scoped`].
pub(crate) fn wgsl_module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// The compute pipeline of `module`'s `entry` with the override `constants`, on `layout` (or,
/// with `None`, the layout the shader implies). Workgroup memory is not zeroed: no shader here
/// declares any. Call inside [`scoped`].
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: Option<&wgpu::PipelineLayout>,
    module: &wgpu::ShaderModule,
    entry: &str,
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout,
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            zero_initialize_workgroup_memory: false,
        },
        cache: None,
    })
}

/// A buffer of `size` bytes for `usage`, not mapped. Call inside [`scoped`].
pub(crate) fn plain_buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage,
        mapped_at_creation: false,
    })
}
