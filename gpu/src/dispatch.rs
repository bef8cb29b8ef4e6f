//! Dispatch: a batch of rays uploaded in chunks within the device's limits, traced by a
//! pipeline of the kernel's group 0 ([`Tracer`]: the smooth kernel's, [`GpuScene::run`], or the
//! flat triangles' own, [`FlatScene`](crate::FlatScene)), and the hits and the shader's status
//! word read back, with the kernel's GPU time from timestamp queries where the adapter has them.

use glam::Vec3;
use smoothtri::{Hit, Ray};

use crate::device::{Gpu, bind_entry, plain_buffer, scoped};
use crate::error::GpuError;
use crate::scene::GpuScene;
use crate::shader::{HIT_BYTES, RAY_BYTES, WORKGROUP};

/// Two resolved timestamp queries (begin and end of the compute pass), 8 bytes each.
const TIMESTAMP_BYTES: usize = 16;

/// Bytes of the status word's buffer (one `u32`, padded).
const STATUS_BYTES: usize = 16;

/// A batch of rays and the interval of `t` they are traced in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Batch<'a> {
    pub(crate) rays: &'a [Ray<f32>],
    pub(crate) t_min: f32,
    pub(crate) t_max: f32,
}

impl<'a> Batch<'a> {
    /// `rays` traced in `[t_min, t_max]`.
    pub(crate) fn new(rays: &'a [Ray<f32>], t_min: f32, t_max: f32) -> Self {
        Batch { rays, t_min, t_max }
    }

    /// [`GpuError::LengthMismatch`] unless `out` has one slot per ray.
    pub(crate) fn check<T>(&self, out: &[T]) -> Result<(), GpuError> {
        if self.rays.len() == out.len() {
            return Ok(());
        }
        Err(GpuError::LengthMismatch {
            rays: self.rays.len(),
            out: out.len(),
        })
    }

    /// The rays of `part` as the shader reads them ([`upload_ray`]).
    fn bytes(&self, part: &[Ray<f32>]) -> Vec<u8> {
        part.iter()
            .flat_map(|r| upload_ray(r, self.t_min, self.t_max))
            .flat_map(f32::to_ne_bytes)
            .collect()
    }
}

/// A pipeline that traces batches with the kernel's group 0
/// ([`TRACE_BINDINGS`](crate::device::TRACE_BINDINGS)), and the scene it traces: the smooth
/// kernel's ([`GpuScene::tracer`]) or the flat triangles' own ([`FlatScene`](crate::FlatScene)).
/// It traces a batch with one dispatch per chunk of rays ([`Tracer::trace`]).
pub(crate) struct Tracer<'a> {
    pub(crate) gpu: &'a Gpu,
    /// The label of its bind groups, passes and their encoders.
    pub(crate) label: &'static str,
    pub(crate) pipeline: &'a wgpu::ComputePipeline,
    /// The layout of its group 0.
    pub(crate) layout: &'a wgpu::BindGroupLayout,
    /// The scene's records, nodes and order (bindings 1 to 3), and its shading data (binding 7)
    /// where the layout has one.
    pub(crate) scene: [&'a wgpu::Buffer; 3],
    pub(crate) shading: Option<&'a wgpu::Buffer>,
    /// The scene's node, order and record counts ([`params_bytes`]).
    pub(crate) counts: [u32; 3],
    /// Bytes per hit the pipeline writes.
    pub(crate) hit_bytes: usize,
}

/// The buffers of a traced batch, one chunk of rays at a time, and the timestamp queries of a
/// timed one.
struct ChunkBuffers {
    rays: wgpu::Buffer,
    hits: wgpu::Buffer,
    status: wgpu::Buffer,
    params: wgpu::Buffer,
    /// The hits, then the status word, then the timestamps, copied out together.
    readback: wgpu::Buffer,
    /// The query set and the buffer it resolves into.
    timing: Option<(wgpu::QuerySet, wgpu::Buffer)>,
}

/// The shader's `Params` uniform for a pass over `rays` rays (0 for a frame) of a scene of
/// `counts` nodes, order entries and records.
pub(crate) fn params_bytes(rays: u32, counts: [u32; 3]) -> Vec<u8> {
    let [nodes, order, records] = counts;
    [rays, nodes, order, records]
        .iter()
        .flat_map(|x| x.to_ne_bytes())
        .collect()
}

