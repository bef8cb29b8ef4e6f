//! The shell's height range and bounding box must contain the whole surface (dense sampling of
//! random patches), with a clearance of [`SHELL_CLEARANCE`] of its width to the height range's
//! faces, in `f64` and `f32`; so must the band that culls rays, with [`BAND_CLEARANCE`].

use crate::common::pins::{BAND_CLEARANCE, SHELL_CLEARANCE};
use crate::common::*;
use glam::DVec3;
use smoothtri::{DPatch, LineField, Patch};

/// The cases of a test: each line field with each normal tilt of `degs` (degrees), the face
/// field's first.
fn cases(degs: &[f64]) -> impl Iterator<Item = (LineField, f64)> + '_ {
    [LineField::Face, LineField::Vertex]
        .into_iter()
        .flat_map(move |f| degs.iter().map(move |&deg| (f, deg)))
}

#[test]
fn height_range_and_box_contain_dense_samples() {
    let mut rng = Rng(7);
    let grid = bary_grid(40);
    for (field, deg) in cases(&[10.0, 20.0, 30.0, 40.0, 50.0]) {
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

/// The residual `z − q(β)` of the world point `x` against the band of `patch`
/// (`PatchData::band_fit`), and the band `[lo, hi]`; `None` for an unbounded band.
fn band_residual(patch: &DPatch, x: DVec3) -> Option<(f64, f64, f64)> {
    let d = patch.data();
    let [lo, hi, _] = d.band;
    if hi == f64::MAX {
        return None;
    }
    let [ex, ey, ez] = d.axes.map(DVec3::from_array);
    let w = x - DVec3::from_array(d.origin);
    let (px, py, pz) = (w.dot(ex), w.dot(ey), w.dot(ez));
    let [_, p1, p2] = d.p;
    let b2 = py / p2[1];
    let b1 = (px - p2[0] * b2) / p1[0];
    let b0 = 1.0 - b1 - b2;
    let [c0, c1, c2] = d.band_fit;
    Some((pz - (c0 * b1 * b2 + c1 * b2 * b0 + c2 * b0 * b1), lo, hi))
}

/// The band (`core/src/surface/band.rs`) holds the whole surface of every patch within 45° on
/// a dense grid, with a clearance of [`BAND_CLEARANCE`] of its width; patches steeper than that
/// have none.
#[test]
fn band_contains_dense_samples() {
    let mut rng = Rng(17);
    let grid = bary_grid(40);
    for (field, deg) in cases(&[20.0, 40.0, 50.0, 60.0]) {
        let (mut worst, mut bounded, mut steep) = (f64::NEG_INFINITY, 0, 0);
        for _ in 0..400 {
            let (p, n) = random_patch(&mut rng, deg);
            let Ok(patch) = DPatch::with_field(p, n, field) else {
                continue;
            };
            let nf = patch.face_normal();
            let cos = n.iter().map(|v| v.normalize().dot(nf)).fold(1.0, f64::min);
            // Exactly the patches within 45° (to rounding) have a band.
            if band_residual(&patch, patch.point(0.3, 0.3)).is_none() {
                assert!(cos < 0.7072, "{p:?} {n:?}");
                steep += 1;
                continue;
            }
            assert!(cos > 0.7070, "{p:?} {n:?}");
            bounded += 1;
            for &(w1, w2) in &grid {
                let Some((r, lo, hi)) = band_residual(&patch, patch.point(w1, w2)) else {
                    unreachable!()
                };
                assert!(
                    r >= lo && r <= hi,
                    "residual {r} outside [{lo}, {hi}] at ({w1},{w2}), {p:?} {n:?}"
                );
                worst = worst.max(((r - hi) / (hi - lo)).max((lo - r) / (hi - lo)));
            }
        }
        eprintln!(
            "{field:?} field, normals ≤ {deg}°: {bounded} patches with a band ({steep} steeper \
             than 45° without), closest approach to its faces {:.3} of its width (bound {BAND_CLEARANCE})",
            -worst
        );
        assert!(bounded > 50, "{bounded}");
        assert!(
            -worst >= BAND_CLEARANCE,
            "normals ≤ {deg}°: the surface comes within {:.3} of the band's width",
            -worst
        );
    }
}
