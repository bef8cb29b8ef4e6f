//! Whole frames on the GPU: [`GpuScene::render_frame`] generates the camera rays, traces them,
//! shades each closest hit (the scene's [`Shading`](crate::Shading) normal, Lambert and ambient
//! light, one shadow ray) and writes the colours and primary hits into a [`GpuFrame`], in one
//! compute pass with no upload but the view and no readback but the frame's counters;
//! [`GpuSurface::present`] draws a frame into a window's swap chain. [`GpuFrame::read`] brings
//! the pixels back for screenshots.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use wgpu::util::DeviceExt;

use crate::device::{
    Gpu, bind_entry as entry, buffer_entry, pipeline_layout, plain_buffer, scoped, wgsl_module,
};
use crate::dispatch::{params_bytes, status_result, word};
use crate::error::GpuError;
use crate::scene::GpuScene;

/// Bytes of the shader's `View` uniform.
const VIEW_BYTES: usize = 96;
/// Bytes per pixel of the shader's `PixelOut`.
const PIXEL_BYTES: usize = 32;
/// Bytes of the frame's counters (`frame_stats`) and of the status word, read back together.
const STATS_BYTES: usize = 16;
/// The frame pass's workgroup: 8 × 8 pixels.
const TILE: u32 = 8;
/// A pixel's patch on a miss (the shader's `MISS`).
const MISS: u32 = u32::MAX;

/// The camera, light and look of a frame: the demo's pinhole camera (pixel `(x, y)`'s ray from
/// `eye` through `forward + right·sx + up·sy`, normalised, with `sx = (2(x + ½)/w − 1)·tan_half·
/// w/h` and `sy = (1 − 2(y + ½)/h)·tan_half`), a directional light, and the shading of
/// `host-demo`'s renderer (orange front faces, blue back faces, ambient 0.12 plus Lambert times
/// the shadow ray's visibility, gamma 2.2; the background's vertical gradient).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameView {
    /// The camera's position (world).
    pub eye: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit right vector of the image plane.
    pub right: Vec3,
    /// Unit up vector of the image plane.
    pub up: Vec3,
    /// Tangent of half the vertical field of view.
    pub tan_half: f32,
    /// Unit direction towards the light.
    pub light: Vec3,
    /// The shadow ray starts `eps` before the hit along the primary ray and ignores hits
    /// nearer than `eps` (scene units).
    pub eps: f32,
    /// `Some(s)`: the heat map of each hit's certified `t_error` instead of the shading,
    /// `log10(t_error·s)` from −9 (blue) to −3 (red), misses black; `s` is usually
    /// 1 / the scene's diagonal.
    pub heat: Option<f32>,
}

impl FrameView {
    /// The view of a pinhole camera given in `f64` (rounded to `f32`): the eye at `eye`, the unit
    /// basis `[forward, right, up]`, `tan_half` the tangent of half the vertical field of view;
    /// lit from the unit direction `light`, shadow rays offset by `eps` (scene units); shaded,
    /// without the heat map (set [`FrameView::heat`] for it).
    pub fn pinhole(
        eye: DVec3,
        [forward, right, up]: [DVec3; 3],
        tan_half: f64,
        light: DVec3,
        eps: f64,
    ) -> FrameView {
        FrameView {
            eye: eye.as_vec3(),
            forward: forward.as_vec3(),
            right: right.as_vec3(),
            up: up.as_vec3(),
            tan_half: tan_half as f32,
            light: light.as_vec3(),
            eps: eps as f32,
            heat: None,
        }
    }
}

/// What a frame cost and found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Rays traced: one per pixel plus the shadow rays of lit hits.
    pub rays: u64,
    /// The largest certified `t_error` of the frame's primary hits (0 without hits).
    pub max_t_error: f32,
    /// Wall-clock seconds from the submission of the frame pass to its completion (the pass
    /// and the counters' readback; without pipeline compilation).
    pub seconds: f64,
}

/// One pixel's primary hit, as [`GpuFrame::read`] returns it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FramePixel {
    /// The index of the hit patch in the scene's patches; `None` on a miss.
    pub patch: Option<u32>,
    /// The hit point (world).
    pub point: Vec3,
    /// The hit's certified bound on its `t` error (0 on a miss).
    pub t_error: f32,
}

