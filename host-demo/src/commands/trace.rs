//! `smoothtri trace`: rays from a CSV file (`ox,oy,oz,dx,dy,dz`), hits out as CSV.

use std::fmt::Write as _;

use smoothtri::{LineField, Ray};
use smoothtri_io::Mesh;

use super::source::MeshSource;
use crate::csvio::{display_name, num, read_text, rows, vec3};
use crate::error::{DemoError, Result};
use crate::tracer::{Mode, Normals, Prec, Precision, Scene, tracer};

/// Options of `trace`.
#[derive(Clone, Debug)]
pub struct TraceOptions {
    /// The mesh (required).
    pub source: MeshSource,
    /// Rays CSV with header `ox,oy,oz,dx,dy,dz` (`-` for stdin).
    pub rays: String,
    /// The surface: `Smooth`, or a peer (`PhongTess`, `Nagata`; [`crate::peers`]).
    pub mode: Mode,
    /// Iteration budget.
    pub iterations: usize,
    /// Kernel precision.
    pub precision: Precision,
    /// The line field the patches are built on.
    pub field: LineField,
    /// The normal of the `snx,sny,snz` columns.
    pub normals: Normals,
}

/// Loads the mesh and traces the rays in the chosen precision.
pub fn run(a: TraceOptions) -> Result<()> {
    let (_, mesh) = a.source.load(false)?;
    if let Some(peer) = crate::peers::peer_of(a.mode) {
        let out = match a.precision {
            Precision::F32 => crate::peers::trace_csv::<f32>(&mesh, peer, &read_rays(&a.rays)?)?,
            Precision::F64 => crate::peers::trace_csv::<f64>(&mesh, peer, &read_rays(&a.rays)?)?,
        };
        return crate::output::write("-", out.as_bytes());
    }
    if a.mode != Mode::Smooth {
        return Err(DemoError::Usage(format!(
            "trace --mode {}: use smooth, phong-tess or nagata",
            a.mode.name()
        )));
    }
    match a.precision {
        Precision::F32 => trace::<f32>(&mesh, &a.rays, a.iterations, a.field, a.normals),
        Precision::F64 => trace::<f64>(&mesh, &a.rays, a.iterations, a.field, a.normals),
    }
}

/// Traces the rays of `rays_path` (`-` for stdin) against `mesh` in precision `F` and prints
/// the closest hit with `t > 0` of each as CSV on stdout, the patches on `field`; the
/// `snx,sny,snz` columns hold the shading normal `normals` asks for (the seams are fitted only
/// for [`Normals::Seamless`]).
pub fn trace<F: Prec>(
    mesh: &Mesh,
    rays_path: &str,
    iterations: usize,
    field: LineField,
    normals: Normals,
) -> Result<()> {
    let t = tracer::<F>(Mode::Smooth, iterations)?;
    let rays = read_rays::<F>(rays_path)?;
    let scene = Scene::<F>::build_with(mesh, field, normals == Normals::Seamless)?;
    if let Some(note) = scene.rejected_note() {
        eprintln!("{note}");
    }
    let bvh = scene.bvh();
    let mut out = String::from("ray,hit,t,x,y,z,nx,ny,nz,snx,sny,snz,triangle,w1,w2,t_error\n");
    for (i, ray) in rays.iter().enumerate() {
        match t.closest_hit(&bvh, ray, F::MIN_POSITIVE, F::MAX) {
            Some(h) => {
                let tri = scene
                    .tri_ids()
                    .get(h.patch as usize)
                    .copied()
                    .unwrap_or(u32::MAX);
                let _ = writeln!(
                    out,
                    "{i},1,{},{},{},{},{tri},{},{},{}",
                    h.t,
                    vec3::<F>(h.point),
                    vec3::<F>(h.normal),
                    vec3::<F>(scene.shading_normal(&h)),
                    h.w1,
                    h.w2,
                    h.t_error
                );
            }
            None => {
                let _ = writeln!(out, "{i},0,,,,,,,,,,,,,,");
            }
        }
    }
    crate::output::write("-", out.as_bytes())
}

/// The rays of `rays_path` (`-` for stdin) in precision `F`.
fn read_rays<F: Prec>(rays_path: &str) -> Result<Vec<Ray<F>>> {
    let text = read_text(rays_path)?;
    let rays_path = display_name(rays_path);
    let rows = rows(&text, rays_path, &["ox", "oy", "oz", "dx", "dy", "dz"])?;
    let mut rays = Vec::with_capacity(rows.len());
    for (line, f) in &rows {
        let mut v = [F::ZERO; 6];
        for (slot, tok) in v.iter_mut().zip(f) {
            *slot = num::<F>(tok, rays_path, *line)?;
        }
        let o = glam::DVec3::new(v[0].to_f64(), v[1].to_f64(), v[2].to_f64());
        let d = glam::DVec3::new(v[3].to_f64(), v[4].to_f64(), v[5].to_f64());
        if d == glam::DVec3::ZERO {
            return Err(DemoError::parse(rays_path, *line, "zero ray direction"));
        }
        rays.push(Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d)));
    }
    Ok(rays)
}
