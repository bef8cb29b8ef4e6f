//! `smoothtri view`: the kernel in real time, in a window (winit). The CPU kernel renders on
//! rayon's threads and softbuffer presents its frames; `--gpu` renders each frame on the GPU
//! in one compute pass of the WGSL kernel (camera rays, closest hits, seamless or Phong
//! normals, shadow rays, shading) and draws it into the window's wgpu swap chain, with no
//! readback but the frame's counters. Orbit with the left mouse button, zoom with the wheel; keys switch the mode,
//! the normals, `N`, the precision and the error heat map (see [`KEYS`]). While the camera
//! moves, frames render at a third of the resolution; once it rests, one full frame follows.
//!
//! Headless (`--frames K --screenshot FILE.png`): K full frames at the fixed camera, then the
//! last one is written (equal, pixel for pixel, to `render` with the same camera, mode and
//! size) and the viewer exits. Under `xvfb-run` this runs without a screen.
//!
//! `--animate` plays the source's animation ([`crate::animate`]: a glTF file's clip, or
//! `--scene twist`) from `--time` on, looping over the clip, each frame's scene built from the
//! pose ([`scene_of_pose`]: the previous pose's scene updated in place). With `--gpu` a smooth
//! scene on the face field moves on the device ([`GpuUpdate`]: each pose's vertices written into
//! its vertex buffers, only the positions for a file without normals, whose normals the device
//! computes; its compute passes re-make the patches, crack closure, seams and the tree's refit;
//! no CPU scene per frame); the flat modes and the vertex field are rewritten in
//! place from the CPU's update ([`gpu_update`]). The camera frames the whole clip. Space pauses.
//! Headless, frame `k` shows `--time` + `k ·` [`FRAME_STEP`], so the last of K frames equals
//! `render --time` at that time.

use std::any::Any;
use std::collections::HashMap;
use std::num::NonZeroU32;
use std::rc::Rc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::DVec3;
use smoothtri::LineField;
use smoothtri_gpu::{FrameStats, FrameView, Gpu, GpuFrame, GpuScene, GpuSurface, GpuUpdate};
use smoothtri_host::Camera;
use smoothtri_io::Mesh;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use super::render::Note;
use super::source::MeshSource;
use crate::animate::{Animation, FRAME_STEP};
use crate::commands::render::build_scene;
use crate::error::{DemoError, Result};
use crate::gpu::{frame_view, gpu_error, gpu_scene, gpu_update, open_gpu, read_frame};
use crate::image::{Image, heat};
use crate::output::Format;
use crate::renderer::{PixelHit, Rendered};
use crate::tracer::{Mode, Normals, Prec, Precision, Scene, tracer};
use crate::up::Up;

/// The keys of the viewer, as its help line and the README list them.
pub const KEYS: &[(&str, &str)] = &[
    ("M", "mode: smooth → flat → phong"),
    ("S", "shading normal: seamless ↔ geometric"),
    ("↑ / ↓", "N (refinement steps) up / down, 0..=16"),
    ("P", "precision: f32 ↔ f64 (CPU)"),
    ("H", "heat map of each pixel's certified t_error"),
    ("R", "reset the camera"),
    ("Space", "pause / play the animation (`--animate`)"),
    ("Esc / Q", "quit"),
];

/// Largest `N` the keys reach (the demo's kernels are compiled for every `N` up to it).
const MAX_N: usize = 16;
/// Frames render at `1 / MOVING_SCALE` of the resolution while the camera moves.
const MOVING_SCALE: u32 = 3;
/// How long after the last input the camera counts as resting.
const REST: Duration = Duration::from_millis(150);
/// Degrees of orbit per pixel of mouse motion.
const ORBIT_DEG_PER_PX: f64 = 0.4;

