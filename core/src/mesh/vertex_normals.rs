//! The steep-normal remedy per vertex, for meshes on the shared line field (docs/METHOD.md §7,
//! "Remedy per vertex"): one clamped normal per vertex, shared by every face around it, so
//! neighbours keep sharing their edges' lines where [`Patch::new_or_tilted_with`] would clamp
//! each patch's own copy of a normal differently.
//!
//! [`Patch::new_or_tilted_with`]: crate::Patch::new_or_tilted_with

use super::topology::MeshError;
use crate::exec::Executor;
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::{NORMAL_CLAMP_DEG, Patch};
use crate::surface::field::LineField;

/// Per-vertex scratch of [`clamp_vertex_normals`] (one entry per vertex).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexClamp<F: Float> {
    /// Sum of the unit normals of the faces around the vertex, weighted by their angles there
    /// (their mean direction).
    mean: V3<F>,
    /// The smallest cap holding the unit normals of the faces around the vertex ([`Cap`]).
    cap: Cap<F>,
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
    /// the remedy goes (to their targets): [`Patch::new_or_tilted_with`] clamps these per
    /// patch (their edges then part; [`close_cracks`](super::close_cracks) closes the gaps).
    ///
    /// [`Patch::new_or_tilted_with`]: crate::Patch::new_or_tilted_with
    pub unresolved: usize,
}

/// Writes into `out` the vertex normals of the mesh (`positions`, `normals`, `triangles`) with
/// the steep-normal remedy applied per vertex: where a triangle's patch on
/// [`LineField::Vertex`] is rejected (a zero, back-facing or near-perpendicular normal, a shell
/// that degenerates), the normals of its three vertices are rotated toward a target until their
/// angle to it is at most a clamp of [`NORMAL_CLAMP_DEG`] (75°, 60°, …, 0° = the target
/// itself), the clamp tightening until every triangle around them is accepted. The target is
/// the direction whose largest angle to the faces around the vertex is least (the axis of the
/// smallest cap holding their unit normals, settled in at most `CAP_PASSES` = 8 passes over the
/// faces), or, where no direction is within about 87° of all of them, the mean of their
/// normals weighted by the faces' angles at the vertex. A triangle rejected even with its three
/// normals at their targets is left to the per-patch remedy and moves no normal. Every face around a vertex then uses the same normal, so the patches built from
/// `out` share their edges' lines (their edge curves meet) wherever they are accepted.
///
/// Preconditions: `normals` and `out` as long as `positions`; `scratch` at least as long;
/// indices below `positions.len()`, distinct within a triangle. Normals need not be unit.
/// Returns the [`VertexClampReport`], or [`MeshError::BadIndex`] /
/// [`MeshError::ScratchTooSmall`] / [`MeshError::VertexCount`] (then `out` is unspecified).
///
/// Work: at most `1 + NORMAL_CLAMP_DEG.len()` patch constructions per triangle and
/// `CAP_PASSES` passes over the faces; no allocation.
/// # Accuracy
/// Unclamped vertices keep their normal bit for bit; a clamped normal is a unit vector at the
/// clamp angle (within rounding) from its target, in the plane of the two.
/// # Panics
/// Never.
pub fn clamp_vertex_normals<F: Float>(
    positions: &[F::Vec3],
    normals: &[F::Vec3],
    triangles: &[[u32; 3]],
    out: &mut [F::Vec3],
    scratch: &mut [VertexClamp<F>],
) -> Result<VertexClampReport, MeshError> {
    remedy(
        positions,
        normals,
        triangles,
        out,
        scratch,
        None::<(&mut [u32], &())>,
    )
}

