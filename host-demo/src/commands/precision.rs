//! `smoothtri precision`: precision versus iteration budget, the hit-point error of f32 and
//! f64 runs at each budget of [`BUDGETS`] against an `f64` reference at N = 40; with `--gpu`
//! also the GPU kernel (f32) at each budget, rows labelled `gpu`.

use std::fmt::Write as _;
use std::sync::Arc;

use glam::DVec3;
use smoothtri::Ray;
use smoothtri_gpu::{Gpu, GpuScene};
use smoothtri_host::{Camera, ErrorStats, Traced, error_stats};
use smoothtri_io::Mesh;

use super::render::{check_outputs, check_size};
use super::source::MeshSource;
use crate::error::{DemoError, Result};
use crate::image::{Image, heat};
use crate::output::Format;
use crate::tracer::{Mode, Prec, Precision, Scene, tracer};
use crate::up::Up;

/// Options of `precision`.
#[derive(Clone, Debug)]
pub struct PrecisionOptions {
    /// The mesh (the torus scene when unset).
    pub source: MeshSource,
    /// Write the table as CSV (`-` for stdout).
    pub csv: Option<String>,
    /// Plot error vs iterations (SVG).
    pub plot: Option<String>,
    /// Render a strip of images at each budget with error heat maps (PNG).
    pub strip: Option<String>,
    /// Ray grid width, 1..=4096.
    pub width: u32,
    /// Ray grid height, 1..=4096.
    pub height: u32,
    /// Camera azimuth and elevation in degrees, relative to the up axis.
    pub view: (f64, f64),
    /// The mesh's up axis (`None`: the source's default, [`MeshSource::up_axis`]).
    pub up: Option<Up>,
    /// Also sweep the GPU kernel (f32), and render the strip on it.
    pub gpu: bool,
}

/// Runs the study on [`PrecisionOptions::source`] (the torus when unset): the table on stdout,
/// and the CSV, plot and strip where asked.
///
/// Before any work the outputs are checked ([`crate::output::check`]): `--csv` a `.csv` (or
/// `-`), `--plot` an `.svg`, `--strip` a `.png`, none the `--mesh` file nor another output.
pub fn run(a: PrecisionOptions) -> Result<()> {
    check_outputs(
        &a.source,
        &[
            ("--csv", a.csv.as_deref(), Format::Csv),
            ("--plot", a.plot.as_deref(), Format::Svg),
            ("--strip", a.strip.as_deref(), Format::Png),
        ],
    )?;
    check_size(a.width, a.height, 4096)?;
    let gpu = if a.gpu {
        Some(crate::gpu::open_gpu()?)
    } else {
        None
    };
    let (name, mesh, _) = a.source.load_upright(true, a.up)?;
    let cam = Camera::for_mesh(&mesh, a.view.0, a.view.1, a.width, a.height);
    let study = sweep_with(&mesh, &cam, gpu.as_ref())?;
    println!(
        "precision study: {name}, {} rays ({}x{}), reference f64 N = 40",
        study.rays, a.width, a.height
    );
    if let Some(g) = &gpu {
        let soft = if g.is_software() {
            " (software Vulkan: its ns/ray are not GPU timings)"
        } else {
            ""
        };
        println!(
            "gpu rows: the GPU kernel (f32) on {}{soft}",
            g.adapter_name()
        );
    }
    print!("{}", study.table());
    if let Some(csv) = &a.csv {
        crate::output::write(csv, study.csv().as_bytes())?;
    }
    if let Some(plot) = &a.plot {
        study.plot(plot, &name)?;
    }
    if let Some(out) = &a.strip {
        let img = strip_with(&mesh, a.view, a.width, a.height, gpu.as_ref())?;
        img.write_png(out)?;
    }
    Ok(())
}

/// The budgets swept.
pub const BUDGETS: [usize; 7] = [0, 1, 2, 4, 8, 16, 24];
/// The reference budget (f64).
pub const REFERENCE_N: usize = 40;

/// One (precision, budget) row of the study. Errors are relative to the bounding-box diagonal.
#[derive(Clone, Debug)]
pub struct Row {
    /// Precision of the run.
    pub precision: Precision,
    /// Whether the run was the GPU kernel (f32; labelled `gpu` in the table and the CSV).
    pub gpu: bool,
    /// Iteration budget.
    pub iterations: usize,
    /// The hit-point errors, `t_error`s, bound coverage and disagreements against the
    /// reference ([`error_stats`]; rays have unit directions, so `mean_t_error` is relative to
    /// the diagonal too).
    pub stats: ErrorStats,
    /// Time per primary ray, nanoseconds (one thread; GPU rows: the whole batch's wall time,
    /// transfers included, per ray).
    pub ns_per_ray: f64,
}

