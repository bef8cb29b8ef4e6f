//! Torus fidelity (docs/METHOD.md §6): maximum distance of the smooth surface to the true torus.

mod common;
use common::*;
use smoothtri::DPatch;
use smoothtri_demo::scenes::{torus, torus_distance};

fn max_error(n: usize, m: usize) -> f64 {
    let mesh = torus(n, n, 1.0, 0.4);
    let grid = bary_grid(m);
    let mut worst = 0.0f64;
    for t in 0..mesh.triangles.len() {
        let (p, nn) = mesh.triangle(t);
        let patch = DPatch::new(p, nn).unwrap();
        for &(w1, w2) in &grid {
            worst = worst.max(torus_distance(patch.point(w1, w2), 1.0, 0.4));
        }
    }
    worst
}

#[test]
fn torus_matches_design_table() {
    for (n, want) in [(8, 7.4e-3), (16, 6.3e-4)] {
        let got = max_error(n, 8);
        eprintln!("torus {n}x{n}: max distance {got:.3e} (docs/METHOD.md: {want:.1e})");
        assert_close!(got, want, 0.1 * want, "torus {n}x{n}");
    }
}
