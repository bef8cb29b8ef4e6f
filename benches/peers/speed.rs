//! The speed table: Mrays/s of each surface on camera and random rays, and instructions per
//! camera ray under callgrind (the bench re-runs itself with `--case`).

use std::process::Command;
use std::time::Instant;

use smoothtri_io::{Mesh, load};
use smoothtri_testkit::assimp_models;
use smoothtri_testkit::scenes::torus;

use crate::common::cpu_name;
use crate::tracers::{SPEED_ROWS, Tracers, rays_of};

fn speed_meshes() -> Vec<(String, Mesh)> {
    let mut v = vec![("torus 8×8".to_string(), torus(8, 8, 1.0, 0.4))];
    if let Ok(Some(dir)) = assimp_models()
        && let Ok(l) = load(&dir.join("OBJ/WusonOBJ.obj").to_string_lossy())
    {
        v.push(("WusonOBJ".to_string(), l.mesh));
    }
    v
}

/// Instructions per camera ray of row `k` on mesh `m` (callgrind, 160×120 rays), or `None`.
fn instructions(m: usize, k: usize) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let count = |reps: usize| -> Option<u64> {
        let out = Command::new("valgrind")
            .args(["--tool=callgrind", "--callgrind-out-file=/dev/null"])
            .arg(&exe)
            .args(["--case", &format!("{m}:{k}:{reps}")])
            .output()
            .ok()?;
        let text = String::from_utf8_lossy(&out.stderr);
        text.lines()
            .find(|l| l.contains("Collected :"))?
            .rsplit(':')
            .next()?
            .trim()
            .parse()
            .ok()
    };
    let (a, b) = (count(1)?, count(0)?);
    Some(a.saturating_sub(b) as f64 / (160.0 * 120.0))
}

/// Prints the speed table.
pub(crate) fn speed() {
    let reps: usize = std::env::var("SMOOTHTRI_PEERS_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let has_valgrind = Command::new("valgrind").arg("--version").output().is_ok();
    println!(
        "\n## Speed, one thread, f32 ({}; 640×480 camera rays of `render`'s view and as many random rays; median of {reps} interleaved rounds; instructions: callgrind, 160×120 camera rays)\n",
        cpu_name()
    );
    println!(
        "| mesh | surface | camera Mrays/s | random Mrays/s | instructions per camera ray | camera ÷ Embree flat (time per ray) | hits (camera) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (mi, (name, mesh)) in speed_meshes().iter().enumerate() {
        let tr = Tracers::new(mesh, None);
        let (cam, rnd) = rays_of(mesh, 640, 480);
        let mut times = vec![[Vec::new(), Vec::new()]; SPEED_ROWS.len()];
        let hits: Vec<_> = (0..SPEED_ROWS.len())
            .map(|k| tr.run(k, mesh, &cam))
            .collect();
        for _ in 0..reps {
            for (k, t) in times.iter_mut().enumerate() {
                for (j, rays) in [&cam, &rnd].into_iter().enumerate() {
                    let s = Instant::now();
                    if tr.run(k, mesh, rays).is_some() {
                        t[j].push(s.elapsed().as_secs_f64());
                    }
                }
            }
        }
        let med = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        let rates: Vec<[Option<f64>; 2]> = times
            .iter_mut()
            .map(|[a, b]| {
                [
                    med(a).map(|s| cam.len() as f64 / s / 1e6),
                    med(b).map(|s| rnd.len() as f64 / s / 1e6),
                ]
            })
            .collect();
        let anchor = rates[0][0];
        for (k, row) in SPEED_ROWS.iter().enumerate() {
            let [c, r] = rates[k];
            let Some(c) = c else { continue };
            let ins = if has_valgrind && k > 0 {
                instructions(mi, k).map_or("—".into(), |x| format!("{x:.0}"))
            } else {
                "—".into()
            };
            let ratio = anchor.map_or("—".into(), |a| format!("{:.1}×", a / c));
            println!(
                "| {name} | {row} | {c:.2} | {:.2} | {ins} | {ratio} | {} |",
                r.unwrap_or(0.0),
                hits[k].unwrap_or(0)
            );
        }
    }
    if !cfg!(feature = "embree") {
        println!("\n(Embree's rows need `--features embree`.)");
    }
}

/// One workload under callgrind: `m:k:reps` (mesh, row, repetitions) on 160×120 camera rays.
pub(crate) fn run_case(spec: &str) -> usize {
    let v: Vec<usize> = spec.split(':').filter_map(|s| s.parse().ok()).collect();
    let (m, k, reps) = (v[0], v[1], v[2]);
    let meshes = speed_meshes();
    let mesh = &meshes[m].1;
    let tr = Tracers::new(mesh, Some(k));
    let (cam, _) = rays_of(mesh, 160, 120);
    let mut hits = 0;
    for _ in 0..reps {
        hits += tr.run(k, mesh, &cam).unwrap_or(0);
    }
    hits
}