/// A row's values in the order of [`CSV_HEADER`] and of the table's columns.
type Values = (
    &'static str,
    usize,
    usize,
    f64,
    f64,
    f64,
    f64,
    f64,
    usize,
    f64,
);

impl Row {
    /// The label of the run: `f32`, `f64` or `gpu`.
    pub fn label(&self) -> &'static str {
        if self.gpu {
            "gpu"
        } else {
            self.precision.name()
        }
    }

    /// The row's values, as the table and the CSV write them (in their columns' order).
    fn values(&self) -> Values {
        (
            self.label(),
            self.iterations,
            self.stats.hits,
            self.stats.max,
            self.stats.p999,
            self.stats.mean,
            self.stats.mean_t_error,
            self.stats.bound_holds,
            self.stats.disagreements,
            self.ns_per_ray,
        )
    }
}

/// The whole study.
pub struct Study {
    /// Rays traced per run.
    pub rays: usize,
    /// Rows, f32 and f64 for each budget.
    pub rows: Vec<Row>,
}

/// A reference hit: `(t, point)`.
type Ref = (f64, DVec3);

fn rays(cam: &Camera) -> Vec<(DVec3, DVec3)> {
    let mut v = Vec::with_capacity(cam.width as usize * cam.height as usize);
    for y in 0..cam.height {
        for x in 0..cam.width {
            v.push(cam.pixel_ray(x, y));
        }
    }
    v
}

/// Traces all rays with budget `n` in precision `F`: per ray `Some((t, point, t_error))`, and
/// the elapsed seconds.
fn trace_all<F: Prec>(
    scene: &Scene<F>,
    rays: &[(DVec3, DVec3)],
    n: usize,
) -> Result<(Vec<Option<Traced>>, f64)> {
    let t = tracer::<F>(Mode::Smooth, n)?;
    let bvh = scene.bvh();
    let start = std::time::Instant::now();
    let out = rays
        .iter()
        .map(|&(o, d)| {
            let r = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
            t.closest_hit(&bvh, &r, F::ZERO, F::MAX)
                .map(|h| (h.t.to_f64(), F::to_dvec3(h.point), h.t_error.to_f64()))
        })
        .collect();
    Ok((out, start.elapsed().as_secs_f64()))
}

/// Traces all rays with budget `n` on the GPU scene `gs`: as [`trace_all`].
fn trace_gpu(
    gs: &GpuScene,
    rays: &[(DVec3, DVec3)],
    n: usize,
) -> Result<(Vec<Option<Traced>>, f64)> {
    let batch: Vec<Ray<f32>> = rays
        .iter()
        .map(|&(o, d)| Ray::new(o.as_vec3(), d.as_vec3()))
        .collect();
    let mut hits = vec![None; batch.len()];
    // Compile the pipeline before the clock starts.
    gs.closest_hit(&[], 0.0, f32::MAX, n, &mut [])
        .map_err(crate::gpu::gpu_error)?;
    let start = std::time::Instant::now();
    gs.closest_hit(&batch, 0.0, f32::MAX, n, &mut hits)
        .map_err(crate::gpu::gpu_error)?;
    let secs = start.elapsed().as_secs_f64();
    let out = hits
        .iter()
        .map(|h| h.map(|h| (f64::from(h.t), h.point.as_dvec3(), f64::from(h.t_error))))
        .collect();
    Ok((out, secs))
}

fn row<F: Prec>(
    scene: &Scene<F>,
    rays: &[(DVec3, DVec3)],
    reference: &[Option<Ref>],
    n: usize,
    diag: f64,
) -> Result<Row> {
    let (res, secs) = trace_all(scene, rays, n)?;
    Ok(row_of(F::PRECISION, false, &res, secs, reference, n, diag))
}

/// The statistics of one run's results `res` (taking `secs`) against the reference.
fn row_of(
    precision: Precision,
    gpu: bool,
    res: &[Option<Traced>],
    secs: f64,
    reference: &[Option<Ref>],
    n: usize,
    diag: f64,
) -> Row {
    Row {
        precision,
        gpu,
        iterations: n,
        stats: error_stats(res, reference, diag),
        ns_per_ray: secs * 1e9 / res.len().max(1) as f64,
    }
}

/// Runs the sweep over [`BUDGETS`] in f32 and f64 on the camera rays of `cam`.
pub fn sweep(mesh: &Mesh, cam: &Camera) -> Result<Study> {
    sweep_with(mesh, cam, None)
}

