//! Stress meshes (issue: reliability): every triangle gets a patch through the documented
//! remedy, every answer is finite, and we measure rays that slip through cracks.

use crate::common::*;
use glam::DVec3;
use smoothtri::accuracy::UNIT_LENGTH_ULPS;
use smoothtri::{Bvh, BvhNode, DPatch, DRay, PatchError, flat_hit};

/// Builds every patch with the remedy; returns patches and the number remedied.
fn build(m: &M) -> (Vec<DPatch>, usize) {
    let mut remedied = 0;
    let ps = m
        .t
        .iter()
        .map(|&[a, b, c]| {
            let patch = DPatch::new_or_tilted([m.p[a], m.p[b], m.p[c]], [m.n[a], m.n[b], m.n[c]])
                .unwrap_or_else(|e| panic!("remedy failed: {e}"));
            remedied += patch.normal_clamp().is_some() as usize;
            patch
        })
        .collect();
    (ps, remedied)
}

/// Shoots rays at random points inside random flat triangles (away from their edges) from
/// outside the mesh; counts rays that miss the smooth surface although they hit the flat
/// mesh, and checks every hit is finite.
fn holes(name: &str, m: &M, rng: &mut Rng) -> (usize, usize) {
    let (ps, remedied) = build(m);
    let mut nodes = vec![BvhNode::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let (mut flat_hits, mut missed) = (0, 0);
    for _ in 0..4000 {
        let o = rng.unit() * 10.0;
        let k = (rng.f() * m.t.len() as f64) as usize % m.t.len();
        let [a, b, c] = m.t[k];
        let (u, v) = (rng.range(0.1, 0.8), rng.range(0.1, 0.8));
        let (u, v) = if u + v > 0.9 {
            (0.9 - v, 0.9 - u)
        } else {
            (u, v)
        };
        let target = m.p[a] * (1.0 - u - v) + m.p[b] * u + m.p[c] * v;
        let ray = DRay::new(o, target - o);
        let flat = bvh.closest_with(&ray, 0.0, f64::INFINITY, |_, p, lo, hi| {
            flat_hit(&p.vertices(), None, &ray, lo, hi)
        });
        let smooth = bvh.closest_hit(&ray, 0.0, f64::INFINITY, 8);
        if let Some(h) = smooth {
            assert!(
                h.t.is_finite()
                    && h.point.is_finite()
                    && h.normal.is_finite()
                    && h.t_error.is_finite(),
                "{name}"
            );
            assert!((h.normal.length() - 1.0).abs() <= UNIT_LENGTH_ULPS * f64::EPSILON);
        }
        if flat.is_some() {
            flat_hits += 1;
            missed += smooth.is_none() as usize;
        }
    }
    eprintln!(
        "{name}: {} patches, {remedied} remedied; {missed} of {flat_hits} rays hitting the flat mesh missed the smooth one",
        ps.len()
    );
    (missed, flat_hits)
}

#[test]
fn stress_meshes_render_complete() {
    let mut rng = Rng(2024);
    let (m1, n1) = holes(
        "box 1x2x4, averaged normals",
        &box_mesh(1.0, 2.0, 4.0),
        &mut rng,
    );
    let (m2, n2) = holes(
        "cylinder 8 sides, averaged cap normals",
        &cylinder(8),
        &mut rng,
    );
    let (m3, n3) = holes(
        "icosphere(2) with 20° noisy normals",
        &noisy_sphere(&mut rng, 20.0),
        &mut rng,
    );
    // A vertex normal opposite its faces.
    let mut bad = box_mesh(1.0, 1.0, 1.0);
    bad.n[3] = -bad.n[3];
    let (m4, n4) = holes("cube with one inverted vertex normal", &bad, &mut rng);
    for (m, n) in [(m1, n1), (m2, n2), (m3, n3), (m4, n4)] {
        assert!(n > 1000);
        // Rays aimed at triangle interiors (10% away from edges) must not fall through.
        assert!(m * 200 <= n, "{m} of {n} rays fell through");
    }
    // The counts docs/MEASUREMENTS.md states ("Reliability and the method's limits"): a
    // change shows here.
    assert_eq!(
        [(m1, n1), (m2, n2), (m3, n3), (m4, n4)],
        [(5, 4000), (0, 4000), (1, 4000), (0, 4000)],
        "rays through cracks (missed, of flat hits): box, cylinder, noisy icosphere, inverted cube"
    );
}

#[test]
fn remedy_only_when_needed_and_errors_stay_errors() {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let up = [DVec3::Z; 3];
    assert_eq!(DPatch::new_or_tilted(p, up).unwrap().normal_clamp(), None);
    let back = DPatch::new_or_tilted(p, [-DVec3::Z, DVec3::Z, DVec3::Z]).unwrap();
    assert!(back.normal_clamp().is_some());
    let zero = DPatch::new_or_tilted(p, [DVec3::ZERO, DVec3::Z, DVec3::Z]).unwrap();
    assert!(zero.normal_clamp().is_some());
    let out = [
        DVec3::new(-1.0, -1.0, 0.05),
        DVec3::new(1.0, 0.0, 0.05),
        DVec3::new(0.0, 1.0, 0.05),
    ];
    assert_eq!(DPatch::new(p, out), Err(PatchError::InvalidShell));
    let fixed = DPatch::new_or_tilted(p, out).unwrap();
    let clamp = fixed.normal_clamp().unwrap();
    assert!(clamp < 89.0);
    // The clamped normals are within the clamp angle.
    for n in fixed.normals() {
        assert!(n.angle_between(DVec3::Z).to_degrees() <= clamp + 1e-9);
    }
    assert_eq!(
        DPatch::new_or_tilted([DVec3::ZERO, DVec3::X, DVec3::X * 2.0], up),
        Err(PatchError::DegenerateTriangle)
    );
    assert_eq!(
        DPatch::new_or_tilted([DVec3::NAN, DVec3::X, DVec3::Y], up),
        Err(PatchError::NonFinite)
    );
}