/// A frame's storage on the GPU: `width × height` colours and primary hits, written by
/// [`GpuScene::render_frame`]. Create one per size and reuse it.
pub struct GpuFrame {
    gpu: Arc<Gpu>,
    width: u32,
    height: u32,
    view: wgpu::Buffer,
    image: wgpu::Buffer,
    pixels: wgpu::Buffer,
    stats: wgpu::Buffer,
    status: wgpu::Buffer,
    params: wgpu::Buffer,
    /// Bound to the batch entry point's ray and hit slots, which the frame pass does not use.
    unused: (wgpu::Buffer, wgpu::Buffer),
    readback: wgpu::Buffer,
    bind: wgpu::BindGroup,
}

impl std::fmt::Debug for GpuFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuFrame")
            .field("width", &self.width)
            .field("height", &self.height)
            .finish()
    }
}

impl GpuFrame {
    /// Allocates a `width × height` frame (36 bytes per pixel). Returns
    /// [`GpuError::TooLarge`] beyond the device's buffer limits or for a zero size.
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32) -> Result<GpuFrame, GpuError> {
        let pixels = u64::from(width) * u64::from(height);
        let limit = gpu.buffer_limit();
        let bytes = pixels * PIXEL_BYTES as u64;
        if pixels == 0 || bytes > limit {
            return Err(GpuError::TooLarge {
                what: "frame",
                bytes,
                limit,
            });
        }
        let device = &gpu.device;
        use wgpu::BufferUsages as U;
        let buf = |label, size, usage| plain_buffer(device, label, size, usage);
        scoped(device, GpuError::Device, || {
            let view = buf("view", VIEW_BYTES as u64, U::UNIFORM | U::COPY_DST);
            let image = buf("image", pixels * 4, U::STORAGE | U::COPY_SRC);
            let pix = buf("pixels", bytes, U::STORAGE | U::COPY_SRC);
            let stats = buf("frame stats", 16, U::STORAGE | U::COPY_SRC | U::COPY_DST);
            let status = buf("status", 16, U::STORAGE | U::COPY_SRC | U::COPY_DST);
            let params = buf("params", 16, U::UNIFORM | U::COPY_DST);
            let unused = (
                buf("rays (unused)", 64, U::STORAGE),
                buf("hits (unused)", 64, U::STORAGE),
            );
            let readback = buf(
                "frame readback",
                pixels * (4 + PIXEL_BYTES as u64) + STATS_BYTES as u64,
                U::MAP_READ | U::COPY_DST,
            );
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("smoothtri frame"),
                layout: &gpu.frame_layout,
                entries: &[
                    entry(0, &view),
                    entry(1, &image),
                    entry(2, &pix),
                    entry(3, &stats),
                ],
            });
            GpuFrame {
                gpu: Arc::clone(gpu),
                width,
                height,
                view,
                image,
                pixels: pix,
                stats,
                status,
                params,
                unused,
                readback,
                bind,
            }
        })
    }

    /// The frame's width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The frame's height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Reads the last rendered frame back: the colours (RGB, row-major, 3 bytes per pixel) and
    /// the primary hits.
    pub fn read(&self) -> Result<(Vec<u8>, Vec<FramePixel>), GpuError> {
        let gpu = &self.gpu;
        let n = u64::from(self.width) * u64::from(self.height);
        let data = scoped(&gpu.device, GpuError::Device, || {
            let mut enc = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("smoothtri frame readback"),
                });
            enc.copy_buffer_to_buffer(&self.image, 0, &self.readback, 0, n * 4);
            enc.copy_buffer_to_buffer(
                &self.pixels,
                0,
                &self.readback,
                n * 4,
                n * PIXEL_BYTES as u64,
            );
            gpu.submit_and_read(enc, &self.readback, 0..n * (4 + PIXEL_BYTES as u64))
        })??;
        let (colours, hits) = data.split_at(data.len().min(n as usize * 4));
        let rgb = colours
            .chunks_exact(4)
            .flat_map(|c| c.iter().take(3).copied())
            .collect();
        let pixels = hits
            .chunks_exact(PIXEL_BYTES)
            .map(|b| {
                let f = |k: usize| f32::from_bits(word(b, k));
                let patch = word(b, 3);
                FramePixel {
                    patch: (patch != MISS).then_some(patch),
                    point: Vec3::new(f(0), f(1), f(2)),
                    t_error: f(4),
                }
            })
            .collect();
        Ok((rgb, pixels))
    }
}

/// The shader's `View` uniform.
fn view_bytes(v: &FrameView, width: u32, height: u32) -> Vec<u8> {
    let f = |x: f32| x.to_ne_bytes();
    let mut b = Vec::with_capacity(VIEW_BYTES);
    let aspect = width as f32 / height.max(1) as f32;
    let heat = v.heat.filter(|s| *s > 0.0 && s.is_finite()).unwrap_or(0.0);
    for (vec, w) in [
        (v.eye, f(v.tan_half)),
        (v.forward, f(aspect)),
        (v.right, f(v.eps)),
        (v.up, f(heat)),
        (v.light, width.to_ne_bytes()),
    ] {
        for c in vec.to_array() {
            b.extend_from_slice(&f(c));
        }
        b.extend_from_slice(&w);
    }
    b.extend_from_slice(&height.to_ne_bytes());
    b.resize(VIEW_BYTES, 0);
    b
}

