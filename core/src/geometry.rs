//! A patch's stored geometry as plain data: what a renderer uploads to a GPU or serialises.
//!
//! [`Patch::data`](crate::Patch::data) returns it; every field is an array of scalars with the
//! meaning documented below, in the layout the kernel uses (the triangle's local frame: origin
//! `P0`, `x` along `P1 − P0`, `z` along the face normal), so a port of the kernel to another
//! language can reproduce the CPU's arithmetic.
//!
//! Inside the crate the same geometry is a `Frame` (the local frame and its maps to world
//! coordinates) and a `Shape` (the local-frame data the surface's math takes).

use crate::aabb::Aabb;
use crate::num::real::{Float, Real};
use crate::num::vec::V3;

/// The stored geometry of one [`Patch`], in plain arrays (`repr(C)`, 60 scalars).
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
    /// How far each side wall `Xk = 0` (`k` the opposite vertex) reaches beyond the kernel's
    /// rounding margin, in barycentric units ([`close_cracks`](crate::mesh::close_cracks);
    /// zeros unless measured).
    pub reach: [F; 3],
    /// The band's fit `[c0, c1, c2]`: `q(β) = c0·β1β2 + c1·β2β0 + c2·β0β1` over the
    /// barycentrics `β` of a local point's `(x, y)` in the triangle (length units; docs/METHOD.md
    /// §8, "Culling").
    pub band_fit: [F; 3],
    /// The band `[lo, hi, per_reach]`: every surface point's `z − q(β)` lies in
    /// `[lo − w, hi + w]` with `w = per_reach · max(reach)` (the reach plus the kernel's wall margin);
    /// `[F::MIN, F::MAX, 0]` (nothing culled) for patches with a vertex normal more than 45°
    /// off the face normal.
    pub band: [F; 3],
}

/// A triangle's local orthonormal frame: origin `P0`, `x` along `P1 − P0`, `z` along the face
/// normal `Nf`, with the maps between it and world coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Frame<F> {
    /// World position of `P0`: the frame's origin.
    pub(crate) origin: V3<F>,
    /// The frame's axes in world coordinates: `x`, `y`, `z = Nf`.
    pub(crate) axes: [V3<F>; 3],
}

impl<F: Float> Frame<F> {
    /// World coordinates of a local-frame point.
    #[inline(always)]
    pub(crate) fn local_to_world<S: Real<F = F>>(&self, v: V3<S>) -> V3<S> {
        let [ex, ey, ez] = self.axes;
        V3::lift(self.origin) + V3::lift(ex) * v.x + V3::lift(ey) * v.y + V3::lift(ez) * v.z
    }

    /// World direction of a local-frame direction.
    #[inline(always)]
    pub(crate) fn local_dir_to_world<S: Real<F = F>>(&self, v: V3<S>) -> V3<S> {
        let [ex, ey, ez] = self.axes;
        V3::lift(ex) * v.x + V3::lift(ey) * v.y + V3::lift(ez) * v.z
    }

    /// Local-frame coordinates of a world point.
    #[inline(always)]
    pub(crate) fn world_to_local(&self, v: V3<F>) -> V3<F> {
        let [ex, ey, ez] = self.axes;
        let w = v - self.origin;
        V3::new(w.dot(ex), w.dot(ey), w.dot(ez))
    }

    /// Local-frame components of a world direction.
    #[inline(always)]
    pub(crate) fn world_dir_to_local(&self, v: V3<F>) -> V3<F> {
        let [ex, ey, ez] = self.axes;
        V3::new(v.dot(ex), v.dot(ey), v.dot(ez))
    }
}

/// The geometry the surface's math works on, in the triangle's local [`Frame`]: vertices,
/// vertex normals, the direction field and the edge spheres' curvatures (the invariants of
/// [`PatchData`]'s fields of the same names).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Shape<F> {
    /// Vertices (`p[0] = 0`, `z = 0`).
    pub(crate) p: [V3<F>; 3],
    /// Unit vertex normals.
    pub(crate) n: [V3<F>; 3],
    /// Direction field `di = ni / (ni·Nf)` (`z = 1`).
    pub(crate) d: [V3<F>; 3],
    /// Curvatures `[κ(S¹j), κ(S²j)]` of edge `j`'s two spheres.
    pub(crate) k: [[F; 2]; 3],
}

