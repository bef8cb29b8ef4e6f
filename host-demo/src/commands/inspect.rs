//! `smoothtri inspect`: mesh statistics, rejected patches, normal angles, cracks, normal jumps
//! (edge curves, geometric and seamless shading normals), memory.

use std::fmt::Write as _;

use smoothtri::mesh::Seam;
use smoothtri::{LineField, Patch};
use smoothtri_host::{EDGE_SAMPLES, cracks};
use smoothtri_io::Mesh;

use super::source::MeshSource;
use crate::error::Result;
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
            sc.report().patches,
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
