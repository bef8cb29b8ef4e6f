//! Dispatch: a batch of rays uploaded in chunks within the device's limits, traced by the
//! pipeline of a query, and the hits and the shader's status word read back ([`GpuScene::run`]),
//! with the kernel's GPU time from timestamp queries where the adapter has them.

use glam::Vec3;
use smoothtri::{Hit, Ray};

use crate::device::scoped;
use crate::error::GpuError;
use crate::scene::GpuScene;
use crate::shader::{HIT_BYTES, RAY_BYTES, WORKGROUP};

/// Two resolved timestamp queries (begin and end of the compute pass), 8 bytes each.
const TIMESTAMP_BYTES: usize = 16;

impl GpuScene {
    /// Traces `rays` in chunks into `out` (`out[i] = map(hit of rays[i])`; `LengthMismatch`
    /// unless the lengths agree); adds the kernel's GPU time to `seconds` when asked and the
    /// device has timestamp queries.
    #[allow(clippy::too_many_arguments)] // one private worker behind the public entry points
    pub(crate) fn run<T>(
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