/// A patch's culling band (`crate::surface::band` computes and applies it): every surface
/// point has `lo ≤ z − q(β) ≤ hi` with `q(β) = c0·β1β2 + c1·β2β0 + c2·β0β1`, widened by
/// `per_reach` times the largest wall reach at the time of the test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Band<F> {
    /// `[c0, c1, c2]`: the fit's coefficient of the product of the two barycentrics other
    /// than `βk` (length units).
    pub(crate) c: [F; 3],
    /// Least and greatest residual `z − q(β)` of a surface point (length units); `∓F::MAX`
    /// for an unbounded band.
    pub(crate) lo: F,
    /// See [`Band::lo`].
    pub(crate) hi: F,
    /// How much both bounds move out per unit of barycentric reach (length units).
    pub(crate) per_reach: F,
}

impl<F: Float> Default for Band<F> {
    fn default() -> Self {
        Band::UNBOUNDED
    }
}

impl<F: Float> Band<F> {
    /// The band that culls nothing.
    pub(crate) const UNBOUNDED: Band<F> = Band {
        c: [F::ZERO; 3],
        lo: F::MIN,
        hi: F::MAX,
        per_reach: F::ZERO,
    };

    /// Whether every value is finite.
    pub(crate) fn is_finite(&self) -> bool {
        let [c0, c1, c2] = self.c;
        let z = c0 * F::ZERO + c1 * F::ZERO + c2 * F::ZERO + self.per_reach * F::ZERO;
        z == F::ZERO && self.lo.is_fin() && self.hi.is_fin()
    }
}

/// The nodes of a [`Predictor`]: the degree-4 lattice's fifteen points less its three vertices.
pub(crate) const PREDICTOR_NODES: usize = 12;

/// A patch's predictor of the crossing (`crate::surface::predictor` builds and evaluates it):
/// the quartic interpolant of the height over the section barycentrics, as its heights at the
/// nodes, and a validated bound of its error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Predictor<F> {
    /// The true height at each node, in the order of `crate::surface::predictor`'s lattice.
    pub(crate) heights: [F; PREDICTOR_NODES],
    /// `|σS − P|` at most this over the triangle (validated); `F::MAX` for no predictor.
    pub(crate) bound: F,
}

impl<F: Float> Predictor<F> {
    /// No predictor: the kernel brackets with true heights.
    pub(crate) const NONE: Self = Predictor {
        heights: [F::ZERO; PREDICTOR_NODES],
        bound: F::MAX,
    };

    /// Whether the patch has a predictor (`crate::surface::predictor`, "Domain").
    #[inline(always)]
    pub(crate) fn usable(&self) -> bool {
        self.bound < F::MAX
    }

    /// The validated bound of `|σS − P|` (height units, the local frame's); `F::MAX` for
    /// [`Predictor::NONE`].
    #[inline(always)]
    pub(crate) fn bound(&self) -> F {
        self.bound
    }

    /// Whether every stored value is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.heights.iter().all(|h| h.is_fin()) && self.bound.is_fin()
    }
}

/// The data of one edge of a [`Shape`] (edge `j` runs from `Pj` to `Pj+1`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgeView<F> {
    /// Start vertex `Pj`.
    pub a: V3<F>,
    /// End vertex `Pj+1`.
    pub b: V3<F>,
    /// Direction field at the start, `dj` (unit height).
    pub da: V3<F>,
    /// Direction field at the end, `dj+1`.
    pub db: V3<F>,
    /// Unit normal at the start.
    pub na: V3<F>,
    /// Unit normal at the end.
    pub nb: V3<F>,
    /// Curvature of `S¹j`.
    pub k1: F,
    /// Curvature of `S²j`.
    pub k2: F,
}

impl<F: Float> Shape<F> {
    /// The same shape in `f64` (exact: every `f32` is an `f64`).
    #[inline]
    pub(crate) fn widen(&self) -> Shape<f64> {
        let v = |v: V3<F>| V3::new(v.x.to_f64(), v.y.to_f64(), v.z.to_f64());
        Shape {
            p: self.p.map(v),
            n: self.n.map(v),
            d: self.d.map(v),
            k: self.k.map(|k| k.map(Float::to_f64)),
        }
    }
}

