//! The steep-normal remedy per vertex, for meshes on the shared line field (docs/METHOD.md §7,
//! "Remedy per vertex"): one clamped normal per vertex, shared by every face around it, so
//! neighbours keep sharing their edges' lines where [`Patch::new_or_tilted_with`] would clamp
//! each patch's own copy of a normal differently.
//!
//! [`Patch::new_or_tilted_with`]: crate::Patch::new_or_tilted_with

use crate::field::LineField;
use crate::patch::{NORMAL_CLAMP_DEG, Patch};
use crate::real::Float;
use crate::seam::SeamError;
use crate::vec::V3;

/// Per-vertex scratch of [`clamp_vertex_normals`] (one entry per vertex).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexClamp<F: Float> {
    /// Sum of the unit normals of the faces around the vertex, weighted by their angles there
    /// (their mean direction).
    mean: V3<F>,
    /// Index + 1 into [`NORMAL_CLAMP_DEG`] of the clamp applied (0: none).
    level: u8,
    /// The pass that last tightened it (a vertex tightens at most once per pass).
    pass: u8,
}

/// What [`clamp_vertex_normals`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexClampReport {
    /// Vertices whose normal was changed.
    pub clamped: usize,
    /// Triangles whose patch the shared field still rejects with every vertex clamped as far as
    /// the remedy goes (to the mean face normal): [`Patch::new_or_tilted_with`] clamps these per
    /// patch (their edges then part; [`close_cracks`](crate::close_cracks) closes the gaps).
    ///
    /// [`Patch::new_or_tilted_with`]: crate::Patch::new_or_tilted_with
    pub unresolved: usize,
}

