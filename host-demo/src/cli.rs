//! Command-line interface: parses the arguments (clap derive) of `render`, `precision`, `trace`,
//! `eval`, `inspect`, `tessellate` and `view` into each command's options struct and runs it ([`crate::commands`]).

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use smoothtri_host::scenes::SCENE_NAMES;

use crate::commands::eval::EvalOptions;
use crate::commands::inspect::InspectOptions;
use crate::commands::precision::PrecisionOptions;
use crate::commands::render::RenderOptions;
use crate::commands::tessellate::TessellateOptions;
use crate::commands::trace::TraceOptions;
use crate::commands::view::ViewOptions;
use crate::commands::{self, MeshSource};
use crate::error::{DemoError, Result};
use crate::tracer::{Field, Mode, Normals, Precision};
use crate::up::Up;
use smoothtri_host::tessellate::Level;

/// Ray tracing of smooth surfaces from triangle meshes with vertex normals.
#[derive(Parser, Debug)]
#[command(name = "smoothtri", version, about)]
pub struct Cli {
    /// Let a glTF file's buffer URIs name files outside its own folder (absolute paths, `..`,
    /// symlinks out of it); for trusted files only. Buffers must still be regular files of at
    /// least their byteLength.
    #[arg(long, global = true)]
    allow_outside_folder: bool,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Render a mesh (default: the built-in 8×8 torus) to a PNG; --time SECONDS: one frame of
    /// its animation.
    Render(RenderArgs),
    /// Sweep the iteration budget and measure hit-point error against an f64 reference.
    Precision(PrecisionArgs),
    /// Trace rays from a CSV file (ox,oy,oz,dx,dy,dz) and print the hits as CSV.
    Trace(TraceArgs),
    /// Evaluate surface points from a CSV file (triangle,w1,w2) and print them as CSV.
    Eval(EvalArgs),
    /// Report mesh statistics: rejected patches, normal angles, cracks, memory.
    Inspect(InspectArgs),
    /// Sample the smooth surface into welded triangles and write them as OBJ, PLY or GLB.
    Tessellate(TessellateArgs),
    /// Show the kernel in real time in a window: orbit with the mouse, zoom with the wheel;
    /// keys M (mode), S (seamless/geometric), Up/Down (N), P (f32/f64), H (error heat map),
    /// R (reset), Space (pause the animation), Esc/Q (quit).
    View(ViewArgs),
}

#[derive(Args, Debug)]
struct ViewArgs {
    #[command(flatten)]
    src: Source,
    #[command(flatten)]
    shot: Shot,
    /// Start with the heat map of each pixel's certified t_error (H switches).
    #[arg(long)]
    heat: bool,
    /// Headless: render K frames at the fixed camera, then exit.
    #[arg(long, value_name = "K")]
    frames: Option<u32>,
    /// Headless: write the last frame as PNG (the same pixels as `render` with this camera).
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<String>,
    /// Headless: write the last frame's primary-hit mask as a plain PBM.
    #[arg(long, value_name = "FILE.pbm")]
    mask: Option<String>,
    /// Play the animation of the glTF file (or --scene twist), looping; Space pauses. Headless,
    /// frame k shows --time + k/30 s.
    #[arg(long)]
    animate: bool,
    #[command(flatten)]
    anim: AnimArgs,
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
    #[command(flatten)]
    shot: Shot,
    /// Render smooth, flat and phong side by side, labelled.
    #[arg(long)]
    compare: bool,
    /// Output PNG (`-` for stdout).
    #[arg(long, default_value = "smoothtri.png")]
    out: String,
    /// Also write the primary-hit mask as a plain PBM (for tests).
    #[arg(long, hide = true)]
    mask: Option<String>,
    /// Also print the scene build's time per step (vertex normals, patches, cracks, seams, BVH)
    /// and the CPU kernel's instruction set (the widest this CPU has; SMOOTHTRI_ISA=sse2, avx2
    /// or avx512 overrides it).
    #[arg(long)]
    verbose: bool,
    /// A shadow-terminator fix for --mode phong: hanika (shadow-ray origin offset) or chiang
    /// (shadowing term).
    #[arg(long, value_enum)]
    terminator: Option<crate::peers::TerminatorFix>,
    #[command(flatten)]
    anim: AnimArgs,
}

