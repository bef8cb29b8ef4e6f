//! The benchmark's baseline (`python/benches/overhead.py`): the same rays through the Rust API
//! as a Rust caller writes it, timed in the same process, so the Python overhead per ray is
//! measured side by side.

use std::time::Instant;

use glam::DVec3;
use pyo3::prelude::*;
use rayon::prelude::*;
use smoothtri::{OwnedScene, Ray, Scene, SceneHit};

use crate::arrays::Reals2;
use crate::batch::Threads;
use crate::budget::Budget;
use crate::precision::Prec;
use crate::scene::{NativeScene, in_precision, parse_budget, ray_rows};

/// The closest hits (`t` in `[0, inf]`) of prepared rays through the Rust API, collected into
/// a `Vec` over rayon's `par_iter` as a Rust caller writes it: `(seconds, hits)`.
fn run<F: Prec>(
    py: Python<'_>,
    scene: &OwnedScene<F>,
    o: &Reals2<'_>,
    d: &Reals2<'_>,
    budget: Budget,
    threads: &Threads,
) -> (f64, usize) {
    let (o, d) = (o.view(), d.view());
    let rays: Vec<Ray<F>> = (0..o.len())
        .map(|i| {
            Ray::new(
                F::from_dvec3(DVec3::from_array(o.row3(i))),
                F::from_dvec3(DVec3::from_array(d.row3(i))),
            )
        })
        .collect();
    let scene = scene.scene();
    py.detach(|| {
        let start = Instant::now();
        let hits = trace_prepared(&scene, &rays, budget, threads);
        let secs = start.elapsed().as_secs_f64();
        (secs, hits.iter().filter(|h| h.is_some()).count())
    })
}

/// The timed part of the baseline, out of line so that an instruction count can name it
/// (`valgrind --tool=callgrind --toggle-collect='*trace_prepared*'`).
#[inline(never)]
fn trace_prepared<F: Prec>(
    scene: &Scene<'_, F>,
    rays: &[Ray<F>],
    budget: Budget,
    threads: &Threads,
) -> Vec<Option<SceneHit<F>>> {
    let inf = F::from_f64(f64::INFINITY);
    match threads {
        Threads::One => rays
            .iter()
            .map(|r| budget.closest(scene, r, F::ZERO, inf))
            .collect(),
        _ => threads.install(|| {
            rays.par_iter()
                .map(|r| budget.closest(scene, r, F::ZERO, inf))
                .collect()
        }),
    }
}

/// `(seconds, hits)` of the closest hits of the rays (`t` in `[0, inf]`) through the core's
/// `Scene::closest_hit` over rayon's `par_iter` into a `Vec`, the rays converted beforehand
/// (not timed). The budget reaches the core as every query of this crate reaches it
/// ([`Budget::closest`]), as a Rust caller with a run-time budget reaches it.
#[pyfunction]
#[pyo3(signature = (scene, origins, directions, *, iterations = 4, threads = None))]
pub fn rust_baseline(
    py: Python<'_>,
    scene: &Bound<'_, NativeScene>,
    origins: &Bound<'_, PyAny>,
    directions: &Bound<'_, PyAny>,
    iterations: i64,
    threads: Option<i64>,
) -> PyResult<(f64, usize)> {
    let budget = parse_budget(iterations, "iterations")?;
    let threads = Threads::new(threads)?;
    let (o, d) = ray_rows(origins, directions)?;
    Ok(in_precision!(&scene.get().snapshot().built, |s| {
        run(py, s, &o, &d, budget, &threads)
    }))
}