/// Writes into `out` the vertex normals of the mesh (`positions`, `normals`, `triangles`) with
/// the steep-normal remedy applied per vertex: where a triangle's patch on
/// [`LineField::Vertex`] is rejected (a zero, back-facing or near-perpendicular normal, a shell
/// that degenerates), the normals of its three vertices are rotated toward the mean of their
/// faces' normals (weighted by the faces' angles at the vertex) until their angle to it is at
/// most a clamp of [`NORMAL_CLAMP_DEG`] (75°, 60°, …, 0° = the mean itself), the clamp
/// tightening until every triangle around them is accepted. A triangle rejected even with its
/// three normals at their means is left to the per-patch remedy and moves no normal. Every face around a vertex then uses the same normal, so the patches built from
/// `out` share their edges' lines (their edge curves meet) wherever they are accepted.
///
/// Preconditions: `normals` and `out` as long as `positions`; `scratch` at least as long;
/// indices below `positions.len()`, distinct within a triangle. Normals need not be unit.
/// Returns the [`VertexClampReport`], or [`SeamError::BadIndex`] /
/// [`SeamError::ScratchTooSmall`] / [`SeamError::LengthMismatch`] (then `out` is unspecified).
///
/// Work: at most `1 + NORMAL_CLAMP_DEG.len()` patch constructions per triangle; no allocation.
/// # Accuracy
/// Unclamped vertices keep their normal bit for bit; a clamped normal is a unit vector at the
/// clamp angle (within rounding) from the mean face normal, in the plane of the two.
/// # Panics
/// Never.
pub fn clamp_vertex_normals<F: Float>(
    positions: &[F::Vec3],
    normals: &[F::Vec3],
    triangles: &[[u32; 3]],
    out: &mut [F::Vec3],
    scratch: &mut [VertexClamp<F>],
) -> Result<VertexClampReport, SeamError> {
    let n = positions.len();
    if normals.len() != n || out.len() != n {
        return Err(SeamError::LengthMismatch {
            patches: n,
            triangles: triangles.len(),
            seams: out.len().min(normals.len()),
        });
    }
    let Some(scratch) = scratch.get_mut(..n) else {
        return Err(SeamError::ScratchTooSmall { needed: n });
    };
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| i as usize);
        if a >= n || b >= n || c >= n || a == b || b == c || a == c {
            return Err(SeamError::BadIndex { triangle: t });
        }
    }
    for (o, s) in out.iter_mut().zip(normals) {
        *o = *s;
    }
    for v in scratch.iter_mut() {
        *v = VertexClamp::default();
    }
    // The mean face normal around each vertex, each face weighted by its angle there (so a
    // quad split into two triangles counts once, whichever corner).
    for tri in triangles {
        let Some(p) = corners::<F>(positions, tri) else {
            continue;
        };
        let [pa, pb, pc] = p;
        let Some(nf) = (pb - pa).cross(pc - pa).try_normalize() else {
            continue;
        };
        for (k, i) in tri.iter().enumerate() {
            let (Some(&o), Some(&u), Some(&w)) = (p.get(k), p.get((k + 1) % 3), p.get((k + 2) % 3))
            else {
                continue;
            };
            let (Some(a), Some(b)) = ((u - o).try_normalize(), (w - o).try_normalize()) else {
                continue;
            };
            let angle = F::from_f64(libm::acos(a.dot(b).to_f64().clamp(-1.0, 1.0)));
            if let Some(v) = scratch.get_mut(*i as usize) {
                v.mean = v.mean + nf * angle;
            }
        }
    }
    let accepted = |out: &[F::Vec3], tri: &[u32; 3]| -> bool {
        let (Some(p), Some(nn)) = (corners(positions, tri), corners(out, tri)) else {
            return true;
        };
        Patch::<F>::with_field(p.map(F::to_glam), nn.map(F::to_glam), LineField::Vertex).is_ok()
    };
    // Each pass tightens the clamp of every vertex of a rejected triangle by one level.
    let mut unresolved = 0;
    for pass in 1..=NORMAL_CLAMP_DEG.len() + 1 {
        let pass = pass as u8;
        unresolved = 0;
        for tri in triangles {
            if accepted(out, tri) {
                continue;
            }
            unresolved += 1;
            // A triangle the field rejects even with its three normals at their means cannot
            // be resolved per vertex: it does not tighten its vertices (which would only move
            // its neighbours' normals), and `new_or_tilted_with` clamps it per patch.
            let means = match tri.map(|i| scratch.get(i as usize).map(|v| v.mean)) {
                [Some(a), Some(b), Some(c)] => Some([a, b, c]),
                _ => None,
            };
            let resolvable = match (corners::<F>(positions, tri), means) {
                (Some(p), Some(m)) => {
                    Patch::<F>::with_field(p.map(F::to_glam), m.map(F::to_glam), LineField::Vertex)
                        .is_ok()
                }
                _ => false,
            };
            if !resolvable {
                continue;
            }
            for &i in tri {
                let i = i as usize;
                let (Some(v), Some(src), Some(dst)) =
                    (scratch.get_mut(i), normals.get(i), out.get_mut(i))
                else {
                    continue;
                };
                if v.pass == pass || usize::from(v.level) >= NORMAL_CLAMP_DEG.len() {
                    continue;
                }
                v.pass = pass;
                let Some(deg) = NORMAL_CLAMP_DEG.get(usize::from(v.level)) else {
                    continue;
                };
                v.level += 1;
                if let Some(c) = clamp_toward(F::from_glam(*src), v.mean, *deg) {
                    *dst = F::to_glam(c);
                }
            }
        }
        if unresolved == 0 {
            break;
        }
    }
    let clamped = out
        .iter()
        .zip(normals)
        .filter(|(a, b)| F::from_glam(**a) != F::from_glam(**b))
        .count();
    Ok(VertexClampReport {
        clamped,
        unresolved,
    })
}

/// `u` rotated toward the direction of `mean` until at most `deg` degrees from it: `None`
/// where it already is (or `mean` is zero), the mean itself where `u` is zero or opposite it.
fn clamp_toward<F: Float>(u: V3<F>, mean: V3<F>, deg: f64) -> Option<V3<F>> {
    let m = mean.try_normalize()?;
    let Some(u) = u.try_normalize() else {
        return Some(m);
    };
    let (s, c) = libm::sincos(deg.to_radians());
    let (sin_max, cos_max) = (F::from_f64(s), F::from_f64(c));
    let cos = u.dot(m);
    if cos >= cos_max {
        return None;
    }
    Some(match (u - m * cos).try_normalize() {
        Some(w) => m * cos_max + w * sin_max,
        None => m,
    })
}

/// The three positions of `tri`.
fn corners<F: Float>(positions: &[F::Vec3], tri: &[u32; 3]) -> Option<[V3<F>; 3]> {
    let [a, b, c] = tri.map(|i| positions.get(i as usize).copied().map(F::from_glam));
    Some([a?, b?, c?])
}
