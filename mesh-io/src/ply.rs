//! Stanford PLY (ASCII and binary): read through the `ply-rs-bw` crate, written
//! ([`write()`]) as binary little-endian by hand.

use glam::DVec3;
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};

use crate::error::{Error, Result};
use crate::mesh::{FloatWidth, LoadedMesh, Mesh};
use crate::options::{BYTES_PER_POSITION, Budget, LoadOptions, read_file};
use crate::weld::{Builder, charge_face};

fn prop_f64(p: &Property) -> Option<f64> {
    use ply_rs_bw::ply::Property as P;
    Some(match *p {
        P::Char(v) => v as f64,
        P::UChar(v) => v as f64,
        P::Short(v) => v as f64,
        P::UShort(v) => v as f64,
        P::Int(v) => v as f64,
        P::UInt(v) => v as f64,
        P::Float(v) => v as f64,
        P::Double(v) => v,
        _ => return None,
    })
}

fn prop_list(p: &Property) -> Option<Vec<i64>> {
    use ply_rs_bw::ply::Property as P;
    Some(match p {
        P::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        P::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        P::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        P::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        P::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        P::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

/// Reads a PLY file: `vertex` elements with `x, y, z` (and optionally `nx, ny, nz`), `face`
/// elements with a `vertex_indices` (or `vertex_index`) list, fan-triangulated; within the
/// default [`LoadOptions`] ([`Error::Budget`] when the file is larger than the budget).
pub fn load(path: &str) -> Result<LoadedMesh> {
    let (bytes, budget) = read_file(path, &LoadOptions::default())?;
    parse_budgeted(&bytes, path, &budget)
}

/// The keywords that start a PLY header line.
const HEADER_KEYWORDS: [&str; 7] = [
    "ply",
    "format",
    "comment",
    "obj_info",
    "element",
    "property",
    "end_header",
];

/// `bytes` with every header line that starts with no PLY keyword (Blender 2.4x writes a bare
/// "Created by Blender3D …" line) or is blank turned into a `comment`, as other readers
/// (assimp, MeshLab) take them; `None` when the header needs no change. The body after
/// `end_header` is kept byte for byte.
fn lenient_header(bytes: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(bytes.len() + 64);
    let mut changed = false;
    let mut rest = bytes;
    while !rest.is_empty() {
        let end = rest
            .iter()
            .position(|&b| b == b'\n')
            .map_or(rest.len(), |i| i + 1);
        let (line, tail) = rest.split_at(end);
        rest = tail;
        let text = String::from_utf8_lossy(line);
        let word = text.split_whitespace().next().unwrap_or("");
        if HEADER_KEYWORDS.contains(&word) {
            out.extend_from_slice(line);
        } else {
            changed = true;
            out.extend_from_slice(b"comment ");
            let start = line.iter().position(|&b| b != b' ' && b != b'\t');
            out.extend_from_slice(start.and_then(|i| line.get(i..)).unwrap_or(b"\n"));
        }
        if word == "end_header" {
            out.extend_from_slice(rest);
            return changed.then_some(out);
        }
    }
    None
}

/// A PLY parser error on one line: its first line, then what it read and why, without the
/// parser's debug structures.
fn one_line(e: &dyn std::fmt::Display) -> String {
    let text = e.to_string();
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let mut out = lines
        .next()
        .unwrap_or("unreadable")
        .trim_end_matches('.')
        .to_owned();
    if let Some(first) = out.get(..1) {
        out = first.to_lowercase() + &out[1..];
    }
    for l in lines {
        if let Some(s) = l.strip_prefix("String:") {
            let s = s.trim().trim_matches('\'');
            let short: String = s.chars().take(48).collect();
            let more = if s.chars().count() > 48 { "…" } else { "" };
            out += &format!(" ('{short}{more}')");
        } else if let Some(why) = l.strip_prefix("Error:")
            && !why.contains('{')
        {
            out += &format!(": {}", why.trim().trim_end_matches('.'));
        }
    }
    out
}

/// A vertex element as the loader keeps it: the six numbers it reads, nothing else.
#[derive(Default)]
struct Vert {
    xyz: [Option<f64>; 3],
    n: [Option<f64>; 3],
}

/// A face element as the loader keeps it: its `vertex_indices` and `vertex_index` lists.
#[derive(Default)]
struct Face {
    indices: Option<Vec<i64>>,
    index: Option<Vec<i64>>,
}

/// Implements the parser's `PropertyAccess` for an element the loader keeps: each listed
/// property (`"key" => field` or `field[index]`, an `Option`) set to what `$read` makes of it,
/// every other property ignored.
macro_rules! kept_properties {
    ($t:ty, $read:ident, $($key:literal => $field:ident $([$i:literal])?),+ $(,)?) => {
        impl PropertyAccess for $t {
            fn new() -> Self {
                <$t>::default()
            }
            fn set_property(&mut self, key: &str, p: Property) -> PropertyAccessResult {
                let slot = match key {
                    $($key => &mut self.$field $([$i])?,)+
                    _ => return PropertyAccessResult::Ignored,
                };
                *slot = $read(&p);
                PropertyAccessResult::Set
            }
        }
    };
}

kept_properties!(
    Vert, prop_f64,
    "x" => xyz[0], "y" => xyz[1], "z" => xyz[2], "nx" => n[0], "ny" => n[1], "nz" => n[2],
);
kept_properties!(Face, prop_list, "vertex_indices" => indices, "vertex_index" => index);

/// An element the loader does not use: read past, nothing kept.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// The fewest bytes one element of `def` takes in `encoding`: binary, the sum of its scalar
/// properties' sizes and its lists' length fields (a list may be empty); ASCII, one digit and
/// one separator per property. At least one byte, so that a count is never free.
fn min_element_bytes(def: &ply_rs_bw::ply::ElementDef, encoding: ply_rs_bw::ply::Encoding) -> u64 {
    use ply_rs_bw::ply::{Encoding, PropertyType, ScalarType as S};
    let size = |t: &S| -> u64 {
        match t {
            S::Char | S::UChar => 1,
            S::Short | S::UShort => 2,
            S::Int | S::UInt | S::Float => 4,
            S::Double => 8,
        }
    };
    let n: u64 = match encoding {
        Encoding::Ascii => 2 * def.properties.len() as u64,
        _ => def
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(t) | PropertyType::List(t, _) => size(t),
            })
            .sum(),
    };
    n.max(1)
}

/// Parses the bytes of a PLY file (see [`load`]); `path` names it in messages. Each element
/// count of the header is checked against the bytes after it before anything is read, and the
/// decoded mesh is held within the default [`LoadOptions::max_bytes`] ([`Error::Budget`]).
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    parse_budgeted(bytes, path, &Budget::new(path, &LoadOptions::default()))
}