impl GpuScene {
    /// Renders one frame of this scene into `frame` with `iterations` refinement steps per
    /// patch test: per pixel the camera ray of `view`, its closest hit, the scene's shading
    /// normal ([`GpuScene::shading`]), Lambert and ambient light and a shadow ray ([`FrameView`]),
    /// all on the GPU in one compute pass; the colours and primary hits stay in `frame`
    /// ([`GpuSurface::present`], [`GpuFrame::read`]). Waits for the pass and returns its counters.
    ///
    /// The hits are the kernel's (the batch queries' arithmetic, the same bounded work); the
    /// colours are the demo renderer's, in `f32`.
    pub fn render_frame(
        &self,
        iterations: usize,
        view: &FrameView,
        frame: &mut GpuFrame,
    ) -> Result<FrameStats, GpuError> {
        let gpu = &self.gpu;
        if !Arc::ptr_eq(gpu, &frame.gpu) {
            return Err(GpuError::Device(
                "the frame belongs to another GPU device".into(),
            ));
        }
        let pipeline = gpu.pipeline(self.key(iterations, false, true))?;
        let device = &gpu.device;
        let params = params_bytes(0, self.counts);
        let start = std::time::Instant::now();
        let data = scoped(device, GpuError::Device, || {
            let bind = self.tracer(&pipeline).group([
                &frame.params,
                &frame.unused.0,
                &frame.unused.1,
                &frame.status,
            ]);
            gpu.queue.write_buffer(&frame.params, 0, &params);
            gpu.queue
                .write_buffer(&frame.view, 0, &view_bytes(view, frame.width, frame.height));
            gpu.queue.write_buffer(&frame.stats, 0, &[0u8; 16]);
            gpu.queue.write_buffer(&frame.status, 0, &[0u8; 16]);
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("smoothtri frame"),
            });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("smoothtri frame"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.set_bind_group(1, &frame.bind, &[]);
                pass.dispatch_workgroups(
                    frame.width.div_ceil(TILE),
                    frame.height.div_ceil(TILE),
                    1,
                );
            }
            enc.copy_buffer_to_buffer(&frame.stats, 0, &frame.readback, 0, 8);
            enc.copy_buffer_to_buffer(&frame.status, 0, &frame.readback, 8, 4);
            gpu.submit_and_read(enc, &frame.readback, 0..STATS_BYTES as u64)
        })??;
        let seconds = start.elapsed().as_secs_f64();
        let word = |k: usize| word(&data, k);
        status_result(word(2))?;
        Ok(FrameStats {
            rays: u64::from(frame.width) * u64::from(frame.height) + u64::from(word(0)),
            max_t_error: f32::from_bits(word(1)),
            seconds,
        })
    }
}

/// A window's swap chain on the device of a [`Gpu`]: [`GpuSurface::present`] draws a
/// [`GpuFrame`] into it, scaled to the window (nearest pixel), without a readback.
pub struct GpuSurface {
    gpu: Arc<Gpu>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    /// The surface's format encodes sRGB: the shader decodes the frame's (already encoded)
    /// colours so the window shows the same bytes.
    srgb: bool,
}

impl std::fmt::Debug for GpuSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuSurface")
            .field("format", &self.config.format)
            .field("width", &self.config.width)
            .field("height", &self.config.height)
            .finish()
    }
}

/// The presentation shader: a full-screen triangle sampling the frame's colours.
const PRESENT_SHADER: &str = include_str!("present.wgsl");

impl GpuSurface {
    /// A swap chain for `window` (anything with window and display handles, e.g.
    /// `Arc<winit::window::Window>`) of `width × height` pixels. Returns [`GpuError::Surface`]
    /// when the device cannot present to it.
    pub fn new(
        gpu: &Arc<Gpu>,
        window: impl Into<wgpu::SurfaceTarget<'static>>,
        width: u32,
        height: u32,
    ) -> Result<GpuSurface, GpuError> {
        let surface = gpu
            .instance
            .create_surface(window)
            .map_err(|e| GpuError::Surface(e.to_string()))?;
        if !gpu.adapter.is_surface_supported(&surface) {
            return Err(GpuError::Surface(format!(
                "{} cannot present to this window",
                gpu.adapter_name()
            )));
        }
        let config = surface_config(&surface.get_capabilities(&gpu.adapter), width, height)?;
        let srgb = config.format.is_srgb();
        let device = &gpu.device;
        let (pipeline, layout, uniform) = scoped(device, GpuError::Shader, || {
            present_pipeline(device, config.format)
        })?;
        let mut s = GpuSurface {
            gpu: Arc::clone(gpu),
            surface,
            config,
            pipeline,
            layout,
            uniform,
            srgb,
        };
        s.configure()?;
        Ok(s)
    }

