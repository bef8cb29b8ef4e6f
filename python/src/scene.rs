//! `NativeScene`: the core's scene of a mesh given as numpy arrays, in `f32` or `f64`, with its
//! batched queries. The Python class `smoothtri.Scene` wraps it (argument defaults, result
//! types, docs).

use std::sync::{Arc, Mutex, PoisonError};

use glam::DVec3;
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use smoothtri::{BuildOptions, LineField, OwnedScene};
use smoothtri_host::RayonExecutor;
use smoothtri_io::Mesh;

use crate::BuildError;
use crate::arrays::{self, Bound1, Reals2};
use crate::batch::{Rows as Out, Threads};
use crate::budget::{Budget, SUPPORTED_TEXT};
use crate::precision::Prec;
use crate::query::{self, BadInput, HitsOut, PointBatch, RayBatch, RayQueryFn, SurfaceOut};

/// The core's scene in the precision it was built in.
#[derive(Clone)]
pub enum Built {
    /// Built and traced in `f32`.
    F32(OwnedScene<f32>),
    /// Built and traced in `f64`.
    F64(OwnedScene<f64>),
}

/// `$body` with `$scene` bound to the scene of `$built` (a [`Built`], by reference), whichever
/// its precision: the expression is compiled once for each.
macro_rules! in_precision {
    ($built:expr, |$scene:ident| $body:expr) => {
        match $built {
            $crate::scene::Built::F32($scene) => $body,
            $crate::scene::Built::F64($scene) => $body,
        }
    };
}
pub(crate) use in_precision;

/// A scene and the mesh of its current pose: never changed once shared (an update makes a
/// new one).
pub struct Posed {
    /// The scene.
    pub built: Built,
    /// The mesh it was built from or last updated to (`f64`, as given): the precision study
    /// rebuilds it in the other precision.
    pub mesh: Mesh,
    /// The number of updates that led to this pose: 0 for the build, then one more for each
    /// successful update.
    pub pose: u64,
}

/// A scene built from numpy arrays (`smoothtri.Scene` wraps it), safe to share between Python
/// threads.
///
/// Concurrency: the current pose is an immutable snapshot, an `Arc<Posed>`, behind a mutex
/// that is held only to clone or replace that `Arc` (nothing else happens under it: no Python
/// call, no query, no release or re-acquisition of the GIL), so taking it can never wait on the
/// GIL nor on a query. A query takes the snapshot, releases the GIL and runs on it; it answers
/// the pose current when it started, whatever updates land meanwhile. `update` releases the GIL,
/// takes the `updating` mutex (updates run one at a time, in the order they take it: the last
/// one wins), moves a copy of the current scene to the new pose and only then swaps the
/// snapshot; queries never wait for it, nor it for them. The copy is the core's in-place
/// update of a clone, so the answers are the in-place update's bit for bit; the scene exists
/// twice while an update runs.
#[pyclass(frozen, module = "smoothtri._smoothtri")]
pub struct NativeScene {
    /// The current pose (held only to clone or swap the `Arc`).
    posed: Mutex<Arc<Posed>>,
    /// Held (without the GIL) by the update in progress, so that updates run one at a time.
    updating: Mutex<()>,
    /// The options it was built with.
    pub options: BuildOptions,
    /// Triangles given (fixed: updates keep the index buffer).
    triangles: usize,
}

impl NativeScene {
    /// The current pose: a snapshot that later updates leave as it is. Takes the snapshot's
    /// mutex only to clone the `Arc` (never poisoned in effect: nothing under it can panic).
    pub fn snapshot(&self) -> Arc<Posed> {
        Arc::clone(&self.posed.lock().unwrap_or_else(PoisonError::into_inner))
    }
}

/// `precision=` as the core's choice.
pub fn parse_precision(p: &str) -> PyResult<&'static str> {
    match p {
        "f32" | "float32" => Ok("f32"),
        "f64" | "float64" => Ok("f64"),
        _ => Err(PyValueError::new_err(format!(
            "precision must be \"f32\" or \"f64\", got {p:?}"
        ))),
    }
}

/// `field=` as the core's line field.
fn parse_field(f: &str) -> PyResult<LineField> {
    match f {
        "face" => Ok(LineField::Face),
        "vertex" => Ok(LineField::Vertex),
        _ => Err(PyValueError::new_err(format!(
            "field must be \"face\" or \"vertex\", got {f:?}"
        ))),
    }
}

