//! The shared line field ([`LineField::Vertex`], docs/METHOD.md §2 "Line fields") in the ray
//! kernel: patches whose sections are tilted (the point-to-section map is a cubic, solved by
//! Newton) are hit where the generic evaluation puts their surface, within `t_error`, in `f64`
//! and `f32`.

use crate::common::*;
use glam::DVec3;
use smoothtri::accuracy::F32_VS_F64_POINT;
use smoothtri::{DPatch, DRay, LineField, Patch, Ray};

/// Random patches (well-shaped, normals within 40° of the face) on the shared field, whose
/// normals make unequal angles with the face (tilted sections); rays from outside, up to 50°
/// off the surface normal, aimed at surface points of a barycentric grid (edges and vertices
/// included): every ray hits, at the target within its `t_error` (`f64`; `f32`, at points a
/// tenth of the triangle inside its edges, within its `t_error` plus twice
/// [`F32_VS_F64_POINT`] of the scale: the f32 patch's own surface, on rounded input, along a
/// ray up to 50° off its normal).
#[test]
fn tilted_sections_are_hit_on_the_surface() {
    let mut rng = Rng(21);
    let grid = bary_grid(6);
    let (mut rays, mut worst64, mut worst32) = (0usize, 0.0f64, 0.0f64);
    for _ in 0..200 {
        let (p, n) = random_patch(&mut rng, 40.0);
        let patch = DPatch::with_field(p, n, LineField::Vertex).unwrap();
        let p32 = Patch::<f32>::with_field(
            p.map(|x| x.as_vec3()),
            n.map(|x| x.as_vec3()),
            LineField::Vertex,
        )
        .unwrap();
        let size = (p[1] - p[0]).length();
        let scale = p.iter().fold(size, |m, v| m.max(v.abs().max_element()));
        for &(w1, w2) in &grid {
            let (x, nrm) = patch.point_normal(w1, w2);
            let u = loop {
                let u = rng.unit();
                if u.dot(nrm) >= 50f64.to_radians().cos() {
                    break u;
                }
            };
            let dist = size;
            let o = x + u * dist;
            let h = patch
                .closest_hit(&DRay::new(o, -u), 0.0, f64::INFINITY, 8)
                .unwrap_or_else(|| panic!("f64 miss at ({w1}, {w2}) of {p:?} {n:?}"));
            let err = (h.t - dist).abs();
            assert!(
                err <= h.t_error + 1e-12 * size,
                "f64: |{} − {dist}| = {err:e} > t_error {:e}",
                h.t,
                h.t_error
            );
            worst64 = worst64.max(err / size);
            // f32 input rounding moves the patch's edges: a ray aimed at an edge may then pass
            // beside it (and hit the continuation in the wall margin); f32 is compared inside.
            if w1.min(w2).min(1.0 - w1 - w2) < 0.1 {
                rays += 1;
                continue;
            }
            let h = p32
                .closest_hit(
                    &Ray::new(o.as_vec3(), (-u).as_vec3()),
                    0.0,
                    f32::INFINITY,
                    8,
                )
                .unwrap_or_else(|| panic!("f32 miss at ({w1}, {w2}) of {p:?} {n:?}"));
            let err = (h.t as f64 - dist).abs();
            assert!(
                err <= h.t_error as f64 + 2.0 * F32_VS_F64_POINT * scale,
                "f32: |{} − {dist}| = {err:e} > t_error {:e}",
                h.t,
                h.t_error
            );
            worst32 = worst32.max(err / scale);
            rays += 1;
        }
    }
    eprintln!(
        "{rays} rays: worst |t − target| {worst64:.1e} (f64) of the size, {worst32:.1e} (f32) of the scale"
    );
}

/// The remedy per vertex (`clamp_vertex_normals`): on the 8-sided cylinder with averaged
/// normals (up to 72° from a face) it clamps vertex normals until every patch is accepted on
/// the shared field, leaves the others bit for bit, and reports typed errors for bad input.
#[test]
fn vertex_clamps_resolve_the_cylinder_and_errors_are_typed() {
    use smoothtri::mesh::{MeshError, VertexClamp, clamp_vertex_normals};
    let m = cylinder(8).to_mesh();
    let n = m.positions.len();
    let mut out = vec![DVec3::ZERO; n];
    let mut scratch = vec![VertexClamp::<f64>::default(); n];
    let r = clamp_vertex_normals(
        &m.positions,
        &m.normals,
        &m.triangles,
        &mut out,
        &mut scratch,
    )
    .unwrap();
    assert!(r.clamped > 0 && r.unresolved == 0, "{r:?}");
    let moved = out.iter().zip(&m.normals).filter(|(a, b)| a != b).count();
    assert_eq!(moved, r.clamped);
    for tri in &m.triangles {
        let p = tri.map(|i| m.positions[i as usize]);
        let nn = tri.map(|i| out[i as usize]);
        assert!(DPatch::with_field(p, nn, LineField::Vertex).is_ok());
    }
    let bad = [[0u32, 1, n as u32]];
    assert_eq!(
        clamp_vertex_normals(&m.positions, &m.normals, &bad, &mut out, &mut scratch),
        Err(MeshError::BadIndex { triangle: 0 })
    );
    assert!(matches!(
        clamp_vertex_normals(
            &m.positions,
            &m.normals,
            &m.triangles,
            &mut out,
            &mut scratch[..1]
        ),
        Err(MeshError::ScratchTooSmall { .. })
    ));
    let (positions, outputs) = (m.positions.len(), out.len());
    assert_eq!(
        clamp_vertex_normals(
            &m.positions,
            &m.normals[..1],
            &m.triangles,
            &mut out,
            &mut scratch
        ),
        Err(MeshError::VertexCount {
            positions,
            normals: 1,
            out: outputs,
        })
    );
}