/// The animation options of `render` and `view`.
#[derive(Args, Debug)]
struct AnimArgs {
    /// Pose the animation at this time, seconds: a glTF file's animation (clamped to its keys)
    /// or --scene twist. render: several comma-separated times render side by side, labelled;
    /// view --animate: the time to start from.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    time: Option<String>,
    /// The glTF animation to play, by index [default: 0].
    #[arg(long, value_name = "INDEX")]
    clip: Option<usize>,
}

impl AnimArgs {
    /// `--time` as seconds, each a finite number at least 0 (one-line usage errors naming the
    /// value otherwise); empty without `--time`.
    fn times(&self) -> Result<Vec<f64>> {
        let Some(text) = self.time.as_deref() else {
            return Ok(Vec::new());
        };
        text.split(',')
            .map(|s| {
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .and_then(|t| crate::animate::check_time(t).ok())
                    .ok_or_else(|| {
                        crate::error::DemoError::Usage(format!(
                            "--time {}: expected a finite number of seconds, at least 0",
                            s.trim()
                        ))
                    })
            })
            .collect()
    }

    /// `--time` as one time (`view`).
    fn time(&self) -> Result<Option<f64>> {
        match self.times()?.as_slice() {
            [] => Ok(None),
            [t] => Ok(Some(*t)),
            _ => Err(crate::error::DemoError::Usage(
                "view: --time takes one time (the start of --animate)".into(),
            )),
        }
    }
}

/// What `render` and `view` share: the kernel, the frame and the camera (`view` starts from
/// them; its keys change them).
#[derive(Args, Debug)]
struct Shot {
    /// Intersection mode (`render --compare` ignores it; `view`: M switches).
    #[arg(long, value_enum, default_value = "smooth")]
    mode: Mode,
    /// Refinement steps of the smooth kernel, eight evaluations each (render 0..=40, view
    /// 0..=16; f32 reaches its rounding floor from about 3).
    #[arg(long, default_value_t = 4)]
    iterations: usize,
    /// Kernel precision (the GPU traces in f32; `view`: P switches).
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
    /// Image width (per panel with --compare; `view`: the window's).
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 480)]
    height: u32,
    /// Camera azimuth and elevation in degrees, relative to the up axis.
    #[arg(long, value_parser = parse_view, default_value = "30,35", allow_hyphen_values = true)]
    view: (f64, f64),
    /// The mesh's up axis [default: y for mesh files (glTF: always y), z for the built-in scenes].
    #[arg(long, value_enum)]
    up: Option<Up>,
    /// Trace on the GPU (the WGSL port of the kernel, f32; Vulkan, or Mesa's software
    /// lavapipe). Without a Vulkan adapter: one line on stderr and a non-zero exit.
    #[arg(long)]
    gpu: bool,
    /// The normal the smooth mode shades with: seamless (continuous across shared edges) or the
    /// patches' exact geometric normal (`view`: S switches).
    #[arg(long, value_enum, default_value = "seamless")]
    normals: Normals,
    /// The line field of the patches: face (the paper's construction) or vertex (shared by
    /// neighbours, so their edge curves meet).
    #[arg(long, value_enum, default_value = "face")]
    field: Field,
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
    /// Camera azimuth and elevation in degrees, relative to the up axis.
    #[arg(long, value_parser = parse_view, default_value = "30,35", allow_hyphen_values = true)]
    view: (f64, f64),
    /// The mesh's up axis [default: y for mesh files (glTF: always y), z for the built-in scenes].
    #[arg(long, value_enum)]
    up: Option<Up>,
    /// Also sweep the GPU kernel (f32; rows labelled gpu) and render --strip on it. Without a
    /// Vulkan adapter: one line on stderr and a non-zero exit.
    #[arg(long)]
    gpu: bool,
}

