//! The scene builder's patch step on the device ([`GpuPatchBuild`], `build.wgsl`): one compute
//! invocation per triangle builds its patch record from vertex buffers that live on the GPU,
//! so a deforming mesh's patches are re-made without a round trip through the host.

use std::sync::{Arc, LazyLock};

use smoothtri::{LineField, NORMAL_CLAMP_DEG};
use wgpu::util::DeviceExt;

use crate::device::{Gpu, bind_entry, scoped};
use crate::error::GpuError;
use crate::shader::{PATCH_VEC4, SHADER, WORKGROUP};

/// The builder's shader: the kernel's (whose height evaluation samples the shell) with its
/// patch records writable, then `build.wgsl`.
pub(crate) static BUILD_SHADER: LazyLock<String> = LazyLock::new(|| {
    let kernel = SHADER.replace(
        "var<storage, read> patches:",
        "var<storage, read_write> patches:",
    );
    format!("{kernel}\n{}", include_str!("build.wgsl"))
});

/// Bytes of the build pass's uniform (`BuildParams` in `build.wgsl`).
const PARAMS_BYTES: usize = 16 + 16 * NORMAL_CLAMP_DEG.len();

/// A mesh's patch construction on the GPU: its triangles, its vertex buffers (positions and
/// normals, three `f32` each, written by the caller or by [`GpuPatchBuild::write_vertices`])
/// and the patch records the pass writes, in the layout the kernel reads
/// ([`smooth_record`](crate::smooth_record)).
///
/// Each [`GpuPatchBuild::run`] builds every triangle's patch as the CPU's
/// `Patch::new_or_tilted_with` on the [`LineField::Face`] field does, in `f32` with the same
/// operations (within rounding: the shell's heights come from the kernel's height evaluation,
/// which matches the CPU's to rounding, `tests/parity.rs`), including the per-patch remedy
/// (the clamps of [`NORMAL_CLAMP_DEG`]) and the placeholder record (an empty box, no surface)
/// of a triangle the CPU rejects, with the CPU's `remedy` byte per triangle. Reaches are 0:
/// crack closure is not part of this pass.
pub struct GpuPatchBuild {
    gpu: Arc<Gpu>,
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    patches: wgpu::Buffer,
    remedy: wgpu::Buffer,
    slots: u32,
    vertices: u32,
}

impl std::fmt::Debug for GpuPatchBuild {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuPatchBuild")
            .field("triangles", &self.slots)
            .field("vertices", &self.vertices)
            .finish()
    }
}