/// `iterations=` as a budget.
pub fn parse_budget(n: i64, name: &str) -> PyResult<Budget> {
    Budget::new(n).ok_or_else(|| {
        PyValueError::new_err(format!(
            "{name} must be one of {SUPPORTED_TEXT} (refinement steps of the kernel), got {n}"
        ))
    })
}

/// The rows of a `(V, 3)` array as `f64` vectors, each component finite.
fn vectors(a: &Reals2<'_>, name: &str) -> PyResult<Vec<DVec3>> {
    let rows = a.view();
    let mut out = Vec::with_capacity(rows.len());
    for i in 0..rows.len() {
        let v = rows.row3(i);
        if let Some(j) = v.iter().position(|x| !x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "{name}[{i}, {j}] = {} is not finite",
                arrays::num(v[j])
            )));
        }
        out.push(DVec3::from_array(v));
    }
    Ok(out)
}

/// The positions and normals of `(vertices, normals)`, checked: shapes, dtypes, one normal per
/// vertex, finite values.
fn vertex_rows(
    vertices: &Bound<'_, PyAny>,
    normals: &Bound<'_, PyAny>,
) -> PyResult<(Vec<DVec3>, Vec<DVec3>)> {
    let (v, n) = arrays::paired_rows(
        (vertices, "vertices"),
        (normals, "normals"),
        "(V, 3)",
        |v, n| format!("normals has {n} rows but vertices has {v}: one normal per vertex"),
    )?;
    Ok((vectors(&v, "vertices")?, vectors(&n, "normals")?))
}

/// The origins and directions of a batch of rays, checked: shapes, dtypes, one of each per
/// ray.
pub fn ray_rows<'py>(
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
) -> PyResult<(Reals2<'py>, Reals2<'py>)> {
    arrays::paired_rows(
        (origins, "origins"),
        (directions, "directions"),
        "(R, 3)",
        |o, d| format!("origins has {o} rows but directions has {d}: one of each per ray"),
    )
}

/// The mesh of `(vertices, normals, faces)`, checked: shapes, dtypes, finite values, indices
/// in range.
pub fn mesh_of(
    vertices: &Bound<'_, PyAny>,
    normals: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
) -> PyResult<Mesh> {
    let (positions, normals) = vertex_rows(vertices, normals)?;
    let flat = arrays::indices(
        faces,
        "faces",
        Some(3),
        "(F, 3)",
        positions.len(),
        "vertex index",
        &format!("the mesh has {} vertices", positions.len()),
    )?;
    let triangles = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Mesh {
        positions,
        normals,
        triangles,
    })
}

/// The scene of `mesh` in precision `F` on `threads` (the same bit for bit on any number).
pub fn build<F: Prec>(
    py: Python<'_>,
    mesh: &Mesh,
    options: &BuildOptions,
    threads: &Threads,
) -> PyResult<OwnedScene<F>> {
    let built = py.detach(|| match threads {
        Threads::One => mesh.build_scene::<F, _, _>(&mut { *options }),
        _ => threads
            .install(|| mesh.build_scene::<F, _, _>(&mut options.with_executor(RayonExecutor))),
    });
    built.map_err(|e| BuildError::new_err(e.to_string()))
}

/// [`OwnedScene::update`] of `scene` to `mesh`'s vertices on `threads`.
fn update_in<F: Prec>(
    mesh: &Mesh,
    scene: &mut OwnedScene<F>,
    options: BuildOptions,
    threads: &Threads,
) -> Result<(), smoothtri::BuildError> {
    match threads {
        Threads::One => mesh.update_scene(scene, &mut { options }).map(drop),
        _ => threads.install(|| {
            mesh.update_scene(scene, &mut options.with_executor(RayonExecutor))
                .map(drop)
        }),
    }
}

/// A bad input of a batch as the Python exception.
fn bad(e: BadInput) -> PyErr {
    PyValueError::new_err(e.why)
}

/// The arguments of a ray query, checked: the rays, their interval of `t`, the budget and the
/// threads.
struct RayQuery<'py> {
    origins: Reals2<'py>,
    directions: Reals2<'py>,
    t_min: Bound1<'py>,
    t_max: Bound1<'py>,
    budget: Budget,
    threads: Threads,
}

