//! The precision study of `smoothtri precision` on the caller's rays: the hit-point error of
//! `f32` and `f64` runs at each iteration budget against an `f64` reference at a high budget,
//! the returned `t_error`'s coverage, hit/miss disagreements and the time per ray.
//!
//! The statistics are those of the demo's `precision` command (host-demo's
//! `commands/precision.rs`, `row_of`): both compute them with `smoothtri_host::error_stats`,
//! so that the same rays give the same table (the Python tests compare the two).

use std::time::Instant;

use glam::DVec3;
use numpy::{Element, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use smoothtri::{BuildOptions, OwnedScene};
use smoothtri_host::{ErrorStats, Traced, error_stats};
use smoothtri_io::Mesh;

use crate::arrays::PerRay;
use crate::batch::{FirstBad, Threads};
use crate::budget::Budget;
use crate::precision::Prec;
use crate::query::RayBatch;
use crate::scene::{Built, NativeScene, build, parse_budget, parse_precision, ray_rows};

/// The closest hit (`t` in `[0, F::MAX]`, as the demo traces) of every ray at `budget`, and
/// the wall time of the batch. Errors on the first ray that is not a ray in `F`.
fn trace_all<F: Prec>(
    scene: &OwnedScene<F>,
    rays: &RayBatch<'_>,
    budget: Budget,
    threads: &Threads,
) -> PyResult<(Vec<Option<Traced>>, f64)> {
    let scene = scene.scene();
    let bad = FirstBad::new();
    let start = Instant::now();
    let out = threads.map(rays.len(), |i| {
        let Some((ray, _, _)) = rays.ray::<F>(i) else {
            bad.report(i);
            return None;
        };
        budget.closest(&scene, &ray, F::ZERO, F::MAX).map(|h| {
            (
                h.hit.t.to_f64(),
                F::to_dvec3(h.hit.point),
                h.hit.t_error.to_f64(),
            )
        })
    });
    let secs = start.elapsed().as_secs_f64();
    match bad.get() {
        Some(i) => Err(PyValueError::new_err(rays.why::<F>(i))),
        None => Ok((out, secs)),
    }
}

/// One row of the study (the demo's `Row`, without the GPU flag).
struct Row {
    precision: &'static str,
    iterations: usize,
    stats: ErrorStats,
    ns_per_ray: f64,
}

/// The statistics of one run `res` (taking `secs`) against the reference `(t, point)`.
fn row_of(
    precision: &'static str,
    iterations: usize,
    res: &[Option<Traced>],
    secs: f64,
    reference: &[Option<(f64, DVec3)>],
    diag: f64,
) -> Row {
    Row {
        precision,
        iterations,
        stats: error_stats(res, reference, diag),
        ns_per_ray: secs * 1e9 / res.len().max(1) as f64,
    }
}

/// A column of the study: `f` of each row, as a numpy array.
fn column<'py, T: Element>(
    py: Python<'py>,
    rows: &[Row],
    f: impl Fn(&Row) -> T,
) -> Bound<'py, PyArray1<T>> {
    PyArray1::from_vec(py, rows.iter().map(f).collect())
}

/// The scene of `base`'s mesh in `F` for the study: `base` itself when it is in `F`, else
/// built on the same line field without seams (they change no hit point).
fn scene_in<F: Prec>(
    py: Python<'_>,
    base: &NativeScene,
    mesh: &Mesh,
    own: Option<&OwnedScene<F>>,
    threads: &Threads,
) -> PyResult<Option<OwnedScene<F>>> {
    if own.is_some() {
        return Ok(None);
    }
    let options = BuildOptions {
        seams: false,
        ..base.options
    };
    build::<F>(py, mesh, &options, threads).map(Some)
}

