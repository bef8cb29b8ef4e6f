//! Wavefront OBJ: an own line parser whose errors name `file:line`, and a writer ([`write()`]).

use std::fmt::Write as _;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{FloatWidth, LoadedMesh, Mesh};
use crate::options::{BYTES_PER_POSITION, Budget, LoadOptions, read_file};
use crate::weld::{Builder, charge_face};

/// Reads and parses an OBJ file (invalid UTF-8 is replaced, not rejected) within the default
/// [`LoadOptions`]; [`Error::Io`] when it cannot be read, [`Error::Budget`] when it is larger
/// than the budget, else as [`parse`].
pub fn load(path: &str) -> Result<LoadedMesh> {
    let (bytes, budget) = read_file(path, &LoadOptions::default())?;
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
                charge_face(
                    budget,
                    corners.len(),
                    |m| Error::parse(path, line, m),
                    |n| format!("face with {n} vertices (need at least 3)"),
                    |n| format!("'f' ({n} triangles)"),
                )?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::BYTES_PER_TRIANGLE;

    fn ok(text: &str) -> LoadedMesh {
        parse(text, "t.obj").unwrap()
    }

    fn err(text: &str) -> String {
        parse(text, "t.obj").map(|_| ()).unwrap_err().to_string()
    }

    #[test]
    fn faces_with_and_without_normals_and_texture_indices() {
        let m = ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1\n");
        assert_eq!(m.mesh.triangles, [[0, 1, 2]]);
        assert!(!m.computed_normals);
        assert_eq!(m.mesh.normals, [DVec3::Z; 3]);
        for face in ["f 1 2 3", "f 1/1 2/1 3/1"] {
            let m = ok(&format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n{face}\n"));
            assert_eq!(m.mesh.triangles.len(), 1, "{face}");
            // Computed: the face's normal, +z for this counter-clockwise triangle.
            assert!(m.computed_normals, "{face}");
            assert!((m.mesh.normals[0].normalize() - DVec3::Z).length() < 1e-12);
        }
        let m = ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
        assert!(!m.computed_normals);
    }

    #[test]
    fn negative_indices_count_back_from_the_last_definition() {
        let m = ok("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\n");
        let (p, n) = m.mesh.triangle(0);
        assert_eq!(
            p,
            [DVec3::ZERO, DVec3::X, DVec3::Y],
            "relative to the vertices so far"
        );
        assert_eq!(n, [DVec3::Z; 3]);
    }

    #[test]
    fn polygons_are_fan_triangulated() {
        let m = ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\nf 1 2 3 4 5\n");
        let tris: Vec<[DVec3; 3]> = (0..3).map(|t| m.mesh.triangle(t).0).collect();
        let v = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        assert_eq!(
            tris,
            [
                [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)],
                [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)],
                [v(0.0, 0.0), v(0.0, 1.0), v(-1.0, 1.0)],
            ]
        );
    }

    #[test]
    fn comments_blank_lines_and_other_statements_are_skipped() {
        let m = ok(
            "# a comment\n\n  \no object\ng group\nusemtl red\ns 1\nmtllib x.mtl\n\
                    v 0 0 0 # trailing\nv 1 0 0 1.0\nv 0 1 0\nl 1 2\nf 1 2 3 # done\n",
        );
        assert_eq!(m.mesh.triangles.len(), 1);
        // A `#` inside a face ends it.
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 # 3\n"),
            "t.obj:4: face with 2 vertices (need at least 3)"
        );
        // Nothing drawable is an empty mesh here ([`crate::parse`] reports it).
        assert!(ok("# nothing\n").mesh.triangles.is_empty());
    }

    #[test]
    fn bad_lines_name_their_line_number() {
        let cases = [
            ("v 0 0\n", "t.obj:1: 'v' needs 3 coordinates, found 2"),
            ("v 0 0 0\nv 0 x 0\n", "t.obj:2: malformed number 'x'"),
            ("\n\nvn 0 0 inf\n", "t.obj:3: non-finite value 'inf'"),
            ("v 0 0 0\nv 0 0 NaN\n", "t.obj:2: non-finite value 'NaN'"),
            ("vt 0 q\n", "t.obj:1: malformed number 'q'"),
            (
                "v 0 0 0\nv 1 0 0\nf 1 2 3\n",
                "t.obj:3: vertex index 3 out of range (1..=2 defined so far)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
                "t.obj:4: vertex index -4 out of range (1..=3 defined so far)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
                "t.obj:4: vertex index 0 out of range (1..=3 defined so far)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
                "t.obj:4: normal index 1 out of range (1..=0 defined so far)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2 3\n",
                "t.obj:4: texture index 1 out of range (1..=0 defined so far)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a\n",
                "t.obj:4: malformed vertex index 'a' in face",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n",
                "t.obj:6: malformed face vertex '1/1/1/1'",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n",
                "t.obj:4: malformed vertex index '99999999999999999999' in face",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(err(text), want, "{text:?}");
        }
    }

    #[test]
    fn the_budget_counts_vertices_and_triangles_by_line() {
        let text: String = (0..10).map(|k| format!("v {k} 0 0\n")).collect::<String>()
            + "f 1 2 3 4 5 6 7 8 9 10\n";
        let budget = |max: u64| Budget::new("t.obj", &LoadOptions::default().with_max_bytes(max));
        // Ten vertices and eight triangles fit exactly.
        let exact = 10 * BYTES_PER_POSITION + 8 * BYTES_PER_TRIANGLE;
        assert!(parse_budgeted(&text, "t.obj", &budget(exact)).is_ok());
        let e = parse_budgeted(&text, "t.obj", &budget(exact - 1))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "t.obj: line 11: 'f' (8 triangles) needs {exact} bytes, over the load budget of {} bytes",
                exact - 1
            )
        );
        let e = parse_budgeted(&text, "t.obj", &budget(5 * BYTES_PER_POSITION))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.obj: line 6: 'v' (vertex) needs"), "{e}");
    }

    #[test]
    fn written_obj_reads_back() {
        let m = ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nf 1//1 2//1 3//1\n");
        let back = ok(std::str::from_utf8(&write(&m.mesh, FloatWidth::F64, "a\nb")).unwrap());
        assert_eq!(back.mesh.positions, m.mesh.positions);
        assert_eq!(back.mesh.normals, [DVec3::Z; 3]);
        assert_eq!(back.mesh.triangles, m.mesh.triangles);
    }
}