/// The interval of `t` of a batch of `r` rays, checked: `t_min` and `t_max` floats or `(r,)`
/// arrays (`None`: `t_min = 0`, `t_max = inf`), no NaN, and `t_min <= t_max` when both are
/// floats.
fn ray_interval<'py>(
    py: Python<'py>,
    t_min: Option<&Bound<'py, PyAny>>,
    t_max: Option<&Bound<'py, PyAny>>,
    r: usize,
) -> PyResult<(Bound1<'py>, Bound1<'py>)> {
    let zero = 0.0f64.into_pyobject(py)?.into_any();
    let inf = f64::INFINITY.into_pyobject(py)?.into_any();
    let t_min = Bound1::new(t_min.unwrap_or(&zero), "t_min", r)?;
    let t_max = Bound1::new(t_max.unwrap_or(&inf), "t_max", r)?;
    if let (Bound1::All(a), Bound1::All(b)) = (&t_min, &t_max)
        && (a.is_nan() || b.is_nan() || a > b)
    {
        return Err(PyValueError::new_err(format!(
            "t_min and t_max must be numbers with t_min <= t_max, got {} and {}",
            arrays::num(*a),
            arrays::num(*b)
        )));
    }
    for (b, name) in [(&t_min, "t_min"), (&t_max, "t_max")] {
        if let Bound1::All(x) = b
            && x.is_nan()
        {
            return Err(PyValueError::new_err(format!("{name} is nan")));
        }
    }
    Ok((t_min, t_max))
}

impl<'py> RayQuery<'py> {
    /// `batched` (a ray query of [`query`]) of these rays through `scene` into `out`, without
    /// the GIL.
    fn run<F: Prec, O: Send>(
        &self,
        py: Python<'_>,
        scene: &OwnedScene<F>,
        out: O,
        batched: RayQueryFn<F, O>,
    ) -> PyResult<()> {
        let batch = RayBatch {
            origins: self.origins.view(),
            directions: self.directions.view(),
            t_min: self.t_min.view(),
            t_max: self.t_max.view(),
        };
        let (budget, threads) = (self.budget, &self.threads);
        let scene = scene.scene();
        py.detach(|| batched(&scene, &batch, budget, out, threads))
            .map_err(bad)
    }
}

/// The `i`-th object of `out` (a tuple of output arrays), if given.
fn out_at<'py>(out: Option<&Bound<'py, PyTuple>>, i: usize) -> PyResult<Option<Bound<'py, PyAny>>> {
    out.map(|t| t.get_item(i)).transpose()
}

/// Checks `out` (a tuple of `n` arrays) before use.
fn check_out(out: Option<&Bound<'_, PyTuple>>, n: usize, what: &str) -> PyResult<()> {
    match out {
        Some(t) if t.len() != n => Err(PyValueError::new_err(format!(
            "out must be a {what} ({n} arrays), got {} arrays",
            t.len()
        ))),
        _ => Ok(()),
    }
}

/// The names of the closest-hit outputs, in the order of the tuple.
pub const HIT_FIELDS: [&str; 8] = [
    "hit",
    "t",
    "t_error",
    "point",
    "normal",
    "shading_normal",
    "triangle",
    "barycentric",
];

/// The names of the evaluation outputs, in the order of the tuple.
pub const SURFACE_FIELDS: [&str; 3] = ["point", "normal", "shading_normal"];

