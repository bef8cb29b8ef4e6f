//! Triangle meshes: the [`Mesh`] type, vertex-normal generation, loading from files ([`load`],
//! or [`parse`] on bytes, picks the loader by extension: [`obj`], [`ply`], [`gltf`] for `.gltf`
//! and `.glb`, the latter's container checked by [`glb`] first) and writing them ([`save`], or
//! [`encode`] to bytes: OBJ, binary PLY, GLB).
//!
//! Triangle ids are the order of triangles in the file after fan-triangulating polygons, over
//! all objects/primitives in file order (glTF: primitives in the order their nodes are met,
//! depth-first through the default scene, once per node that draws the mesh). Vertex normals come from the file (per corner); where a
//! file has none, angle-weighted vertex normals are computed ([`LoadedMesh::computed_normals`]).

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use crate::error::{DemoError, Result};

pub mod glb;
pub mod gltf;
pub mod obj;
pub mod ply;

/// An indexed triangle mesh with per-vertex normals, in `f64`.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex normals (one per position, any positive length).
    pub normals: Vec<DVec3>,
    /// Triangles as indices into `positions`/`normals`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The three corners and normals of triangle `t`.
    pub fn triangle(&self, t: usize) -> ([DVec3; 3], [DVec3; 3]) {
        let [a, b, c] = self.triangles[t].map(|i| i as usize);
        (
            [self.positions[a], self.positions[b], self.positions[c]],
            [self.normals[a], self.normals[b], self.normals[c]],
        )
    }

    /// Axis-aligned bounds (min, max) of the vertices.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Length of the bounding-box diagonal.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).length()
    }
}

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

/// Where Debian's `assimp-testmodels` keeps its files (`/usr/share/assimp/models`), for the tests
/// and benchmarks that run on real exports: `Ok(Some(dir))` when it is installed, `Ok(None)`
/// when it is not (the caller skips), `Err` when it is not but `SMOOTHTRI_REQUIRE_ASSETS` is set
/// (CI installs the package, so a missing one there is a failure, not a skip).
pub fn assimp_models() -> std::result::Result<Option<std::path::PathBuf>, String> {
    let root = Path::new("/usr/share/assimp/models");
    if root.is_dir() {
        Ok(Some(root.to_path_buf()))
    } else if std::env::var_os("SMOOTHTRI_REQUIRE_ASSETS").is_some() {
        Err(format!(
            "{} is missing: install Debian's assimp-testmodels",
            root.display()
        ))
    } else {
        eprintln!("skipped: no {}", root.display());
        Ok(None)
    }
}

/// The lower-case extension of `path`, if it has one.
pub fn extension(path: &str) -> Option<String> {
    Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

/// Reads a mesh, choosing the format by extension (`.obj`, `.ply`, `.gltf`, `.glb`).
pub fn load(path: &str) -> Result<LoadedMesh> {
    format_of(
        path,
        "obj, .ply, .gltf or .glb",
        &["obj", "ply", "gltf", "glb"],
    )?;
    let bytes = std::fs::read(path).map_err(|e| DemoError::io(path, e))?;
    parse(&bytes, path)
}

/// The extension of `path` when it is one of `allowed`; else a format error listing `expected`.
fn format_of(path: &str, expected: &str, allowed: &[&str]) -> Result<String> {
    match extension(path) {
        Some(e) if allowed.contains(&e.as_str()) => Ok(e),
        _ => Err(DemoError::format(
            path,
            format!("unknown mesh format (expected .{expected})"),
        )),
    }
}

/// Parses the bytes of a mesh file, the format chosen by the extension of `path` as in
/// [`load`] (`path` also names the file in messages and anchors a glTF's external buffers).
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    let ext = format_of(
        path,
        "obj, .ply, .gltf or .glb",
        &["obj", "ply", "gltf", "glb"],
    )?;
    let out = match ext.as_str() {
        "obj" => obj::parse(&String::from_utf8_lossy(bytes), path)?,
        "ply" => ply::parse(bytes, path)?,
        _ => gltf::parse(bytes, path)?,
    };
    if out.mesh.triangles.is_empty() {
        return Err(DemoError::Empty {
            msg: format!("{path}: the mesh has no triangles"),
        });
    }
    Ok(out)
}

/// The bytes of `mesh` in the format of `path`'s extension: `.obj` ([`obj::write`]), `.ply`
/// (binary, [`ply::write`]) or `.glb` ([`gltf::write_glb`], always `f32`). Numbers are written
/// in `precision` where the format allows; `comment` goes into the file's comment lines (OBJ,
/// PLY) or `asset.generator` (glTF).
pub fn encode(
    mesh: &Mesh,
    path: &str,
    precision: crate::tracer::Precision,
    comment: &str,
) -> Result<Vec<u8>> {
    let ext = format_of(path, "obj, .ply or .glb", &["obj", "ply", "glb"])?;
    Ok(match ext.as_str() {
        "obj" => obj::write(mesh, precision, comment),
        "ply" => ply::write(mesh, precision, comment),
        _ => gltf::write_glb(mesh, comment)?,
    })
}

/// Writes `mesh` to `path` ([`encode`]); returns the number of bytes written.
pub fn save(
    mesh: &Mesh,
    path: &str,
    precision: crate::tracer::Precision,
    comment: &str,
) -> Result<usize> {
    let bytes = encode(mesh, path, precision, comment)?;
    std::fs::write(path, &bytes).map_err(|e| DemoError::io(path, e))?;
    Ok(bytes.len())
}

/// One triangle corner as a loader reads it: an index into [`Builder::positions`] and the
/// file's normal for that corner, if it has one.
pub(crate) type Corner = (usize, Option<DVec3>);

/// Builds a [`Mesh`] from triangles of [`Corner`]s, computing angle-weighted normals for
/// corners without one. Shared by all loaders.
pub(crate) struct Builder {
    /// Positions the corners index.
    pub positions: Vec<DVec3>,
    /// Triangles in file order.
    pub tris: Vec<[Corner; 3]>,
}

impl Builder {
    /// The mesh (one vertex per distinct (position, normal) pair) and whether any normal was
    /// computed.
    pub fn finish(self) -> (Mesh, bool) {
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

    /// [`Builder::finish`] as a [`LoadedMesh`] with the given warnings.
    pub fn into_loaded(self, warnings: Vec<String>) -> LoadedMesh {
        let (mesh, computed_normals) = self.finish();
        LoadedMesh {
            mesh,
            computed_normals,
            warnings,
        }
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
