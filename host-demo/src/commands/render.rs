//! `smoothtri render`: a mesh (default: the built-in torus) to a PNG, one mode or smooth, flat
//! and phong side by side.

use crate::camera::{Camera, Up};
use crate::error::{DemoError, Result};
use crate::image::Image;
use crate::mesh::Mesh;
use crate::tracer::{Mode, Prec, Precision, Scene, tracer};

use super::MeshSource;

/// Options of `render`.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// The mesh (the torus scene when unset).
    pub source: MeshSource,
    /// Intersection mode (ignored with `compare`).
    pub mode: Mode,
    /// Render smooth, flat and phong side by side, labelled.
    pub compare: bool,
    /// Iteration budget of the smooth kernel.
    pub iterations: usize,
    /// Kernel precision.
    pub precision: Precision,
    /// Image width (per panel with `compare`), 1..=16384.
    pub width: u32,
    /// Image height, 1..=16384.
    pub height: u32,
    /// Output PNG (`-` for stdout).
    pub out: String,
    /// Camera azimuth and elevation in degrees, relative to the up axis.
    pub view: (f64, f64),
    /// The mesh's up axis (`None`: the source's default, [`MeshSource::up_axis`]).
    pub up: Option<Up>,
    /// Also write the primary-hit mask as a plain PBM.
    pub mask: Option<String>,
}

/// One rendered panel and its primary-hit mask.
pub(crate) struct Panel {
    /// The shaded image.
    pub image: Image,
    /// Rays traced (primary and shadow).
    pub rays: u64,
    /// Wall time, seconds.
    pub seconds: f64,
    /// Primary hits per pixel.
    pub mask: Vec<crate::renderer::PixelHit>,
}

/// [`render_panel`] in the precision `prec` names.
pub(crate) fn render_panel_in(
    prec: Precision,
    mesh: &Mesh,
    cam: &Camera,
    mode: Mode,
    n: usize,
    note: bool,
) -> Result<Panel> {
    match prec {
        Precision::F32 => render_panel::<f32>(mesh, cam, mode, n, note),
        Precision::F64 => render_panel::<f64>(mesh, cam, mode, n, note),
    }
}

/// Panels of equal size side by side, 4 white pixels apart, each with its label in the top
/// left corner (the layout of `render --compare`).
pub(crate) fn side_by_side(panels: &[(&Image, String)]) -> Image {
    let gap = 4;
    let (w, h) = panels.first().map_or((1, 1), |(i, _)| (i.width, i.height));
    let n = panels.len() as u32;
    let mut img = Image::new(w * n + gap * n.saturating_sub(1), h, [255, 255, 255]);
    let scale = if w >= 400 { 2 } else { 1 };
    for (k, (p, label)) in panels.iter().enumerate() {
        let x = (k as u32 * (w + gap)) as i64;
        img.blit(p, x, 0);
        img.label(label, x + 4 * scale, 4 * scale, scale, [255, 255, 255]);
    }
    img
}

/// Builds the scene in precision `F` and renders one panel in `mode` with budget `n`; `note`
/// prints the scene's note about skipped or clamped triangles.
fn render_panel<F: Prec>(
    mesh: &Mesh,
    cam: &Camera,
    mode: Mode,
    n: usize,
    note: bool,
) -> Result<Panel> {
    let scene = Scene::<F>::build(mesh)?;
    if let Some(text) = scene.rejected_note().filter(|_| note) {
        eprintln!("{text}");
    }
    let t = tracer::<F>(mode, n)?;
    let r = crate::renderer::render(&scene, cam, t, mesh.diagonal(), true);
    Ok(Panel {
        image: r.image,
        rays: r.rays,
        seconds: r.seconds,
        mask: r.hits,
    })
}

/// Renders [`RenderOptions::source`] (the torus when unset) to a PNG and reports the ray rate
/// and the crack count on stdout (stderr when the PNG goes to stdout).
pub fn run(a: RenderOptions) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 16384 || a.height > 16384 {
        return Err(DemoError::Usage(
            "--width and --height must be in 1..=16384".into(),
        ));
    }
    tracer::<f32>(Mode::Smooth, a.iterations)?;
    let (_, mesh, _) = a.source.load_upright(true, a.up)?;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
    let modes: Vec<Mode> = if a.compare {
        vec![Mode::Smooth, Mode::Flat, Mode::Phong]
    } else {
        vec![a.mode]
    };
    let mut panels = Vec::new();
    for (k, &m) in modes.iter().enumerate() {
        panels.push(render_panel_in(
            a.precision,
            &mesh,
            &cam,
            m,
            a.iterations,
            k == 0,
        )?);
    }
    let prec = a.precision;
    let image = if a.compare {
        let labelled: Vec<(&Image, String)> = panels
            .iter()
            .zip(&modes)
            .map(|(p, m)| {
                let label = match m {
                    Mode::Smooth => format!("SMOOTH N={}", a.iterations),
                    Mode::Flat => "FLAT".to_string(),
                    Mode::Phong => "PHONG".to_string(),
                };
                (&p.image, label)
            })
            .collect();
        side_by_side(&labelled)
    } else {
        panels[0].image.clone()
    };
    image.write_png(&a.out)?;
    if let Some(mask) = &a.mask {
        let p = &panels[0];
        crate::image::write_bytes(
            mask,
            crate::renderer::mask_pbm(a.width, a.height, &p.mask).as_bytes(),
        )?;
    }
    // Cracks between neighbouring patches: primary rays that hit the flat mesh well inside its
    // silhouette (the pixel and its four neighbours hit) but miss the smooth surface.
    let crack = if modes.first() == Some(&Mode::Smooth) {
        let flat_mask = if a.compare {
            None
        } else {
            Some(render_panel_in(a.precision, &mesh, &cam, Mode::Flat, 0, false)?.mask)
        };
        let flat = flat_mask
            .as_deref()
            .or(panels.get(1).map(|p| p.mask.as_slice()));
        flat.map(|f| crate::renderer::crack_misses(a.width, a.height, &panels[0].mask, f))
    } else {
        None
    };
    let rays: u64 = panels.iter().map(|p| p.rays).sum();
    let secs: f64 = panels.iter().map(|p| p.seconds).sum();
    let mode_s = if a.compare {
        "smooth/flat/phong".to_string()
    } else {
        a.mode.name().to_string()
    };
    let msg = format!(
        "wrote {} ({}x{}, {mode_s}, {prec}, iterations N = {}): {rays} rays in {:.3} s = {:.0} rays/s",
        a.out,
        image.width,
        image.height,
        a.iterations,
        secs,
        rays as f64 / secs.max(1e-9)
    );
    let msg = match crack {
        Some((missed, holes, inside)) => format!(
            "{msg}\ncracks: {missed} of {inside} primary rays inside the flat mesh's silhouette missed the smooth surface ({holes} isolated holes)"
        ),
        None => msg,
    };
    if a.out == "-" {
        eprintln!("{msg}");
    } else {
        println!("{msg}");
    }
    Ok(())
}