fn closest_hit_in<'py, F: Prec>(
    py: Python<'py>,
    scene: &OwnedScene<F>,
    query: &RayQuery<'py>,
    out: Option<&Bound<'py, PyTuple>>,
) -> PyResult<Bound<'py, PyTuple>> {
    check_out(out, 8, "Hits")?;
    let r = query.origins.len();
    let name = |i: usize| format!("out.{}", HIT_FIELDS[i]);
    let d = F::DTYPE;
    let hit =
        arrays::output::<bool, numpy::Ix1>(py, out_at(out, 0)?.as_ref(), &name(0), &[r], "bool")?;
    let t = arrays::output::<F, numpy::Ix1>(py, out_at(out, 1)?.as_ref(), &name(1), &[r], d)?;
    let te = arrays::output::<F, numpy::Ix1>(py, out_at(out, 2)?.as_ref(), &name(2), &[r], d)?;
    let p = arrays::output::<F, numpy::Ix2>(py, out_at(out, 3)?.as_ref(), &name(3), &[r, 3], d)?;
    let n = arrays::output::<F, numpy::Ix2>(py, out_at(out, 4)?.as_ref(), &name(4), &[r, 3], d)?;
    let s = arrays::output::<F, numpy::Ix2>(py, out_at(out, 5)?.as_ref(), &name(5), &[r, 3], d)?;
    let tri =
        arrays::output::<i64, numpy::Ix1>(py, out_at(out, 6)?.as_ref(), &name(6), &[r], "int64")?;
    let b = arrays::output::<F, numpy::Ix2>(py, out_at(out, 7)?.as_ref(), &name(7), &[r, 2], d)?;
    {
        let mut w = (
            arrays::write(&hit, &name(0))?,
            arrays::write(&t, &name(1))?,
            arrays::write(&te, &name(2))?,
            arrays::write(&p, &name(3))?,
            arrays::write(&n, &name(4))?,
            arrays::write(&s, &name(5))?,
            arrays::write(&tri, &name(6))?,
            arrays::write(&b, &name(7))?,
        );
        let hits = HitsOut {
            hit: arrays::slice(&mut w.0, &name(0))?,
            t: arrays::slice(&mut w.1, &name(1))?,
            t_error: arrays::slice(&mut w.2, &name(2))?,
            point: Out(arrays::slice(&mut w.3, &name(3))?),
            normal: Out(arrays::slice(&mut w.4, &name(4))?),
            shading_normal: Out(arrays::slice(&mut w.5, &name(5))?),
            triangle: arrays::slice(&mut w.6, &name(6))?,
            barycentric: Out(arrays::slice(&mut w.7, &name(7))?),
        };
        query.run(py, scene, hits, query::closest_hit)?;
    }
    PyTuple::new(
        py,
        [
            hit.into_any(),
            t.into_any(),
            te.into_any(),
            p.into_any(),
            n.into_any(),
            s.into_any(),
            tri.into_any(),
            b.into_any(),
        ],
    )
}

fn any_hit_in<'py, F: Prec>(
    py: Python<'py>,
    scene: &OwnedScene<F>,
    query: &RayQuery<'py>,
    out: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let r = query.origins.len();
    let a = arrays::output::<bool, numpy::Ix1>(py, out, "out", &[r], "bool")?;
    {
        let mut w = arrays::write(&a, "out")?;
        let slots = arrays::slice(&mut w, "out")?;
        query.run(py, scene, slots, query::any_hit)?;
    }
    Ok(a)
}

fn evaluate_in<'py, F: Prec>(
    py: Python<'py>,
    scene: &OwnedScene<F>,
    triangles: &[u32],
    barycentrics: &Reals2<'py>,
    threads: &Threads,
    out: Option<&Bound<'py, PyTuple>>,
) -> PyResult<Bound<'py, PyTuple>> {
    check_out(out, 3, "SurfacePoints")?;
    let m = triangles.len();
    let name = |i: usize| format!("out.{}", SURFACE_FIELDS[i]);
    let d = F::DTYPE;
    let arrays: Vec<Bound<'py, PyArray2<F>>> = (0..3)
        .map(|i| {
            arrays::output::<F, numpy::Ix2>(py, out_at(out, i)?.as_ref(), &name(i), &[m, 3], d)
        })
        .collect::<PyResult<_>>()?;
    {
        let mut w = arrays
            .iter()
            .enumerate()
            .map(|(i, a)| arrays::write(a, &name(i)))
            .collect::<PyResult<Vec<_>>>()?;
        let mut slices = w.iter_mut();
        let mut next = |i: usize| -> PyResult<Out<'_, F, 3>> {
            let a = slices
                .next()
                .ok_or_else(|| PyValueError::new_err("internal: missing output"))?;
            Ok(Out(arrays::slice(a, &name(i))?))
        };
        let surface = SurfaceOut {
            point: next(0)?,
            normal: next(1)?,
            shading_normal: next(2)?,
        };
        let points = PointBatch {
            triangles,
            barycentric: barycentrics.view(),
        };
        let scene = scene.scene();
        py.detach(|| query::evaluate(&scene, &points, surface, threads))
            .map_err(bad)?;
    }
    PyTuple::new(py, arrays)
}

