//! `smoothtri view`: the kernel in real time, in a window (winit). The CPU kernel renders on
//! rayon's threads and softbuffer presents its frames; `--gpu` renders each frame on the GPU
//! in one compute pass of the WGSL kernel (camera rays, closest hits, seamless or Phong
//! normals, shadow rays, shading) and draws it into the window's wgpu swap chain, with no
//! readback but the frame's counters. Orbit with the left mouse button, zoom with the wheel;
//! keys switch the mode, the normals, `N`, the precision and the error heat map (see [`KEYS`]).
//! While the camera moves, frames render at a third of the resolution; once it rests, one full
//! frame follows.
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
//!
//! One idea per file: this file the options, the viewer's state (its settings included) and
//! the entry point; `app.rs` the winit application (the window, its events, the waits);
//! `input.rs` what the keys and the mouse change; `frame.rs` rendering and presenting a frame;
//! `gpu.rs` the `--gpu` side (the device's scenes and frames, the device update); `cache.rs`
//! the scenes by precision and seams and [`scene_of_pose`]; `playback.rs` the animation's
//! clock; `headless.rs` the screenshot, the mask and the summary line; `heat.rs` the CPU's heat
//! map.
//!
//! [`GpuUpdate`]: smoothtri_gpu::GpuUpdate
//! [`gpu_update`]: crate::gpu::gpu_update
//! [`FRAME_STEP`]: crate::animate::FRAME_STEP

mod app;
mod cache;
mod frame;
mod gpu;
mod headless;
mod heat;
mod input;
mod playback;

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use smoothtri::LineField;
use smoothtri_host::Camera;
use smoothtri_io::Mesh;
use winit::dpi::PhysicalSize;
use winit::event_loop::EventLoop;
use winit::window::Window;

pub use cache::scene_of_pose;
pub use input::KEYS;

use self::cache::Scenes;
use self::frame::{Frame, Presenter};
use self::gpu::GpuView;
use self::input::{MAX_N, REST};
use self::playback::Playing;
use super::render::{check_outputs, check_size};
use super::source::MeshSource;
use crate::animate::Animation;
use crate::error::{DemoError, Result};
use crate::gpu::open_gpu;
use crate::output::Format;
use crate::tracer::{Mode, Normals, Precision, tracer};
use crate::up::Up;

/// Options of `view`.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// The mesh (the torus scene when unset).
    pub source: MeshSource,
    /// The mesh's up axis (`None`: the source's default).
    pub up: Option<Up>,
    /// Camera azimuth and elevation in degrees at start.
    pub view: (f64, f64),
    /// Intersection mode at start.
    pub mode: Mode,
    /// Refinement steps at start.
    pub iterations: usize,
    /// Precision at start.
    pub precision: Precision,
    /// The normal the smooth mode shades with at start.
    pub normals: Normals,
    /// Start with the error heat map.
    pub heat: bool,
    /// The line field of the patches.
    pub field: LineField,
    /// Render with the GPU kernel (f32).
    pub gpu: bool,
    /// Window (and frame) width at start, 1..=16384.
    pub width: u32,
    /// Window (and frame) height at start, 1..=16384.
    pub height: u32,
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

/// What the keys and the mouse change ([`input`]).
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
    check_outputs(
        &o.source,
        &[
            ("--screenshot", o.screenshot.as_deref(), Format::Png),
            ("--mask", o.mask.as_deref(), Format::Pbm),
        ],
    )?;
    check_size(o.width, o.height, 16384)?;
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
        let animation = Animation::open(&o.source, o.up, o.clip)?;
        let (mesh, sphere, p) = Playing::start(animation, o.time.unwrap_or(0.0))?;
        (mesh, sphere, Some(p))
    } else {
        let (_, mesh, _) = o.source.load_upright(true, o.up)?;
        let sphere = Camera::mesh_sphere(&mesh);
        (mesh, sphere, None)
    };
    let gpu = if o.gpu {
        Some(GpuView::new(open_gpu()?))
    } else {
        None
    };
    let event_loop = EventLoop::new().map_err(no_display)?;
    let mut viewer = Viewer {
        sphere,
        diag: mesh.diagonal(),
        settings: Settings::initial(&o),
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