/// `smoothtri.precision_sweep`: the study as a dict of columns.
#[pyfunction]
#[pyo3(signature = (scene, origins, directions, *, iterations, precisions, reference_iterations = 40, threads = None))]
#[allow(clippy::too_many_arguments)]
pub fn precision_sweep<'py>(
    py: Python<'py>,
    scene: &Bound<'py, NativeScene>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    iterations: Vec<i64>,
    precisions: Vec<String>,
    reference_iterations: i64,
    threads: Option<i64>,
) -> PyResult<Bound<'py, PyDict>> {
    let base = scene.get();
    let budgets = iterations
        .iter()
        .map(|&n| parse_budget(n, "iterations"))
        .collect::<PyResult<Vec<_>>>()?;
    let reference_budget = parse_budget(reference_iterations, "reference_iterations")?;
    let precisions = precisions
        .iter()
        .map(|p| parse_precision(p))
        .collect::<PyResult<Vec<_>>>()?;
    if precisions.is_empty() {
        return Err(PyValueError::new_err(
            "precision must name f32, f64 or both",
        ));
    }
    let threads = Threads::new(threads)?;
    let (o, d) = ray_rows(origins, directions)?;
    let rays = RayBatch {
        origins: o.view(),
        directions: d.view(),
        t_min: PerRay::All(0.0),
        t_max: PerRay::All(f64::INFINITY),
    };
    // One snapshot for the whole study: an update meanwhile does not mix two poses.
    let posed = base.snapshot();
    let (own32, own64) = match &posed.built {
        Built::F32(s) => (Some(s), None),
        Built::F64(s) => (None, Some(s)),
    };
    let need32 = precisions.contains(&"f32");
    let made32 = if need32 {
        scene_in::<f32>(py, base, &posed.mesh, own32, &threads)?
    } else {
        None
    };
    let made64 = scene_in::<f64>(py, base, &posed.mesh, own64, &threads)?;
    let s32 = own32.or(made32.as_ref());
    let s64 = own64
        .or(made64.as_ref())
        .ok_or_else(|| PyValueError::new_err("internal: no f64 scene"))?;
    let (lo, hi) = posed.mesh.bounds();
    let diag = (hi - lo).length().max(f64::MIN_POSITIVE);
    let reference: Vec<Option<(f64, DVec3)>> = py
        .detach(|| trace_all(s64, &rays, reference_budget, &threads))?
        .0
        .iter()
        .map(|r| r.map(|(t, p, _)| (t, p)))
        .collect();
    let mut rows = Vec::new();
    for &budget in &budgets {
        for &p in &precisions {
            let (res, secs) = match (p, s32) {
                ("f32", Some(s)) => py.detach(|| trace_all(s, &rays, budget, &threads))?,
                _ => py.detach(|| trace_all(s64, &rays, budget, &threads))?,
            };
            rows.push(row_of(p, budget.get(), &res, secs, &reference, diag));
        }
    }
    let out = PyDict::new(py);
    let precision: Vec<&str> = rows.iter().map(|r| r.precision).collect();
    out.set_item("precision", precision)?;
    out.set_item("iterations", column(py, &rows, |r| r.iterations as i64))?;
    out.set_item("hits", column(py, &rows, |r| r.stats.hits as i64))?;
    out.set_item("max_error", column(py, &rows, |r| r.stats.max))?;
    out.set_item("p999_error", column(py, &rows, |r| r.stats.p999))?;
    out.set_item("mean_error", column(py, &rows, |r| r.stats.mean))?;
    out.set_item("mean_t_error", column(py, &rows, |r| r.stats.mean_t_error))?;
    out.set_item("bound_holds", column(py, &rows, |r| r.stats.bound_holds))?;
    out.set_item(
        "disagreements",
        column(py, &rows, |r| r.stats.disagreements as i64),
    )?;
    out.set_item("ns_per_ray", column(py, &rows, |r| r.ns_per_ray))?;
    out.set_item("rays", rays.len())?;
    out.set_item("diagonal", diag)?;
    out.set_item("reference_iterations", reference_budget.get())?;
    out.set_item("threads", threads.count())?;
    Ok(out)
}
