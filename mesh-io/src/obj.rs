//! Wavefront OBJ: an own line parser whose errors name `file:line`, and a writer ([`write()`]).

use std::fmt::Write as _;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{FloatWidth, LoadedMesh, Mesh};
use crate::options::{BYTES_PER_POSITION, BYTES_PER_TRIANGLE, Budget, LoadOptions, read_file};
use crate::weld::Builder;

/// Reads and parses an OBJ file (invalid UTF-8 is replaced, not rejected) within the default
/// [`LoadOptions`]; [`Error::Io`] when it cannot be read, [`Error::Budget`] when it is larger
/// than the budget, else as [`parse`].
pub fn load(path: &str) -> Result<LoadedMesh> {
    let budget = Budget::new(path, &LoadOptions::default());
    let bytes = read_file(path, &budget)?;
    parse_budgeted(&String::from_utf8_lossy(&bytes), path, &budget)
}

/// Parses a finite number, or reports [`Error::Parse`] at `path:line` with what is wrong
/// (malformed, or not finite). Also for other line-based text files (the demo's CSV readers).
pub fn parse_f64(tok: &str, path: &str, line: usize) -> Result<f64> {
    let v: f64 = tok
        .parse()
        .map_err(|_| Error::parse(path, line, format!("malformed number '{tok}'")))?;
    if !v.is_finite() {
        return Err(Error::parse(
            path,
            line,
            format!("non-finite value '{tok}'"),
        ));
    }
    Ok(v)
}

/// Resolves an OBJ index (1-based, or negative relative to the current count).
fn obj_index(tok: &str, count: usize, what: &str, path: &str, line: usize) -> Result<usize> {
    let i: i64 = tok.parse().map_err(|_| {
        Error::parse(
            path,
            line,
            format!("malformed {what} index '{tok}' in face"),
        )
    })?;
    let r = if i > 0 {
        i - 1
    } else if i < 0 {
        count as i64 + i
    } else {
        -1
    };
    if r < 0 || r as usize >= count {
        return Err(Error::parse(
            path,
            line,
            format!("{what} index {i} out of range (1..={count} defined so far)"),
        ));
    }
    Ok(r as usize)
}

/// Parses Wavefront OBJ text (`v`, `vn`, `vt`, `f` with `v`, `v/vt`, `v//vn`, `v/vt/vn`,
/// negative indices; `#` comments and other statements ignored). Polygons are
/// fan-triangulated. The decoded mesh is held within the default [`LoadOptions::max_bytes`]
/// ([`Error::Budget`] naming the line past it).
pub fn parse(text: &str, path: &str) -> Result<LoadedMesh> {
    parse_budgeted(text, path, &Budget::new(path, &LoadOptions::default()))
}

/// [`parse`], the decoded mesh charged to `budget` line by line (nothing is reserved ahead:
/// every vertex, normal and triangle comes from a line of the text).
pub(crate) fn parse_budgeted(text: &str, path: &str, budget: &Budget) -> Result<LoadedMesh> {
    let mut positions = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    let mut n_vt = 0usize;
    let mut tris = Vec::new();
    for (ln, raw) in text.lines().enumerate() {
        let line = ln + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        match kw {
            "v" | "vn" => {
                let nums: Vec<&str> = toks.collect();
                if nums.len() < 3 {
                    return Err(Error::parse(
                        path,
                        line,
                        format!("'{kw}' needs 3 coordinates, found {}", nums.len()),
                    ));
                }
                let mut c = [0.0; 3];
                for (slot, tok) in c.iter_mut().zip(&nums) {
                    *slot = parse_f64(tok, path, line)?;
                }
                for tok in &nums[3..] {
                    parse_f64(tok, path, line)?;
                }
                let (what, size) = if kw == "v" {
                    ("vertex", BYTES_PER_POSITION)
                } else {
                    ("vertex normal", 24)
                };
                budget.charge(1, size).map_err(|()| {
                    budget.typed(Error::parse(path, line, format!("'{kw}' ({what})")))
                })?;
                if kw == "v" {
                    positions.push(DVec3::from_array(c));
                } else {
                    normals.push(DVec3::from_array(c));
                }
            }
            "vt" => {
                for tok in toks {
                    parse_f64(tok, path, line)?;
                }
                n_vt += 1;
            }
            "f" => {
                let mut corners = Vec::new();
                for tok in toks {
                    let mut parts = tok.split('/');
                    let v = parts.next().unwrap_or("");
                    let vi = obj_index(v, positions.len(), "vertex", path, line)?;
                    let vt = parts.next();
                    if let Some(vt) = vt.filter(|s| !s.is_empty()) {
                        obj_index(vt, n_vt, "texture", path, line)?;
                    }
                    let vn = match parts.next().filter(|s| !s.is_empty()) {
                        Some(s) => {
                            Some(normals[obj_index(s, normals.len(), "normal", path, line)?])
                        }
                        None => None,
                    };
                    if parts.next().is_some() {
                        return Err(Error::parse(
                            path,
                            line,
                            format!("malformed face vertex '{tok}'"),
                        ));
                    }
                    corners.push((vi, vn));
                }
                if corners.len() < 3 {
                    return Err(Error::parse(
                        path,
                        line,
                        format!("face with {} vertices (need at least 3)", corners.len()),
                    ));
                }
                budget
                    .charge(corners.len() as u64 - 2, BYTES_PER_TRIANGLE)
                    .map_err(|()| {
                        budget.typed(Error::parse(
                            path,
                            line,
                            format!("'f' ({} triangles)", corners.len() - 2),
                        ))
                    })?;
                for k in 1..corners.len() - 1 {
                    tris.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(Builder { positions, tris }.into_loaded(Vec::new()))
}

/// OBJ text of `mesh`: `comment` as `#` lines, then `v x y z`, `vn nx ny nz` (unit length) and
/// `f a//a b//b c//c` (1-based; positions and normals share indices). Numbers are printed
/// shortest-round-trip in `width`, so they read back exactly in it.
pub fn write(mesh: &Mesh, width: FloatWidth, comment: &str) -> Vec<u8> {
    let mut s = String::new();
    for line in comment.lines() {
        let _ = writeln!(s, "# {line}");
    }
    let mut vec3 = |kw: &str, v: DVec3| {
        let _ = match width {
            FloatWidth::F32 => {
                let [x, y, z] = v.as_vec3().to_array();
                writeln!(s, "{kw} {x} {y} {z}")
            }
            FloatWidth::F64 => writeln!(s, "{kw} {} {} {}", v.x, v.y, v.z),
        };
    };
    for p in &mesh.positions {
        vec3("v", *p);
    }
    for n in &mesh.normals {
        vec3("vn", n.normalize_or_zero());
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as u64 + 1);
        let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
    }
    s.into_bytes()
}
