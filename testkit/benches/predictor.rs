//! The rates of issue 63's predicted search on the benches' rays: `cargo bench -p smoothtri-testkit --bench
//! predictor`.
//!
//! For each camera ray of `smoothtri render`'s default image (640×480, the default view) that
//! hits the scene, the hit's patch is searched again by `smoothtri::internal::predictor_study`:
//! today's search (its true height evaluations at the budget `N`) beside the predicted one (the
//! quartic interpolant's crossing, one true evaluation and one step with its slope, a
//! certifying pair at the early-stop width, four more points, or today's search as the
//! fallback; `core/src/kernel/study.rs`). The table gives the share of hits certified with 3
//! and with 7 true evaluations, the fallbacks, the mean true evaluations per hit of each
//! search, the predictor's crossing and the stepped point from today's crossing in early-stop
//! widths (median and 90th percentile), the certified brackets that miss today's crossing, and
//! the interpolant's largest error over each patch (16-lattice, over the longest edge; median
//! and largest over the patches). `f32`, the face line field, no seams, as the Embree bench
//! builds its scenes. The meshes: the built-in 8×8 torus and teapot and, when Debian's
//! `assimp-testmodels` is installed, the scanned `WusonOBJ.obj`. Results: docs/MEASUREMENTS.md,
//! "The predictor's rates".
//!
//! Counts, not timings: the figures are the same on every machine.

use smoothtri::internal::{PredictorOutcome, predictor_error, predictor_study};
use smoothtri::{LineField, Ray};
use smoothtri_host::percentile;
use smoothtri_io::load;
use smoothtri_testkit::scenes::builtin;
use smoothtri_testkit::{Camera, Mesh, assimp_models, build_scene};

/// `smoothtri render`'s defaults: image size and view (azimuth, elevation).
const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
const VIEW: (f64, f64) = (30.0, 35.0);
/// The refinement budget of the Embree bench's Rust row (today's search stops early, at the
/// same point for any larger budget: N = 8 gives the same counts).
const N: usize = 4;

/// Prints the table's row of `mesh`; returns the hits certified elsewhere (ray index, outcome).
fn row(name: &str, mesh: &Mesh, n: usize) -> Vec<(usize, PredictorOutcome)> {
    let owned = build_scene::<f32>(mesh, LineField::Face, false).expect("the scene builds");
    let scene = owned.scene();
    let patches = scene.bvh().patches();
    let rays: Vec<Ray> = Camera::for_mesh(mesh, VIEW.0, VIEW.1, WIDTH, HEIGHT).rays_f32();
    let (mut hits, mut pair, mut four, mut fallback, mut wrong) = (0usize, 0, 0, 0, 0);
    let (mut evals, mut today) = (0u64, 0u64);
    let (mut predicted, mut stepped) = (Vec::new(), Vec::new());
    let mut elsewhere = Vec::new();
    for (i, ray) in rays.iter().enumerate() {
        let Some(h) = scene.bvh().closest_hit(ray, 0.0, f32::INFINITY, n) else {
            continue;
        };
        let Some(patch) = patches.get(h.patch as usize) else {
            continue;
        };
        let Some(o) = predictor_study(patch, ray, 0.0, f32::INFINITY, n) else {
            continue;
        };
        hits += 1;
        match o.stage {
            1 => pair += 1,
            2 => four += 1,
            _ => fallback += 1,
        }
        if !o.agrees {
            wrong += 1;
            elsewhere.push((i, o));
        }
        evals += u64::from(o.evals);
        today += u64::from(o.today_evals);
        predicted.push(o.predicted_off);
        stepped.push(o.stepped_off);
    }
    let mut errors: Vec<f64> = patches
        .iter()
        .filter(|p| p.rejected().is_none())
        .map(predictor_error)
        .collect();
    for v in [&mut predicted, &mut stepped, &mut errors] {
        v.sort_by(f64::total_cmp);
    }
    let pct = |k: usize| 100.0 * k as f64 / hits.max(1) as f64;
    let per = |e: u64| e as f64 / hits.max(1) as f64;
    println!(
        "| {name} | {n} | {hits} | {:.1} % | {:.1} % | {:.1} % | {:.2} | {:.2} | {:.2} / {:.1} | \
         {:.2} / {:.1} | {wrong} | {:.1e} / {:.1e} |",
        pct(pair),
        pct(four),
        pct(fallback),
        per(today),
        per(evals),
        percentile(&predicted, 0.5),
        percentile(&predicted, 0.9),
        percentile(&stepped, 0.5),
        percentile(&stepped, 0.9),
        percentile(&errors, 0.5),
        percentile(&errors, 1.0),
    );
    elsewhere
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
        "| mesh | N | hits | 3 evals | 7 evals | fallback | today evals/hit | predicted evals/hit \
         | τp off (median / p90, stops) | τ1 off (median / p90) | missed | interpolant error \
         (median / max) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut elsewhere = Vec::new();
    for (name, mesh) in &meshes {
        elsewhere.extend(
            row(name, mesh, N)
                .into_iter()
                .map(|(i, o)| (name.clone(), i, o)),
        );
    }
    // The hits whose certified bracket does not hold today's crossing, each listed (pixel
    // x, y of the 640×480 image).
    println!("\n| mesh | pixel | today's t ± t_error | certified bracket | stage |");
    println!("|---|---|---|---|---|");
    for (name, i, o) in elsewhere {
        let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
        println!(
            "| {name} | {x}, {y} | {:.6} ± {:.1e} | [{:.6}, {:.6}] | {} |",
            o.today[0], o.today[1], o.certified[0], o.certified[1], o.stage
        );
    }
}
