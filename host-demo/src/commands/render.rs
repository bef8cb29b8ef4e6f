//! `smoothtri render`: a mesh (default: the built-in torus) to a PNG, one mode or smooth, flat
//! and phong side by side; on the CPU, or with `--gpu` on the GPU kernel
//! ([`crate::gpu::render_gpu`]).

use std::any::Any;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

use smoothtri::LineField;
use smoothtri_gpu::Gpu;
use smoothtri_host::Camera;
use smoothtri_io::Mesh;

use crate::animate::{Animation, check_time, frame};
use crate::error::{DemoError, Result};
use crate::gpu::{open_gpu, render_gpu};
use crate::image::Image;
use crate::output::Format;
use crate::tracer::{Mode, Normals, Prec, Precision, Scene, tracer};
use crate::up::Up;

use super::source::MeshSource;

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
    /// Trace on the GPU (`smoothtri-gpu`, f32) instead of the CPU.
    pub gpu: bool,
    /// The normal the smooth mode shades with.
    pub normals: Normals,
    /// The line field the patches are built on (`smoothtri::LineField`).
    pub field: LineField,
    /// Print the build's time per step (`--verbose`).
    pub verbose: bool,
    /// A shadow-terminator fix for `Mode::Phong` ([`crate::peers`]).
    pub terminator: Option<crate::peers::TerminatorFix>,
    /// Render the source's animation at these times, seconds (`--time`; [`crate::animate`]):
    /// one frame, or several side by side ([`render_strip`]); empty: the static
    /// mesh.
    pub time: Vec<f64>,
    /// The animation's clip (`--clip`, with `time`; default the first).
    pub clip: Option<usize>,
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

/// What `render` prints on stderr about a scene it builds.
#[derive(Clone, Copy, Debug, Default)]
pub struct Note {
    /// The note about skipped and clamped triangles.
    pub skipped: bool,
    /// The build's time per step (`--verbose`).
    pub timing: bool,
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
    let shot = Shot {
        mesh,
        cam,
        mode,
        n,
        note: Note {
            skipped: note,
            timing: false,
        },
        normals: Normals::default(),
        field: LineField::Face,
    };
    render_panel_with(&SceneCache::default(), prec, shot)
}

/// [`render_panel_in`] shading smooth hits with the shot's normals, the patches on its field.
fn render_panel_with(cache: &SceneCache, prec: Precision, shot: Shot<'_>) -> Result<Panel> {
    match prec {
        Precision::F32 => render_panel::<f32>(cache, shot),
        Precision::F64 => render_panel::<f64>(cache, shot),
    }
}

/// One panel to render: `mesh` through `cam` in `mode` with budget `n`, smooth hits shaded with
/// `normals`, the patches on `field`; `note` says what to print about the scene it builds.
#[derive(Clone, Copy)]
struct Shot<'a> {
    mesh: &'a Mesh,
    cam: &'a Camera,
    mode: Mode,
    n: usize,
    note: Note,
    normals: Normals,
    field: LineField,
}

impl Shot<'_> {
    /// Whether the panel's scene has seams: only the smooth mode shades with them.
    fn seams(&self) -> bool {
        self.normals == Normals::Seamless && self.mode == Mode::Smooth
    }
}