impl Tracer<'_> {
    /// Group 0 over the scene and a pass's own buffers: the parameters, the rays, the hits and
    /// the status word (bindings 0, 4, 5 and 6; the frame pass binds unused ones for `rays` and
    /// `hits`). Call inside [`scoped`].
    pub(crate) fn group(
        &self,
        [params, rays, hits, status]: [&wgpu::Buffer; 4],
    ) -> wgpu::BindGroup {
        let [records, nodes, order] = self.scene;
        let buffers = [params, records, nodes, order, rays, hits, status];
        let entries: Vec<_> = (0..)
            .zip(buffers.into_iter().chain(self.shading))
            .map(|(k, b)| bind_entry(k, b))
            .collect();
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(self.label),
                layout: self.layout,
                entries: &entries,
            })
    }

    /// Traces `batch` in chunks into `out` (`out[i] = map(rays[i]'s hit as the pipeline wrote
    /// it)`, as long as the batch: [`Batch::check`]); adds the kernel's GPU time to `seconds`
    /// when asked and the device has timestamp queries. Returns the chunks' status words or-ed,
    /// for the caller to read (the bits are its pipeline's).
    pub(crate) fn trace<T>(
        &self,
        batch: Batch<'_>,
        mut seconds: Option<&mut f64>,
        out: &mut [T],
        map: impl Fn(&[u8]) -> T,
    ) -> Result<u32, GpuError> {
        if batch.rays.is_empty() {
            return Ok(0);
        }
        let chunk = self.gpu.chunk().min(batch.rays.len());
        let buffers = self.buffers(chunk, seconds.is_some())?;
        let bind = scoped(&self.gpu.device, GpuError::Device, || {
            self.group([
                &buffers.params,
                &buffers.rays,
                &buffers.hits,
                &buffers.status,
            ])
        })?;
        let mut status = 0u32;
        for (c, part) in batch.rays.chunks(chunk).enumerate() {
            let n = part.len();
            let data = self.dispatch(&buffers, &bind, n, &batch.bytes(part))?;
            let hit_bytes = n * self.hit_bytes;
            let Some((hits, tail)) = data
                .split_at_checked(hit_bytes)
                .filter(|(_, t)| t.len() >= 4)
            else {
                return Err(GpuError::Device("short readback".into()));
            };
            status |= word(tail, 0);
            if let (Some(total), Some(_)) = (seconds.as_deref_mut(), &buffers.timing) {
                *total += self.elapsed(tail);
            }
            for (k, h) in hits.chunks_exact(self.hit_bytes).enumerate() {
                if let Some(slot) = out.get_mut(c * chunk + k) {
                    *slot = map(h);
                }
            }
        }
        Ok(status)
    }

    /// The buffers for chunks of `chunk` rays, with timestamp queries when `timed` and the
    /// device has them.
    fn buffers(&self, chunk: usize, timed: bool) -> Result<ChunkBuffers, GpuError> {
        let device = &self.gpu.device;
        let buf = |label, size: usize, usage| plain_buffer(device, label, size as u64, usage);
        use wgpu::BufferUsages as U;
        scoped(device, GpuError::Device, || {
            let timing = (timed && self.gpu.timestamps).then(|| {
                let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("kernel time"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                });
                let resolve = buf(
                    "timestamps",
                    TIMESTAMP_BYTES,
                    U::QUERY_RESOLVE | U::COPY_SRC,
                );
                (set, resolve)
            });
            let hits = chunk * self.hit_bytes;
            ChunkBuffers {
                rays: buf("rays", chunk * RAY_BYTES, U::STORAGE | U::COPY_DST),
                hits: buf("hits", hits, U::STORAGE | U::COPY_SRC),
                status: buf(
                    "status",
                    STATUS_BYTES,
                    U::STORAGE | U::COPY_SRC | U::COPY_DST,
                ),
                params: buf("params", 16, U::UNIFORM | U::COPY_DST),
                readback: buf(
                    "readback",
                    hits + STATUS_BYTES + TIMESTAMP_BYTES,
                    U::MAP_READ | U::COPY_DST,
                ),
                timing,
            }
        })
    }

    /// Traces one chunk of `n` rays (`rays`, as the shader reads them) and reads back its hits,
    /// its status word and, when timed, its timestamps.
    fn dispatch(
        &self,
        b: &ChunkBuffers,
        bind: &wgpu::BindGroup,
        n: usize,
        rays: &[u8],
    ) -> Result<Vec<u8>, GpuError> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        scoped(device, GpuError::Device, || {
            queue.write_buffer(&b.rays, 0, rays);
            queue.write_buffer(&b.params, 0, &params_bytes(n as u32, self.counts));
            queue.write_buffer(&b.status, 0, &[0u8; STATUS_BYTES]);
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some(self.label),
            });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(self.label),
                    timestamp_writes: b.timing.as_ref().map(|(set, _)| {
                        wgpu::ComputePassTimestampWrites {
                            query_set: set,
                            beginning_of_pass_write_index: Some(0),
                            end_of_pass_write_index: Some(1),
                        }
                    }),
                });
                pass.set_pipeline(self.pipeline);
                pass.set_bind_group(0, bind, &[]);
                pass.dispatch_workgroups((n as u32).div_ceil(WORKGROUP), 1, 1);
            }
            let hit_bytes = (n * self.hit_bytes) as u64;
            let status = STATUS_BYTES as u64;
            enc.copy_buffer_to_buffer(&b.hits, 0, &b.readback, 0, hit_bytes);
            enc.copy_buffer_to_buffer(&b.status, 0, &b.readback, hit_bytes, status);
            let mut range = 0..hit_bytes + status;
            if let Some((set, resolve)) = &b.timing {
                let bytes = TIMESTAMP_BYTES as u64;
                enc.resolve_query_set(set, 0..2, resolve, 0);
                enc.copy_buffer_to_buffer(resolve, 0, &b.readback, range.end, bytes);
                range.end += bytes;
            }
            self.gpu.submit_and_read(enc, &b.readback, range)
        })?
    }

    /// The seconds between a chunk's two timestamps, read back after its status word (`tail`:
    /// the readback from the status word on); 0 where they are missing.
    fn elapsed(&self, tail: &[u8]) -> f64 {
        let tick = |k: usize| {
            let at = STATUS_BYTES + 8 * k;
            tail.get(at..at + 8).map(|b| {
                let mut t = [0u8; 8];
                t.copy_from_slice(b);
                u64::from_ne_bytes(t)
            })
        };
        match (tick(0), tick(1)) {
            (Some(begin), Some(end)) => {
                let period = f64::from(self.gpu.queue.get_timestamp_period());
                end.saturating_sub(begin) as f64 * period * 1e-9
            }
            _ => 0.0,
        }
    }
}

