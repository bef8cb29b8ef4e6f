//! `trace` and `eval`: CSV in, CSV out, floats printed shortest-round-trip.

use std::fmt::Write as _;
use std::io::Read;

use smoothtri::Ray;

use crate::error::{DemoError, Result};
use crate::scene::{Mode, Prec, Scene, tracer};
use crate::scenes::Mesh;

/// Reads a whole text file, or stdin for `-`.
pub fn read_text(path: &str) -> Result<String> {
    if path == "-" {
        let mut s = String::new();
        std::io::stdin()
            .read_to_string(&mut s)
            .map_err(|e| DemoError::io("<stdin>", e))?;
        Ok(s)
    } else {
        std::fs::read_to_string(path).map_err(|e| DemoError::io(path, e))
    }
}

/// The name of an input in messages (`<stdin>` for `-`).
fn display_name(path: &str) -> &str {
    if path == "-" { "<stdin>" } else { path }
}

/// Data rows of a CSV text with the given header: `(line number, fields)`.
fn rows<'a>(text: &'a str, path: &str, header: &[&str]) -> Result<Vec<(usize, Vec<&'a str>)>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let want = header.join(",");
    let Some((hl, h)) = lines.next() else {
        return Err(DemoError::parse(
            path,
            1,
            format!("empty file, expected header '{want}'"),
        ));
    };
    let got: Vec<String> = h
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    if got != header {
        return Err(DemoError::parse(
            path,
            hl + 1,
            format!("expected header '{want}', found '{}'", h.trim()),
        ));
    }
    let mut out = Vec::new();
    for (i, l) in lines {
        let f: Vec<&str> = l.split(',').map(str::trim).collect();
        if f.len() != header.len() {
            return Err(DemoError::parse(
                path,
                i + 1,
                format!("expected {} fields, found {}", header.len(), f.len()),
            ));
        }
        out.push((i + 1, f));
    }
    Ok(out)
}

fn num<F: Prec>(tok: &str, path: &str, line: usize) -> Result<F> {
    let v = crate::mesh::parse_f64(tok, path, line)?;
    // Parse in the target precision directly so printed values read back exactly.
    let f = if F::NAME == "f32" {
        F::from_f64(tok.parse::<f32>().map(f64::from).unwrap_or(v))
    } else {
        F::from_f64(v)
    };
    Ok(f)
}

fn vec3<F: Prec>(v: F::Vec3) -> String {
    let [x, y, z] = F::arr(v);
    format!("{x},{y},{z}")
}

/// `smoothtri trace`: closest hit with `t > 0` for each ray.
pub fn trace<F: Prec>(mesh: &Mesh, rays_path: &str, iterations: usize) -> Result<()> {
    let t = tracer::<F>(Mode::Smooth, iterations)?;
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
        rays.push(Ray::<F>::new(F::v(o), F::v(d)));
    }
    let scene = Scene::<F>::build(mesh)?;
    if let Some(note) = scene.rejected_note() {
        eprintln!("{note}");
    }
    let bvh = scene.bvh();
    let mut out = String::from("ray,hit,t,x,y,z,nx,ny,nz,triangle,w1,w2,t_error\n");
    for (i, ray) in rays.iter().enumerate() {
        match t.closest(&bvh, ray, F::MIN_POSITIVE, F::MAX) {
            Some(h) => {
                let tri = scene
                    .tri_ids
                    .get(h.patch as usize)
                    .copied()
                    .unwrap_or(u32::MAX);
                let _ = writeln!(
                    out,
                    "{i},1,{},{},{},{tri},{},{},{}",
                    h.t,
                    vec3::<F>(h.point),
                    vec3::<F>(h.normal),
                    h.w1,
                    h.w2,
                    h.t_error
                );
            }
            None => {
                let _ = writeln!(out, "{i},0,,,,,,,,,,,");
            }
        }
    }
    crate::image::write_bytes("-", out.as_bytes())
}

/// `smoothtri eval`: surface point and normal at `(triangle, w1, w2)`.
pub fn eval<F: Prec>(mesh: &Mesh, points_path: &str) -> Result<()> {
    let text = read_text(points_path)?;
    let points_path = display_name(points_path);
    let rows = rows(&text, points_path, &["triangle", "w1", "w2"])?;
    let scene = Scene::<F>::build(mesh)?;
    let mut out = String::from("triangle,w1,w2,x,y,z,nx,ny,nz\n");
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
        let Some(pi) = scene.patch_of_tri[tri] else {
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
        let patch = &scene.patches[pi as usize];
        let (mut p, mut n) = patch.point_normal(w1, w2);
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
            p = F::v(ps[c]);
            n = F::v(ns[c].normalize_or_zero());
        }
        let _ = writeln!(out, "{tri},{w1},{w2},{},{}", vec3::<F>(p), vec3::<F>(n));
    }
    crate::image::write_bytes("-", out.as_bytes())
}