/// [`clamp_vertex_normals`], with each pass's patch constructions run on `executor` ahead of
/// the pass where `pool` gives one flag per triangle: the pass itself stays in triangle order
/// (a triangle whose vertex an earlier triangle of the same pass tightened is checked again),
/// so the result is bit for bit the serial one.
pub(crate) fn remedy<F: Float>(
    positions: &[F::Vec3],
    normals: &[F::Vec3],
    triangles: &[[u32; 3]],
    out: &mut [F::Vec3],
    scratch: &mut [VertexClamp<F>],
    mut pool: Option<(&mut [u32], &impl Executor)>,
) -> Result<VertexClampReport, MeshError> {
    let n = positions.len();
    if normals.len() != n || out.len() != n {
        return Err(MeshError::VertexCount {
            positions: n,
            normals: normals.len(),
            out: out.len(),
        });
    }
    let Some(scratch) = scratch.get_mut(..n) else {
        return Err(MeshError::ScratchTooSmall { needed: n });
    };
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| i as usize);
        if a >= n || b >= n || c >= n || a == b || b == c || a == c {
            return Err(MeshError::BadIndex { triangle: t });
        }
    }
    for (o, s) in out.iter_mut().zip(normals) {
        *o = *s;
    }
    for v in scratch.iter_mut() {
        *v = VertexClamp::default();
    }
    // The mean face normal around each vertex, each face weighted by its angle there (so a
    // quad split into two triangles counts once, whichever corner), and the first pass of the
    // smallest caps below.
    for tri in triangles {
        let Some(p) = corners::<F>(positions, tri) else {
            continue;
        };
        let [pa, pb, pc] = p;
        let Some(nf) = (pb - pa).cross(pc - pa).try_normalize() else {
            continue;
        };
        for i in tri {
            if let Some(v) = scratch.get_mut(*i as usize) {
                v.cap.grow(nf);
            }
        }
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
    // The smallest cap of each vertex's face normals: passes over the faces until none lies
    // outside its vertex's cap (each growth strictly widens a cap, so this settles; the cap
    // count bounds the work). The first pass ran with the means.
    for _ in 1..CAP_PASSES {
        let mut grew = false;
        for tri in triangles {
            let Some([pa, pb, pc]) = corners::<F>(positions, tri) else {
                continue;
            };
            let Some(nf) = (pb - pa).cross(pc - pa).try_normalize() else {
                continue;
            };
            for i in tri {
                if let Some(v) = scratch.get_mut(*i as usize) {
                    grew |= v.cap.grow(nf);
                }
            }
        }
        if !grew {
            break;
        }
    }
    // Each pass tightens the clamp of every vertex of a rejected triangle by one level.
    let mut unresolved = 0;
    for pass in 1..=NORMAL_CLAMP_DEG.len() + 1 {
        let pass = pass as u8;
        unresolved = 0;
        // With a pool: every triangle's check against the normals at the pass's start, in
        // parallel (flag 1: accepted).
        let ahead = match pool.as_mut() {
            Some((flags, executor)) => {
                let flags = flags.get_mut(..triangles.len());
                if let Some(flags) = flags {
                    let now: &[F::Vec3] = out;
                    executor.run_chunks(flags, 64, &|start, chunk| {
                        for (k, f) in chunk.iter_mut().enumerate() {
                            let ok = triangles.get(start + k).is_none_or(|t| accepted(now, t));
                            *f = u32::from(ok);
                        }
                    });
                }
                pool.as_ref().map(|(flags, _)| &**flags)
            }
            None => None,
        };
        for (i, tri) in triangles.iter().enumerate() {
            // The check ahead holds unless a vertex was tightened earlier in this pass.
            let touched = tri
                .iter()
                .any(|&v| scratch.get(v as usize).is_some_and(|c| c.pass == pass));
            let ok = match ahead.and_then(|f| f.get(i)) {
                Some(&f) if !touched => f == 1,
                _ => accepted(out, tri),
            };
            if ok {
                continue;
            }
            unresolved += 1;
            // A triangle the field rejects even with its three normals at their targets cannot
            // be resolved per vertex: it does not tighten its vertices (which would only move
            // its neighbours' normals), and `new_or_tilted_with` clamps it per patch.
            let targets = match tri.map(|i| scratch.get(i as usize).map(VertexClamp::target)) {
                [Some(a), Some(b), Some(c)] => Some([a, b, c]),
                _ => None,
            };
            let resolvable = match (corners::<F>(positions, tri), targets) {
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
                if let Some(c) = clamp_toward(F::from_glam(*src), v.target(), *deg) {
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

/// Passes over the faces that [`clamp_vertex_normals`] makes at most to settle the caps. A cap
/// widens only when a face normal lies outside it, and its boundary then holds that normal, so
/// a second pass finds the few normals the first had passed before the cap moved; meshes need
/// two or three.
pub const CAP_PASSES: usize = 8;

/// Smallest angle, as a cosine, between a cap's axis and the faces around a vertex for the axis
/// to be the remedy's target: below it (the faces do not fit in a hemisphere, or nearly not) the
/// angle-weighted mean is the target instead.
const MIN_CAP_COS: f64 = 0.05;

impl<F: Float> VertexClamp<F> {
    /// The direction the vertex's normal is clamped toward: the axis of the smallest cap holding
    /// its faces' normals (the direction whose largest angle to those faces is least), or the
    /// angle-weighted mean where that cap is (nearly) a hemisphere or wider.
    fn target(&self) -> V3<F> {
        if self.cap.count > 0 && self.cap.cos > F::from_f64(MIN_CAP_COS) {
            self.cap.axis
        } else {
            self.mean
        }
    }
}

/// A cap of the unit sphere (`axis·p ≥ cos`) with the (up to three) points on its boundary
/// that define it: the smallest cap holding the points it has been grown by, where they fit in
/// a hemisphere (the minimum enclosing circle on the sphere, grown point by point as in
/// Welzl's algorithm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Cap<F: Float> {
    axis: V3<F>,
    cos: F,
    support: [V3<F>; 3],
    count: u8,
}

impl<F: Float> Cap<F> {
    /// Whether `p` is in the cap, within a rounding margin.
    fn holds(&self, p: V3<F>) -> bool {
        self.axis.dot(p) >= self.cos - F::from_f64(16.0) * F::EPSILON
    }

    /// Grows the cap to hold the unit vector `p`: the smallest cap through `p` and a subset of
    /// the support (at most two of them) that holds the whole support. Returns whether it
    /// changed.
    fn grow(&mut self, p: V3<F>) -> bool {
        if self.count == 0 {
            *self = Cap {
                axis: p,
                cos: F::ONE,
                support: [p; 3],
                count: 1,
            };
            return true;
        }
        if self.holds(p) {
            return false;
        }
        let n = usize::from(self.count).min(3);
        // The support points (at most two) that join `p` on the new boundary.
        const SUBSETS: [(Option<usize>, Option<usize>); 7] = [
            (None, None),
            (Some(0), None),
            (Some(1), None),
            (Some(2), None),
            (Some(0), Some(1)),
            (Some(0), Some(2)),
            (Some(1), Some(2)),
        ];
        let support = self.support;
        let pick = |k: Option<usize>| k.and_then(|k| support.get(k).copied());
        let mut best: Option<Cap<F>> = None;
        for (a, b) in SUBSETS {
            if a.is_some_and(|k| k >= n) || b.is_some_and(|k| k >= n) {
                continue;
            }
            let (a, b) = (pick(a), pick(b));
            let Some((axis, cos)) = cap_through(p, a, b) else {
                continue;
            };
            let cand = Cap {
                axis,
                cos,
                support: [p, a.unwrap_or(p), b.unwrap_or(p)],
                count: 1 + u8::from(a.is_some()) + u8::from(b.is_some()),
            };
            if !support.iter().take(n).all(|&q| cand.holds(q)) {
                continue;
            }
            if best.is_none_or(|c| cand.cos > c.cos) {
                best = Some(cand);
            }
        }
        match best {
            Some(c) => {
                *self = c;
                true
            }
            // Rounding left no candidate: keep the cap (its target falls back if too wide).
            None => false,
        }
    }
}

/// The smallest cap with the unit vectors `p`, `a`, `b` (those given) on its boundary: `p`
/// itself; the midpoint direction of two; the circle through three, on the side of `p`. `None`
/// where it degenerates (opposite or collinear points).
fn cap_through<F: Float>(p: V3<F>, a: Option<V3<F>>, b: Option<V3<F>>) -> Option<(V3<F>, F)> {
    let axis = match (a, b) {
        (None, None) => return Some((p, F::ONE)),
        (Some(q), None) | (None, Some(q)) => (p + q).try_normalize()?,
        (Some(a), Some(b)) => {
            let n = (a - p).cross(b - p).try_normalize()?;
            if n.dot(p) < F::ZERO { -n } else { n }
        }
    };
    let cos = axis.dot(p);
    if cos.is_fin() {
        Some((axis, cos))
    } else {
        None
    }
}

/// `u` rotated toward the direction of `target` until at most `deg` degrees from it: `None`
/// where it already is (or `target` is zero), the target itself where `u` is zero or opposite it.
fn clamp_toward<F: Float>(u: V3<F>, target: V3<F>, deg: f64) -> Option<V3<F>> {
    let m = target.try_normalize()?;
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

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> V3<f64> {
        V3 { x, y, z }.try_normalize().unwrap_or(V3 { x, y, z })
    }

    /// The smallest cap: a cube corner's three face normals (whatever the order, with a normal
    /// inside the cap added first or last) give the axis `(1, 1, 1)/√3` at 54.7°; two normals
    /// the midpoint; one normal itself; normals that fill more than a hemisphere give a cap
    /// the target does not use (the mean instead).
    #[test]
    fn caps_are_the_smallest() {
        let inner = v(1.0, 1.0, 1.2);
        let corner = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
        let orders = [[0, 1, 2], [2, 1, 0], [1, 2, 0]];
        for order in orders {
            for inner_first in [true, false] {
                let mut cap = Cap::<f64>::default();
                if inner_first {
                    assert!(cap.grow(inner));
                }
                for k in order {
                    if let Some(&p) = corner.get(k) {
                        cap.grow(p);
                    }
                }
                if !inner_first {
                    assert!(!cap.grow(inner), "an inner normal does not move the cap");
                }
                let axis = v(1.0, 1.0, 1.0);
                assert!((cap.axis - axis).length() < 1e-12, "{:?}", cap.axis);
                assert!((cap.cos - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{}", cap.cos);
            }
        }
        let mut cap = Cap::<f64>::default();
        cap.grow(v(1.0, 0.0, 0.0));
        assert_eq!((cap.axis, cap.cos), (v(1.0, 0.0, 0.0), 1.0));
        cap.grow(v(0.0, 1.0, 0.0));
        assert!((cap.axis - v(1.0, 1.0, 0.0)).length() < 1e-12);
        // Four normals around the equator and one pole: no direction is within 87° of all.
        let mut clamp = VertexClamp::<f64> {
            mean: V3 {
                x: 0.0,
                y: 0.0,
                z: 1.0,
            },
            ..VertexClamp::default()
        };
        for p in [
            v(1.0, 0.0, -0.2),
            v(-1.0, 0.0, -0.2),
            v(0.0, 1.0, -0.2),
            v(0.0, -1.0, -0.2),
            v(0.0, 0.0, 1.0),
        ] {
            clamp.cap.grow(p);
        }
        assert!(clamp.cap.cos <= MIN_CAP_COS, "{}", clamp.cap.cos);
        assert_eq!(clamp.target(), clamp.mean);
    }
}