/// Options of `view`.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// The mesh (the torus scene when unset).
    pub source: MeshSource,
    /// Intersection mode at start.
    pub mode: Mode,
    /// Refinement steps at start.
    pub iterations: usize,
    /// Precision at start.
    pub precision: Precision,
    /// Window (and frame) width at start, 1..=16384.
    pub width: u32,
    /// Window (and frame) height at start, 1..=16384.
    pub height: u32,
    /// Camera azimuth and elevation in degrees at start.
    pub view: (f64, f64),
    /// The mesh's up axis (`None`: the source's default).
    pub up: Option<Up>,
    /// Render with the GPU kernel (f32).
    pub gpu: bool,
    /// The normal the smooth mode shades with at start.
    pub normals: Normals,
    /// The line field of the patches.
    pub field: LineField,
    /// Start with the error heat map.
    pub heat: bool,
    /// Headless: render this many frames at the fixed camera, then exit.
    pub frames: Option<u32>,
    /// Headless: write the last frame here (PNG).
    pub screenshot: Option<String>,
    /// Headless: write the last frame's primary-hit mask here (PBM).
    pub mask: Option<String>,
    /// Play the source's animation ([`crate::animate`]).
    pub animate: bool,
    /// With `animate`: the time to start from, seconds.
    pub time: Option<f64>,
    /// With `animate`: the glTF clip (default the first).
    pub clip: Option<usize>,
}

/// What the keys and the mouse change.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Settings {
    mode: Mode,
    n: usize,
    precision: Precision,
    normals: Normals,
    heat: bool,
    az: f64,
    el: f64,
    zoom: f64,
}

/// The scenes built so far, by precision and seams (built on first use), and those of the
/// previous pose of an animation (what the next pose's scene is made from).
#[derive(Default)]
struct Scenes {
    built: HashMap<(Precision, bool), Rc<dyn Any>>,
    previous: HashMap<(Precision, bool), Rc<dyn Any>>,
    /// Whether the note about skipped triangles was printed.
    noted: bool,
}

impl Scenes {
    fn get<F: Prec>(&mut self, mesh: &Mesh, field: LineField, seams: bool) -> Result<Rc<Scene<F>>> {
        let key = (F::PRECISION, seams);
        if let Some(s) = self
            .built
            .get(&key)
            .and_then(|s| Rc::clone(s).downcast::<Scene<F>>().ok())
        {
            return Ok(s);
        }
        let note = Note {
            skipped: !std::mem::replace(&mut self.noted, true),
            timing: false,
        };
        let previous = self
            .previous
            .remove(&key)
            .and_then(|s| s.downcast::<Scene<F>>().ok())
            .and_then(|s| Rc::try_unwrap(s).ok());
        let scene = Rc::new(scene_of_pose::<F>(previous, mesh, note, field, seams)?);
        self.built.insert(key, Rc::clone(&scene) as Rc<dyn Any>);
        Ok(scene)
    }

    /// The mesh moved: the scenes built so far become the previous pose's.
    fn posed(&mut self) {
        self.previous.clear();
        self.previous.extend(self.built.drain());
    }
}

/// The animation being played: the source, where it started and the clock, or the time it is
/// paused at.
struct Playing {
    animation: Animation,
    /// The clip time at `clock`'s start, seconds.
    offset: f64,
    clock: Instant,
    paused: Option<f64>,
    /// The time of the pose in the viewer's mesh.
    shown: f64,
}

impl Playing {
    /// The clip time now (interactive: by the wall clock, looping over the clip).
    fn now(&self) -> f64 {
        let t = self
            .paused
            .unwrap_or_else(|| self.offset + self.clock.elapsed().as_secs_f64());
        self.wrap(t)
    }

    /// `t` looped into the clip (the twisting torus repeats with its period anyway).
    fn wrap(&self, t: f64) -> f64 {
        let d = self.animation.duration;
        if d > 0.0 { t % d } else { 0.0 }
    }

    fn toggle_pause(&mut self) {
        match self.paused.take() {
            Some(t) => {
                self.offset = t;
                self.clock = Instant::now();
            }
            None => self.paused = Some(self.now()),
        }
    }
}

/// One rendered frame and what the title shows of it.
struct Frame {
    /// The CPU's image and hits; `None` for a GPU frame, which stays on the GPU
    /// ([`GpuView::frame`]) until a screenshot reads it back.
    pixels: Option<(Image, Vec<PixelHit>)>,
    width: u32,
    height: u32,
    rays: u64,
    seconds: f64,
    max_t_error: f64,
}

