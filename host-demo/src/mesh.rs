//! Mesh loading: OBJ (own parser, errors with file:line), PLY (ply-rs-bw), glTF/GLB (gltf).
//!
//! Triangle ids are the order of triangles in the file after fan-triangulating polygons, over
//! all objects/primitives in file order. Vertex normals come from the file (per corner); where a
//! file has none, angle-weighted vertex normals are computed ([`LoadedMesh::computed_normals`]).

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use crate::error::{DemoError, Result};
use crate::scenes::Mesh;

/// A mesh read from a file.
#[derive(Clone, Debug)]
pub struct LoadedMesh {
    /// The mesh (vertices deduplicated per (position, normal) pair).
    pub mesh: Mesh,
    /// `true` when some or all vertex normals were computed (angle-weighted) because the file
    /// had none for them.
    pub computed_normals: bool,
    /// Warnings to show on stderr (skipped primitives and the like).
    pub warnings: Vec<String>,
}

/// Reads a mesh, choosing the format by extension (`.obj`, `.ply`, `.gltf`, `.glb`).
pub fn load(path: &str) -> Result<LoadedMesh> {
    let ext = Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let out = match ext.as_str() {
        "obj" => {
            let text = std::fs::read(path).map_err(|e| DemoError::io(path, e))?;
            let text = String::from_utf8_lossy(&text);
            parse_obj(&text, path)?
        }
        "ply" => load_ply(path)?,
        "gltf" | "glb" => load_gltf_guarded(path)?,
        _ => {
            return Err(DemoError::format(
                path,
                "unknown mesh format (expected .obj, .ply, .gltf or .glb)",
            ));
        }
    };
    if out.mesh.triangles.is_empty() {
        return Err(DemoError::Empty {
            msg: format!("{path}: the mesh has no triangles"),
        });
    }
    Ok(out)
}

/// Builds a mesh from corners `(position index, optional normal)` of triangles, computing
/// angle-weighted normals for corners without one.
struct Builder {
    positions: Vec<DVec3>,
    tris: Vec<[(usize, Option<DVec3>); 3]>,
}

impl Builder {
    fn finish(self) -> (Mesh, bool) {
        let needs = self.tris.iter().any(|t| t.iter().any(|(_, n)| n.is_none()));
        let computed = if needs {
            angle_weighted_normals(
                &self.positions,
                self.tris.iter().map(|t| [t[0].0, t[1].0, t[2].0]),
            )
        } else {
            Vec::new()
        };
        let mut mesh = Mesh::default();
        let mut map: HashMap<(usize, [u64; 3]), u32> = HashMap::new();
        for t in &self.tris {
            let mut ids = [0u32; 3];
            for (slot, &(p, n)) in ids.iter_mut().zip(t.iter()) {
                let normal = n.unwrap_or_else(|| computed.get(p).copied().unwrap_or(DVec3::ZERO));
                let key = (p, normal.to_array().map(f64::to_bits));
                *slot = *map.entry(key).or_insert_with(|| {
                    mesh.positions.push(self.positions[p]);
                    mesh.normals.push(normal);
                    (mesh.positions.len() - 1) as u32
                });
            }
            mesh.triangles.push(ids);
        }
        (mesh, needs)
    }
}

/// Angle-weighted vertex normals (Thürmer & Wüthrich): each triangle adds its unit face normal
/// times its corner angle to its three vertices. Degenerate triangles add nothing.
pub fn angle_weighted_normals(
    positions: &[DVec3],
    tris: impl Iterator<Item = [usize; 3]>,
) -> Vec<DVec3> {
    let mut acc = vec![DVec3::ZERO; positions.len()];
    for [a, b, c] in tris {
        let (pa, pb, pc) = (positions[a], positions[b], positions[c]);
        let Some(nf) = (pb - pa).cross(pc - pa).try_normalize() else {
            continue;
        };
        for (i, o1, o2) in [(a, pb, pc), (b, pc, pa), (c, pa, pb)] {
            let p = positions[i];
            let (Some(u), Some(v)) = ((o1 - p).try_normalize(), (o2 - p).try_normalize()) else {
                continue;
            };
            let ang = u.dot(v).clamp(-1.0, 1.0).acos();
            acc[i] += nf * ang;
        }
    }
    acc.into_iter()
        .map(|n| n.try_normalize().unwrap_or(DVec3::ZERO))
        .collect()
}