impl<F: Copy> Shape<F> {
    /// The data of edge `j` (from `Pj` to `Pj+1`); `j` is 0, 1 or 2 (anything else means 2).
    #[inline(always)]
    pub(crate) fn edge(&self, j: usize) -> EdgeView<F> {
        let [p0, p1, p2] = self.p;
        let [n0, n1, n2] = self.n;
        let [d0, d1, d2] = self.d;
        let [k0, k1, k2] = self.k;
        let (a, b, da, db, na, nb, k) = match j {
            0 => (p0, p1, d0, d1, n0, n1, k0),
            1 => (p1, p2, d1, d2, n1, n2, k1),
            _ => (p2, p0, d2, d0, n2, n0, k2),
        };
        let [k1, k2] = k;
        EdgeView {
            a,
            b,
            da,
            db,
            na,
            nb,
            k1,
            k2,
        }
    }
}

/// A smooth triangular patch (the construction of Gusyatin & Sorokin, docs/METHOD.md §2–§5) in
/// precision `F` (`f32`, the default, or `f64`; see [`DPatch`](crate::patch::DPatch)).
///
/// Built from a triangle `P0 P1 P2`, counter-clockwise seen from the side its normals point to,
/// and three vertex normals (any positive length). The surface interpolates the vertices with
/// the given normals, passes through the edge conjugation lines, and reproduces spheres exactly.
///
/// Memory: `size_of::<Patch<f32>>()` is 304 bytes, `Patch<f64>` 608 bytes (checked by a test),
/// 52 of them (`f32`) the predictor's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch<F: Float = f32> {
    /// The local frame (origin `P0`, axes) and its maps to world coordinates.
    pub(crate) frame: Frame<F>,
    /// Vertices, normals, direction field and edge-sphere curvatures in the local frame.
    pub(crate) shape: Shape<F>,
    /// Conservative height range of the surface over the triangle.
    pub(crate) sigma: [F; 2],
    /// World bounding box of the shell (min, max), cached for the kernel and the BVH.
    pub(crate) bbox: Aabb<F>,
    /// Index + 1 into [`NORMAL_CLAMP_DEG`](crate::patch::NORMAL_CLAMP_DEG) of the clamp applied by [`Patch::new_or_tilted`]
    /// (0: the normals were used as given).
    pub(crate) remedy: u8,
    /// How far each side wall `Xk = 0` (`k` the opposite vertex) is moved outward beyond the
    /// kernel's rounding margin, in barycentric units: 0 unless
    /// [`close_cracks`](crate::mesh::close_cracks) measured a gap to the neighbour there.
    pub(crate) reach: [F; 3],
    /// The band that culls rays before sampling ([`crate::surface::band`]).
    pub(crate) band: Band<F>,
    /// The predictor of the crossing and its bound ([`crate::surface::predictor`]).
    pub(crate) predictor: Predictor<F>,
}

/// A placeholder for caller storage (e.g. the slots of a
/// [`SceneStorage`](crate::SceneStorage)): all zeros with an empty bounding box, so no ray
/// query ever reaches its surface. Not a patch of any triangle.
impl<F: Float> Default for Patch<F> {
    fn default() -> Self {
        Patch {
            frame: Frame::default(),
            shape: Shape::default(),
            sigma: [F::ZERO; 2],
            bbox: Aabb::EMPTY,
            remedy: 0,
            reach: [F::ZERO; 3],
            band: Band::UNBOUNDED,
            predictor: Predictor::NONE,
        }
    }
}

impl<F: Float> Patch<F> {
    /// The patch's frame and shape widened to `f64` (exactly).
    pub(crate) fn widened(&self) -> (Frame<f64>, Shape<f64>) {
        let v = |v: V3<F>| V3::new(v.x.to_f64(), v.y.to_f64(), v.z.to_f64());
        let frame = Frame {
            origin: v(self.frame.origin),
            axes: self.frame.axes.map(v),
        };
        (frame, self.shape.widen())
    }
}
