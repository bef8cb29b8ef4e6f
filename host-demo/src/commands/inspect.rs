//! `smoothtri inspect`: mesh statistics, rejected patches, normal angles, cracks, normal jumps
//! (edge curves, geometric and seamless shading normals), memory.

use std::collections::HashMap;
use std::fmt::Write as _;

use glam::DVec3;
use smoothtri::mesh::Seam;
use smoothtri::{DPatch, LineField, Patch};

use super::MeshSource;
use crate::error::Result;
use crate::mesh::Mesh;
use crate::tracer::{Prec, Precision, Scene};

/// Options of `inspect`.
#[derive(Clone, Debug)]
pub struct InspectOptions {
    /// The mesh (required).
    pub source: MeshSource,
    /// Precision of the patches whose rejections are reported.
    pub precision: Precision,
    /// The line field the patches are built on.
    pub field: LineField,
}

/// Loads the mesh and prints the report of [`inspect`] on stdout.
pub fn run(a: InspectOptions) -> Result<()> {
    let (name, mesh) = a.source.load(false)?;
    let text = match a.precision {
        Precision::F32 => inspect::<f32>(&name, &mesh, a.field)?,
        Precision::F64 => inspect::<f64>(&name, &mesh, a.field)?,
    };
    print!("{text}");
    Ok(())
}

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
    let scene = Scene::<f64>::build_with(mesh, field, true).ok();
    let patches: Vec<Option<DPatch>> = (0..mesh.triangles.len())
        .map(|t| {
            let sc = scene.as_ref()?;
            sc.patch_of_tri(t).map(|i| sc.patches()[i])
        })
        .collect();
    let seams: Vec<Seam<f64>> = (0..mesh.triangles.len())
        .map(|t| {
            scene
                .as_ref()
                .and_then(|sc| sc.patch_of_tri(t).map(|i| sc.seams()[i]))
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

/// The report of `smoothtri inspect` for precision `F`, the patches on `field`.
pub fn inspect<F: Prec>(name: &str, mesh: &Mesh, field: LineField) -> Result<String> {
    let mut s = String::new();
    let (lo, hi) = mesh.bounds();
    let diag = (hi - lo).length();
    let _ = writeln!(s, "mesh: {name}");
    let _ = writeln!(
        s,
        "triangles: {}   vertices: {}",
        mesh.triangles.len(),
        mesh.positions.len()
    );
    let _ = writeln!(
        s,
        "bounding box: min ({}, {}, {})  max ({}, {}, {})  diagonal {}",
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, diag
    );
    let scene = Scene::<F>::build_with(mesh, field, true);
    let _ = writeln!(
        s,
        "line field: {}",
        match field {
            LineField::Face => "face (the paper's construction; --field vertex shares edges)",
            LineField::Vertex => "vertex (shared by neighbours: their edge curves meet)",
        }
    );
    let scene = match scene {
        Ok(sc) => Some(sc),
        Err(e) => {
            let _ = writeln!(s, "patches ({}): none accepted: {e}", F::PRECISION);
            None
        }
    };
    if let Some(sc) = &scene {
        let _ = writeln!(
            s,
            "patches ({}): {} accepted, {} rejected",
            F::PRECISION,
            sc.patches().len(),
            sc.rejected.len()
        );
        for (why, n) in sc.rejected_summary() {
            let _ = writeln!(s, "  rejected {n:>6} × {why}");
        }
        let _ = writeln!(
            s,
            "  remedied (normals clamped toward the face normal, Patch::new_or_tilted): {}{}",
            sc.remedied().len(),
            if sc.remedied().is_empty() {
                String::new()
            } else {
                format!(" = {}", sc.remedied_summary())
            }
        );
        let shown: Vec<String> = sc
            .rejected
            .iter()
            .take(10)
            .map(|(t, _)| t.to_string())
            .collect();
        if !shown.is_empty() {
            let more = if sc.rejected.len() > 10 { ", …" } else { "" };
            let _ = writeln!(s, "  rejected triangle ids: {}{more}", shown.join(", "));
        }
    }
    // Histogram of vertex-normal angles to face normals.
    let bins = [0.0, 5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0, 180.1];
    let mut counts = vec![0usize; bins.len() - 1];
    let mut degenerate = 0usize;
    let mut max_ang = 0.0f64;
    for t in 0..mesh.triangles.len() {
        let (p, n) = mesh.triangle(t);
        let Some(nf) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
            degenerate += 1;
            continue;
        };
        for v in n {
            let Some(v) = v.try_normalize() else {
                continue;
            };
            let a = nf.dot(v).clamp(-1.0, 1.0).acos().to_degrees();
            max_ang = max_ang.max(a);
            if let Some(i) = bins.windows(2).position(|w| a >= w[0] && a < w[1]) {
                counts[i] += 1;
            }
        }
    }
    let total: usize = counts.iter().sum();
    let _ = writeln!(
        s,
        "vertex-normal angle to face normal (degrees), {total} corners, max {max_ang:.2}:"
    );
    let peak = counts.iter().copied().max().unwrap_or(0).max(1);
    for (i, &c) in counts.iter().enumerate() {
        let hi_s = if i + 2 == bins.len() {
            "180".to_string()
        } else {
            format!("{}", bins[i + 1])
        };
        let bar = "#".repeat((c * 40).div_ceil(peak));
        let _ = writeln!(s, "  [{:>3}, {:>3})  {c:>7}  {bar}", bins[i], hi_s);
    }
    if degenerate > 0 {
        let _ = writeln!(s, "  ({degenerate} triangles with zero area left out)");
    }
    let c = cracks(mesh, field);
    let _ = writeln!(
        s,
        "shared edges: {} interior, {} boundary, {} non-manifold ({} samples per edge, f64 patches)",
        c.edges, c.boundary, c.non_manifold, EDGE_SAMPLES
    );
    let _ = writeln!(
        s,
        "              {} of them next to a patch whose normals were clamped per patch; {} \
         creases (split normals: left out, no jump to remove)",
        c.remedied, c.creases
    );
    let _ = writeln!(
        s,
        "crack width:  max {:.3e} ({:.3e} of diagonal), mean {:.3e} (edges without a clamped side)",
        c.max_gap,
        c.max_gap / diag.max(f64::MIN_POSITIVE),
        c.mean_gap
    );
    let _ = writeln!(
        s,
        "normal jump:  max {:.4}°, mean {:.4}° (edge-curve normals, edge_point_normal)",
        c.max_jump_deg, c.mean_jump_deg
    );
    let _ = writeln!(
        s,
        "              max {:.4}°, mean {:.4}° (surface normals, point_normal on the edge)",
        c.max_surface_jump_deg, c.mean_surface_jump_deg
    );
    let _ = writeln!(
        s,
        "              max {:.4}°, mean {:.4}° (seamless shading normals, Seam::shading_normal; \
         {} edges fitted)",
        c.max_shading_jump_deg, c.mean_shading_jump_deg, c.seam_edges
    );
    if c.unjoined > 0 {
        let _ = writeln!(
            s,
            "              {} edges with no seam (their vertices not shared in the index buffer, \
             or a common normal the fit declined): max {:.4}°",
            c.unjoined, c.max_unjoined_jump_deg
        );
    }
    if let Some(sc) = &scene {
        let pbytes = std::mem::size_of_val(sc.patches());
        let bvh = sc.bvh();
        let _ = writeln!(
            s,
            "memory ({}): patches {} bytes ({} × {}), BVH {} bytes ({} nodes + indices), total {} bytes",
            F::PRECISION,
            pbytes,
            sc.patches().len(),
            std::mem::size_of::<Patch<F>>(),
            bvh.memory_bytes(),
            bvh.node_count(),
            pbytes + bvh.memory_bytes()
        );
        let _ = writeln!(
            s,
            "seams ({}): {} bytes ({} × {}), {} shared edges fitted (seamless shading normals)",
            F::PRECISION,
            std::mem::size_of_val(sc.seams()),
            sc.seams().len(),
            std::mem::size_of::<Seam<F>>(),
            sc.report().seam_edges.unwrap_or(0)
        );
        let (p, se, b) = sc.bytes_per_triangle();
        let _ = writeln!(
            s,
            "per triangle ({}): patch {p:.0} + seams {se:.0} + BVH {b:.0} = {:.0} bytes",
            F::PRECISION,
            p + se + b
        );
        let _ = writeln!(s, "build ({}): {}", F::PRECISION, sc.timing_line());
        let _ = writeln!(
            s,
            "cracks closed ({}): {} of {} shared edges part, widest gap {:.3e} ({:.3e} of \
             diagonal); each side reaches across by {}× the gap (at most {} of its altitude, \
             smoothtri::close_cracks)",
            F::PRECISION,
            sc.report().cracks.open_edges,
            sc.report().cracks.shared_edges,
            sc.report().cracks.widest_gap,
            sc.report().cracks.widest_gap / diag.max(f64::MIN_POSITIVE),
            smoothtri::internal::CRACK_REACH,
            smoothtri::internal::MAX_CRACK_REACH
        );
        if let Some(vc) = sc.report().vertex_clamps {
            let _ = writeln!(
                s,
                "remedy per vertex ({}): {} vertex normals clamped (one normal for all faces \
                 around the vertex, smoothtri::clamp_vertex_normals); {} triangles still \
                 clamped per patch",
                F::PRECISION,
                vc.clamped,
                vc.unresolved
            );
        }
    }
    Ok(s)
}
