//! The shell's height range and bounding box must contain the whole surface (dense sampling of
//! random patches), with a clearance of [`SHELL_CLEARANCE`] of its width to the height range's
//! faces, in `f64` and `f32`; so must the band that culls rays, with [`BAND_CLEARANCE`], and
//! the predictor's bound the predictor's error, with [`PREDICTOR_CLEARANCE`].

use crate::common::pins::{BAND_CLEARANCE, PREDICTOR_CLEARANCE, SHELL_CLEARANCE};
use crate::common::*;
use glam::DVec3;
use smoothtri::internal::predictor_error;
use smoothtri::{DPatch, LineField, Patch};
use smoothtri_testkit::scenes;

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

/// The predictor's bound (`core/src/surface/predictor.rs`) holds on a dense grid (the degree-24
/// lattice, 325 points) of every patch that has one, random and real, with a clearance of
/// [`PREDICTOR_CLEARANCE`] of the bound: exactly the patches within its domain (parallel
/// sections, normals within 45°) have one.
#[test]
fn predictor_bound_holds_on_dense_grids() {
    let mut rng = Rng(63);
    let mut worst = 0.0f64;
    let mut check = |what: &str, patch: &DPatch| -> bool {
        let Some([error, bound]) = predictor_error(patch, 24) else {
            return false;
        };
        assert!(
            error <= bound,
            "{what}: error {error:.3e} above its bound {bound:.3e}"
        );
        worst = worst.max(error / bound);
        true
    };
    for (field, deg) in cases(&[20.0, 40.0, 50.0]) {
        let (mut with, mut without) = (0, 0);
        for _ in 0..150 {
            let (p, n) = random_patch(&mut rng, deg);
            let Ok(patch) = DPatch::with_field(p, n, field) else {
                continue;
            };
            let nf = patch.face_normal();
            let cos = n.iter().map(|v| v.normalize().dot(nf)).fold(1.0, f64::min);
            let parallel = field == LineField::Face || {
                let d = patch.data().d;
                d.iter().all(|d| d[2] == 1.0)
            };
            if check("random", &patch) {
                assert!(parallel && cos > 0.7070, "{p:?} {n:?}");
                with += 1;
            } else {
                assert!(!parallel || cos < 0.7072, "{p:?} {n:?}");
                without += 1;
            }
        }
        eprintln!(
            "{field:?} field, normals ≤ {deg}°: {with} patches with a predictor, {without} without"
        );
    }
    let mut real = 0;
    for (name, mesh) in [
        ("torus 8×8", scenes::torus(8, 8, 1.0, 0.4)),
        ("teapot", scenes::teapot(4)),
    ] {
        for t in &mesh.triangles {
            let [p, n] = [&mesh.positions, &mesh.normals].map(|v| t.map(|i| v[i as usize]));
            if let Ok(patch) = DPatch::new(p, n) {
                real += usize::from(check(name, &patch));
            }
        }
    }
    eprintln!(
        "{real} real patches with a predictor; the largest error is {worst:.3} of the bound \
         (clearance {PREDICTOR_CLEARANCE})"
    );
    assert!(real > 500, "{real}");
    assert!(
        1.0 - worst >= PREDICTOR_CLEARANCE,
        "the error comes within {:.3} of the bound",
        1.0 - worst
    );
}
