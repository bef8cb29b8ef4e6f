//! Rendering and presenting one frame: the camera of the settings, the CPU's render (or the
//! GPU's, [`super::gpu`]), the window's title, and the frame into the window (softbuffer for the
//! CPU's frames, the swap chain for the GPU's); reduced while the camera moves.

use std::num::NonZeroU32;
use std::sync::Arc;

use smoothtri_host::Camera;
use winit::dpi::PhysicalSize;
use winit::window::Window;

use super::Viewer;
use super::heat::heat_map;
use super::input::REST;
use crate::error::{DemoError, Result};
use crate::gpu::gpu_error;
use crate::image::Image;
use crate::renderer::{PixelHit, Rendered};
use crate::tracer::{Mode, Prec, Precision, tracer};

/// Frames render at `1 / MOVING_SCALE` of the resolution while the camera moves.
const MOVING_SCALE: u32 = 3;

/// One rendered frame and what the title shows of it.
pub(super) struct Frame {
    /// The CPU's image and hits; `None` for a GPU frame, which stays on the GPU
    /// ([`super::gpu::GpuView::frame`]) until a screenshot reads it back.
    pub(super) pixels: Option<(Image, Vec<PixelHit>)>,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) rays: u64,
    pub(super) seconds: f64,
    pub(super) max_t_error: f64,
}

/// How frames reach the window.
pub(super) enum Presenter {
    /// The CPU's frames, copied into the window's buffer.
    Soft(softbuffer::Surface<Arc<Window>, Arc<Window>>),
    /// The GPU's frames, drawn into its swap chain.
    Gpu,
}

impl Viewer {
    /// The camera of the current settings for a `w`×`h` frame: `render`'s camera at zoom 1.
    fn camera(&self, w: u32, h: u32) -> Camera {
        let s = &self.settings;
        if s.zoom == 1.0 && self.playing.is_none() {
            return Camera::for_mesh(&self.mesh, s.az, s.el, w, h);
        }
        let (c, r) = self.sphere;
        Camera::look_at_sphere(c, r * s.zoom, s.az, s.el, w, h)
    }

    /// Renders one `w`×`h` frame with the current settings.
    fn render(&mut self, w: u32, h: u32) -> Result<Frame> {
        let cam = self.camera(w, h);
        let s = self.settings;
        let seams = s.seams();
        if self.gpu.is_some() {
            return self.render_gpu(&cam, w, h, seams);
        }
        let r: Rendered = match s.precision {
            Precision::F32 => self.render_cpu::<f32>(&cam, seams)?,
            Precision::F64 => self.render_cpu::<f64>(&cam, seams)?,
        };
        let max_t_error = r.hits.iter().map(|p| p.t_error).fold(0.0, f64::max);
        let image = if s.heat {
            heat_map(&r, self.diag)
        } else {
            r.image
        };
        Ok(Frame {
            width: image.width,
            height: image.height,
            pixels: Some((image, r.hits)),
            rays: r.rays,
            seconds: r.seconds,
            max_t_error,
        })
    }

    /// Renders through `cam` on the CPU in precision `F` (the scene with seams when `seams`).
    fn render_cpu<F: Prec>(&mut self, cam: &Camera, seams: bool) -> Result<Rendered> {
        let scene = self
            .scenes
            .get::<F>(&self.mesh, self.options.field, seams)?;
        let t = tracer::<F>(self.settings.mode, self.settings.n)?;
        Ok(crate::renderer::render(&scene, cam, t, self.diag, false))
    }

    /// The window's title for `frame`.
    pub(super) fn title(&self, frame: &Frame, reduced: bool) -> String {
        let s = &self.settings;
        let n = if s.mode == Mode::Smooth {
            format!(" N={}", s.n)
        } else {
            String::new()
        };
        let normals = if s.mode == Mode::Smooth {
            format!(" {}", s.normals.name())
        } else {
            String::new()
        };
        let device = if self.gpu.is_some() { "GPU" } else { "CPU" };
        let time = match &self.playing {
            Some(p) if p.paused.is_some() => format!(" t={:.2} s (paused)", p.shown),
            Some(p) => format!(" t={:.2} s", p.shown),
            None => String::new(),
        };
        format!(
            "smoothtri view — {}{n} {}{normals}{} ({device}){time} — {:.1} ms, {:.2} Mrays/s, max t_error {:.1e}{}",
            s.mode.name(),
            if self.gpu.is_some() {
                Precision::F32
            } else {
                s.precision
            },
            if s.heat { " heat" } else { "" },
            frame.seconds * 1e3,
            frame.rays as f64 / frame.seconds.max(1e-9) / 1e6,
            frame.max_t_error,
            if reduced {
                " (moving: 1/3 resolution)"
            } else {
                ""
            }
        )
    }

    /// Renders and presents a frame for the window's current size (headless: the requested
    /// size); a reduced one while the camera moves.
    pub(super) fn redraw(&mut self) -> Result<()> {
        let Some(window) = self.window.clone() else {
            return Ok(());
        };
        let size = self.size;
        let headless = self.options.frames.is_some();
        let (fw, fh) = if headless {
            (self.options.width, self.options.height)
        } else {
            (size.width, size.height)
        };
        if fw == 0 || fh == 0 || size.width == 0 || size.height == 0 {
            return Ok(()); // minimised
        }
        let moving = !headless && self.last_input.elapsed() < REST;
        let (rw, rh) = if moving {
            ((fw / MOVING_SCALE).max(1), (fh / MOVING_SCALE).max(1))
        } else {
            (fw, fh)
        };
        self.advance()?;
        let frame = self.render(rw, rh)?;
        window.set_title(&self.title(&frame, moving));
        match (self.surface.as_mut(), &frame.pixels, self.gpu.as_mut()) {
            (Some(Presenter::Soft(surface)), Some((image, _)), _) => present(surface, image, size)?,
            (Some(Presenter::Gpu), None, Some(g)) => {
                if let (Some(surface), Some((f, _, _))) = (g.surface.as_mut(), &g.frame) {
                    surface
                        .resize(size.width, size.height)
                        .and_then(|()| surface.present(f))
                        .map_err(gpu_error)?;
                }
            }
            _ => {}
        }
        if !moving {
            self.shown = Some((self.settings, fw, fh));
        }
        self.totals.0 += frame.seconds;
        self.totals.1 += frame.rays;
        self.last = Some(frame);
        Ok(())
    }
}

/// Copies `image` into the window's buffer, scaled (nearest pixel) to the window's size.
fn present(
    surface: &mut softbuffer::Surface<Arc<Window>, Arc<Window>>,
    image: &Image,
    size: PhysicalSize<u32>,
) -> Result<()> {
    let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
        return Ok(());
    };
    let display = |e: softbuffer::SoftBufferError| DemoError::Usage(format!("view: {e}"));
    surface.resize(w, h).map_err(display)?;
    let mut buffer = surface.buffer_mut().map_err(display)?;
    let (iw, ih) = (image.width.max(1), image.height.max(1));
    for (y, row) in buffer.chunks_mut(size.width as usize).enumerate() {
        let sy = (y as u64 * u64::from(ih) / u64::from(size.height)) as u32;
        for (x, px) in row.iter_mut().enumerate() {
            let sx = (x as u64 * u64::from(iw) / u64::from(size.width)) as u32;
            let [r, g, b] = image.get(sx, sy);
            *px = (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b);
        }
    }
    buffer.present().map_err(display)
}