/// Parses a finite number, or reports `path:line` with what is wrong.
pub(crate) fn parse_f64(tok: &str, path: &str, line: usize) -> Result<f64> {
    let v: f64 = tok
        .parse()
        .map_err(|_| DemoError::parse(path, line, format!("malformed number '{tok}'")))?;
    if !v.is_finite() {
        return Err(DemoError::parse(
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
        DemoError::parse(
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
        return Err(DemoError::parse(
            path,
            line,
            format!("{what} index {i} out of range (1..={count} defined so far)"),
        ));
    }
    Ok(r as usize)
}

/// Parses Wavefront OBJ text (`v`, `vn`, `vt`, `f` with `v`, `v/vt`, `v//vn`, `v/vt/vn`,
/// negative indices; other statements ignored). Polygons are fan-triangulated.
pub fn parse_obj(text: &str, path: &str) -> Result<LoadedMesh> {
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
                    return Err(DemoError::parse(
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
                        return Err(DemoError::parse(
                            path,
                            line,
                            format!("malformed face vertex '{tok}'"),
                        ));
                    }
                    corners.push((vi, vn));
                }
                if corners.len() < 3 {
                    return Err(DemoError::parse(
                        path,
                        line,
                        format!("face with {} vertices (need at least 3)", corners.len()),
                    ));
                }
                for k in 1..corners.len() - 1 {
                    tris.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    let (mesh, computed_normals) = Builder { positions, tris }.finish();
    Ok(LoadedMesh {
        mesh,
        computed_normals,
        warnings: Vec::new(),
    })
}

fn prop_f64(p: &ply_rs_bw::ply::Property) -> Option<f64> {
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

fn prop_list(p: &ply_rs_bw::ply::Property) -> Option<Vec<i64>> {
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

fn load_ply(path: &str) -> Result<LoadedMesh> {
    let file = std::fs::File::open(path).map_err(|e| DemoError::io(path, e))?;
    let mut reader = std::io::BufReader::new(file);
    let parser = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new();
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|e| DemoError::format(path, format!("malformed PLY: {e}")))?;
    let verts = ply
        .payload
        .get("vertex")
        .ok_or_else(|| DemoError::format(path, "PLY has no 'vertex' element"))?;
    let mut positions = Vec::with_capacity(verts.len());
    let mut file_normals = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        let get = |k: &str| v.get(k).and_then(prop_f64);
        let (Some(x), Some(y), Some(z)) = (get("x"), get("y"), get("z")) else {
            return Err(DemoError::format(
                path,
                format!("vertex {i} lacks numeric x, y, z"),
            ));
        };
        let p = DVec3::new(x, y, z);
        if !p.is_finite() {
            return Err(DemoError::format(path, format!("vertex {i} is not finite")));
        }
        positions.push(p);
        let n = match (get("nx"), get("ny"), get("nz")) {
            (Some(x), Some(y), Some(z)) => {
                let n = DVec3::new(x, y, z);
                if !n.is_finite() {
                    return Err(DemoError::format(
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
    let mut tris = Vec::new();
    if let Some(faces) = ply.payload.get("face") {
        for (fi, f) in faces.iter().enumerate() {
            let list = f
                .get("vertex_indices")
                .or_else(|| f.get("vertex_index"))
                .and_then(prop_list)
                .ok_or_else(|| {
                    DemoError::format(path, format!("face {fi} has no vertex_indices list"))
                })?;
            if list.len() < 3 {
                return Err(DemoError::format(
                    path,
                    format!("face {fi} has {} vertices (need at least 3)", list.len()),
                ));
            }
            let mut corners = Vec::with_capacity(list.len());
            for &i in &list {
                if i < 0 || i as usize >= positions.len() {
                    return Err(DemoError::format(
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
    }
    let (mesh, computed_normals) = Builder { positions, tris }.finish();
    Ok(LoadedMesh {
        mesh,
        computed_normals,
        warnings: Vec::new(),
    })
}

fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        } as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// [`load_gltf`] with a guard: the `gltf` crate panics on some malformed binary headers (found by
/// the `gltf` fuzz target, e.g. a GLB header announcing a chunk longer than the file); that
/// panic becomes a readable error instead of a crash.
fn load_gltf_guarded(path: &str) -> Result<LoadedMesh> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let out = std::panic::catch_unwind(|| load_gltf(path));
    std::panic::set_hook(hook);
    match out {
        Ok(r) => r,
        Err(_) => Err(DemoError::Format {
            path: path.to_string(),
            msg: "malformed glTF/GLB (the gltf parser rejected its structure)".into(),
        }),
    }
}

fn load_gltf(path: &str) -> Result<LoadedMesh> {
    let bytes = std::fs::read(path).map_err(|e| DemoError::io(path, e))?;
    let gltf = gltf::Gltf::from_slice(&bytes)
        .map_err(|e| DemoError::format(path, format!("malformed glTF: {e}")))?;
    let base = Path::new(path).parent().unwrap_or(Path::new("."));
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for b in gltf.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| DemoError::format(path, "GLB has no binary chunk"))?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let b64 = rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        DemoError::format(path, "unsupported data URI (expected base64)")
                    })?;
                    base64_decode(b64)
                        .ok_or_else(|| DemoError::format(path, "malformed base64 data URI"))?
                } else {
                    let p = base.join(uri);
                    let ps = p.display().to_string();
                    std::fs::read(&p).map_err(|e| DemoError::io(&ps, e))?
                }
            }
        };
        if data.len() < b.length() {
            return Err(DemoError::format(
                path,
                format!(
                    "buffer {} is shorter ({} bytes) than declared ({})",
                    b.index(),
                    data.len(),
                    b.length()
                ),
            ));
        }
        buffers.push(data);
    }
    // World transform of the first node that instantiates each mesh.
    let mut mesh_xf: HashMap<usize, glam::DMat4> = HashMap::new();
    fn visit(n: gltf::Node, parent: glam::DMat4, out: &mut HashMap<usize, glam::DMat4>) {
        let m = parent * glam::Mat4::from_cols_array_2d(&n.transform().matrix()).as_dmat4();
        if let Some(mesh) = n.mesh() {
            out.entry(mesh.index()).or_insert(m);
        }
        for c in n.children() {
            visit(c, m, out);
        }
    }
    for scene in gltf.scenes() {
        for n in scene.nodes() {
            visit(n, glam::DMat4::IDENTITY, &mut mesh_xf);
        }
    }
    let mut warnings = Vec::new();
    let mut positions = Vec::new();
    let mut tris = Vec::new();
    for mesh in gltf.meshes() {
        let xf = mesh_xf
            .get(&mesh.index())
            .copied()
            .unwrap_or(glam::DMat4::IDENTITY);
        let nxf = glam::DMat3::from_mat4(xf).inverse().transpose();
        for prim in mesh.primitives() {
            if prim.mode() != gltf::mesh::Mode::Triangles {
                warnings.push(format!(
                    "mesh {} primitive {}: mode {:?} is not triangles, skipped",
                    mesh.index(),
                    prim.index(),
                    prim.mode()
                ));
                continue;
            }
            let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
            let Some(pos) = reader.read_positions() else {
                warnings.push(format!(
                    "mesh {} primitive {}: no POSITION, skipped",
                    mesh.index(),
                    prim.index()
                ));
                continue;
            };
            let first = positions.len();
            for p in pos {
                let p = xf.transform_point3(DVec3::from_array(p.map(f64::from)));
                if !p.is_finite() {
                    return Err(DemoError::format(path, "non-finite vertex position"));
                }
                positions.push(p);
            }
            let count = positions.len() - first;
            let normals: Option<Vec<DVec3>> = reader.read_normals().map(|it| {
                it.map(|n| nxf * DVec3::from_array(n.map(f64::from)))
                    .collect()
            });
            if let Some(ns) = &normals {
                if ns.len() != count {
                    return Err(DemoError::format(path, "NORMAL and POSITION counts differ"));
                }
                if ns.iter().any(|n| !n.is_finite()) {
                    return Err(DemoError::format(path, "non-finite vertex normal"));
                }
            }
            let idx: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count as u32).collect(),
            };
            if !idx.len().is_multiple_of(3) {
                return Err(DemoError::format(
                    path,
                    format!("index count {} is not a multiple of 3", idx.len()),
                ));
            }
            for c in idx.chunks_exact(3) {
                let mut t = [(0usize, None); 3];
                for (slot, &i) in t.iter_mut().zip(c) {
                    if i as usize >= count {
                        return Err(DemoError::format(
                            path,
                            format!("index {i} out of range (0..{count})"),
                        ));
                    }
                    *slot = (first + i as usize, normals.as_ref().map(|n| n[i as usize]));
                }
                tris.push(t);
            }
        }
    }
    let (mesh, computed_normals) = Builder { positions, tris }.finish();
    Ok(LoadedMesh {
        mesh,
        computed_normals,
        warnings,
    })
}