/// [`sweep`], with the GPU kernel's rows (f32, after the CPU's at each budget) when `gpu` is
/// given.
pub fn sweep_with(mesh: &Mesh, cam: &Camera, gpu: Option<&Arc<Gpu>>) -> Result<Study> {
    let (lo, hi) = mesh.bounds();
    let diag = (hi - lo).length().max(f64::MIN_POSITIVE);
    let s32 = Scene::<f32>::build(mesh)?;
    let s64 = Scene::<f64>::build(mesh)?;
    for note in [s32.rejected_note(), s64.rejected_note()]
        .into_iter()
        .flatten()
    {
        eprintln!("{note}");
    }
    let rays = rays(cam);
    let (rf, _) = trace_all(&s64, &rays, REFERENCE_N)?;
    let reference: Vec<Option<Ref>> = rf.iter().map(|r| r.map(|(t, p, _)| (t, p))).collect();
    let gs = match gpu {
        Some(g) => Some(GpuScene::smooth(g, &s32.bvh()).map_err(crate::gpu::gpu_error)?),
        None => None,
    };
    let mut rows = Vec::new();
    for &n in &BUDGETS {
        rows.push(row(&s32, &rays, &reference, n, diag)?);
        rows.push(row(&s64, &rays, &reference, n, diag)?);
        if let Some(gs) = &gs {
            let (res, secs) = trace_gpu(gs, &rays, n)?;
            rows.push(row_of(
                Precision::F32,
                true,
                &res,
                secs,
                &reference,
                n,
                diag,
            ));
        }
    }
    Ok(Study {
        rays: rays.len(),
        rows,
    })
}

/// CSV header of [`Study::csv`].
pub const CSV_HEADER: &str = "precision,iterations,hits,max_error,p999_error,mean_error,mean_t_error,bound_holds,hit_miss_disagreements,ns_per_ray";

impl Study {
    /// Fixed-width table.
    pub fn table(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{:>4} {:>3} {:>6} {:>10} {:>10} {:>10} {:>12} {:>8} {:>9} {:>9}",
            "prec",
            "N",
            "hits",
            "max err",
            "p99.9 err",
            "mean err",
            "mean t_err",
            "bound ok",
            "hit/miss",
            "ns/ray"
        );
        for r in &self.rows {
            let (label, n, hits, max, p999, mean, t_error, holds, disagree, ns) = r.values();
            let _ = writeln!(
                s,
                "{label:>4} {n:>3} {hits:>6} {max:>10.2e} {p999:>10.2e} {mean:>10.2e} \
                 {t_error:>12.2e} {:>7.2}% {disagree:>9} {ns:>9.0}",
                holds * 100.0
            );
        }
        s.push_str(
            "errors: hit-point distance to the f64 N=40 reference / bounding-box diagonal\n",
        );
        s
    }

    /// CSV with [`CSV_HEADER`].
    pub fn csv(&self) -> String {
        let mut s = String::from(CSV_HEADER);
        s.push('\n');
        for r in &self.rows {
            let (label, n, hits, max, p999, mean, t_error, holds, disagree, ns) = r.values();
            let _ = writeln!(
                s,
                "{label},{n},{hits},{max},{p999},{mean},{t_error},{holds},{disagree},{ns}"
            );
        }
        s
    }

    /// SVG plot of max and 99.9th-percentile error versus iterations, log scale.
    pub fn plot(&self, path: &str, name: &str) -> Result<()> {
        use plotters::prelude::*;
        let floor = 1e-17;
        let ymax = self.rows.iter().map(|r| r.stats.max).fold(1e-3, f64::max) * 3.0;
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
            let err = |e: &dyn std::fmt::Display| DemoError::output(path, e.to_string());
            root.fill(&WHITE).map_err(|e| err(&e))?;
            let mut chart = ChartBuilder::on(&root)
                .caption(
                    format!("smoothtri: hit-point error vs iterations ({name})"),
                    ("sans-serif", 18),
                )
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(0f64..25f64, (floor..ymax).log_scale())
                .map_err(|e| err(&e))?;
            chart
                .configure_mesh()
                .x_desc("iteration budget N")
                .y_desc("error / bounding-box diagonal")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .draw()
                .map_err(|e| err(&e))?;
            let mut series = vec![
                (Precision::F32, false, false, RGBColor(220, 80, 30)),
                (Precision::F64, false, false, RGBColor(30, 90, 200)),
                (Precision::F32, false, true, RGBColor(240, 160, 120)),
                (Precision::F64, false, true, RGBColor(120, 160, 230)),
            ];
            if self.rows.iter().any(|r| r.gpu) {
                series.push((Precision::F32, true, false, RGBColor(40, 150, 60)));
                series.push((Precision::F32, true, true, RGBColor(140, 210, 150)));
            }
            for (prec, gpu, p999, color) in series {
                let pts: Vec<(f64, f64)> = self
                    .rows
                    .iter()
                    .filter(|r| r.precision == prec && r.gpu == gpu)
                    .map(|r| {
                        let v = if p999 { r.stats.p999 } else { r.stats.max };
                        (r.iterations as f64, v.max(floor))
                    })
                    .collect();
                let name = if gpu {
                    "gpu f32".to_string()
                } else {
                    prec.to_string()
                };
                let label = format!("{name} {}", if p999 { "99.9th pct" } else { "max" });
                let style = if p999 {
                    ShapeStyle::from(&color).stroke_width(1)
                } else {
                    ShapeStyle::from(&color).stroke_width(2)
                };
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(|e| err(&e))?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| err(&e))?;
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(|e| err(&e))?;
            root.present().map_err(|e| err(&e))?;
        }
        crate::output::write(path, svg.as_bytes())
    }
}