    /// Configures the swap chain as `config` says (on creation, after a resize, and when the
    /// window reports it outdated).
    fn configure(&mut self) -> Result<(), GpuError> {
        scoped(&self.gpu.device, GpuError::Surface, || {
            self.surface.configure(&self.gpu.device, &self.config);
        })
    }

    /// Resizes the swap chain to the window's new size (a zero side is kept at 1: a minimised
    /// window).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), GpuError> {
        let (w, h) = (width.max(1), height.max(1));
        if (w, h) == (self.config.width, self.config.height) {
            return Ok(());
        }
        self.config.width = w;
        self.config.height = h;
        self.configure()
    }

    /// Draws `frame` into the window, scaled to the swap chain's size (nearest pixel), and
    /// presents it. A frame the window cannot take now (occluded, timed out, outdated) is
    /// skipped, the swap chain reconfigured where needed.
    pub fn present(&mut self, frame: &GpuFrame) -> Result<(), GpuError> {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => t,
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => {
                drop(t);
                return self.configure();
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                return self.configure();
            }
            other => {
                return Err(GpuError::Surface(format!(
                    "the swap chain gave no image ({other:?})"
                )));
            }
        };
        let gpu = &self.gpu;
        let device = &gpu.device;
        scoped(device, GpuError::Surface, || {
            let words = [
                frame.width,
                frame.height,
                self.config.width,
                self.config.height,
                u32::from(self.srgb),
                0,
                0,
                0,
            ];
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_ne_bytes()).collect();
            gpu.queue.write_buffer(&self.uniform, 0, &bytes);
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("smoothtri present"),
                layout: &self.layout,
                entries: &[entry(0, &self.uniform), entry(1, &frame.image)],
            });
            let view = texture
                .texture
                .create_view(&wgpu::TextureViewDescriptor::default());
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("smoothtri present"),
            });
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("smoothtri present"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.draw(0..3, 0..1);
            }
            gpu.queue.submit([enc.finish()]);
            gpu.queue.present(texture);
        })
    }
}

/// The swap chain's configuration for a window of `caps` and `width × height` pixels (a zero
/// side kept at 1): an 8-bit RGBA or BGRA format where the window offers one (else its first),
/// no vertical sync. [`GpuError::Surface`] when the window offers no format.
fn surface_config(
    caps: &wgpu::SurfaceCapabilities,
    width: u32,
    height: u32,
) -> Result<wgpu::SurfaceConfiguration, GpuError> {
    use wgpu::TextureFormat as T;
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| matches!(f, T::Bgra8Unorm | T::Rgba8Unorm))
        .or_else(|| caps.formats.first().copied())
        .ok_or_else(|| GpuError::Surface("the window offers no format".into()))?;
    let alpha_mode = caps
        .alpha_modes
        .first()
        .copied()
        .unwrap_or(wgpu::CompositeAlphaMode::Auto);
    Ok(wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: width.max(1),
        height: height.max(1),
        present_mode: wgpu::PresentMode::AutoNoVsync,
        desired_maximum_frame_latency: 2,
        alpha_mode,
        view_formats: vec![],
        color_space: Default::default(),
    })
}

/// The presentation pipeline for swap chain images of `format`, its group's layout (the
/// sizes' uniform and the frame's colours) and the uniform. Call inside [`scoped`].
fn present_pipeline(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout, wgpu::Buffer) {
    let module = wgsl_module(device, "smoothtri present", PRESENT_SHADER);
    let stage = wgpu::ShaderStages::FRAGMENT;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("smoothtri present"),
        entries: &[
            buffer_entry(0, stage, wgpu::BufferBindingType::Uniform),
            buffer_entry(
                1,
                stage,
                wgpu::BufferBindingType::Storage { read_only: true },
            ),
        ],
    });
    let pl = pipeline_layout(device, "smoothtri present", &[&layout]);
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("smoothtri present"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        multiview_mask: None,
        cache: None,
    });
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("smoothtri present"),
        contents: &[0u8; 32],
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    (pipeline, layout, uniform)
}
