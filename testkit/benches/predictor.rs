//! The predicted search on the benches' rays: `cargo bench -p smoothtri-testkit --bench
//! predictor`.
//!
//! For each camera ray of `smoothtri render`'s default image (640×480, the default view) that
//! hits the scene, the hit's patch is tested again by `smoothtri::internal::search_study`: the
//! kernel's predicted search (`core/src/kernel/predicted.rs`) beside the bracketing alone, at
//! the budget `N`. The table gives the share of hits on patches with a predictor, how the
//! predicted search ended (certified by its five true evaluations; with one more for
//! an end only the predictor had signed; refined further; or bracketing with true heights
//! where the predictor could not decide), the mean true evaluations per hit of each search,
//! the hits whose two crossings differ by more than both `t_error`s, and the predictor's
//! error over each patch (16-lattice, over the longest edge) against its bound: the median
//! error, the median bound and the largest ratio of error to bound. `f32`, the face line
//! field, no seams, as the Embree bench builds its scenes. The meshes: the built-in 8×8 torus
//! and teapot and, when Debian's `assimp-testmodels` is installed, the scanned
//! `WusonOBJ.obj`. Results: docs/MEASUREMENTS.md, "The predicted search".
//!
//! Counts, not timings: the figures are the same on every machine.

use smoothtri::internal::{predictor_error, search_study};
use smoothtri::{LineField, Ray};
use smoothtri_host::percentile;
use smoothtri_io::load;
use smoothtri_testkit::scenes::builtin;
use smoothtri_testkit::{Camera, Mesh, assimp_models, build_scene};

/// `smoothtri render`'s defaults: image size and view (azimuth, elevation).
const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
const VIEW: (f64, f64) = (30.0, 35.0);
/// The refinement budget of the Embree bench's Rust row.
const N: usize = 4;

/// Prints the table's row of `mesh`.
fn row(name: &str, mesh: &Mesh, n: usize) {
    let owned = build_scene::<f32>(mesh, LineField::Face, false).expect("the scene builds");
    let scene = owned.scene();
    let patches = scene.bvh().patches();
    let rays: Vec<Ray> = Camera::for_mesh(mesh, VIEW.0, VIEW.1, WIDTH, HEIGHT).rays_f32();
    let (mut hits, mut usable, mut differ) = (0usize, 0usize, 0usize);
    // Certified by the five, by six or seven, refined, bracketed.
    let mut ends = [0usize; 4];
    let (mut evals, mut bracketing) = (0u64, 0u64);
    for ray in &rays {
        let Some(h) = scene.bvh().closest_hit(ray, 0.0, f32::INFINITY, n) else {
            continue;
        };
        let Some(patch) = patches.get(h.patch as usize) else {
            continue;
        };
        let [p, b] = search_study(patch, ray, 0.0, f32::INFINITY, n);
        let (Some([tp, ep]), Some([tb, eb])) = (p.crossing, b.crossing) else {
            continue;
        };
        hits += 1;
        evals += u64::from(p.evals);
        bracketing += u64::from(b.evals);
        differ += usize::from((tp - tb).abs() > ep + eb);
        if predictor_error(patch, 4).is_none() {
            continue;
        }
        usable += 1;
        let end = match p.evals {
            e if e % 4 == 0 => 3,
            5 => 0,
            6 => 1,
            _ => 2,
        };
        ends[end] += 1;
    }
    let errors: Vec<[f64; 2]> = patches
        .iter()
        .filter(|p| p.rejected().is_none())
        .filter_map(|p| predictor_error(p, 16))
        .collect();
    let mut measured: Vec<f64> = errors.iter().map(|e| e[0]).collect();
    let mut bounds: Vec<f64> = errors.iter().map(|e| e[1]).collect();
    let ratio = errors.iter().map(|e| e[0] / e[1]).fold(0.0, f64::max);
    measured.sort_by(f64::total_cmp);
    bounds.sort_by(f64::total_cmp);
    let pct = |k: usize, of: usize| 100.0 * k as f64 / of.max(1) as f64;
    let per = |e: u64| e as f64 / hits.max(1) as f64;
    println!(
        "| {name} | {n} | {hits} | {:.1} % | {:.1} % | {:.1} % | {:.1} % | {:.1} % | {:.2} | {:.2} \
         | {differ} | {:.1e} | {:.1e} | {ratio:.2} |",
        pct(usable, hits),
        pct(ends[0], usable),
        pct(ends[1], usable),
        pct(ends[2], usable),
        pct(ends[3], usable),
        per(bracketing),
        per(evals),
        percentile(&measured, 0.5),
        percentile(&bounds, 0.5),
    );
}

fn main() {
    let mut meshes = vec![
        (
            "torus 8×8".to_string(),
            builtin("torus").expect("the torus"),
        ),
        ("teapot".to_string(), builtin("teapot").expect("the teapot")),
    ];
    if let Ok(Some(dir)) = assimp_models() {
        let path = dir.join("OBJ/WusonOBJ.obj");
        if let Ok(loaded) = load(&path.to_string_lossy()) {
            meshes.push(("WusonOBJ".to_string(), loaded.mesh));
        }
    }
    println!(
        "| mesh | N | hits | on a predictor | 5 evals | 6 evals | refined | bracketed | bracketing \
         evals/hit | predicted evals/hit | differ | error (median) | bound (median) | \
         error / bound (max) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, mesh) in &meshes {
        row(name, mesh, N);
    }
}
