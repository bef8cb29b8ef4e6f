//! `smoothtri eval`: surface points from a CSV file (`triangle,w1,w2`), points and normals out
//! as CSV.

use std::fmt::Write as _;

use smoothtri_io::Mesh;

use super::source::MeshSource;
use crate::csvio::{display_name, num, read_text, rows, vec3};
use crate::error::{DemoError, Result};
use crate::tracer::{Normals, Prec, Precision, Scene};

/// Options of `eval`.
#[derive(Clone, Debug)]
pub struct EvalOptions {
    /// The mesh (required).
    pub source: MeshSource,
    /// Points CSV with header `triangle,w1,w2` (`-` for stdin).
    pub points: String,
    /// Evaluation precision.
    pub precision: Precision,
    /// The normal of the `snx,sny,snz` columns.
    pub normals: Normals,
}

/// Loads the mesh and evaluates the points in the chosen precision.
pub fn run(a: EvalOptions) -> Result<()> {
    let (_, mesh) = a.source.load(false)?;
    match a.precision {
        Precision::F32 => eval::<f32>(&mesh, &a.points, a.normals),
        Precision::F64 => eval::<f64>(&mesh, &a.points, a.normals),
    }
}

/// Evaluates the surface point and normal at each `(triangle, w1, w2)` of `points_path` (`-`
/// for stdin) in precision `F` and prints them as CSV on stdout, with the shading normal
/// `normals` asks for (the seams are fitted only for [`Normals::Seamless`]).
pub fn eval<F: Prec>(mesh: &Mesh, points_path: &str, normals: Normals) -> Result<()> {
    let text = read_text(points_path)?;
    let points_path = display_name(points_path);
    let rows = rows(&text, points_path, &["triangle", "w1", "w2"])?;
    let scene = Scene::<F>::build_with(
        mesh,
        smoothtri::LineField::Face,
        normals == Normals::Seamless,
    )?;
    let mut out = String::from("triangle,w1,w2,x,y,z,nx,ny,nz,snx,sny,snz\n");
    for (line, f) in &rows {
        let tri: usize = f[0].parse().map_err(|_| {
            DemoError::parse(
                points_path,
                *line,
                format!("malformed triangle id '{}'", f[0]),
            )
        })?;
        if tri >= mesh.triangles.len() {
            return Err(DemoError::parse(
                points_path,
                *line,
                format!(
                    "triangle {tri} out of range (the mesh has {})",
                    mesh.triangles.len()
                ),
            ));
        }
        let w1 = num::<F>(f[1], points_path, *line)?;
        let w2 = num::<F>(f[2], points_path, *line)?;
        let Some(pi) = scene.patch_of_tri(tri) else {
            let why = scene
                .rejected
                .iter()
                .find(|(t, _)| *t as usize == tri)
                .map(|(_, e)| e.to_string())
                .unwrap_or_default();
            return Err(DemoError::parse(
                points_path,
                *line,
                format!("triangle {tri} was rejected by the core: {why}"),
            ));
        };
        let patch = &scene.patches()[pi];
        let (mut p, mut n) = patch.point_normal(w1, w2);
        // The seam's correction (none without seams): at the vertices it is the vertex normal.
        let mut sn = match scene.seams().get(pi) {
            Some(seam) => seam.correct(patch, w1, w2, n),
            None => n,
        };
        // The surface interpolates the vertices exactly: return the input vertex itself there
        // (the patch's local frame would round it).
        let (z, o) = (F::ZERO, F::ONE);
        let corner = if w1 == z && w2 == z {
            Some(0)
        } else if w1 == o && w2 == z {
            Some(1)
        } else if w1 == z && w2 == o {
            Some(2)
        } else {
            None
        };
        if let Some(c) = corner {
            let (ps, ns) = mesh.triangle(tri);
            p = F::from_dvec3(ps[c]);
            n = F::from_dvec3(ns[c].normalize_or_zero());
            sn = n;
        }
        let _ = writeln!(
            out,
            "{tri},{w1},{w2},{},{},{}",
            vec3::<F>(p),
            vec3::<F>(n),
            vec3::<F>(sn)
        );
    }
    crate::output::write("-", out.as_bytes())
}