/// Strip of f32 renders at each budget of [`BUDGETS`] (top) with per-pixel error heat maps
/// against the f64 N = 40 reference (bottom; log scale 1e-12 … 1e-1 of the diagonal; magenta
/// where hit and miss disagree).
pub fn strip(mesh: &Mesh, view: (f64, f64), w: u32, h: u32) -> Result<Image> {
    strip_with(mesh, view, w, h, None)
}

/// [`strip`], the f32 renders on the GPU kernel when `gpu` is given.
pub fn strip_with(
    mesh: &Mesh,
    view: (f64, f64),
    w: u32,
    h: u32,
    gpu: Option<&Arc<Gpu>>,
) -> Result<Image> {
    let cam = Camera::for_mesh(mesh, view.0, view.1, w, h);
    let diag = mesh.diagonal().max(f64::MIN_POSITIVE);
    let s32 = Scene::<f32>::build(mesh)?;
    let s64 = Scene::<f64>::build(mesh)?;
    let reference = crate::renderer::render(
        &s64,
        &cam,
        tracer::<f64>(Mode::Smooth, REFERENCE_N)?,
        diag,
        false,
    );
    let gap = 4u32;
    let top = 14u32;
    let mut img = Image::new(
        BUDGETS.len() as u32 * (w + gap) - gap,
        top + 2 * h + gap + 14,
        [255, 255, 255],
    );
    for (k, &n) in BUDGETS.iter().enumerate() {
        let r = match gpu {
            Some(g) => crate::gpu::render_gpu(g, &s32, &cam, Mode::Smooth, n, diag)?,
            None => {
                crate::renderer::render(&s32, &cam, tracer::<f32>(Mode::Smooth, n)?, diag, false)
            }
        };
        let x0 = (k as u32 * (w + gap)) as i64;
        img.blit(&r.image, x0, top as i64);
        let mut hm = Image::new(w, h, [0, 0, 0]);
        for (i, (a, b)) in r.hits.iter().zip(&reference.hits).enumerate() {
            let (x, y) = ((i as u32 % w) as i64, (i as u32 / w) as i64);
            let c = match (a.hit, b.hit) {
                (true, true) => {
                    let e = (a.point - b.point).length() / diag;
                    let l = (e.max(1e-12).log10() + 12.0) / 11.0;
                    heat(l)
                }
                (false, false) => [0, 0, 0],
                _ => [255, 0, 255],
            };
            hm.put(x, y, c);
        }
        img.blit(&hm, x0, (top + h + gap) as i64);
        img.label(&format!("N={n}"), x0 + 3, 3, 1, [255, 255, 255]);
    }
    // Colour-bar legend under the heat maps.
    let ly = (top + 2 * h + gap + 3) as i64;
    img.label("ERR 1E-12", 2, ly, 1, [255, 255, 255]);
    for i in 0..200 {
        let c = heat(i as f64 / 199.0);
        img.fill(62 + i, ly - 1, 1, 9, c);
    }
    img.label(
        if gpu.is_some() {
            "1E-1 OF DIAGONAL; GPU F32 VS F64 N=40"
        } else {
            "1E-1 OF DIAGONAL; F32 VS F64 N=40"
        },
        266,
        ly,
        1,
        [255, 255, 255],
    );
    Ok(img)
}
