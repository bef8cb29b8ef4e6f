//! `smoothtri tessellate`: the smooth surface sampled into welded triangles and written as OBJ,
//! PLY or GLB for other renderers ([`smoothtri_host::tessellate`] has the rules), with the measured
//! distance to the smooth surface and, optionally, a picture of both.

use std::fmt::Write as _;

use smoothtri_host::Camera;
use smoothtri_io::Mesh;

use super::render::{check_outputs, check_size};
use super::source::MeshSource;
use crate::error::{DemoError, Result};
use crate::output::Format;
use crate::tracer::{Mode, Prec, Precision, Scene};
use crate::up::Up;
use smoothtri_host::tessellate::{
    Level, TessellateError, Tessellation, max_distance, max_distance_to, surface_distance_to,
    tessellate,
};

/// Options of `tessellate`.
#[derive(Clone, Debug)]
pub struct TessellateOptions {
    /// The mesh (required).
    pub source: MeshSource,
    /// Uniform level or per-patch error target.
    pub level: Level,
    /// Output file: `.obj`, `.ply` or `.glb`.
    pub out: String,
    /// Precision of the patches and of the numbers written (GLB: always `f32`).
    pub precision: Precision,
    /// Also render the traced smooth surface beside the flat-shaded tessellation to this PNG.
    pub picture: Option<String>,
    /// Size of each panel of the picture.
    pub size: (u32, u32),
    /// Camera azimuth and elevation of the picture, relative to the up axis.
    pub view: (f64, f64),
    /// The mesh's up axis for the picture (`None`: the source's default).
    pub up: Option<Up>,
}

/// Largest uniform level and `--max-level` accepted.
pub const MAX_LEVEL: u32 = 256;

/// Checks the options that need no mesh: the level, the error target, the picture's size and
/// the outputs ([`crate::output::check`]: `--out` an `.obj`, `.ply` or `.glb`, `--picture` a
/// `.png`, neither the `--mesh` file nor each other).
fn check(a: &TessellateOptions) -> Result<()> {
    match a.level {
        Level::Uniform(l) if !(1..=MAX_LEVEL).contains(&l) => {
            return Err(DemoError::Usage(format!(
                "--level must be in 1..={MAX_LEVEL}, got {l}"
            )));
        }
        Level::MaxError {
            max_error,
            max_level,
        } => {
            if !(max_error.is_finite() && max_error > 0.0) {
                return Err(DemoError::Usage(format!(
                    "--max-error must be a positive distance, got {max_error}"
                )));
            }
            if !max_level.is_power_of_two() || max_level > MAX_LEVEL {
                return Err(DemoError::Usage(format!(
                    "--max-level must be a power of two up to {MAX_LEVEL}, got {max_level}"
                )));
            }
        }
        Level::Uniform(_) => {}
    }
    if a.picture.is_some() {
        let (w, h) = a.size;
        check_size(w, h, 16384)?;
    }
    // The output format is chosen by extension; neither output may be the input or the other.
    check_outputs(
        &a.source,
        &[
            ("--out", Some(a.out.as_str()), Format::Mesh),
            ("--picture", a.picture.as_deref(), Format::Png),
        ],
    )
}

/// Loads the mesh, tessellates it, writes `--out` and prints the report on stdout.
pub fn run(a: TessellateOptions) -> Result<()> {
    check(&a)?;
    // The up axis only frames the picture (the output keeps the file's coordinates), but a
    // wrong one is reported, before the work.
    a.source.up_axis(a.up)?;
    let (name, mesh) = a.source.load(false)?;
    let text = match a.precision {
        Precision::F32 => run_in::<f32>(&a, &name, &mesh)?,
        Precision::F64 => run_in::<f64>(&a, &name, &mesh)?,
    };
    print!("{text}");
    Ok(())
}