/// [`parse`], what it decodes charged to `budget` before it is read.
pub(crate) fn parse_budgeted(bytes: &[u8], path: &str, budget: &Budget) -> Result<LoadedMesh> {
    use ply_rs_bw::parser::{Parser, Reader};
    let lenient = lenient_header(bytes);
    let body: &[u8] = lenient.as_deref().unwrap_or(bytes);
    let malformed =
        |e: &dyn std::fmt::Display| Error::format(path, format!("malformed PLY: {}", one_line(e)));
    let mut reader = Reader::new(body);
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| malformed(&e))?;
    // Every element count against the bytes present: a header cannot ask for more elements
    // than the file could hold.
    let have = reader.get_ref().len() as u64;
    let mut need = 0u64;
    for def in header.elements.values() {
        let min = min_element_bytes(def, header.encoding);
        need = need.saturating_add((def.count as u64).saturating_mul(min));
        if need > have {
            return Err(Error::format(
                path,
                format!(
                    "element '{}' declares {} elements of at least {min} bytes each, more than \
                     the {have} bytes after the header hold",
                    def.name, def.count
                ),
            ));
        }
    }
    let mut verts: Option<Vec<Vert>> = None;
    let mut faces: Option<Vec<Face>> = None;
    for def in header.elements.values() {
        let count = def.count as u64;
        let field = |what: &str| format!("element '{}' ({count} {what})", def.name);
        match def.name.as_str() {
            "vertex" => {
                let size = (std::mem::size_of::<Vert>() + 24) as u64 + BYTES_PER_POSITION;
                budget
                    .charge(count, size)
                    .map_err(|()| budget.typed(Error::format(path, field("vertices"))))?;
                verts = Some(
                    Parser::<Vert>::new()
                        .read_payload_for_element(&mut reader, def, &header)
                        .map_err(|e| malformed(&e))?,
                );
            }
            "face" => {
                budget
                    .charge(count, std::mem::size_of::<Face>() as u64)
                    .map_err(|()| budget.typed(Error::format(path, field("faces"))))?;
                let read = Parser::<Face>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| malformed(&e))?;
                let lists: u64 = read
                    .iter()
                    .map(|f| {
                        (f.indices.as_ref().map_or(0, Vec::len)
                            + f.index.as_ref().map_or(0, Vec::len)) as u64
                    })
                    .sum();
                budget
                    .charge(lists, 8)
                    .map_err(|()| budget.typed(Error::format(path, field("faces' index lists"))))?;
                faces = Some(read);
            }
            _ => {
                Parser::<Skip>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| malformed(&e))?;
            }
        }
    }
    let verts = verts.ok_or_else(|| Error::format(path, "PLY has no 'vertex' element"))?;
    let mut positions = Vec::with_capacity(verts.len());
    let mut file_normals = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        let [Some(x), Some(y), Some(z)] = v.xyz else {
            return Err(Error::format(
                path,
                format!("vertex {i} lacks numeric x, y, z"),
            ));
        };
        let p = DVec3::new(x, y, z);
        if !p.is_finite() {
            return Err(Error::format(path, format!("vertex {i} is not finite")));
        }
        positions.push(p);
        let n = match v.n {
            [Some(x), Some(y), Some(z)] => {
                let n = DVec3::new(x, y, z);
                if !n.is_finite() {
                    return Err(Error::format(
                        path,
                        format!("normal of vertex {i} is not finite"),
                    ));
                }
                Some(n)
            }
            _ => None,
        };
        file_normals.push(n);
    }
    drop(verts);
    let mut tris = Vec::new();
    for (fi, f) in faces.iter().flatten().enumerate() {
        let list =
            f.indices.as_ref().or(f.index.as_ref()).ok_or_else(|| {
                Error::format(path, format!("face {fi} has no vertex_indices list"))
            })?;
        charge_face(
            budget,
            list.len(),
            |m| Error::format(path, m),
            |n| format!("face {fi} has {n} vertices (need at least 3)"),
            |n| format!("face {fi} ({n} triangles)"),
        )?;
        let mut corners = Vec::with_capacity(list.len());
        for &i in list {
            if i < 0 || i as usize >= positions.len() {
                return Err(Error::format(
                    path,
                    format!(
                        "face {fi}: vertex index {i} out of range (0..{})",
                        positions.len()
                    ),
                ));
            }
            corners.push((i as usize, file_normals[i as usize]));
        }
        for k in 1..corners.len() - 1 {
            tris.push([corners[0], corners[k], corners[k + 1]]);
        }
    }
    Ok(Builder { positions, tris }.into_loaded(Vec::new()))
}

