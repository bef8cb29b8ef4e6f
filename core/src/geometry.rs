//! A patch's stored geometry as plain data: what a renderer uploads to a GPU or serialises.
//!
//! [`Patch::data`](crate::Patch::data) returns it; every field is an array of scalars with the
//! meaning documented below, in the layout the kernel uses (the triangle's local frame: origin
//! `P0`, `x` along `P1 − P0`, `z` along the face normal), so a port of the kernel to another
//! language can reproduce the CPU's arithmetic.

use crate::real::Float;

/// The stored geometry of one [`Patch`](crate::Patch), in plain arrays (`repr(C)`, 54 scalars).
///
/// Invariants of an accepted patch (checked by [`Patch::new`](crate::Patch::new)): every value
/// finite, `axes` orthonormal and right-handed, `p[0] = 0`, `p[1].y = p[1].z = p[2].z = 0`,
/// `n` unit with `n[i].z ≥` [`MIN_NORMAL_COS`](crate::patch::MIN_NORMAL_COS), `d[i] = n[i] / n[i].z`
/// (so `d[i].z = 1`), `sigma[0] ≤ 0 ≤ sigma[1]`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchData<F: Float> {
    /// World position of `P0`: the local frame's origin.
    pub origin: [F; 3],
    /// The local frame's axes `x`, `y`, `z = Nf` in world coordinates (unit, orthogonal).
    pub axes: [[F; 3]; 3],
    /// The vertices in the local frame.
    pub p: [[F; 3]; 3],
    /// The unit vertex normals in the local frame.
    pub n: [[F; 3]; 3],
    /// The direction field `di = ni / (ni·Nf)` at the vertices, local frame (`z = 1`).
    pub d: [[F; 3]; 3],
    /// Signed curvatures `[κ(S¹j), κ(S²j)]` of edge `j`'s two spheres (edge `j` runs from `Pj`
    /// to `Pj+1`; docs/METHOD.md §3–§4), in inverse length units.
    pub k: [[F; 2]; 3],
    /// Conservative height range `[σmin, σmax]` of the surface over the triangle's plane.
    pub sigma: [F; 2],
    /// World bounding box of the shell: minimum corner.
    pub bbox_min: [F; 3],
    /// World bounding box of the shell: maximum corner.
    pub bbox_max: [F; 3],
}
