//! The core against the independent f64 reference implementation in `tests/data/`, within the
//! named bounds of [`smoothtri::accuracy`]; prints the worst errors measured
//! (`cargo test --release --test suite reference:: -- --nocapture`).

use crate::common::*;
use glam::{DVec3, Vec3};
use smoothtri::accuracy::*;
use smoothtri::{DPatch, Patch};

fn v(r: &[f64], i: usize) -> DVec3 {
    DVec3::new(r[i], r[i + 1], r[i + 2])
}

#[test]
fn surface_points_match_reference_f64_and_f32() {
    let (h, rows) = read_csv("surface_points.csv");
    assert_eq!(h.len(), 27);
    assert!(rows.len() >= 500);
    let (mut worst64, mut worst_scale, mut worst32, mut worst_n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for r in &rows {
        let p = [v(r, 1), v(r, 4), v(r, 7)];
        let n = [v(r, 10), v(r, 13), v(r, 16)];
        let (w1, w2) = (r[19], r[20]);
        let want = v(r, 21);
        let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
        let patch = DPatch::new(p, n).unwrap();
        let (got, nrm) = patch.point_normal(w1, w2);
        // The reference works in world coordinates: on its small triangles far from the origin
        // (size 1e-2 at |x| ≈ 9) it differs from ours by ~100 ulps of the coordinates (1e-11 of
        // the size), while ours is shift-invariant to 2 ulps. Check both scales.
        let scale = p.iter().fold(size, |m, x| m.max(x.abs().max_element()));
        let e = (got - want).length() / size;
        let e_scale = (got - want).length() / scale;
        // Each relative error within its bound, the message naming the case; then the worst.
        let within =
            |worst: &mut f64, e: f64, bound: f64, got: &dyn std::fmt::Display, what: &str| {
                *worst = worst.max(e);
                assert!(
                    e <= bound,
                    "{what}patch {} at ({w1},{w2}): {got} vs {want}, rel {e:e}",
                    r[0]
                );
            };
        within(&mut worst64, e, F64_SURFACE_VS_REFERENCE_OF_SIZE, &got, "");
        within(
            &mut worst_scale,
            e_scale,
            F64_SURFACE_VS_REFERENCE,
            &got,
            "",
        );
        let wn = v(r, 24);
        if wn.is_finite() {
            let en = (nrm - wn).length();
            worst_n = worst_n.max(en);
            assert!(
                en <= F64_NORMAL_VS_REFERENCE,
                "normal of patch {} at ({w1},{w2}): {nrm} vs {wn}",
                r[0]
            );
        }
        let p32 = p.map(|x| x.as_vec3());
        let n32 = n.map(|x| x.as_vec3());
        let patch32: Patch = Patch::new(p32, n32).unwrap();
        let got32: Vec3 = patch32.point(w1 as f32, w2 as f32);
        // Same (rounded) input in f64: isolates the f32 arithmetic from input rounding.
        let want32 = DPatch::new(p32.map(|x| x.as_dvec3()), n32.map(|x| x.as_dvec3()))
            .unwrap()
            .point(w1 as f32 as f64, w2 as f32 as f64);
        // f32 output cannot be finer than the rounding of world coordinates: scale by the
        // larger of the triangle size and the coordinates' magnitude (`scale`).
        let e32 = (got32.as_dvec3() - want32).length() / scale;
        within(&mut worst32, e32, F32_VS_F64_POINT, &got32, "f32 ");
    }
    eprintln!(
        "reference surface points: worst error f64 {worst64:.2e} of the size, {worst_scale:.2e} of \
         the scale; normals {worst_n:.2e}; f32 vs f64 {worst32:.2e} of the scale"
    );
}

#[test]
fn edge_points_match_reference() {
    let (_, srows) = read_csv("surface_points.csv");
    let (h, rows) = read_csv("edge_points.csv");
    assert_eq!(h.len(), 9);
    let (mut worst, mut worst_n) = (0.0f64, 0.0f64);
    for r in &rows {
        let id = r[0];
        let s = srows.iter().find(|s| s[0] == id).unwrap();
        let p = [v(s, 1), v(s, 4), v(s, 7)];
        let n = [v(s, 10), v(s, 13), v(s, 16)];
        let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
        let patch = DPatch::new(p, n).unwrap();
        let (c, cn) = patch.edge_point_normal(r[1] as usize, r[2]);
        let e = (c - v(r, 3)).length() / size;
        let en = (cn - v(r, 6)).length();
        worst = worst.max(e);
        worst_n = worst_n.max(en);
        assert!(e <= F64_EDGE_VS_REFERENCE, "edge point {r:?}: {c}");
        assert!(
            en <= F64_EDGE_NORMAL_VS_REFERENCE,
            "edge normal {r:?}: {cn}"
        );
    }
    eprintln!("reference edge points: worst error {worst:.2e} of the size, normals {worst_n:.2e}");
}
