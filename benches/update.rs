//! Animated meshes: the time to update a deforming mesh's scene each frame, against a full build,
//! on one thread and on more (issue 48's figures).
//!
//! `cargo bench --bench update` builds the twisting torus (`smoothtri_testkit::twist`, about
//! 10k, 100k and 1M triangles) at `t = 0`, then updates it to `FRAMES` later poses, with and
//! without seamless normals, on rayon pools of each thread count, and prints the median time
//! per update, the triangles per second, whether the BVH was refitted, and where the time goes
//! per step. Timings, not tests: the numbers depend on the machine (named in the output).
//!
//! Environment: `SMOOTHTRI_BENCH_SIZES` (default `10k,100k`; `1m` adds the largest),
//! `SMOOTHTRI_BENCH_THREADS` (default `1,2` and every core the machine has, e.g. `1,2,16`).

use std::time::Instant;

use glam::DVec3;
use smoothtri::{BuildObserver, BuildOptions, BuildStage, LineField, OwnedScene, Vertices};
use smoothtri_testkit::RayonExecutor;
use smoothtri_testkit::twist::{TWIST_SIDES, twist_pose, twisting_torus};

mod common;
use common::cpu_name;

/// Poses per measurement (a tenth of a period apart).
const FRAMES: usize = 6;

/// Times the steps of a build or an update.
#[derive(Default)]
struct Stages {
    at: Option<(BuildStage, Instant)>,
    seconds: Vec<(BuildStage, f64)>,
}

impl BuildObserver for Stages {
    fn stage(&mut self, stage: BuildStage) {
        let now = Instant::now();
        if let Some((s, t)) = self.at.take() {
            self.seconds.push((s, (now - t).as_secs_f64()));
        }
        if stage != BuildStage::Done {
            self.at = Some((stage, now));
        }
    }
}

fn packed(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

struct Row {
    triangles: usize,
    seams: bool,
    threads: usize,
    build: f64,
    update: f64,
    refits: usize,
    stages: Vec<(BuildStage, f64)>,
    build_stages: Vec<(BuildStage, f64)>,
}

fn measure(side: usize, seams: bool) -> Row {
    let m = twisting_torus(side, 0.0);
    let (p, n) = (packed(&m.positions), packed(&m.normals));
    let mut stages = Stages::default();
    let t0 = Instant::now();
    let mut scene = OwnedScene::<f32>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        &mut BuildOptions {
            field: LineField::Face,
            seams,
            observer: &mut stages,
            executor: RayonExecutor,
        },
    )
    .expect("the twisting torus builds");
    let build = t0.elapsed().as_secs_f64();
    let build_stages = stages.seconds;
    let (mut pos, mut nrm) = (m.positions.clone(), m.normals.clone());
    let mut times = Vec::new();
    let mut refits = 0;
    let mut last = Vec::new();
    // The first update also allocates the scratch the build freed and pairs the edges again:
    // warm up with one, then time the frames.
    for k in 0..=FRAMES {
        twist_pose(side, 0.4 * (k as f64 + 1.0), &mut pos, &mut nrm);
        let (p, n) = (packed(&pos), packed(&nrm));
        let mut stages = Stages::default();
        let t = Instant::now();
        let r = *scene
            .update(
                Vertices::packed(&p),
                Vertices::packed(&n),
                &mut BuildOptions {
                    field: LineField::Face,
                    seams,
                    observer: &mut stages,
                    executor: RayonExecutor,
                },
            )
            .expect("the update succeeds");
        if k > 0 {
            times.push(t.elapsed().as_secs_f64());
            refits += usize::from(r.bvh_refitted);
            last = stages.seconds;
        }
    }
    Row {
        triangles: m.triangles.len(),
        seams,
        threads: rayon::current_num_threads(),
        build,
        update: median(times),
        refits,
        stages: last,
        build_stages,
    }
}

fn list(var: &str, default: &str) -> Vec<String> {
    std::env::var(var)
        .unwrap_or_else(|_| default.to_owned())
        .split(',')
        .map(|s| s.trim().to_lowercase())
        .filter(|s| !s.is_empty())
        .collect()
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is read.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let default_threads = if cores > 2 {
        format!("1,2,{cores}")
    } else {
        "1,2".to_owned()
    };
    let threads: Vec<usize> = list("SMOOTHTRI_BENCH_THREADS", &default_threads)
        .iter()
        .filter_map(|s| s.parse().ok())
        .collect();
    let sides: Vec<usize> = list("SMOOTHTRI_BENCH_SIZES", "10k,100k")
        .iter()
        .filter_map(|s| match s.as_str() {
            "10k" => TWIST_SIDES.first().copied(),
            "100k" => TWIST_SIDES.get(1).copied(),
            "1m" => TWIST_SIDES.get(2).copied(),
            _ => None,
        })
        .collect();
    println!(
        "\n## Updating the twisting torus (f32; {}, {cores} cores; median of {FRAMES} frames)\n",
        cpu_name()
    );
    println!(
        "| triangles | seams | threads | full build | update | update, triangles/s | refitted | update steps | full build steps |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for &side in &sides {
        for seams in [false, true] {
            for &k in &threads {
                let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(k).build() else {
                    continue;
                };
                let r = pool.install(|| measure(side, seams));
                let named = |stages: &[(BuildStage, f64)]| {
                    stages
                        .iter()
                        .map(|(s, t)| format!("{} {:.1} ms", s.name(), t * 1e3))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                let (steps, build_steps) = (named(&r.stages), named(&r.build_stages));
                println!(
                    "| {} | {} | {} | {:.1} ms | {:.1} ms | {:.0} | {} of {FRAMES} | {steps} | {build_steps} |",
                    r.triangles,
                    if r.seams { "yes" } else { "no" },
                    r.threads,
                    r.build * 1e3,
                    r.update * 1e3,
                    r.triangles as f64 / r.update,
                    r.refits,
                );
            }
        }
    }
}