/// `levels: 12 × 1, 40 × 2, 76 × 4` of a per-patch level list.
fn level_summary(levels: &[u32]) -> String {
    let mut m = std::collections::BTreeMap::new();
    for &l in levels {
        *m.entry(l).or_insert(0usize) += 1;
    }
    m.iter()
        .map(|(l, n)| format!("{n} × L = {l}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The work of [`run`] in precision `F`; returns the report.
fn run_in<F: Prec>(a: &TessellateOptions, name: &str, mesh: &Mesh) -> Result<String> {
    let start = std::time::Instant::now();
    let scene = Scene::<F>::build(mesh)?;
    if let Some(note) = scene.rejected_note() {
        eprintln!("{note}");
    }
    let t = tessellate(mesh, &scene.core(), a.level).map_err(|e| match e {
        TessellateError::TooLarge { .. } => DemoError::Usage(format!(
            "{e}: choose a lower --level or a larger --max-error"
        )),
        TessellateError::SceneMismatch { .. } => DemoError::Usage(e.to_string()),
    })?;
    let level_s = match a.level {
        Level::Uniform(l) => format!("level {l}"),
        Level::MaxError { max_error, .. } => format!("max error {max_error:e}"),
    };
    let comment = format!(
        "smoothtri tessellate: {name}, {level_s}, {}, {} triangles, {} vertices",
        F::PRECISION,
        t.mesh.triangles.len(),
        t.mesh.positions.len()
    );
    let encoded = smoothtri_io::encode(&t.mesh, &a.out, F::PRECISION.into(), &comment)?;
    crate::output::write(&a.out, &encoded)?;
    let bytes = encoded.len();
    let secs = start.elapsed().as_secs_f64();
    let diag = mesh.diagonal();
    let dist = max_distance(&t, &scene.core());
    let mut s = String::new();
    let _ = writeln!(
        s,
        "tessellated {name}: {} patches, {} ({})",
        scene.patches().len(),
        match a.level {
            Level::Uniform(l) => format!("level {l} ({} sub-triangles each)", l * l),
            Level::MaxError { .. } => level_summary(&t.levels),
        },
        F::PRECISION
    );
    let _ = writeln!(
        s,
        "wrote {}: {} triangles, {} vertices, {bytes} bytes ({secs:.2} s)",
        a.out,
        t.mesh.triangles.len(),
        t.mesh.positions.len()
    );
    let _ = writeln!(
        s,
        "max distance to the smooth surface: {:.3e} ({:.2e} of the bounding-box diagonal, on \
         triangle {})",
        dist.max,
        dist.max / diag.max(f64::MIN_POSITIVE),
        dist.worst_triangle
    );
    if !scene.remedied().is_empty() {
        let _ = writeln!(
            s,
            "  over the {} patches with their normals as given (not clamped): {:.3e}",
            scene.report().patches - scene.remedied().len(),
            dist.max_unclamped
        );
    }
    if let Level::MaxError {
        max_error,
        max_level,
    } = a.level
        && t.capped > 0
    {
        let _ = writeln!(
            s,
            "note: {} patches reached --max-level {max_level} with their bound still above \
             {max_error:e}",
            t.capped
        );
    }
    let w = &t.weld;
    let _ = writeln!(
        s,
        "welded {} edge samples on {} shared edges; before welding the two sides were at most \
         {:.1e} apart (mean {:.1e}), each welded sample is their midpoint",
        w.welded_samples, w.shared_edges, w.max_gap, w.mean_gap
    );
    if let Some((surface, f)) = a
        .source
        .scene
        .as_deref()
        .and_then(smoothtri_host::scenes::exact_distance)
    {
        let _ = writeln!(
            s,
            "max distance to the exact {surface}: {:.3e} (the smooth surface itself: {:.3e})",
            max_distance_to(&t, f),
            surface_distance_to(&scene.core(), f)
        );
    }
    if F::PRECISION == Precision::F64 && smoothtri_io::extension(&a.out).as_deref() == Some("glb") {
        let _ = writeln!(s, "note: glTF stores f32: the numbers were rounded to f32");
    }
    if let Some(pic) = &a.picture {
        picture(a, mesh, &t, pic)?;
        let _ = writeln!(s, "wrote {pic}");
    }
    Ok(s)
}

/// Renders the traced smooth surface of `mesh` and the flat-shaded tessellation side by side,
/// through the same camera, to `path`.
fn picture(a: &TessellateOptions, mesh: &Mesh, t: &Tessellation, path: &str) -> Result<()> {
    let up = a.source.up_axis(a.up)?;
    let (mesh, tess) = (up.mesh_to_z_up(mesh), up.mesh_to_z_up(&t.mesh));
    let (w, h) = a.size;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, w, h);
    let smooth = super::render::render_panel_in(a.precision, &mesh, &cam, Mode::Smooth, 4, false)?;
    let flat = super::render::render_panel_in(a.precision, &tess, &cam, Mode::Flat, 0, false)?;
    let label = match a.level {
        Level::Uniform(l) => format!("TESSELLATED L={l}, FLAT"),
        Level::MaxError { max_error, .. } => format!("TESSELLATED E={max_error:e}, FLAT"),
    };
    let img = super::render::side_by_side(&[
        (&smooth.image, "TRACED SMOOTH N=4".to_string()),
        (&flat.image, label),
    ]);
    img.write_png(path)
}