/// Panels of equal size side by side, 4 white pixels apart, each with its label in the top
/// left corner (the layout of `render --compare`).
pub fn side_by_side(panels: &[(&Image, String)]) -> Image {
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

/// The first scene a `render` call built (any precision) and whether it has seams: the flat and
/// Phong panels, and the flat silhouettes of the crack check, trace its patches again instead
/// of building them twice (the patches and their crack closure are the same with or without
/// seams, and those modes never shade with the seams).
#[derive(Default)]
pub(crate) struct SceneCache(RefCell<Option<(Rc<dyn Any>, bool)>>);

impl SceneCache {
    /// The cached scene if it is in precision `F` and serves a panel in `mode` that needs
    /// `seams` (or not).
    fn get<F: Prec>(&self, mode: Mode, seams: bool) -> Option<Rc<Scene<F>>> {
        let cached = self.0.borrow();
        let (scene, has) = cached.as_ref()?;
        if mode == Mode::Smooth && *has != seams {
            return None;
        }
        Rc::clone(scene).downcast::<Scene<F>>().ok()
    }
}

/// Builds the scene in precision `F` (or takes it from `cache`) and renders one panel of `shot`;
/// its note prints the scene's note about skipped or clamped triangles.
fn render_panel<F: Prec>(cache: &SceneCache, shot: Shot<'_>) -> Result<Panel> {
    let seams = shot.seams();
    let scene = match cache.get::<F>(shot.mode, seams) {
        Some(scene) => scene,
        None => {
            let scene = Rc::new(build_scene::<F>(shot.mesh, shot.note, shot.field, seams)?);
            let mut slot = cache.0.borrow_mut();
            if slot.is_none() {
                *slot = Some((Rc::clone(&scene) as Rc<dyn Any>, seams));
            }
            scene
        }
    };
    let t = tracer::<F>(shot.mode, shot.n)?;
    let r = crate::renderer::render(&scene, shot.cam, t, shot.mesh.diagonal(), true);
    Ok(Panel::from(r))
}

/// The scene of `mesh` in precision `F` on `field`; `note` prints its note about skipped or
/// clamped triangles.
pub(crate) fn build_scene<F: Prec>(
    mesh: &Mesh,
    note: Note,
    field: LineField,
    seams: bool,
) -> Result<Scene<F>> {
    let scene = Scene::<F>::build_with(mesh, field, seams)?;
    if let Some(text) = scene.rejected_note().filter(|_| note.skipped) {
        eprintln!("{text}");
    }
    if note.timing {
        eprintln!("build ({}): {}", F::PRECISION, scene.timing_line());
    }
    Ok(scene)
}

impl From<crate::renderer::Rendered> for Panel {
    fn from(r: crate::renderer::Rendered) -> Self {
        Panel {
            image: r.image,
            rays: r.rays,
            seconds: r.seconds,
            mask: r.hits,
        }
    }
}

/// [`render_panel`] on the GPU (f32).
fn render_panel_gpu(gpu: &Arc<Gpu>, shot: Shot<'_>) -> Result<Panel> {
    // As on the CPU: the smooth mode with seamless normals shades with the seams (before, the
    // GPU panel was built without them and shaded with the geometric normal).
    let mut scene = build_scene::<f32>(shot.mesh, shot.note, shot.field, shot.seams())?;
    scene.normals = shot.normals;
    let r = render_gpu(
        gpu,
        &scene,
        shot.cam,
        shot.mode,
        shot.n,
        shot.mesh.diagonal(),
    )?;
    Ok(Panel::from(r))
}

/// Checks a command's `outputs` (flag, path if given, format) before any work
/// ([`crate::output::check`]): each named for its format, none the `--mesh` file of `source` nor
/// another output; `render`, `view` and `precision` check theirs with it.
pub(crate) fn check_outputs(
    source: &MeshSource,
    outputs: &[(&'static str, Option<&str>, Format)],
) -> Result<()> {
    crate::output::check(
        &crate::output::inputs(&[("--mesh", source.mesh.as_deref())]),
        &crate::output::outputs(outputs),
    )
}

/// Refuses a `--width` or `--height` outside `1..=max` (a usage error); `render`, `view`,
/// `precision` and `tessellate` check their sizes with it.
pub(crate) fn check_size(width: u32, height: u32, max: u32) -> Result<()> {
    if width == 0 || height == 0 || width > max || height > max {
        return Err(DemoError::Usage(format!(
            "--width and --height must be in 1..={max}"
        )));
    }
    Ok(())
}

/// Prints `msg` on stdout, or on stderr when the PNG goes to stdout (`out` is `-`).
fn report(out: &str, msg: &str) {
    if out == "-" {
        eprintln!("{msg}");
    } else {
        println!("{msg}");
    }
}

/// Renders [`RenderOptions::source`] (the torus when unset) to a PNG and reports the ray rate
/// and the crack count on stdout (stderr when the PNG goes to stdout).
///
/// Before any work the outputs are checked ([`crate::output::check`]): `--out` a `.png` (or
/// `-`), `--mask` a `.pbm`, neither the `--mesh` file nor each other.
pub fn run(a: RenderOptions) -> Result<()> {
    check_outputs(
        &a.source,
        &[
            ("--out", Some(a.out.as_str()), Format::Png),
            ("--mask", a.mask.as_deref(), Format::Pbm),
        ],
    )?;
    check_size(a.width, a.height, 16384)?;
    tracer::<f32>(Mode::Smooth, a.iterations)?;
    if a.time.len() > 1 {
        return render_strip(&a);
    }
    if !a.compare && (crate::peers::peer_of(a.mode).is_some() || a.terminator.is_some()) {
        if !a.time.is_empty() {
            return Err(DemoError::Usage(
                "--time renders smoothtri's own modes: leave --mode phong-tess|nagata and --terminator out".into(),
            ));
        }
        return render_peers(&a);
    }
    let gpu = if a.gpu {
        if a.precision != Precision::F32 {
            return Err(DemoError::Usage(
                "--gpu traces in f32: leave --precision out or set it to f32".into(),
            ));
        }
        Some(open_gpu()?)
    } else {
        None
    };
    let (mesh, cam) = match a.time.as_slice() {
        &[t] => frame(&a.source, a.up, a.clip, t, a.view, (a.width, a.height))?,
        _ if a.clip.is_some() => {
            return Err(DemoError::Usage("--clip needs --time SECONDS".into()));
        }
        _ => {
            let (_, mesh, _) = a.source.load_upright(true, a.up)?;
            let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
            (mesh, cam)
        }
    };
    let modes: Vec<Mode> = if a.compare {
        vec![Mode::Smooth, Mode::Flat, Mode::Phong]
    } else {
        vec![a.mode]
    };
    let mut panels = Vec::new();
    let cache = SceneCache::default();
    let panel = |mode: Mode, n: usize, first: bool| {
        let shot = Shot {
            mesh: &mesh,
            cam: &cam,
            mode,
            n,
            note: Note {
                skipped: first,
                timing: first && a.verbose,
            },
            normals: a.normals,
            field: a.field,
        };
        match &gpu {
            Some(g) => render_panel_gpu(g, shot),
            None => render_panel_with(&cache, a.precision, shot),
        }
    };
    for (k, &m) in modes.iter().enumerate() {
        panels.push(panel(m, a.iterations, k == 0)?);
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
                    other => other.name().to_uppercase(),
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
        crate::output::write(
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
            Some(panel(Mode::Flat, 0, false)?.mask)
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
    if a.verbose && gpu.is_none() {
        eprintln!("CPU kernel: {}", smoothtri_isa::kernels().isa());
    }
    let device = match &gpu {
        Some(g) if g.is_software() => format!(
            ", GPU kernel on {} (software Vulkan: a correctness run, not a GPU timing)",
            g.adapter_name()
        ),
        Some(g) => format!(", GPU kernel on {}", g.adapter_name()),
        None => String::new(),
    };
    let msg = format!(
        "wrote {} ({}x{}, {mode_s}, {prec}, iterations N = {}, {} normals{device}): {rays} rays in {:.3} s = {:.0} rays/s",
        a.out,
        image.width,
        image.height,
        a.iterations,
        a.normals.name(),
        secs,
        rays as f64 / secs.max(1e-9)
    );
    let msg = match crack {
        Some((missed, holes, inside)) => format!(
            "{msg}\ncracks: {missed} of {inside} primary rays inside the flat mesh's silhouette missed the smooth surface ({holes} isolated holes)"
        ),
        None => msg,
    };
    report(&a.out, &msg);
    Ok(())
}

/// `render` of a peer surface or with a terminator fix ([`crate::peers`], CPU only).
fn render_peers(a: &RenderOptions) -> Result<()> {
    if a.gpu {
        return Err(DemoError::Usage(
            "--gpu does not trace --mode phong-tess or nagata, nor --terminator".into(),
        ));
    }
    let (_, mesh, _) = a.source.load_upright(true, a.up)?;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
    let s = crate::peers::render_image(&mesh, &cam, a.mode, a.terminator, a.precision)?;
    s.image.write_png(&a.out)?;
    if let Some(mask) = &a.mask {
        let hits: Vec<crate::renderer::PixelHit> = s
            .pixels
            .iter()
            .map(|p| crate::renderer::PixelHit {
                hit: p.hit,
                ..crate::renderer::PixelHit::default()
            })
            .collect();
        crate::output::write(
            mask,
            crate::renderer::mask_pbm(a.width, a.height, &hits).as_bytes(),
        )?;
    }
    let fix = a
        .terminator
        .map_or(String::new(), |f| format!(", terminator fix {}", f.name()));
    let msg = format!(
        "wrote {} ({}x{}, {}{fix}, {}): {} rays in {:.3} s = {:.0} rays/s",
        a.out,
        a.width,
        a.height,
        a.mode.name(),
        a.precision,
        s.rays,
        s.seconds,
        s.rays as f64 / s.seconds.max(1e-9)
    );
    report(&a.out, &msg);
    Ok(())
}

/// `render --time T1,T2,…`: the animation at each time side by side (smooth, flat or Phong as
/// `--mode` says, on the CPU), each panel labelled with its time, one camera framing the whole
/// clip; written to `--out` with a line on stdout (stderr when the PNG goes to stdout).
///
/// Returns a usage error with `--compare`, `--gpu` or `--mask` (one time each), and the errors
/// of [`frame`] and of the renders.
pub fn render_strip(a: &RenderOptions) -> Result<()> {
    if a.compare || a.gpu || a.mask.is_some() {
        return Err(DemoError::Usage(
            "several --time values render one panel each on the CPU: leave out --compare, \
             --gpu and --mask"
                .into(),
        ));
    }
    let times: Vec<f64> = a
        .time
        .iter()
        .map(|&t| check_time(t))
        .collect::<Result<_>>()?;
    let mut anim = Animation::open(&a.source, a.up, a.clip)?;
    let (c, r) = anim.sphere()?;
    let cam = Camera::look_at_sphere(c, r, a.view.0, a.view.1, a.width, a.height);
    let mut mesh = anim.rest();
    let (mut panels, mut rays, mut seconds) = (Vec::new(), 0, 0.0);
    for (k, &t) in times.iter().enumerate() {
        anim.pose(t, &mut mesh)?;
        let shot = Shot {
            mesh: &mesh,
            cam: &cam,
            mode: a.mode,
            n: a.iterations,
            note: Note {
                skipped: k == 0,
                timing: a.verbose,
            },
            normals: a.normals,
            field: a.field,
        };
        let p = render_panel_with(&SceneCache::default(), a.precision, shot)?;
        rays += p.rays;
        seconds += p.seconds;
        panels.push((p.image, format!("T={t} S")));
    }
    let labelled: Vec<_> = panels.iter().map(|(i, l)| (i, l.clone())).collect();
    let image = side_by_side(&labelled);
    image.write_png(&a.out)?;
    let msg = format!(
        "wrote {} ({}x{}, {}, {} at {} times, {}, iterations N = {}): {rays} rays in {seconds:.3} s",
        a.out,
        image.width,
        image.height,
        anim.name,
        a.mode.name(),
        times.len(),
        a.precision,
        a.iterations
    );
    report(&a.out, &msg);
    Ok(())
}
