//! Cracks and normal jumps between neighbouring patches of a mesh's scene, measured edge by
//! edge ([`cracks`]): what `smoothtri inspect` reports and the suite's real-mesh tests pin.

use std::collections::HashMap;

use glam::DVec3;
use smoothtri::mesh::Seam;
use smoothtri::{DPatch, LineField};
use smoothtri_io::Mesh;

use crate::executor::build_scene;

/// Samples per shared edge for crack measurement.
pub const EDGE_SAMPLES: usize = 9;

/// Crack statistics over interior edges.
#[derive(Clone, Debug, Default)]
pub struct Cracks {
    /// Interior edges measured (shared by exactly two accepted triangles).
    pub edges: usize,
    /// Edges used by one triangle only.
    pub boundary: usize,
    /// Edges used by more than two triangles.
    pub non_manifold: usize,
    /// Maximum distance between the two patches' edge curves, over the edges with no side
    /// clamped per patch (a clamp moves that side's edge curve by design).
    pub max_gap: f64,
    /// Mean over edges of the per-edge maximum distance.
    pub mean_gap: f64,
    /// Maximum angle between the two patches' edge normals, degrees.
    pub max_jump_deg: f64,
    /// Mean over edges of the per-edge maximum normal angle, degrees.
    pub mean_jump_deg: f64,
    /// Maximum angle between the two patches' *surface* normals (`point_normal`, from the
    /// exact derivatives) at the same edge samples, degrees: what shading sees.
    pub max_surface_jump_deg: f64,
    /// Mean over edges of the per-edge maximum surface-normal angle, degrees.
    pub mean_surface_jump_deg: f64,
    /// Maximum angle, over the edges with a seam, between the two patches' seamless *shading* normals
    /// ([`Seam::shading_normal`](smoothtri::mesh::Seam::shading_normal), seams fitted by [`fit_seams`](smoothtri::mesh::fit_seams) on the mesh's index buffer) at
    /// the same edge samples, degrees: what the smooth render mode shades with by default.
    pub max_shading_jump_deg: f64,
    /// Mean over edges of the per-edge maximum shading-normal angle, degrees.
    pub mean_shading_jump_deg: f64,
    /// Measured edges next to a patch whose normals were clamped per patch (the remedy of
    /// `Patch::new_or_tilted`): that side no longer interpolates the mesh's normals there.
    pub remedied: usize,
    /// Edges whose two sides carry different normals at a shared position (split normals: a
    /// crease the mesh asks for), left out of the jumps: there is no jump to remove.
    pub creases: usize,
    /// Measured edges with no seam fitted: both sides' normals agree, but the index buffer does
    /// not join them (unwelded vertices), or the fit declined (a common normal near
    /// perpendicular to the interpolated vertex normals, a non-finite sample).
    pub unjoined: usize,
    /// Largest shading jump across the edges of [`Cracks::unjoined`], degrees.
    pub max_unjoined_jump_deg: f64,
    /// Shared edges [`fit_seams`](smoothtri::mesh::fit_seams) fitted (matched by vertex index, so vertices split in the
    /// index buffer make boundaries there, unlike the position matching above).
    pub seam_edges: usize,
}

/// Barycentrics `(w1, w2)` of the point at `t` on edge `e` (from vertex `e` to `e + 1`).
fn edge_bary(e: usize, t: f64) -> (f64, f64) {
    let mut w = [0.0; 3];
    w[e % 3] = 1.0 - t;
    w[(e + 1) % 3] = t;
    (w[1], w[2])
}

/// An undirected edge: its two endpoints' exact bit patterns, smaller first.
type EdgeKey = ([u64; 3], [u64; 3]);

fn key(p: DVec3) -> [u64; 3] {
    p.to_array().map(|c| (c + 0.0).to_bits())
}