/// The GPU side of `--gpu`: the device, the uploaded scenes, the frame storage and the
/// window's swap chain.
struct GpuView {
    gpu: Arc<Gpu>,
    /// Per mode and shading normal, each with whether the mesh moved since it was written
    /// (`--animate`: moved in place before its next frame, on the device by its
    /// [`GpuUpdate`] where it has one, else by [`gpu_update`] from the CPU's update).
    scenes: HashMap<(Mode, Normals), (Rc<GpuScene>, bool)>,
    /// `--animate`: the device updates of the smooth scenes (face field), by the same key.
    updates: HashMap<(Mode, Normals), GpuUpdate>,
    /// The last frame (its size is the last frame's) and the scene and counters it was
    /// rendered with.
    frame: Option<(GpuFrame, Rc<GpuScene>, FrameStats)>,
    surface: Option<GpuSurface>,
}

impl GpuView {
    /// The frame storage for a `w`×`h` frame: the last frame's when its size is the same. The
    /// last frame holds its scene: taken first, so that a moved scene can be written in place
    /// rather than uploaded anew.
    fn take_frame(&mut self, w: u32, h: u32) -> Result<GpuFrame> {
        match self.frame.take() {
            Some((f, _, _)) if (f.width(), f.height()) == (w, h) => Ok(f),
            _ => GpuFrame::new(&self.gpu, w, h).map_err(gpu_error),
        }
    }

    /// Renders `gs` into `frame` with budget `n` through `view` and keeps both as the last
    /// frame.
    fn draw(
        &mut self,
        gs: Rc<GpuScene>,
        mut frame: GpuFrame,
        n: usize,
        view: &FrameView,
    ) -> Result<Frame> {
        let stats = gs.render_frame(n, view, &mut frame).map_err(gpu_error)?;
        let (width, height) = (frame.width(), frame.height());
        self.frame = Some((frame, gs, stats));
        Ok(Frame {
            pixels: None,
            width,
            height,
            rays: stats.rays,
            seconds: stats.seconds,
            max_t_error: f64::from(stats.max_t_error),
        })
    }
}

/// How frames reach the window.
enum Presenter {
    /// The CPU's frames, copied into the window's buffer.
    Soft(softbuffer::Surface<Arc<Window>, Arc<Window>>),
    /// The GPU's frames, drawn into its swap chain.
    Gpu,
}

/// The viewer: the mesh, its scenes, the settings and the window.
struct Viewer {
    options: ViewOptions,
    mesh: Mesh,
    /// The sphere the camera frames (centre and radius), as `render`'s camera.
    sphere: (DVec3, f64),
    diag: f64,
    gpu: Option<GpuView>,
    scenes: Scenes,
    settings: Settings,
    window: Option<Arc<Window>>,
    /// The window's inner size, from its creation and its `Resized` events (never asked of
    /// the window: winit's X11 backend panics when asked about a window another client
    /// destroyed).
    size: PhysicalSize<u32>,
    surface: Option<Presenter>,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    last_input: Instant,
    /// The settings and size of the last full-resolution frame (nothing to refine when equal).
    shown: Option<(Settings, u32, u32)>,
    frames_done: u32,
    /// Render seconds and rays of the frames so far (headless summary).
    totals: (f64, u64),
    last: Option<Frame>,
    error: Option<DemoError>,
    /// `--animate`: what is played.
    playing: Option<Playing>,
}

impl Viewer {
    fn initial_settings(o: &ViewOptions) -> Settings {
        Settings {
            mode: o.mode,
            n: o.iterations,
            precision: o.precision,
            normals: o.normals,
            heat: o.heat,
            az: o.view.0,
            el: o.view.1,
            zoom: 1.0,
        }
    }

    /// The camera of the current settings for a `w`×`h` frame: `render`'s camera at zoom 1.
    fn camera(&self, w: u32, h: u32) -> Camera {
        let s = &self.settings;
        if s.zoom == 1.0 && self.playing.is_none() {
            return Camera::for_mesh(&self.mesh, s.az, s.el, w, h);
        }
        let (c, r) = self.sphere;
        Camera::look_at_sphere(c, r * s.zoom, s.az, s.el, w, h)
    }

