//! Command-line interface (clap derive): `render`, `precision`, `trace`, `eval`, `inspect`.

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::error::{DemoError, Result};
use crate::image::Image;
use crate::scene::{Camera, Mode, Prec, Scene, parse_view, tracer};
use crate::scenes::{Mesh, SCENE_NAMES, builtin};

/// Ray tracing of smooth surfaces from triangle meshes with vertex normals.
#[derive(Parser, Debug)]
#[command(name = "smoothtri", version, about)]
pub struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Render a mesh (default: the built-in 8×8 torus) to a PNG.
    Render(RenderArgs),
    /// Sweep the iteration budget and measure hit-point error against an f64 reference.
    Precision(PrecisionArgs),
    /// Trace rays from a CSV file (ox,oy,oz,dx,dy,dz) and print the hits as CSV.
    Trace(TraceArgs),
    /// Evaluate surface points from a CSV file (triangle,w1,w2) and print them as CSV.
    Eval(EvalArgs),
    /// Report mesh statistics: rejected patches, normal angles, cracks, memory.
    Inspect(InspectArgs),
}

/// Floating-point precision of the kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// Single precision (the real-time path).
    F32,
    /// Double precision.
    F64,
}

#[derive(Args, Debug, Clone)]
#[group(multiple = false)]
struct Source {
    /// Mesh file: OBJ, PLY, glTF or GLB.
    #[arg(long, value_name = "PATH")]
    mesh: Option<String>,
    /// Built-in scene.
    #[arg(long, value_parser = SCENE_NAMES)]
    scene: Option<String>,
}

#[derive(Args, Debug)]
struct RenderArgs {
    #[command(flatten)]
    src: Source,
    /// Intersection mode.
    #[arg(long, value_enum, default_value = "smooth")]
    mode: Mode,
    /// Render smooth, flat and phong side by side, labelled.
    #[arg(long)]
    compare: bool,
    /// Iteration budget of the smooth kernel (0..=40).
    #[arg(long, default_value_t = 8)]
    iterations: usize,
    /// Kernel precision.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
    /// Image width (per panel with --compare).
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 480)]
    height: u32,
    /// Output PNG (`-` for stdout).
    #[arg(long, default_value = "smoothtri.png")]
    out: String,
    /// Camera azimuth and elevation in degrees.
    #[arg(long, value_parser = parse_view, default_value = "30,35", allow_hyphen_values = true)]
    view: (f64, f64),
    /// Also write the primary-hit mask as a plain PBM (for tests).
    #[arg(long, hide = true)]
    mask: Option<String>,
}

#[derive(Args, Debug)]
struct PrecisionArgs {
    #[command(flatten)]
    src: Source,
    /// Write the table as CSV (`-` for stdout).
    #[arg(long)]
    csv: Option<String>,
    /// Plot error vs iterations (SVG).
    #[arg(long)]
    plot: Option<String>,
    /// Render a strip of images at each budget with error heat maps (PNG).
    #[arg(long)]
    strip: Option<String>,
    /// Ray grid width.
    #[arg(long, default_value_t = 200)]
    width: u32,
    /// Ray grid height.
    #[arg(long, default_value_t = 150)]
    height: u32,
    /// Camera azimuth and elevation in degrees.
    #[arg(long, value_parser = parse_view, default_value = "30,35", allow_hyphen_values = true)]
    view: (f64, f64),
}

#[derive(Args, Debug)]
struct TraceArgs {
    #[command(flatten)]
    src: Source,
    /// Rays CSV with header ox,oy,oz,dx,dy,dz (`-` for stdin).
    #[arg(long)]
    rays: String,
    /// Iteration budget (0..=40).
    #[arg(long, default_value_t = 8)]
    iterations: usize,
    /// Kernel precision.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
}

#[derive(Args, Debug)]
struct EvalArgs {
    #[command(flatten)]
    src: Source,
    /// Points CSV with header triangle,w1,w2 (`-` for stdin).
    #[arg(long)]
    points: String,
    /// Evaluation precision.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
}

#[derive(Args, Debug)]
struct InspectArgs {
    #[command(flatten)]
    src: Source,
    /// Precision of the patches whose rejections are reported.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
}

/// Entry point of the binary: parses arguments, runs, prints errors, returns the exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Render(a) => cmd_render(a),
        Cmd::Precision(a) => cmd_precision(a),
        Cmd::Trace(a) => {
            let (_, mesh) = load_source(&a.src, false)?;
            match a.precision {
                Precision::F32 => crate::csvio::trace::<f32>(&mesh, &a.rays, a.iterations),
                Precision::F64 => crate::csvio::trace::<f64>(&mesh, &a.rays, a.iterations),
            }
        }
        Cmd::Eval(a) => {
            let (_, mesh) = load_source(&a.src, false)?;
            match a.precision {
                Precision::F32 => crate::csvio::eval::<f32>(&mesh, &a.points),
                Precision::F64 => crate::csvio::eval::<f64>(&mesh, &a.points),
            }
        }
        Cmd::Inspect(a) => {
            let (name, mesh) = load_source(&a.src, false)?;
            let text = match a.precision {
                Precision::F32 => crate::inspect::inspect::<f32>(&name, &mesh)?,
                Precision::F64 => crate::inspect::inspect::<f64>(&name, &mesh)?,
            };
            print!("{text}");
            Ok(())
        }
    }
}