#[derive(Args, Debug)]
struct TraceArgs {
    #[command(flatten)]
    src: Source,
    /// Rays CSV with header ox,oy,oz,dx,dy,dz (`-` for stdin).
    #[arg(long)]
    rays: String,
    /// The surface: smooth (the patches), or the peers phong-tess and nagata (w1,w2 then the
    /// barycentrics on that patch, t_error 0).
    #[arg(long, value_enum, default_value = "smooth")]
    mode: Mode,
    /// Refinement steps, eight evaluations each (0..=40).
    #[arg(long, default_value_t = 4)]
    iterations: usize,
    /// Kernel precision.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
    /// The line field of the patches: face (the paper's construction) or vertex (shared by
    /// neighbours, so their edge curves meet).
    #[arg(long, value_enum, default_value = "face")]
    field: Field,
    /// The normal of the snx,sny,snz columns: seamless (continuous across shared edges, what
    /// `render` shades with) or the patches' exact geometric normal (then equal to nx,ny,nz).
    #[arg(long, value_enum, default_value = "seamless")]
    normals: Normals,
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
    /// The normal of the snx,sny,snz columns: seamless (continuous across shared edges, what
    /// `render` shades with) or the patches' exact geometric normal (then equal to nx,ny,nz).
    #[arg(long, value_enum, default_value = "seamless")]
    normals: Normals,
}

#[derive(Args, Debug)]
struct InspectArgs {
    #[command(flatten)]
    src: Source,
    /// Precision of the patches whose rejections are reported.
    #[arg(long, value_enum, default_value = "f32")]
    precision: Precision,
    /// The line field of the patches: face (the paper's construction) or vertex (shared by
    /// neighbours, so their edge curves meet).
    #[arg(long, value_enum, default_value = "face")]
    field: Field,
}