    /// `--animate`: poses the mesh at the animation's time for this frame (headless: frame
    /// `k` at `--time` + `k ·` [`FRAME_STEP`]) when that time changed; the scenes follow.
    fn advance(&mut self) -> Result<()> {
        let headless = self.options.frames.is_some();
        let frame = f64::from(self.frames_done);
        let Some(p) = self.playing.as_mut() else {
            return Ok(());
        };
        let t = if headless {
            p.wrap(p.offset + frame * FRAME_STEP)
        } else {
            p.now()
        };
        if t == p.shown {
            return Ok(());
        }
        p.animation.pose(t, &mut self.mesh)?;
        p.shown = t;
        self.diag = self.mesh.diagonal();
        self.scenes.posed();
        if let Some(g) = self.gpu.as_mut() {
            for (_, stale) in g.scenes.values_mut() {
                *stale = true;
            }
        }
        Ok(())
    }

    /// Renders one `w`×`h` frame with the current settings.
    fn render(&mut self, w: u32, h: u32) -> Result<Frame> {
        let cam = self.camera(w, h);
        let s = self.settings;
        let seams = s.normals == Normals::Seamless && s.mode == Mode::Smooth;
        if self.gpu.is_some() {
            let key = (s.mode, s.normals);
            let on_device = self.gpu.as_ref().is_some_and(|g| {
                g.updates.contains_key(&key) && g.scenes.get(&key).is_some_and(|(_, stale)| *stale)
            });
            if on_device {
                return self.render_device_update(key, &cam, w, h);
            }
            let scene = self
                .scenes
                .get::<f32>(&self.mesh, self.options.field, seams)?;
            let Some(g) = self.gpu.as_mut() else {
                return Err(DemoError::Usage("view: no GPU".into()));
            };
            let frame = g.take_frame(w, h)?;
            let gs = match g.scenes.get_mut(&key) {
                Some((gs, stale)) => {
                    if *stale {
                        match Rc::get_mut(gs) {
                            Some(m) => gpu_update(m, &scene)?,
                            None => *gs = Rc::new(gpu_scene(&g.gpu, &scene, s.mode)?),
                        }
                        *stale = false;
                    }
                    Rc::clone(gs)
                }
                None => {
                    let gs = Rc::new(gpu_scene(&g.gpu, &scene, s.mode)?);
                    g.scenes.insert(key, (Rc::clone(&gs), false));
                    // A played smooth scene moves on the device from now on.
                    if self.playing.is_some()
                        && s.mode == Mode::Smooth
                        && self.options.field == LineField::Face
                    {
                        let mut up = GpuUpdate::new(
                            &gs,
                            &scene.core(),
                            &self.mesh.triangles,
                            self.mesh.positions.len(),
                            self.options.field,
                        )
                        .map_err(gpu_error)?;
                        // A file without normals: the device computes them from the positions.
                        up.generate_normals(
                            self.playing
                                .as_ref()
                                .is_some_and(|p| p.animation.normals_from_positions()),
                        );
                        g.updates.insert(key, up);
                    }
                    gs
                }
            };
            return g.draw(gs, frame, s.n, &frame_view(&cam, self.diag, s.heat));
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

    /// `--gpu --animate`: moves the smooth scene of `key` to the mesh's pose on the device
    /// (the posed vertices written into its [`GpuUpdate`]'s buffers, the update's passes, no
    /// CPU scene) and renders it.
    fn render_device_update(
        &mut self,
        key: (Mode, Normals),
        cam: &Camera,
        w: u32,
        h: u32,
    ) -> Result<Frame> {
        let s = self.settings;
        let Some(g) = self.gpu.as_mut() else {
            return Err(DemoError::Usage("view: no GPU".into()));
        };
        let (Some((gs, stale)), Some(up)) = (g.scenes.get_mut(&key), g.updates.get(&key)) else {
            return Err(DemoError::Usage("view: no device update".into()));
        };
        let f32s =
            |v: &[DVec3]| -> Vec<f32> { v.iter().flat_map(|p| p.as_vec3().to_array()).collect() };
        if up.generates_normals() {
            up.write_positions(&f32s(&self.mesh.positions))
        } else {
            up.write_vertices(&f32s(&self.mesh.positions), &f32s(&self.mesh.normals))
        }
        .map_err(gpu_error)?;
        up.run(gs).map_err(gpu_error)?;
        *stale = false;
        let gs = Rc::clone(gs);
        let frame = g.take_frame(w, h)?;
        g.draw(gs, frame, s.n, &frame_view(cam, self.diag, s.heat))
    }

    fn render_cpu<F: Prec>(&mut self, cam: &Camera, seams: bool) -> Result<Rendered> {
        let scene = self
            .scenes
            .get::<F>(&self.mesh, self.options.field, seams)?;
        let t = tracer::<F>(self.settings.mode, self.settings.n)?;
        Ok(crate::renderer::render(&scene, cam, t, self.diag, false))
    }

    /// The window's title for `frame`.
    fn title(&self, frame: &Frame, reduced: bool) -> String {
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
    fn redraw(&mut self) -> Result<()> {
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

    /// Notes an input that changes the view.
    fn changed(&mut self) {
        self.last_input = Instant::now();
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    fn key(&mut self, key: &Key, event_loop: &ActiveEventLoop) {
        let s = &mut self.settings;
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::ArrowUp) => s.n = (s.n + 1).min(MAX_N),
            Key::Named(NamedKey::ArrowDown) => s.n = s.n.saturating_sub(1),
            Key::Character(c) => match c.to_ascii_lowercase().as_str() {
                "q" => event_loop.exit(),
                "m" => {
                    s.mode = match s.mode {
                        Mode::Smooth => Mode::Flat,
                        Mode::Flat => Mode::Phong,
                        Mode::Phong | Mode::PhongTess | Mode::Nagata => Mode::Smooth,
                    }
                }
                "s" => {
                    s.normals = match s.normals {
                        Normals::Seamless => Normals::Geometric,
                        Normals::Geometric => Normals::Seamless,
                    }
                }
                "p" if self.gpu.is_none() => {
                    s.precision = match s.precision {
                        Precision::F32 => Precision::F64,
                        Precision::F64 => Precision::F32,
                    }
                }
                "h" => s.heat = !s.heat,
                "r" => *s = Self::initial_settings(&self.options),
                _ => return,
            },
            Key::Named(NamedKey::Space) => match self.playing.as_mut() {
                Some(p) => p.toggle_pause(),
                None => return,
            },
            _ => return,
        }
        self.changed();
    }

    /// Headless: writes the last frame and its mask, and prints the frame rate.
    fn write_outputs(&mut self) -> Result<()> {
        let Some(frame) = &self.last else {
            return Err(DemoError::Usage("view: no frame was rendered".into()));
        };
        let (image, hits) = match (&frame.pixels, &self.gpu) {
            (Some((image, hits)), _) => (image.clone(), hits.clone()),
            (
                None,
                Some(GpuView {
                    frame: Some((f, _, stats)),
                    ..
                }),
            ) => {
                let seams = self.settings.normals == Normals::Seamless
                    && self.settings.mode == Mode::Smooth;
                let scene = self
                    .scenes
                    .get::<f32>(&self.mesh, self.options.field, seams)?;
                let r = read_frame(&scene, f, *stats)?;
                (r.image, r.hits)
            }
            _ => return Err(DemoError::Usage("view: no frame was rendered".into())),
        };
        let Some(frame) = &self.last else {
            return Err(DemoError::Usage("view: no frame was rendered".into()));
        };
        let (secs, rays) = self.totals;
        let k = f64::from(self.frames_done.max(1));
        println!(
            "view: {} frames of {}x{} ({}): {:.1} ms per frame ({:.1} frames/s), {:.2} Mrays/s",
            self.frames_done,
            frame.width,
            frame.height,
            self.title(frame, false)
                .split(" — ")
                .nth(1)
                .unwrap_or_default(),
            secs / k * 1e3,
            k / secs.max(1e-9),
            rays as f64 / secs.max(1e-9) / 1e6
        );
        if let Some(path) = &self.options.screenshot {
            image.write_png(path)?;
        }
        if let Some(path) = &self.options.mask {
            crate::output::write(
                path,
                crate::renderer::mask_pbm(image.width, image.height, &hits).as_bytes(),
            )?;
        }
        Ok(())
    }

    fn fail(&mut self, e: DemoError, event_loop: &ActiveEventLoop) {
        self.error.get_or_insert(e);
        event_loop.exit();
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

/// Each hit pixel coloured by its certified `t_error` relative to the scene's diagonal, on the
/// heat scale of `precision --strip` from 1e-9 (blue) to 1e-3 (red); misses black.
fn heat_map(r: &Rendered, diag: f64) -> Image {
    let (w, h) = (r.image.width, r.image.height);
    let mut img = Image::new(w, h, [0, 0, 0]);
    for (i, p) in r.hits.iter().enumerate() {
        if !p.hit {
            continue;
        }
        let rel = (p.t_error / diag.max(f64::MIN_POSITIVE)).max(1e-12);
        let l = ((rel.log10() + 9.0) / 6.0).clamp(0.0, 1.0);
        let (x, y) = (i as u32 % w.max(1), i as u32 / w.max(1));
        img.put(i64::from(x), i64::from(y), heat(l));
    }
    img
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attrs = Window::default_attributes()
            .with_title("smoothtri view")
            .with_inner_size(PhysicalSize::new(self.options.width, self.options.height));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => {
                return self.fail(
                    DemoError::Usage(format!("view: cannot open a window: {e}")),
                    event_loop,
                );
            }
        };
        self.size = window.inner_size();
        if let Some(g) = self.gpu.as_mut() {
            let size = self.size;
            match GpuSurface::new(&g.gpu, Arc::clone(&window), size.width, size.height) {
                Ok(s) => {
                    g.surface = Some(s);
                    self.surface = Some(Presenter::Gpu);
                }
                Err(e) => return self.fail(gpu_error(e), event_loop),
            }
        } else {
            let surface = softbuffer::Context::new(Arc::clone(&window))
                .and_then(|c| softbuffer::Surface::new(&c, Arc::clone(&window)));
            match surface {
                Ok(s) => self.surface = Some(Presenter::Soft(s)),
                Err(e) => {
                    return self.fail(
                        DemoError::Usage(format!("view: cannot draw into the window: {e}")),
                        event_loop,
                    );
                }
            }
        }
        window.request_redraw();
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let headless = self.options.frames.is_some();
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => {
                // Drop the surfaces and the window first: a window destroyed by another client
                // must not be asked for its size again (winit's X11 backend panics on that).
                self.surface = None;
                if let Some(g) = self.gpu.as_mut() {
                    g.surface = None;
                }
                self.window = None;
                event_loop.exit();
            }
            WindowEvent::Resized(size) => {
                self.size = size;
                self.shown = None;
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    return self.fail(e, event_loop);
                }
                if let Some(k) = self.options.frames {
                    self.frames_done += 1;
                    if self.frames_done >= k {
                        if let Err(e) = self.write_outputs() {
                            return self.fail(e, event_loop);
                        }
                        event_loop.exit();
                    } else if let Some(w) = &self.window {
                        w.request_redraw();
                    }
                }
            }
            _ if headless => {}
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(&event.logical_key, event_loop);
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let Some((x0, y0)) = self.drag {
                    let s = &mut self.settings;
                    s.az -= (position.x - x0) * ORBIT_DEG_PER_PX;
                    s.el = (s.el + (position.y - y0) * ORBIT_DEG_PER_PX).clamp(-89.0, 89.0);
                    self.drag = Some(self.cursor);
                    self.changed();
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                let s = &mut self.settings;
                s.zoom = (s.zoom * 0.9f64.powf(steps)).clamp(0.05, 20.0);
                self.changed();
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.options.frames.is_some() {
            return;
        }
        // A playing animation: the next frame at once.
        if self.playing.as_ref().is_some_and(|p| p.paused.is_none()) {
            if let Some(w) = &self.window {
                w.request_redraw();
            }
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        // Once the camera rests, one full-resolution frame of what is shown.
        let size = self.window.as_ref().map(|_| self.size);
        let full = size.map(|s| (self.settings, s.width, s.height));
        if full.is_some() && full != self.shown {
            let rest_at = self.last_input + REST;
            if Instant::now() >= rest_at {
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(rest_at));
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}

/// The one-line error of a missing display.
fn no_display(e: impl std::fmt::Display) -> DemoError {
    DemoError::Usage(format!(
        "view: no display to open a window on ({e}); set DISPLAY (X11, or XWayland) or run \
         headless under xvfb-run"
    ))
}

/// Opens the viewer; returns when its window closes (or, headless, after the frames).
///
/// Before any work the outputs are checked ([`crate::output::check`]): `--screenshot` a `.png`,
/// `--mask` a `.pbm`, neither the `--mesh` file nor each other.
pub fn run(o: ViewOptions) -> Result<()> {
    crate::output::check(
        &crate::output::inputs(&[("--mesh", o.source.mesh.as_deref())]),
        &crate::output::outputs(&[
            ("--screenshot", o.screenshot.as_deref(), Format::Png),
            ("--mask", o.mask.as_deref(), Format::Pbm),
        ]),
    )?;
    if o.width == 0 || o.height == 0 || o.width > 16384 || o.height > 16384 {
        return Err(DemoError::Usage(
            "--width and --height must be in 1..=16384".into(),
        ));
    }
    if o.frames == Some(0) {
        return Err(DemoError::Usage("--frames must be at least 1".into()));
    }
    if o.frames.is_none() && (o.screenshot.is_some() || o.mask.is_some()) {
        return Err(DemoError::Usage(
            "--screenshot and --mask need --frames K (headless)".into(),
        ));
    }
    if o.iterations > MAX_N {
        return Err(DemoError::Usage(format!(
            "view: --iterations must be in 0..={MAX_N}"
        )));
    }
    tracer::<f32>(Mode::Smooth, o.iterations)?;
    if o.gpu && o.precision != Precision::F32 {
        return Err(DemoError::Usage(
            "--gpu traces in f32: leave --precision out or set it to f32".into(),
        ));
    }
    if !o.animate && (o.time.is_some() || o.clip.is_some()) {
        return Err(DemoError::Usage("--time and --clip need --animate".into()));
    }
    if let Some(t) = o.time {
        crate::animate::check_time(t)?;
    }
    // Without X11 there is no window: say so before loading anything.
    if std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        return Err(no_display("DISPLAY is not set"));
    }
    let (mesh, sphere, playing) = if o.animate {
        let mut animation = Animation::open(&o.source, o.up, o.clip)?;
        let sphere = animation.sphere()?;
        let start = o.time.unwrap_or(0.0);
        let mut mesh = animation.rest();
        let mut p = Playing {
            animation,
            offset: start,
            clock: Instant::now(),
            paused: None,
            shown: 0.0,
        };
        p.shown = p.wrap(start);
        p.animation.pose(p.shown, &mut mesh)?;
        (mesh, sphere, Some(p))
    } else {
        let (_, mesh, _) = o.source.load_upright(true, o.up)?;
        let sphere = Camera::mesh_sphere(&mesh);
        (mesh, sphere, None)
    };
    let gpu = if o.gpu {
        Some(GpuView {
            gpu: open_gpu()?,
            scenes: HashMap::new(),
            updates: HashMap::new(),
            frame: None,
            surface: None,
        })
    } else {
        None
    };
    let event_loop = EventLoop::new().map_err(no_display)?;
    let mut viewer = Viewer {
        sphere,
        diag: mesh.diagonal(),
        settings: Viewer::initial_settings(&o),
        options: o,
        mesh,
        gpu,
        scenes: Scenes::default(),
        window: None,
        size: PhysicalSize::new(0, 0),
        surface: None,
        drag: None,
        cursor: (0.0, 0.0),
        last_input: Instant::now()
            .checked_sub(REST)
            .unwrap_or_else(Instant::now),
        shown: None,
        frames_done: 0,
        totals: (0.0, 0),
        last: None,
        error: None,
        playing,
    };
    event_loop
        .run_app(&mut viewer)
        .map_err(|e| DemoError::Usage(format!("view: {e}")))?;
    match viewer.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The scene of a posed `mesh` in precision `F` (on `field`, with seams when `seams`), given
/// the scene of the previous pose of the same animation when there is one (same triangles,
/// same options): the one place where an animation turns posed vertices into a scene. The
/// previous scene is updated in place ([`Scene::update`]); without one, or where the update
/// refuses the vertices, the scene is built afresh (as `render` builds a scene).
pub fn scene_of_pose<F: Prec>(
    previous: Option<Scene<F>>,
    mesh: &Mesh,
    note: Note,
    field: LineField,
    seams: bool,
) -> Result<Scene<F>> {
    if let Some(mut scene) = previous
        && scene.update(mesh, field, seams).is_ok()
    {
        if note.timing {
            eprintln!("update ({}): {}", F::PRECISION, scene.timing_line());
        }
        return Ok(scene);
    }
    build_scene::<F>(mesh, note, field, seams)
}