impl GpuPatchBuild {
    /// The build of `triangles` (vertex indices) over `vertex_count` vertices, on the
    /// [`LineField::Face`] field, with the vertex buffers zeroed.
    ///
    /// Returns [`GpuError::Unsupported`] for [`LineField::Vertex`] (its per-vertex remedy
    /// runs in triangle order on the CPU), [`GpuError::TooLarge`] beyond the device's buffer
    /// or dispatch limits, and [`GpuError::Shader`] / [`GpuError::Device`] for device errors.
    /// Indices out of range are not an error here: their triangles get the placeholder
    /// record, as on the CPU.
    ///
    /// # Panics
    /// Never.
    pub fn new(
        gpu: &Arc<Gpu>,
        vertex_count: usize,
        triangles: &[[u32; 3]],
        field: LineField,
    ) -> Result<GpuPatchBuild, GpuError> {
        if field != LineField::Face {
            return Err(GpuError::Unsupported(
                "the device builds patches on LineField::Face only",
            ));
        }
        let too_large = |what: &'static str, bytes: usize| GpuError::TooLarge {
            what,
            bytes: bytes as u64,
            limit: gpu.buffer_limit(),
        };
        let slots = u32::try_from(triangles.len()).map_err(|_| too_large("triangle", 0))?;
        let vertices = u32::try_from(vertex_count).map_err(|_| too_large("vertex", 0))?;
        let groups = triangles.len().div_ceil(WORKGROUP as usize);
        if groups > gpu.limits.max_compute_workgroups_per_dimension as usize {
            return Err(too_large("triangle", triangles.len() * 12));
        }
        let tri_bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_ne_bytes())
            .collect();
        let mut params = Vec::with_capacity(PARAMS_BYTES);
        for w in [slots, 0, vertices, 0] {
            params.extend_from_slice(&w.to_ne_bytes());
        }
        for deg in NORMAL_CLAMP_DEG {
            // As the CPU: sine and cosine in f64, rounded once.
            let (s, c) = deg.to_radians().sin_cos();
            for x in [c as f32, s as f32, 0.0, 0.0] {
                params.extend_from_slice(&x.to_ne_bytes());
            }
        }
        let module_source = BUILD_SHADER.as_str();
        let device = &gpu.device;
        let (pipeline, bind, positions, normals, patches, remedy) =
            scoped(device, GpuError::Shader, || {
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("smoothtri build"),
                    source: wgpu::ShaderSource::Wgsl(module_source.into()),
                });
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("smoothtri build_patches"),
                    layout: None,
                    module: &module,
                    entry_point: Some("build_patches"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &[("TILTED", 1.0)],
                        zero_initialize_workgroup_memory: false,
                    },
                    cache: None,
                });
                use wgpu::BufferUsages as U;
                let zeroed = |what: &'static str, bytes: usize, usage: U| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(what),
                        size: bytes.max(16) as u64,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let v_bytes = 12 * vertex_count;
                let positions = zeroed("positions", v_bytes, U::STORAGE | U::COPY_DST);
                let normals = zeroed("normals", v_bytes, U::STORAGE | U::COPY_DST);
                let patches = zeroed(
                    "patch",
                    16 * PATCH_VEC4 * triangles.len(),
                    U::STORAGE | U::COPY_SRC | U::COPY_DST,
                );
                let remedy = zeroed("remedy", 4 * triangles.len(), U::STORAGE | U::COPY_SRC);
                let tris = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("triangles"),
                    contents: if tri_bytes.is_empty() { &[0; 16] } else { &tri_bytes },
                    usage: U::STORAGE,
                });
                let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("build params"),
                    contents: &params,
                    usage: U::UNIFORM,
                });
                let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("smoothtri build"),
                    layout: &pipeline.get_bind_group_layout(0),
                    entries: &[
                        bind_entry(1, &patches),
                        bind_entry(8, &uniform),
                        bind_entry(9, &positions),
                        bind_entry(10, &normals),
                        bind_entry(11, &tris),
                        bind_entry(12, &remedy),
                    ],
                });
                (pipeline, bind, positions, normals, patches, remedy)
            })?;
        for (what, bytes) in [
            ("positions", 12 * vertex_count),
            ("patch", 16 * PATCH_VEC4 * triangles.len()),
        ] {
            if bytes as u64 > gpu.buffer_limit() {
                return Err(too_large(what, bytes));
            }
        }
        Ok(GpuPatchBuild {
            gpu: Arc::clone(gpu),
            pipeline,
            bind,
            positions,
            normals,
            patches,
            remedy,
            slots,
            vertices,
        })
    }

    /// The vertex positions on the device: three `f32` per vertex, `x y z`, vertex after
    /// vertex. A caller's own pass (skinning, morphing) may write it directly.
    pub fn positions(&self) -> &wgpu::Buffer {
        &self.positions
    }

    /// The vertex normals on the device, laid out as [`GpuPatchBuild::positions`] (any
    /// positive length: the pass normalises them).
    pub fn normals(&self) -> &wgpu::Buffer {
        &self.normals
    }

    /// The patch records the pass writes: [`PATCH_VEC4`] `vec4<f32>` per triangle.
    pub fn patches(&self) -> &wgpu::Buffer {
        &self.patches
    }

    /// Writes the vertices from the host (`positions` and `normals`: three `f32` per
    /// vertex). Returns [`GpuError::VertexCount`] when a length is not three per vertex.
    ///
    /// # Panics
    /// Never.
    pub fn write_vertices(&self, positions: &[f32], normals: &[f32]) -> Result<(), GpuError> {
        let want = 3 * self.vertices as usize;
        for given in [positions.len(), normals.len()] {
            if given != want {
                return Err(GpuError::VertexCount {
                    expected: want,
                    given,
                });
            }
        }
        if want == 0 {
            return Ok(());
        }
        let bytes = |v: &[f32]| v.iter().flat_map(|x| x.to_ne_bytes()).collect::<Vec<u8>>();
        self.gpu
            .queue
            .write_buffer(&self.positions, 0, &bytes(positions));
        self.gpu.queue.write_buffer(&self.normals, 0, &bytes(normals));
        Ok(())
    }

    /// Records the pass into `enc` (one dispatch over the triangles).
    pub fn encode(&self, enc: &mut wgpu::CommandEncoder) {
        if self.slots == 0 {
            return;
        }
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("smoothtri build_patches"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.dispatch_workgroups(self.slots.div_ceil(WORKGROUP), 1, 1);
    }

    /// Builds the patches from the vertex buffers' current contents and waits for the device.
    ///
    /// # Panics
    /// Never.
    pub fn run(&self) -> Result<(), GpuError> {
        self.read(false).map(|_| ())
    }

    /// Runs the pass and reads back the records ([`PATCH_VEC4`] `vec4<f32>` per triangle, as
    /// `f32`) and the `remedy` byte of each triangle (the CPU's `Patch::remedy`: 0, the clamp
    /// index + 1, or `0x80 |` the rejection's code). For tests and tools: a frame's update
    /// reads nothing back.
    ///
    /// # Panics
    /// Never.
    pub fn run_and_read(&self) -> Result<(Vec<f32>, Vec<u32>), GpuError> {
        self.read(true)
            .map(|o| o.unwrap_or_default())
    }

    fn read(&self, back: bool) -> Result<Option<(Vec<f32>, Vec<u32>)>, GpuError> {
        let gpu = &self.gpu;
        let device = &gpu.device;
        let n = self.slots as u64;
        let (p_bytes, r_bytes) = (16 * PATCH_VEC4 as u64 * n, 4 * n);
        scoped(device, GpuError::Device, || {
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("smoothtri build"),
            });
            self.encode(&mut enc);
            if !back || n == 0 {
                gpu.queue.submit([enc.finish()]);
                let _ = device.poll(wgpu::PollType::wait_indefinitely());
                return Ok(None);
            }
            let read_buf = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("build readback"),
                size: p_bytes + r_bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.copy_buffer_to_buffer(&self.patches, 0, &read_buf, 0, p_bytes);
            enc.copy_buffer_to_buffer(&self.remedy, 0, &read_buf, p_bytes, r_bytes);
            let bytes = gpu.submit_and_read(enc, &read_buf, 0..p_bytes + r_bytes)?;
            let words: Vec<[u8; 4]> = bytes
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect();
            let split = (p_bytes / 4) as usize;
            let (p, r) = words.split_at(split.min(words.len()));
            Ok(Some((
                p.iter().map(|w| f32::from_ne_bytes(*w)).collect(),
                r.iter().map(|w| u32::from_ne_bytes(*w)).collect(),
            )))
        })?
    }
}
