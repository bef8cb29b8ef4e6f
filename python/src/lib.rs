//! # `smoothtri._smoothtri`
//!
//! The native half of the Python package `smoothtri` (the Python half, `python/smoothtri/`,
//! gives the API its defaults, result types and docs): the core's scene built from numpy
//! arrays ([`scene`]), its batched queries on rayon's threads with the GIL released
//! ([`query`], [`batch`]), the precision study ([`sweep`]), mesh files and camera rays
//! ([`io`]), and the benchmark's Rust baseline ([`bench`]). Inputs are checked with messages
//! that name the argument ([`arrays`]); nothing a caller passes makes it panic.
//!
//! The core's queries take the iteration budget `N` at compile time; [`budget`] is the one
//! place that turns the caller's run-time integer into it.
#![forbid(unsafe_code)]

use pyo3::prelude::*;

mod arrays;
mod batch;
mod bench;
mod budget;
mod io;
mod precision;
mod query;
mod scene;
mod sweep;

pyo3::create_exception!(
    _smoothtri,
    BuildError,
    pyo3::exceptions::PyValueError,
    "The scene could not be built: no triangles, or every triangle rejected (the message says why)."
);

pyo3::create_exception!(
    _smoothtri,
    LoadError,
    pyo3::exceptions::PyValueError,
    "A mesh file is malformed or of an unknown format (the message names the file and the line or element)."
);

/// The module `smoothtri._smoothtri`.
#[pymodule]
fn _smoothtri(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<scene::NativeScene>()?;
    m.add_function(wrap_pyfunction!(sweep::precision_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(io::load, m)?)?;
    m.add_function(wrap_pyfunction!(io::camera_rays, m)?)?;
    m.add_function(wrap_pyfunction!(bench::rust_baseline, m)?)?;
    m.add("BuildError", py.get_type::<BuildError>())?;
    m.add("LoadError", py.get_type::<LoadError>())?;
    m.add("LoadBudgetError", py.get_type::<io::LoadBudgetError>())?;
    m.add(
        "OutsideFolderError",
        py.get_type::<io::OutsideFolderError>(),
    )?;
    m.add("DEFAULT_MAX_BYTES", smoothtri_io::DEFAULT_MAX_BYTES)?;
    m.add("SUPPORTED_ITERATIONS", budget::Budget::all())?;
    m.add("HIT_FIELDS", scene::HIT_FIELDS.to_vec())?;
    m.add("SURFACE_FIELDS", scene::SURFACE_FIELDS.to_vec())?;
    m.add("MAX_THREADS", batch::MAX_THREADS)?;
    // The core's named accuracy bounds that the Python docs and tests cite.
    let accuracy = pyo3::types::PyDict::new(py);
    macro_rules! bound {
        ($($name:ident)*) => {
            $(accuracy.set_item(stringify!($name), smoothtri::accuracy::$name)?;)*
        };
    }
    bound!(
        F64_INTERPOLATION F32_INTERPOLATION F64_SPHERE_POINT F32_SPHERE_POINT
        F64_SPHERE_NORMAL F32_SPHERE_NORMAL F32_VS_F64_POINT F32_VS_F64_NORMAL
        F64_SURFACE_VS_REFERENCE UNIT_LENGTH_ULPS F64_SPHERE_HIT F32_SPHERE_HIT F64_SPHERE_HIT_T
        SEAM_JUMP_DEG
    );
    m.add("ACCURACY", accuracy)?;
    // Where the renders start secondary rays, as a fraction of the scene's bounding-box
    // diagonal (the trimesh intersector's multiple hits step past a hit by it).
    let offset = pyo3::types::PyDict::new(py);
    offset.set_item("f32", smoothtri_host::SHADOW_OFFSET_F32)?;
    offset.set_item("f64", smoothtri_host::SHADOW_OFFSET_F64)?;
    m.add("SECONDARY_RAY_OFFSET", offset)?;
    Ok(())
}