#[pymethods]
impl NativeScene {
    #[new]
    #[pyo3(signature = (vertices, normals, faces, *, precision = "f32", seams = true, field = "face", threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        normals: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        precision: &str,
        seams: bool,
        field: &str,
        threads: Option<i64>,
    ) -> PyResult<Self> {
        let precision = parse_precision(precision)?;
        let options = BuildOptions {
            field: parse_field(field)?,
            seams,
            ..BuildOptions::default()
        };
        let threads = Threads::new(threads)?;
        let mesh = mesh_of(vertices, normals, faces)?;
        let built = match precision {
            "f32" => Built::F32(build::<f32>(py, &mesh, &options, &threads)?),
            _ => Built::F64(build::<f64>(py, &mesh, &options, &threads)?),
        };
        Ok(NativeScene {
            triangles: mesh.triangles.len(),
            posed: Mutex::new(Arc::new(Posed {
                built,
                mesh,
                pose: 0,
            })),
            updating: Mutex::new(()),
            options,
        })
    }

    /// Moves the scene to new vertex positions and normals (the same faces): the core's
    /// update, equal to a fresh build of them, of a copy that then replaces the current
    /// snapshot (queries in flight finish on the pose they started on). Errors (the scene
    /// then unchanged): `ValueError` for bad arrays or another vertex count, `BuildError` when
    /// the core refuses the update.
    #[pyo3(signature = (vertices, normals, *, threads = None))]
    fn update<'py>(
        &self,
        py: Python<'py>,
        vertices: &Bound<'py, PyAny>,
        normals: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<()> {
        let (positions, normals) = vertex_rows(vertices, normals)?;
        let threads = Threads::new(threads)?;
        let options = self.options;
        py.detach(|| {
            // Updates one at a time, taken without the GIL; a panic of an earlier update left
            // the snapshot as it was, so the lock is usable.
            let _one_at_a_time = self.updating.lock().unwrap_or_else(PoisonError::into_inner);
            let old = self.snapshot();
            let count = old.mesh.positions.len();
            if positions.len() != count {
                return Err(PyValueError::new_err(format!(
                    "vertices has {} rows but the scene was built from {count}: an update keeps the vertices and faces",
                    positions.len()
                )));
            }
            let mesh = Mesh {
                positions,
                normals,
                triangles: old.mesh.triangles.clone(),
            };
            // The core's update in place, of a copy: queries keep reading `old` meanwhile.
            let mut built = old.built.clone();
            in_precision!(&mut built, |s| update_in(&mesh, s, options, &threads))
                .map_err(|e| BuildError::new_err(e.to_string()))?;
            let new = Arc::new(Posed {
                built,
                mesh,
                pose: old.pose + 1,
            });
            let previous = core::mem::replace(
                &mut *self.posed.lock().unwrap_or_else(PoisonError::into_inner),
                new,
            );
            // The old pose is freed here, outside the lock, unless a query still reads it
            // (then at that query's end).
            drop(previous);
            drop(old);
            Ok(())
        })
    }

    /// `"f32"` or `"f64"`.
    #[getter]
    fn precision(&self) -> &'static str {
        match self.snapshot().built {
            Built::F32(_) => "f32",
            Built::F64(_) => "f64",
        }
    }

    /// Whether the seamless shading normals were fitted.
    #[getter]
    fn seams(&self) -> bool {
        self.options.seams
    }

    /// `"face"` or `"vertex"`.
    #[getter]
    fn field(&self) -> &'static str {
        match self.options.field {
            LineField::Vertex => "vertex",
            _ => "face",
        }
    }

    /// The number of vertices given.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.snapshot().mesh.positions.len()
    }

    /// The number of triangles given.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// The number of updates that led to the current pose: 0 after the build, one more after
    /// each successful update.
    #[getter]
    fn pose(&self) -> u64 {
        self.snapshot().pose
    }

    /// What the build (or the last update) did, as a dict (see `smoothtri.BuildReport`), plus
    /// `"pose"`: the [`pose`](Self::pose) it describes, all of one snapshot.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let posed = self.snapshot();
        let (r, memory) = in_precision!(&posed.built, |s| (
            *s.scene().report(),
            s.scene().memory_bytes()
        ));
        let d = PyDict::new(py);
        d.set_item("pose", posed.pose)?;
        d.set_item("triangles", r.triangles)?;
        d.set_item("patches", r.patches)?;
        let rejected = PyDict::new(py);
        for (why, n) in r.rejected.by_reason() {
            rejected.set_item(why, n)?;
        }
        d.set_item("rejected", rejected)?;
        d.set_item(
            "first_rejected",
            r.first_rejected.map(|(t, e)| (t, e.to_string())),
        )?;
        d.set_item("remedied", r.remedied)?;
        d.set_item("first_remedied", r.first_remedied)?;
        d.set_item(
            "vertex_clamps",
            r.vertex_clamps.map(|v| (v.clamped, v.unresolved)),
        )?;
        d.set_item("shared_edges", r.cracks.shared_edges)?;
        d.set_item("open_edges", r.cracks.open_edges)?;
        d.set_item("widest_gap", r.cracks.widest_gap)?;
        d.set_item("seam_edges", r.seam_edges)?;
        d.set_item("bvh_nodes", r.bvh_nodes)?;
        d.set_item("bvh_refitted", r.bvh_refitted)?;
        d.set_item("memory_bytes", memory)?;
        Ok(d)
    }

    /// The batched ray query named by `query`: `"closest_hit"`, the closest hits as a tuple of
    /// arrays in the order of `HIT_FIELDS` (`out`: such a tuple); `"any_hit"`, whether each ray
    /// hits anything as a bool array (`out`: such an array). The rays' arguments are checked
    /// the same way for both, before `query` and `out`.
    #[pyo3(signature = (query, origins, directions, *, iterations = 4, t_min = None, t_max = None, threads = None, out = None))]
    #[allow(clippy::too_many_arguments)]
    fn ray_query<'py>(
        &self,
        py: Python<'py>,
        query: &str,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        iterations: i64,
        t_min: Option<&Bound<'py, PyAny>>,
        t_max: Option<&Bound<'py, PyAny>>,
        threads: Option<i64>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        // Checked in this order: `iterations`, the rays, their interval, `threads`.
        let budget = parse_budget(iterations, "iterations")?;
        let (origins, directions) = ray_rows(origins, directions)?;
        let (t_min, t_max) = ray_interval(py, t_min, t_max, origins.len())?;
        let rays = RayQuery {
            origins,
            directions,
            t_min,
            t_max,
            budget,
            threads: Threads::new(threads)?,
        };
        let posed = self.snapshot();
        match query {
            "closest_hit" => {
                let out = out.map(|o| o.cast::<PyTuple>()).transpose()?;
                in_precision!(&posed.built, |s| closest_hit_in(py, s, &rays, out))
                    .map(Bound::into_any)
            }
            "any_hit" => {
                in_precision!(&posed.built, |s| any_hit_in(py, s, &rays, out)).map(Bound::into_any)
            }
            _ => Err(PyValueError::new_err(format!(
                "query must be \"closest_hit\" or \"any_hit\", got {query:?}"
            ))),
        }
    }

    /// Surface points and normals: a tuple of arrays in the order of `SURFACE_FIELDS`.
    #[pyo3(signature = (triangles, barycentrics, *, threads = None, out = None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        triangles: &Bound<'py, PyAny>,
        barycentrics: &Bound<'py, PyAny>,
        threads: Option<i64>,
        out: Option<&Bound<'py, PyTuple>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let f = self.triangles;
        let triangles = arrays::indices(
            triangles,
            "triangles",
            None,
            "(M,)",
            f,
            "triangle index",
            &format!("the mesh has {f} triangles"),
        )?;
        let bary = Reals2::new(barycentrics, "barycentrics", 2, "(M, 2)")?;
        if bary.len() != triangles.len() {
            return Err(PyValueError::new_err(format!(
                "triangles has {} elements but barycentrics has {} rows: one of each per point",
                triangles.len(),
                bary.len()
            )));
        }
        let threads = Threads::new(threads)?;
        in_precision!(&self.snapshot().built, |s| {
            evaluate_in(py, s, &triangles, &bary, &threads, out)
        })
    }
}