/// A binary little-endian PLY of `mesh`: `vertex` elements with `x, y, z, nx, ny, nz` (`float`
/// for [`FloatWidth::F32`], `double` for [`FloatWidth::F64`]; normals unit length), `face`
/// elements with a `uchar`-counted `uint` list `vertex_indices`, and `comment` lines, one per
/// line of `comment`.
pub fn write(mesh: &Mesh, width: FloatWidth, comment: &str) -> Vec<u8> {
    let ty = match width {
        FloatWidth::F32 => "float",
        FloatWidth::F64 => "double",
    };
    let mut head = String::from("ply\nformat binary_little_endian 1.0\n");
    for line in comment.lines() {
        head += &format!("comment {line}\n");
    }
    head += &format!("element vertex {}\n", mesh.positions.len());
    for c in ["x", "y", "z", "nx", "ny", "nz"] {
        head += &format!("property {ty} {c}\n");
    }
    head += &format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.triangles.len()
    );
    let mut out = head.into_bytes();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        for c in p
            .to_array()
            .into_iter()
            .chain(n.normalize_or_zero().to_array())
        {
            match width {
                FloatWidth::F32 => out.extend((c as f32).to_le_bytes()),
                FloatWidth::F64 => out.extend(c.to_le_bytes()),
            }
        }
    }
    for t in &mesh.triangles {
        out.push(3);
        for i in t {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "property float x\nproperty float y\nproperty float z\n";

    fn ok(bytes: &[u8]) -> LoadedMesh {
        parse(bytes, "t.ply").unwrap()
    }

    fn err(bytes: &[u8]) -> String {
        parse(bytes, "t.ply").map(|_| ()).unwrap_err().to_string()
    }

    /// An ASCII PLY of `verts` vertex lines (x y z [nx ny nz]) and `faces` face lines.
    fn ascii(normals: bool, verts: &[&str], faces: &[&str]) -> Vec<u8> {
        let n = if normals {
            "property float nx\nproperty float ny\nproperty float nz\n"
        } else {
            ""
        };
        let mut s = format!(
            "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex {}\n{HEAD}{n}element face {}\n\
             property list uchar int vertex_indices\nend_header\n",
            verts.len(),
            faces.len()
        );
        for l in verts.iter().chain(faces) {
            s += l;
            s += "\n";
        }
        s.into_bytes()
    }

    #[test]
    fn ascii_faces_with_normals_and_polygons() {
        let m = ok(&ascii(
            true,
            &["0 0 0 0 0 1", "1 0 0 0 0 1", "1 1 0 0 0 1", "0 1 0 0 0 1"],
            &["4 0 1 2 3"],
        ));
        assert_eq!(m.mesh.triangles.len(), 2, "a quad is two triangles");
        assert!(!m.computed_normals);
        let (p, n) = m.mesh.triangle(1);
        assert_eq!(p, [DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::Y]);
        assert_eq!(n, [DVec3::Z; 3]);
        // Without normals they are computed.
        let m = ok(&ascii(false, &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 2"]));
        assert!(m.computed_normals);
    }

    #[test]
    fn other_elements_and_properties_are_skipped() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement material 1\nproperty list uchar float rgb\n\
             element vertex 3\n{HEAD}property uchar red\nelement face 1\nproperty uchar flags\n\
             property list uchar uint vertex_index\nelement edge 1\nproperty int a\nproperty int b\n\
             end_header\n3 0.5 0.5 0.5\n0 0 0 7\n1 0 0 7\n0 1 0 7\n9 3 0 1 2\n0 1\n"
        );
        let m = ok(text.as_bytes());
        assert_eq!(m.mesh.triangles.len(), 1, "vertex_index is read too");
    }

    /// A binary little-endian PLY of `verts` (x, y, z floats) and triangles (uchar-counted
    /// int lists).
    fn binary(verts: &[[f32; 3]], tris: &[[i32; 3]]) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex {}\n{HEAD}element face {}\n\
             property list uchar int vertex_indices\nend_header\n",
            verts.len(),
            tris.len()
        )
        .into_bytes();
        for v in verts {
            out.extend(v.iter().flat_map(|c| c.to_le_bytes()));
        }
        for t in tris {
            out.push(3);
            out.extend(t.iter().flat_map(|i| i.to_le_bytes()));
        }
        out
    }

    #[test]
    fn binary_files_read_and_truncations_are_errors() {
        let bytes = binary(
            &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2]],
        );
        assert_eq!(ok(&bytes).mesh.triangles, [[0, 1, 2]]);
        // Every truncation of the body is an error, never a panic or a short mesh.
        let body = bytes.len() - (3 * 12 + 13);
        for n in body..bytes.len() {
            let e = err(&bytes[..n]);
            assert!(e.starts_with("t.ply: "), "{n}: {e}");
        }
        assert!(
            err(&bytes[..body + 5])
                .contains("element 'vertex' declares 3 elements of at least 12 bytes")
        );
        // The binary writer's output reads back.
        let m = ok(&bytes);
        let again = ok(&write(&m.mesh, FloatWidth::F32, "x"));
        assert_eq!(again.mesh.positions, m.mesh.positions);
    }

    #[test]
    fn huge_element_counts_are_refused_before_reading() {
        for (format, min) in [
            ("binary_little_endian", 12),
            ("binary_big_endian", 12),
            ("ascii", 6),
        ] {
            let text = format!(
                "ply\nformat {format} 1.0\nelement vertex 4000000000\n{HEAD}end_header\n0 0 0\n"
            );
            assert_eq!(
                err(text.as_bytes()),
                format!(
                    "t.ply: element 'vertex' declares 4000000000 elements of at least {min} \
                     bytes each, more than the 6 bytes after the header hold"
                ),
                "{format}"
            );
        }
        // Faces count too, after the vertices: a list's length field is one byte at least.
        let mut bytes = binary(&[[0.0; 3]; 3], &[]);
        let at = bytes
            .windows(12)
            .position(|w| w == b"element face")
            .unwrap();
        bytes.splice(at..at + 14, b"element face 999999999999".iter().copied());
        let e = err(&bytes);
        assert!(
            e.contains("element 'face' declares 999999999999 elements of at least 1 bytes"),
            "{e}"
        );
        // A count past usize is the parser's error.
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n{HEAD}end_header\n"
        );
        assert!(err(text.as_bytes()).starts_with("t.ply: malformed PLY"));
    }

    #[test]
    fn malformed_files_are_errors_naming_the_element() {
        let cases: [(Vec<u8>, &str); 6] = [
            (
                ascii(false, &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 3"]),
                "t.ply: face 0: vertex index 3 out of range (0..3)",
            ),
            (
                ascii(false, &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 -1"]),
                "t.ply: face 0: vertex index -1 out of range (0..3)",
            ),
            (
                ascii(false, &["0 0 0", "1 0 0", "0 1 0"], &["2 0 1"]),
                "t.ply: face 0 has 2 vertices (need at least 3)",
            ),
            (
                binary(
                    &[[0.0, 0.0, f32::NAN], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                    &[[0, 1, 2]],
                ),
                "t.ply: vertex 0 is not finite",
            ),
            (
                b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
                    .to_vec(),
                "t.ply: PLY has no 'vertex' element",
            ),
            (
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n".to_vec(),
                "t.ply: vertex 0 lacks numeric x, y, z",
            ),
        ];
        for (bytes, want) in cases {
            assert_eq!(err(&bytes), want);
        }
        assert!(err(b"not a ply\n").starts_with("t.ply: malformed PLY"));
        // A bad ASCII body line is named by its line number in the file.
        let e = err(&ascii(false, &["0 0 0", "1 0 x", "0 1 0"], &["3 0 1 2"]));
        assert!(
            e.starts_with("t.ply: malformed PLY: line 12: ") && e.contains("'1 0 x'"),
            "{e}"
        );
        assert!(
            err(b"ply\nformat ascii 1.0\nelement vertex 1\n").starts_with("t.ply: malformed PLY")
        );
    }

    #[test]
    fn a_bare_header_line_is_taken_as_a_comment() {
        let mut bytes = ascii(false, &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 2"]);
        bytes.splice(4..4, b"Created by Blender3D 2.49\n".iter().copied());
        assert_eq!(ok(&bytes).mesh.triangles.len(), 1);
    }
}
