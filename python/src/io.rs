//! Meshes from files (`smoothtri.load`, through `smoothtri-io`) and the demo's camera rays
//! (`smoothtri.camera_rays`, through the test kit's camera).

use glam::DVec3;
use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use smoothtri_host::Camera;
use smoothtri_io::Mesh;

use crate::LoadError;
use crate::arrays::Reals2;

pyo3::create_exception!(
    _smoothtri,
    LoadBudgetError,
    LoadError,
    "Loading the file would take more memory than its budget (`max_bytes`; the message names the file and the field)."
);

pyo3::create_exception!(
    _smoothtri,
    OutsideFolderError,
    LoadError,
    "A glTF buffer URI resolves outside the file's folder (refused unless `allow_outside_folder=True`; the message names the file and the URI)."
);

/// Rows of vectors as an `(N, 3)` `float64` array.
fn vec3_array<'py>(py: Python<'py>, v: &[DVec3]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = v.iter().flat_map(|p| p.to_array()).collect();
    let a = Array2::from_shape_vec((v.len(), 3), flat)
        .map_err(|e| PyValueError::new_err(format!("internal shape error: {e}")))?;
    Ok(PyArray2::from_owned_array(py, a))
}

/// `smoothtri.load`: a mesh file's vertices, normals and faces as a dict of arrays, loaded
/// within `max_bytes` (default `smoothtri_io::DEFAULT_MAX_BYTES`), glTF buffers outside the
/// file's folder only with `allow_outside_folder`.
#[pyfunction]
#[pyo3(signature = (path, *, allow_outside_folder = false, max_bytes = None))]
pub fn load<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    allow_outside_folder: bool,
    max_bytes: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let name = path.to_string_lossy().into_owned();
    let mut options =
        smoothtri_io::LoadOptions::default().with_allow_outside_folder(allow_outside_folder);
    if let Some(m) = max_bytes {
        options = options.with_max_bytes(m);
    }
    let loaded = py
        .detach(|| smoothtri_io::load_with(&name, &options))
        .map_err(|e| match &e {
            smoothtri_io::Error::Io { source, .. }
                if source.kind() == std::io::ErrorKind::NotFound =>
            {
                PyFileNotFoundError::new_err(e.to_string())
            }
            smoothtri_io::Error::Io { .. } => PyOSError::new_err(e.to_string()),
            smoothtri_io::Error::Budget { .. } => LoadBudgetError::new_err(e.to_string()),
            smoothtri_io::Error::OutsideFolder { .. } => OutsideFolderError::new_err(e.to_string()),
            _ => LoadError::new_err(e.to_string()),
        })?;
    let m = &loaded.mesh;
    let faces: Vec<i64> = m.triangles.iter().flat_map(|t| t.map(i64::from)).collect();
    let faces = Array2::from_shape_vec((m.triangles.len(), 3), faces)
        .map_err(|e| PyValueError::new_err(format!("internal shape error: {e}")))?;
    let d = PyDict::new(py);
    d.set_item("vertices", vec3_array(py, &m.positions)?)?;
    d.set_item("normals", vec3_array(py, &m.normals)?)?;
    d.set_item("faces", PyArray2::from_owned_array(py, faces))?;
    d.set_item("computed_normals", loaded.computed_normals)?;
    d.set_item("warnings", loaded.warnings.clone())?;
    Ok(d)
}

/// A point or direction of a mesh whose up axis is `up`, in the camera's z-up frame (an exact
/// permutation with one sign change; the demo's `--up`).
fn to_z_up(up: char, v: DVec3) -> DVec3 {
    match up {
        'x' => DVec3::new(v.y, v.z, v.x),
        'y' => DVec3::new(v.x, -v.z, v.y),
        _ => v,
    }
}

/// The inverse of [`to_z_up`].
fn from_z_up(up: char, v: DVec3) -> DVec3 {
    match up {
        'x' => DVec3::new(v.z, v.x, v.y),
        'y' => DVec3::new(v.x, v.z, -v.y),
        _ => v,
    }
}

/// Ray origins and directions, `(R, 3)` each.
type Rays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// `smoothtri.camera_rays`: the rays through the pixel centres of the demo's camera framed on
/// the vertices, row by row from the top, as `(origins, directions)` `float64` arrays.
#[pyfunction]
#[pyo3(signature = (vertices, width, height, *, azimuth = 30.0, elevation = 35.0, up = "z"))]
pub fn camera_rays<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    width: i64,
    height: i64,
    azimuth: f64,
    elevation: f64,
    up: &str,
) -> PyResult<Rays<'py>> {
    let size = |n: i64, name: &str| {
        u32::try_from(n)
            .ok()
            .filter(|n| (1..=16384).contains(n))
            .ok_or_else(|| PyValueError::new_err(format!("{name} must be in 1..=16384, got {n}")))
    };
    let (w, h) = (size(width, "width")?, size(height, "height")?);
    let up = match up {
        "x" | "y" | "z" => up.chars().next().unwrap_or('z'),
        _ => {
            return Err(PyValueError::new_err(format!(
                "up must be \"x\", \"y\" or \"z\", got {up:?}"
            )));
        }
    };
    if !(azimuth.is_finite() && elevation.is_finite()) {
        return Err(PyValueError::new_err(
            "azimuth and elevation must be finite (degrees)",
        ));
    }
    let v = Reals2::new(vertices, "vertices", 3, "(V, 3)")?;
    let rows = v.view();
    let mut positions = Vec::with_capacity(rows.len());
    for i in 0..rows.len() {
        let p = DVec3::from_array(rows.row3(i));
        if !p.is_finite() {
            return Err(PyValueError::new_err(format!(
                "vertices[{i}] is not finite"
            )));
        }
        positions.push(to_z_up(up, p));
    }
    if positions.is_empty() {
        return Err(PyValueError::new_err("vertices is empty: nothing to frame"));
    }
    let mesh = Mesh {
        positions,
        ..Mesh::default()
    };
    let cam = Camera::for_mesh(&mesh, azimuth, elevation, w, h);
    let n = w as usize * h as usize;
    let (mut o, mut d) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for y in 0..h {
        for x in 0..w {
            let (eye, dir) = cam.pixel_ray(x, y);
            o.push(from_z_up(up, eye));
            d.push(from_z_up(up, dir));
        }
    }
    Ok((vec3_array(py, &o)?, vec3_array(py, &d)?))
}