impl GpuScene {
    /// The smooth kernel's [`Tracer`] over this scene with `pipeline` (compiled for one of the
    /// scene's keys, [`GpuScene::key`]).
    pub(crate) fn tracer<'a>(&'a self, pipeline: &'a wgpu::ComputePipeline) -> Tracer<'a> {
        Tracer {
            gpu: &self.gpu,
            label: "smoothtri",
            pipeline,
            layout: &self.gpu.layout,
            scene: [&self.patches, &self.nodes, &self.order],
            shading: Some(&self.shade_in),
            counts: self.counts,
            hit_bytes: HIT_BYTES,
        }
    }

    /// Traces `batch` with `iterations` refinement steps (any hits where `any`) into `out`
    /// (`out[i] = map(hit of rays[i])`; `LengthMismatch` unless the lengths agree); adds the
    /// kernel's GPU time to `seconds` when asked and the device has timestamp queries.
    pub(crate) fn run<T>(
        &self,
        iterations: usize,
        any: bool,
        batch: Batch<'_>,
        seconds: Option<&mut f64>,
        out: &mut [T],
        map: impl Fn(&Raw) -> T,
    ) -> Result<(), GpuError> {
        batch.check(out)?;
        let pipeline = self.gpu.pipeline(self.key(iterations, any, false))?;
        let tracer = self.tracer(&pipeline);
        status_result(tracer.trace(batch, seconds, out, |h| map(&parse_hit(h)))?)
    }
}

/// The 8 floats of one ray as the shader reads them: `origin, t_min, dir, t_max`. Rays the CPU
/// rejects are marked with `t_min > t_max` (and zeroed); infinite bounds become ±`f32::MAX`
/// (the same intervals: every box is finite).
pub(crate) fn upload_ray(r: &Ray<f32>, t_min: f32, t_max: f32) -> [f32; 8] {
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

/// One traced ray as the shader wrote it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Raw {
    pub(crate) t: f32,
    pub(crate) t_error: f32,
    pub(crate) w1: f32,
    pub(crate) w2: f32,
    pub(crate) point: [f32; 3],
    pub(crate) patch: u32,
    pub(crate) normal: [f32; 3],
    pub(crate) flags: u32,
    pub(crate) shading: [f32; 3],
}

impl Raw {
    /// The hit of a closest-hit query, `None` on a miss.
    pub(crate) fn hit(&self) -> Option<Hit<f32>> {
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
pub(crate) fn status_result(status: u32) -> Result<(), GpuError> {
    if status & 1 != 0 {
        return Err(GpuError::CorruptTree);
    }
    if status & 2 != 0 {
        return Err(GpuError::StackOverflow);
    }
    Ok(())
}

/// The `k`-th 32-bit word of bytes read back (0 past the end).
pub(crate) fn word(b: &[u8], k: usize) -> u32 {
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