/// Loads `--mesh` or `--scene` (the torus when neither is given and `default_torus`), printing
/// notes about computed normals and skipped primitives on stderr.
fn load_source(src: &Source, default_torus: bool) -> Result<(String, Mesh)> {
    if let Some(path) = &src.mesh {
        let loaded = crate::mesh::load(path)?;
        for w in &loaded.warnings {
            eprintln!("warning: {path}: {w}");
        }
        if loaded.computed_normals {
            eprintln!(
                "note: {path} has no vertex normals (for some or all corners): computed angle-weighted normals"
            );
        }
        return Ok((path.clone(), loaded.mesh));
    }
    let name = match (&src.scene, default_torus) {
        (Some(s), _) => s.clone(),
        (None, true) => "torus".to_string(),
        (None, false) => {
            return Err(DemoError::Usage(
                "one of --mesh PATH or --scene NAME is required".into(),
            ));
        }
    };
    let mesh = builtin(&name).ok_or_else(|| DemoError::Usage(format!("unknown scene '{name}'")))?;
    Ok((format!("{name} (built-in)"), mesh))
}

/// Bounding-box diagonal of a mesh.
pub fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).length()
}

struct Panel {
    image: Image,
    rays: u64,
    seconds: f64,
    mask: Vec<crate::render::PixelHit>,
}

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
    let r = crate::render::render(&scene, cam, t, diagonal(mesh), true);
    Ok(Panel {
        image: r.image,
        rays: r.rays,
        seconds: r.seconds,
        mask: r.hits,
    })
}

fn cmd_render(a: RenderArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 16384 || a.height > 16384 {
        return Err(DemoError::Usage(
            "--width and --height must be in 1..=16384".into(),
        ));
    }
    tracer::<f32>(Mode::Smooth, a.iterations)?;
    let (_, mesh) = load_source(&a.src, true)?;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
    let modes: Vec<Mode> = if a.compare {
        vec![Mode::Smooth, Mode::Flat, Mode::Phong]
    } else {
        vec![a.mode]
    };
    let mut panels = Vec::new();
    for (k, &m) in modes.iter().enumerate() {
        let p = match a.precision {
            Precision::F32 => render_panel::<f32>(&mesh, &cam, m, a.iterations, k == 0)?,
            Precision::F64 => render_panel::<f64>(&mesh, &cam, m, a.iterations, k == 0)?,
        };
        panels.push(p);
    }
    let prec = match a.precision {
        Precision::F32 => "f32",
        Precision::F64 => "f64",
    };
    let image = if a.compare {
        let gap = 4;
        let mut img = Image::new(a.width * 3 + gap * 2, a.height, [255, 255, 255]);
        let scale = if a.width >= 400 { 2 } else { 1 };
        for (k, (p, m)) in panels.iter().zip(&modes).enumerate() {
            let x = (k as u32 * (a.width + gap)) as i64;
            img.blit(&p.image, x, 0);
            let label = match m {
                Mode::Smooth => format!("SMOOTH N={}", a.iterations),
                Mode::Flat => "FLAT".to_string(),
                Mode::Phong => "PHONG".to_string(),
            };
            img.label(&label, x + 4 * scale, 4 * scale, scale, [255, 255, 255]);
        }
        img
    } else {
        panels[0].image.clone()
    };
    image.write_png(&a.out)?;
    if let Some(mask) = &a.mask {
        let p = &panels[0];
        crate::image::write_bytes(
            mask,
            crate::render::mask_pbm(a.width, a.height, &p.mask).as_bytes(),
        )?;
    }
    // Cracks between neighbouring patches: primary rays that hit the flat mesh well inside its
    // silhouette (the pixel and its four neighbours hit) but miss the smooth surface.
    let crack = if modes.first() == Some(&Mode::Smooth) {
        let flat_mask = if a.compare {
            None
        } else {
            Some(match a.precision {
                Precision::F32 => render_panel::<f32>(&mesh, &cam, Mode::Flat, 0, false)?.mask,
                Precision::F64 => render_panel::<f64>(&mesh, &cam, Mode::Flat, 0, false)?.mask,
            })
        };
        let flat = flat_mask
            .as_deref()
            .or(panels.get(1).map(|p| p.mask.as_slice()));
        flat.map(|f| crate::render::crack_misses(a.width, a.height, &panels[0].mask, f))
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

fn cmd_precision(a: PrecisionArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 4096 || a.height > 4096 {
        return Err(DemoError::Usage(
            "--width and --height must be in 1..=4096".into(),
        ));
    }
    let (name, mesh) = load_source(&a.src, true)?;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
    let study = crate::precision::sweep(&mesh, &cam)?;
    println!(
        "precision study: {name}, {} rays ({}x{}), reference f64 N = 40",
        study.rays, a.width, a.height
    );
    print!("{}", study.table());
    if let Some(csv) = &a.csv {
        crate::image::write_bytes(csv, study.csv().as_bytes())?;
    }
    if let Some(plot) = &a.plot {
        study.plot(plot, &name)?;
    }
    if let Some(strip) = &a.strip {
        let img = crate::precision::strip(&mesh, a.view, a.width, a.height)?;
        img.write_png(strip)?;
    }
    Ok(())
}
