//! The demo on the GPU (`smoothtri-gpu`): opening the device ([`open_gpu`]), a [`Scene`]'s
//! patches or flat triangles uploaded for a render mode ([`gpu_scene`]), the frame pass's view
//! of a [`Camera`] ([`frame_view`]) and whole renders read back as the CPU renderer returns them
//! ([`render_gpu`], [`read_frame`]). Used by `render --gpu`, `precision --gpu` and `view --gpu`.

use std::sync::Arc;

use smoothtri_gpu::{FrameStats, FrameView, Gpu, GpuFrame, GpuScene, Shading};
use smoothtri_host::{Camera, SHADOW_OFFSET_F32};

use crate::error::{DemoError, Result};
use crate::image::Image;
use crate::renderer::{PixelHit, Rendered};
use crate::tracer::{Mode, Normals, Scene};

/// Opens the GPU for `--gpu`: its error (no adapter, no device) becomes the one-line message
/// the command exits with.
pub fn open_gpu() -> Result<Arc<Gpu>> {
    Gpu::new().map_err(gpu_error)
}

/// A GPU failure as the demo's error (one line).
pub fn gpu_error(e: smoothtri_gpu::GpuError) -> DemoError {
    DemoError::Usage(format!("--gpu: {e}"))
}

/// The GPU scene of `scene` for `mode`: the smooth patches with the seamless normal when the
/// scene shades with it (built with seams), else with the geometric one; the flat triangles,
/// with their vertex normals for `Mode::Phong`.
pub fn gpu_scene(gpu: &Arc<Gpu>, scene: &Scene<f32>, mode: Mode) -> Result<GpuScene> {
    let bvh = scene.bvh();
    let seams = scene.seams();
    match mode {
        Mode::Smooth
            if scene.normals == Normals::Seamless && seams.len() == bvh.patches().len() =>
        {
            GpuScene::smooth_seamless(gpu, &bvh, seams)
        }
        Mode::Smooth => GpuScene::smooth(gpu, &bvh),
        Mode::Flat => GpuScene::flat(gpu, &bvh),
        Mode::Phong => GpuScene::phong(gpu, &bvh),
        Mode::PhongTess | Mode::Nagata => {
            return Err(DemoError::Usage(format!(
                "--gpu does not trace --mode {}",
                mode.name()
            )));
        }
    }
    .map_err(gpu_error)
}

/// Moves `gs`, uploaded by [`gpu_scene`] from an earlier pose of `scene`'s mesh, to `scene`
/// in place ([`GpuScene::update`]: the same kind and shading, no buffer allocated where the
/// lengths stayed).
pub fn gpu_update(gs: &mut GpuScene, scene: &Scene<f32>) -> Result<()> {
    let seams = (gs.shading() == Shading::Seamless).then(|| scene.seams());
    gs.update(&scene.bvh(), seams).map_err(gpu_error)
}

/// The frame pass's view of `cam`: its camera, its light ([`Camera::light_dir`]), the
/// shadow-ray offset of the CPU renderer in `f32` (`diag` · [`SHADOW_OFFSET_F32`], `diag` the
/// scene's bounding-box diagonal), and the heat map of `t_error` relative to `diag` when
/// `heat`.
pub fn frame_view(cam: &Camera, diag: f64, heat: bool) -> FrameView {
    let basis = [cam.forward, cam.right, cam.up];
    let eps = diag * SHADOW_OFFSET_F32;
    FrameView {
        heat: heat.then(|| (1.0 / diag.max(f64::MIN_POSITIVE)) as f32),
        ..FrameView::pinhole(cam.eye, basis, cam.tan_half, cam.light_dir(), eps)
    }
}

/// The frame in `frame` as the CPU renderer returns one: the image and each pixel's primary
/// hit (`triangle` the mesh triangle of the hit patch).
pub fn read_frame(scene: &Scene<f32>, frame: &GpuFrame, stats: FrameStats) -> Result<Rendered> {
    let (data, pixels) = frame.read().map_err(gpu_error)?;
    let hits = pixels
        .iter()
        .map(|p| match p.patch {
            Some(patch) => PixelHit {
                hit: true,
                point: p.point.as_dvec3(),
                t_error: f64::from(p.t_error),
                triangle: scene
                    .tri_ids()
                    .get(patch as usize)
                    .copied()
                    .unwrap_or(u32::MAX),
            },
            None => PixelHit::default(),
        })
        .collect();
    Ok(Rendered {
        image: Image {
            width: frame.width(),
            height: frame.height(),
            data,
        },
        hits,
        rays: stats.rays,
        seconds: stats.seconds,
    })
}

/// Renders `scene` through `cam` on the GPU, as [`crate::renderer::render`] does on the CPU
/// (the same camera, shading, light and shadow-ray offset), in one frame pass
/// ([`GpuScene::render_frame`]: rays, closest hits, shading normals and shadow rays all on the
/// GPU), then reads the frame back. `Mode::Smooth` traces the patches with budget `n` and
/// shades with the scene's normal (seamless when built with seams); `Flat` and `Phong` trace
/// the flat triangles, Phong with the interpolated vertex normals. `diag` is the scene's
/// bounding-box diagonal. The time is the frame pass's (without the upload, the pipeline's
/// compilation and the readback of the pixels).
pub fn render_gpu(
    gpu: &Arc<Gpu>,
    scene: &Scene<f32>,
    cam: &Camera,
    mode: Mode,
    n: usize,
    diag: f64,
) -> Result<Rendered> {
    let gs = gpu_scene(gpu, scene, mode)?;
    let mut frame = GpuFrame::new(gpu, cam.width, cam.height).map_err(gpu_error)?;
    let view = frame_view(cam, diag, false);
    let stats = gs.render_frame(n, &view, &mut frame).map_err(gpu_error)?;
    read_frame(scene, &frame, stats)
}
