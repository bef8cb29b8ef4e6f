//! From the corners a loader reads to a [`Mesh`]: each face checked and its triangles charged
//! before it is fan-triangulated ([`charge_face`]), one vertex per distinct (position, normal)
//! pair, and angle-weighted normals ([`angle_weighted_normals`]) where the file has none.

use std::collections::HashMap;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{LoadedMesh, Mesh};
use crate::options::{BYTES_PER_TRIANGLE, Budget};

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
        let (mesh, computed, _) = self.finish_sourced();
        (mesh, computed)
    }

    /// [`Builder::finish`], and for each vertex of the mesh the index in
    /// [`Builder::positions`] it was made from (the glTF animation poses the mesh's vertices
    /// from them).
    pub fn finish_sourced(self) -> (Mesh, bool, Vec<usize>) {
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
        let mut sources = Vec::new();
        let mut map: HashMap<(usize, [u64; 3]), u32> = HashMap::new();
        for t in &self.tris {
            let mut ids = [0u32; 3];
            for (slot, &(p, n)) in ids.iter_mut().zip(t.iter()) {
                let normal = n.unwrap_or_else(|| computed.get(p).copied().unwrap_or(DVec3::ZERO));
                let key = (p, normal.to_array().map(f64::to_bits));
                *slot = *map.entry(key).or_insert_with(|| {
                    mesh.positions.push(self.positions[p]);
                    mesh.normals.push(normal);
                    sources.push(p);
                    (mesh.positions.len() - 1) as u32
                });
            }
            mesh.triangles.push(ids);
        }
        (mesh, needs, sources)
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

/// Checks a face of `corners` corners before it is fan-triangulated (an OBJ `f` line, a PLY
/// face) and charges its `corners − 2` triangles to `budget` ([`BYTES_PER_TRIANGLE`] each).
/// Fewer than three corners is the error `error` makes of `few(corners)`; past the budget,
/// the budget's error ([`Budget::typed`]) of `error(over(corners − 2))`.
pub(crate) fn charge_face(
    budget: &Budget,
    corners: usize,
    error: impl FnOnce(String) -> Error,
    few: impl FnOnce(usize) -> String,
    over: impl FnOnce(usize) -> String,
) -> Result<()> {
    if corners < 3 {
        return Err(error(few(corners)));
    }
    budget
        .charge(corners as u64 - 2, BYTES_PER_TRIANGLE)
        .map_err(|()| budget.typed(error(over(corners - 2))))
}

/// Angle-weighted vertex normals (Thürmer & Wüthrich): each triangle adds its unit face normal
/// times its corner angle to its three vertices. Degenerate triangles add nothing; a vertex no
/// triangle adds to gets the zero vector. Returns one unit (or zero) normal per position
/// ([`angle_weighted_normals_into`] into a new vector).
///
/// # Panics
/// When an index of `tris` is not an index of `positions`.
pub fn angle_weighted_normals(
    positions: &[DVec3],
    tris: impl Iterator<Item = [usize; 3]>,
) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; positions.len()];
    angle_weighted_normals_into(positions, tris, &mut out);
    out
}

/// [`angle_weighted_normals`] written into `out` (one per position), without allocating: what
/// an animation computes every frame for a mesh whose file has no normals. The same numbers,
/// bit for bit.
///
/// # Panics
/// When an index of `tris` is not an index of `positions`, or `out` is shorter than
/// `positions`.
pub fn angle_weighted_normals_into(
    positions: &[DVec3],
    tris: impl Iterator<Item = [usize; 3]>,
    out: &mut [DVec3],
) {
    let acc = &mut out[..positions.len()];
    acc.fill(DVec3::ZERO);
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
    for n in acc.iter_mut() {
        *n = n.try_normalize().unwrap_or(DVec3::ZERO);
    }
}
