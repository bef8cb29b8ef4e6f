//! The shell's height range and bounding box must contain the whole surface (dense sampling of
//! random patches), with a clearance of [`SHELL_CLEARANCE`] of its width to the height range's
//! faces, in `f64` and `f32`.

use crate::common::pins::SHELL_CLEARANCE;
use crate::common::*;
use smoothtri::{DPatch, LineField, Patch};

#[test]
fn height_range_and_box_contain_dense_samples() {
    let mut rng = Rng(7);
    let grid = bary_grid(40);
    let cases = [LineField::Face, LineField::Vertex]
        .into_iter()
        .flat_map(|f| [10.0, 20.0, 30.0, 40.0, 50.0].map(|deg| (f, deg)));
    for (field, deg) in cases {
        let mut worst = f64::NEG_INFINITY;
        for _ in 0..400 {
            let (p, n) = random_patch(&mut rng, deg);
            let patch = DPatch::with_field(p, n, field).unwrap();
            let (lo, hi) = patch.height_range();
            let (bmin, bmax) = (patch.bounds().min(), patch.bounds().max());
            for &(w1, w2) in &grid {
                let h = patch.height(w1, w2);
                assert!(
                    h >= lo && h <= hi,
                    "height {h} outside [{lo}, {hi}] at ({w1},{w2}), {p:?} {n:?}"
                );
                let x = patch.point(w1, w2);
                assert!(
                    x.cmpge(bmin).all() && x.cmple(bmax).all(),
                    "{x} outside box {bmin} {bmax}"
                );
                // Fraction of the margin used: (excursion beyond the height's own range) / width.
                worst = worst.max(((h - hi) / (hi - lo)).max((lo - h) / (hi - lo)));
            }
        }
        eprintln!(
            "{field:?} field, normals ≤ {deg}°: closest approach to the shell's faces {:.3} of its width \
             (bound {SHELL_CLEARANCE})",
            -worst
        );
        assert!(
            -worst >= SHELL_CLEARANCE,
            "normals ≤ {deg}°: the surface comes within {:.3} of the shell's width",
            -worst
        );
    }
}

#[test]
fn f32_height_range_contains_dense_samples() {
    let mut rng = Rng(8);
    let grid = bary_grid(24);
    for _ in 0..500 {
        let (p, n) = random_patch(&mut rng, 40.0);
        let patch: Patch = Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3())).unwrap();
        let (lo, hi) = patch.height_range();
        for &(w1, w2) in &grid {
            let h = patch.height(w1 as f32, w2 as f32);
            assert!(h >= lo && h <= hi, "f32 height {h} outside [{lo}, {hi}]");
        }
    }
}