#[derive(Args, Debug)]
struct TessellateArgs {
    #[command(flatten)]
    src: Source,
    /// Sub-triangles per patch: L×L (1..=256) [default: 4 unless --max-error is given].
    #[arg(long, value_name = "L", conflicts_with = "max_error")]
    level: Option<u32>,
    /// Instead of --level: per patch the smallest power-of-two level whose measured distance
    /// to the surface is at most E (mesh units); shared edges take the larger level.
    #[arg(long, value_name = "E")]
    max_error: Option<f64>,
    /// Cap of the levels chosen by --max-error (a power of two).
    #[arg(long, value_name = "L", default_value_t = 64)]
    max_level: u32,
    /// Output file: .obj, .ply (binary) or .glb.
    #[arg(long)]
    out: String,
    /// Precision of the patches and of the numbers written (GLB stores f32 only).
    #[arg(long, value_enum, default_value = "f64")]
    precision: Precision,
    /// Also render the traced smooth surface beside the flat-shaded tessellation (PNG).
    #[arg(long, value_name = "PNG")]
    picture: Option<String>,
    /// Width of each panel of --picture.
    #[arg(long, default_value_t = 480)]
    width: u32,
    /// Height of --picture.
    #[arg(long, default_value_t = 360)]
    height: u32,
    /// Camera azimuth and elevation of --picture, relative to the up axis.
    #[arg(long, value_parser = parse_view, default_value = "30,35", allow_hyphen_values = true)]
    view: (f64, f64),
    /// The mesh's up axis, for --picture (the output keeps the file's coordinates) [default: y
    /// for mesh files (glTF: always y), z for the built-in scenes].
    #[arg(long, value_enum)]
    up: Option<Up>,
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
    // A `SMOOTHTRI_ISA` that names no instruction set, or one this CPU lacks, is a usage error
    // here (the C library falls back to the best the CPU has).
    smoothtri_isa::Kernels::from_env().map_err(|e| DemoError::Usage(e.to_string()))?;
    let allow = cli.allow_outside_folder;
    match cli.cmd {
        Cmd::Render(a) => commands::render::run(RenderOptions {
            source: a.src.mesh_source(allow),
            mode: a.shot.mode,
            compare: a.compare,
            iterations: a.shot.iterations,
            precision: a.shot.precision,
            width: a.shot.width,
            height: a.shot.height,
            out: a.out,
            view: a.shot.view,
            up: a.shot.up,
            mask: a.mask,
            gpu: a.shot.gpu,
            normals: a.shot.normals,
            field: a.shot.field.into(),
            verbose: a.verbose,
            terminator: a.terminator,
            time: a.anim.times()?,
            clip: a.anim.clip,
        }),
        Cmd::View(a) => commands::view::run(ViewOptions {
            source: a.src.mesh_source(allow),
            mode: a.shot.mode,
            iterations: a.shot.iterations,
            precision: a.shot.precision,
            width: a.shot.width,
            height: a.shot.height,
            view: a.shot.view,
            up: a.shot.up,
            gpu: a.shot.gpu,
            normals: a.shot.normals,
            field: a.shot.field.into(),
            heat: a.heat,
            frames: a.frames,
            screenshot: a.screenshot,
            mask: a.mask,
            animate: a.animate,
            time: a.anim.time()?,
            clip: a.anim.clip,
        }),
        Cmd::Precision(a) => commands::precision::run(PrecisionOptions {
            source: a.src.mesh_source(allow),
            csv: a.csv,
            plot: a.plot,
            strip: a.strip,
            width: a.width,
            height: a.height,
            view: a.view,
            up: a.up,
            gpu: a.gpu,
        }),
        Cmd::Trace(a) => commands::trace::run(TraceOptions {
            source: a.src.mesh_source(allow),
            rays: a.rays,
            mode: a.mode,
            iterations: a.iterations,
            precision: a.precision,
            field: a.field.into(),
            normals: a.normals,
        }),
        Cmd::Eval(a) => commands::eval::run(EvalOptions {
            source: a.src.mesh_source(allow),
            points: a.points,
            precision: a.precision,
            normals: a.normals,
        }),
        Cmd::Inspect(a) => commands::inspect::run(InspectOptions {
            source: a.src.mesh_source(allow),
            precision: a.precision,
            field: a.field.into(),
        }),
        Cmd::Tessellate(a) => commands::tessellate::run(TessellateOptions {
            source: a.src.mesh_source(allow),
            level: match a.max_error {
                Some(max_error) => Level::MaxError {
                    max_error,
                    max_level: a.max_level,
                },
                None => Level::Uniform(a.level.unwrap_or(4)),
            },
            out: a.out,
            precision: a.precision,
            picture: a.picture,
            size: (a.width, a.height),
            view: a.view,
            up: a.up,
        }),
    }
}

impl Source {
    /// The command's [`MeshSource`], glTF buffers allowed outside the file's folder when
    /// `allow_outside_folder` (`--allow-outside-folder`).
    fn mesh_source(self, allow_outside_folder: bool) -> MeshSource {
        MeshSource {
            mesh: self.mesh,
            scene: self.scene,
            allow_outside_folder,
        }
    }
}

/// Parses `--view` values: `"AZ,EL"` in degrees, elevation within [-90, 90].
pub fn parse_view(s: &str) -> std::result::Result<(f64, f64), String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("expected AZ,EL in degrees, got '{s}'"))?;
    let a: f64 = a
        .trim()
        .parse()
        .map_err(|_| format!("malformed azimuth '{a}'"))?;
    let e: f64 = e
        .trim()
        .parse()
        .map_err(|_| format!("malformed elevation '{e}'"))?;
    if !a.is_finite() || !e.is_finite() || e.abs() > 90.0 {
        return Err(format!(
            "view angles must be finite, elevation within [-90, 90]: '{s}'"
        ));
    }
    Ok((a, e))
}