/// Measures the cracks and normal jumps between f64 patches across shared edges (edges matched
/// by exact vertex positions; the second patch's edge is walked in the matching direction),
/// the patches on `field`.
pub fn cracks(mesh: &Mesh, field: LineField) -> Cracks {
    // The f64 scene as the builder makes it (crack closure, seams); a triangle the core
    // rejects has no patch and the zero seam. Edges of patches the per-patch remedy clamped
    // are counted apart (`Cracks::remedied`).
    let owned = build_scene::<f64>(mesh, field, true).ok();
    let scene = owned.as_ref().map(|o| o.scene());
    let patch_of = |t: usize| {
        let sc = scene.as_ref()?;
        sc.patch_index(u32::try_from(t).ok()?)
    };
    let patches: Vec<Option<DPatch>> = (0..mesh.triangles.len())
        .map(|t| Some(scene.as_ref()?.patches()[patch_of(t)?]))
        .collect();
    let seams: Vec<Seam<f64>> = (0..mesh.triangles.len())
        .map(|t| {
            scene
                .as_ref()
                .and_then(|sc| patch_of(t).map(|i| sc.seams()[i]))
                .unwrap_or_default()
        })
        .collect();
    let seam_edges = scene
        .as_ref()
        .and_then(|sc| sc.report().seam_edges)
        .unwrap_or(0);
    // Undirected edge → list of (triangle, local edge, forward?) with forward meaning the
    // edge runs from the smaller key to the larger.
    let mut edges: HashMap<EdgeKey, Vec<(usize, usize, bool)>> = HashMap::new();
    for t in 0..mesh.triangles.len() {
        let (p, _) = mesh.triangle(t);
        for e in 0..3 {
            let (a, b) = (key(p[e]), key(p[(e + 1) % 3]));
            if a == b {
                continue;
            }
            let fwd = a < b;
            let k = if fwd { (a, b) } else { (b, a) };
            edges.entry(k).or_default().push((t, e, fwd));
        }
    }
    let mut c = Cracks {
        seam_edges,
        ..Cracks::default()
    };
    let (mut sum_gap, mut sum_jump, mut sum_sjump, mut sum_hjump) = (0.0, 0.0, 0.0, 0.0);
    for list in edges.values() {
        match list.len() {
            1 => c.boundary += 1,
            2 => {
                let (ta, ea, fa) = list[0];
                let (tb, eb, fb) = list[1];
                let (Some(pa), Some(pb)) = (&patches[ta], &patches[tb]) else {
                    continue;
                };
                // The mesh's normals at the two shared positions, from each side.
                let (na, nb) = (mesh.triangle(ta).1, mesh.triangle(tb).1);
                let ends_a = [na[ea], na[(ea + 1) % 3]];
                let ends_b = [nb[eb], nb[(eb + 1) % 3]];
                let ends_b = if fa == fb {
                    ends_b
                } else {
                    [ends_b[1], ends_b[0]]
                };
                let same = |u: DVec3, v: DVec3| {
                    u.normalize_or_zero().dot(v.normalize_or_zero()) > 1.0 - 1e-12
                };
                if !(same(ends_a[0], ends_b[0]) && same(ends_a[1], ends_b[1])) {
                    c.creases += 1;
                    continue;
                }
                let clamped = pa.normal_clamp().is_some() || pb.normal_clamp().is_some();
                c.remedied += usize::from(clamped);
                let fitted = |seam: &Seam<f64>, e: usize| {
                    seam.free[e]
                        || seam.common[e]
                            .iter()
                            .chain(&seam.common_along[e])
                            .any(|&c| c != 0.0)
                };
                let joined = fitted(&seams[ta], ea) && fitted(&seams[tb], eb);
                let (mut gap, mut jump, mut sjump, mut hjump) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
                for k in 0..EDGE_SAMPLES {
                    // Between the vertices: where a per-patch clamp moved a vertex normal, the
                    // shading normal at the vertex itself is each side's own.
                    let t = (k as f64 + 0.5) / EDGE_SAMPLES as f64;
                    let tb_ = if fa == fb { t } else { 1.0 - t };
                    let (xa, na) = pa.edge_point_normal(ea, t);
                    let (xb, nb) = pb.edge_point_normal(eb, tb_);
                    gap = gap.max((xa - xb).length());
                    jump = jump.max(na.dot(nb).clamp(-1.0, 1.0).acos().to_degrees());
                    let (a1, a2) = edge_bary(ea, t);
                    let (b1, b2) = edge_bary(eb, tb_);
                    let sa = pa.point_normal(a1, a2).1;
                    let sb = pb.point_normal(b1, b2).1;
                    sjump = sjump.max(sa.dot(sb).clamp(-1.0, 1.0).acos().to_degrees());
                    let ha = seams[ta].shading_normal(pa, a1, a2);
                    let hb = seams[tb].shading_normal(pb, b1, b2);
                    hjump = hjump.max(ha.dot(hb).clamp(-1.0, 1.0).acos().to_degrees());
                }
                c.edges += 1;
                if !joined {
                    c.unjoined += 1;
                    c.max_unjoined_jump_deg = c.max_unjoined_jump_deg.max(hjump);
                }
                // The crack width between patches on the mesh's own normals: a per-patch clamp
                // moves a side's edge curve off its neighbour's by design (closed by the kernel).
                if !clamped {
                    sum_gap += gap;
                    c.max_gap = c.max_gap.max(gap);
                }
                sum_jump += jump;
                sum_sjump += sjump;
                if joined {
                    sum_hjump += hjump;
                    c.max_shading_jump_deg = c.max_shading_jump_deg.max(hjump);
                }
                c.max_surface_jump_deg = c.max_surface_jump_deg.max(sjump);
                c.max_jump_deg = c.max_jump_deg.max(jump);
            }
            _ => c.non_manifold += 1,
        }
    }
    if c.edges > 0 {
        c.mean_gap = sum_gap / (c.edges - c.remedied).max(1) as f64;
        c.mean_jump_deg = sum_jump / c.edges as f64;
        c.mean_surface_jump_deg = sum_sjump / c.edges as f64;
        c.mean_shading_jump_deg = sum_hjump / (c.edges - c.unjoined).max(1) as f64;
    }
    c
}
