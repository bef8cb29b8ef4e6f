//! `view --gpu`: the device, its scenes (uploaded once, moved in place by `--animate`: on the
//! device by a [`GpuUpdate`] where it has one, else from the CPU's update), the frame storage,
//! and rendering a frame on it.

use std::collections::HashMap;
use std::rc::Rc;
use std::sync::Arc;

use glam::DVec3;
use smoothtri::LineField;
use smoothtri_gpu::{FrameStats, FrameView, Gpu, GpuFrame, GpuScene, GpuSurface, GpuUpdate};
use smoothtri_host::Camera;

use super::Viewer;
use super::frame::Frame;
use crate::error::{DemoError, Result};
use crate::gpu::{frame_view, gpu_error, gpu_scene, gpu_update};
use crate::tracer::{Mode, Normals};

/// The GPU side of `--gpu`: the device, the uploaded scenes, the frame storage and the
/// window's swap chain.
pub(super) struct GpuView {
    pub(super) gpu: Arc<Gpu>,
    /// Per mode and shading normal, each with whether the mesh moved since it was written
    /// (`--animate`: moved in place before its next frame, on the device by its
    /// [`GpuUpdate`] where it has one, else by [`gpu_update`] from the CPU's update).
    scenes: HashMap<(Mode, Normals), (Rc<GpuScene>, bool)>,
    /// `--animate`: the device updates of the smooth scenes (face field), by the same key.
    updates: HashMap<(Mode, Normals), GpuUpdate>,
    /// The last frame (its size is the last frame's) and the scene and counters it was
    /// rendered with.
    pub(super) frame: Option<(GpuFrame, Rc<GpuScene>, FrameStats)>,
    pub(super) surface: Option<GpuSurface>,
}

impl GpuView {
    /// The GPU side on `gpu`, before any scene, frame or window.
    pub(super) fn new(gpu: Arc<Gpu>) -> Self {
        GpuView {
            gpu,
            scenes: HashMap::new(),
            updates: HashMap::new(),
            frame: None,
            surface: None,
        }
    }

    /// The mesh moved: every scene written so far is stale.
    pub(super) fn posed(&mut self) {
        for (_, stale) in self.scenes.values_mut() {
            *stale = true;
        }
    }

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

impl Viewer {
    /// Renders one `w`×`h` frame through `cam` with the current settings on the GPU (the scene
    /// with seams when `seams`): the scene uploaded on first use, moved in place when stale.
    pub(super) fn render_gpu(
        &mut self,
        cam: &Camera,
        w: u32,
        h: u32,
        seams: bool,
    ) -> Result<Frame> {
        let s = self.settings;
        let key = (s.mode, s.normals);
        let on_device = self.gpu.as_ref().is_some_and(|g| {
            g.updates.contains_key(&key) && g.scenes.get(&key).is_some_and(|(_, stale)| *stale)
        });
        if on_device {
            return self.render_device_update(key, cam, w, h);
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
        g.draw(gs, frame, s.n, &frame_view(cam, self.diag, s.heat))
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
}
