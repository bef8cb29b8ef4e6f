//! Seamless shading normals (docs/METHOD.md, "Seamless shading normals"): a correction of the
//! surface normal that makes it continuous across the shared edges of a mesh, while the surface
//! itself (and its exact geometric normal, [`Patch::point_normal`], [`Hit::normal`]) stays as it
//! is.
//!
//! The geometric normals of two neighbouring patches differ along their shared edge (by up to
//! 5.8° on the 8×8 torus), which shows as creases in shading. [`fit_seams`] fits, once per
//! mesh, for every edge shared by two patches a *common* edge normal `m(t)` (the average of the
//! two sides' geometric normals) and each side's *own* normal `o(t)`. The own normal is a twist
//! of the edge curve's normal `n*(t)` (eq. (3)) about the curve's tangent `T`; the common one
//! two tilts of the interpolated vertex normal `g(t)`, in a frame built from the edge's shared
//! data alone (its vertices and their normals: `g = normalize((1 − t)·na + t·nb)`,
//! `ĝ = normalize(ê × g)` with `ê` the chord, `â = g × ĝ`), so that both neighbours evaluate
//! the same common normal even where their edge curves part:
//!
//! ```text
//! o(t) = normalize(n*(t) + τ_o(t)·b̂(t)),   b̂ = T × n* / |T|,
//! m(t) = normalize(g(t) + τ_b(t)·ĝ(t) + τ_a(t)·â(t)),   τ(t) = t(1 − t)·Σ_k c_k (2t − 1)^k
//! ```
//!
//! with [`TWIST_TERMS`] coefficients `c_k` each, stored per patch in a [`Seam`].
//! [`Seam::shading_normal`] then returns
//!
//! ```text
//! n_s(X) = normalize(n_g(X) + Σ_j β_j(X)·(m_j(t_j) − o_j(t_j))),
//! β_j = (X_j X_{j+1})² / Σ_i (X_i X_{i+1})²,   t_j = X_{j+1} / (X_j + X_{j+1})
//! ```
//!
//! (edge `j` runs from `Pj` to `Pj+1`; `β = 0` at the vertices). On edge `j` only `β_j = 1` is
//! left and `n_s = m_j + (n_g − o_j)`: the common normal up to the fits' residual, the same
//! from both sides. At the vertices `n_s` is the vertex normal; on a sphere `m = o = n*` and the
//! correction vanishes (normals stay radial). Points are never changed.
//!
//! Memory: `size_of::<Seam<f32>>()` is 432 bytes (`f64`: 864), beside the patch's 228.

use core::fmt;

use crate::dual::{Dual, split};
use crate::edge::edge_point;
use crate::geometry::{EdgeView, Frame, Shape};
use crate::patch::Patch;
use crate::real::Float;
use crate::surface::{self, project_bary};
use crate::vec::V3;

#[cfg(doc)]
use crate::ray::Hit;

/// Number of twist coefficients per edge and fit (`τ(t) = t(1 − t)·Σ_{k<TWIST_TERMS} c_k
/// (2t − 1)^k`).
///
/// Twelve terms on [`FIT_SAMPLES`] = 49 samples: the jump across shared edges is then 2e-4° on
/// the irregular icosphere and 3e-5° on the 8×8 torus
/// ([`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG)), and 0.025° on the built-in (coarse)
/// teapot, where the geometric normal swings by up to 27° along an edge
/// ([`SEAM_JUMP_TEAPOT_DEG`](crate::accuracy::SEAM_JUMP_TEAPOT_DEG)). Measured alternatives
/// on that teapot: eight terms on 33 samples 0.23°, ten on 41 0.079°. Each term costs 36
/// bytes per patch in `f32` (three fits of three edges).
pub const TWIST_TERMS: usize = 12;

/// Samples per shared edge of the least-squares fit (`t = (s + ½) / FIT_SAMPLES`); see
/// [`TWIST_TERMS`] for the choice. [`fit_seams`] evaluates `2·FIT_SAMPLES` geometric normals
/// per shared edge.
pub const FIT_SAMPLES: usize = 49;

/// The seam correction of one patch: twist coefficients of its three edges (edge `j` from `Pj`
/// to `Pj+1`, parameter `t` from 0 at `Pj`; see the [module](self) for the formula). All zeros
/// (the [`Default`]) means no correction: [`Seam::shading_normal`] is then the geometric
/// normal. [`fit_seams`] leaves the zeros on boundary and non-manifold edges and on lone
/// triangles.
///
/// Memory: 432 bytes in `f32`, 864 in `f64` (checked by a test).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Seam<F: Float> {
    /// Per edge, the coefficients of the common edge normal's tilt across the edge, `τ_b` (the
    /// same normal, fitted by each neighbour in the frame both build from the edge's vertices
    /// and their normals).
    pub common: [[F; TWIST_TERMS]; 3],
    /// Per edge, the coefficients of the common edge normal's tilt along the edge, `τ_a`.
    pub common_along: [[F; TWIST_TERMS]; 3],
    /// Per edge, the coefficients of this patch's own surface normal's twist `τ_{f,e}` along
    /// the edge.
    pub own: [[F; TWIST_TERMS]; 3],
}

/// Scratch entry of [`fit_seams`]: one triangle edge keyed by its two vertex indices. The
/// caller provides `3 × triangles` of them (any contents; [`SeamEdge::default`] will do).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SeamEdge {
    /// `lo << 32 | hi` of the two vertex indices.
    key: u64,
    /// `3 × triangle + local edge`.
    slot: u32,
}

/// Why [`fit_seams`] could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeamError {
    /// The patches, the triangles and the seams differ in number.
    LengthMismatch {
        /// Patches given.
        patches: usize,
        /// Triangles given.
        triangles: usize,
        /// Seams given.
        seams: usize,
    },
    /// The scratch storage holds fewer than `3 × triangles` entries.
    ScratchTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// More triangles than the scratch entries can index (`3 × triangles` must fit a `u32`).
    TooManyTriangles,
    /// [`close_cracks`](crate::crack::close_cracks): the patches and the triangles differ in
    /// number.
    PatchCount {
        /// Patches given.
        patches: usize,
        /// Triangles given.
        triangles: usize,
    },
    /// A triangle has a vertex index at or above the vertex count, or repeats an index.
    BadIndex {
        /// The triangle.
        triangle: usize,
    },
}

impl fmt::Display for SeamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SeamError::LengthMismatch {
                patches,
                triangles,
                seams,
            } => write!(
                f,
                "seams: {patches} patches, {triangles} triangles and {seams} seams differ in number"
            ),
            SeamError::PatchCount { patches, triangles } => write!(
                f,
                "cracks: {patches} patches and {triangles} triangles differ in number"
            ),
            SeamError::ScratchTooSmall { needed } => {
                write!(f, "seams: scratch too small, need {needed} edge entries")
            }
            SeamError::TooManyTriangles => f.write_str("seams: too many triangles"),
            SeamError::BadIndex { triangle } => write!(
                f,
                "seams: triangle {triangle} has an out-of-range or repeated vertex index"
            ),
        }
    }
}

impl core::error::Error for SeamError {}

/// Fits the [`Seam`]s of a mesh's patches: for every edge shared by exactly two triangles that
/// traverse it in opposite directions, the common and the own normal twists of both sides
/// (least squares on [`FIT_SAMPLES`] points, [`TWIST_TERMS`] terms, in `f64` whatever `F`).
///
/// `patches[i]` must be the patch of triangle `triangles[i]` (vertex indices in the patch's
/// vertex order, `< vertex_count`); `seams` receives one [`Seam`] per patch (overwritten);
/// `scratch` holds at least `3 × triangles.len()` entries (its contents on return are
/// unspecified). Edges are matched by their vertex indices, so vertices that should be smooth
/// across an edge must share the index (a split vertex makes a boundary). Boundary edges,
/// edges of more than two triangles, edges traversed twice in the same direction, edges whose
/// endpoints do not coincide in the two patches (beyond `√ε` of the edge's length) and edges
/// whose fit is not finite get zeros: no correction.
///
/// Returns the number of shared edges fitted, or a [`SeamError`] when the lengths differ, the
/// scratch is too small, or an index is out of range or repeated within a triangle.
///
/// Work: `2·FIT_SAMPLES` normal evaluations per shared edge and one heapsort of the edges
/// (`O(n log n)`, in place, no allocation).
///
/// # Accuracy
/// The fit's residual decides the jump of [`Seam::shading_normal`] across the edges: see
/// [`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG).
/// # Panics
/// Never.
pub fn fit_seams<F: Float>(
    patches: &[Patch<F>],
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &mut [SeamEdge],
    seams: &mut [Seam<F>],
) -> Result<usize, SeamError> {
    let n = patches.len();
    if triangles.len() != n || seams.len() != n {
        return Err(SeamError::LengthMismatch {
            patches: n,
            triangles: triangles.len(),
            seams: seams.len(),
        });
    }
    for s in seams.iter_mut() {
        *s = Seam::default();
    }
    let fit = FitMatrix::new();
    let mut fitted = 0usize;
    for_each_shared_edge(triangles, vertex_count, scratch, |ta, ja, tb, jb| {
        let (Some(pa), Some(pb)) = (patches.get(ta), patches.get(tb)) else {
            return;
        };
        let Some((sa, sb)) = fit_edge(&fit, pa, ja, pb, jb) else {
            return;
        };
        if let Some(seam) = seams.get_mut(ta) {
            seam.set(ja, sa);
        }
        if let Some(seam) = seams.get_mut(tb) {
            seam.set(jb, sb);
        }
        fitted += 1;
    })?;
    Ok(fitted)
}

/// Calls `visit(ta, ja, tb, jb)` for every edge shared by exactly two triangles that traverse
/// it in opposite directions: edge `ja` of triangle `ta` (from its vertex `ja` to `ja + 1`) and
/// edge `jb` of triangle `tb`, in the order of the edges' sorted vertex keys. `scratch` holds at
/// least `3 × triangles.len()` entries (contents on return unspecified).
///
/// Errors: [`SeamError::TooManyTriangles`], [`SeamError::ScratchTooSmall`] and
/// [`SeamError::BadIndex`] (an index at or above `vertex_count`, or repeated in a triangle).
pub(crate) fn for_each_shared_edge(
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &mut [SeamEdge],
    mut visit: impl FnMut(usize, usize, usize, usize),
) -> Result<(), SeamError> {
    let Some(needed) = triangles.len().checked_mul(3) else {
        return Err(SeamError::TooManyTriangles);
    };
    if u32::try_from(needed).is_err() {
        return Err(SeamError::TooManyTriangles);
    }
    let Some(edges) = scratch.get_mut(..needed) else {
        return Err(SeamError::ScratchTooSmall { needed });
    };
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = *tri;
        let ok = [a, b, c]
            .iter()
            .all(|&i| usize::try_from(i).is_ok_and(|i| i < vertex_count));
        if !ok || a == b || b == c || c == a {
            return Err(SeamError::BadIndex { triangle: t });
        }
    }
    let mut slots = edges.iter_mut();
    for (t, tri) in triangles.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = edge_ends(tri, j);
            if let Some(e) = slots.next() {
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                *e = SeamEdge {
                    key: (u64::from(lo) << 32) | u64::from(hi),
                    slot: (3 * t + j) as u32,
                };
            }
        }
    }
    heap_sort(edges);
    let mut rest: &[SeamEdge] = edges;
    while let Some(first) = rest.first() {
        let run = rest.iter().take_while(|e| e.key == first.key).count();
        let (group, tail) = rest.split_at(run.min(rest.len()));
        rest = tail;
        let [ea, eb] = match group {
            [ea, eb] => [*ea, *eb],
            _ => continue,
        };
        let (ta, ja) = (ea.slot as usize / 3, ea.slot as usize % 3);
        let (tb, jb) = (eb.slot as usize / 3, eb.slot as usize % 3);
        let (Some(tri_a), Some(tri_b)) = (triangles.get(ta), triangles.get(tb)) else {
            continue;
        };
        // Opposite directions: A runs a → b, B runs b → a.
        if edge_ends(tri_a, ja).0 == edge_ends(tri_b, jb).0 {
            continue;
        }
        visit(ta, ja, tb, jb);
    }
    Ok(())
}

/// `true` when entry `a` sorts before entry `b` (by key, then slot); `false` out of range.
#[inline(always)]
fn before(v: &[SeamEdge], a: usize, b: usize) -> bool {
    match (v.get(a), v.get(b)) {
        (Some(x), Some(y)) => (x.key, x.slot) < (y.key, y.slot),
        _ => false,
    }
}

/// Swaps entries `a` and `b` when both are in range.
#[inline(always)]
fn swap_in(v: &mut [SeamEdge], a: usize, b: usize) {
    if a < v.len() && b < v.len() {
        v.swap(a, b);
    }
}

/// Moves entry `root` down the max-heap `v[..end]`.
fn sift_down(v: &mut [SeamEdge], mut root: usize, end: usize) {
    loop {
        let mut child = 2 * root + 1;
        if child >= end {
            return;
        }
        if child + 1 < end && before(v, child, child + 1) {
            child += 1;
        }
        if !before(v, root, child) {
            return;
        }
        swap_in(v, root, child);
        root = child;
    }
}

/// Sorts the edges by key, then slot: an in-place heapsort, `O(n log n)`, no recursion. (Core's
/// `sort_unstable_by` keeps a panic path for inconsistent orderings, which the crate's no-panic
/// link proof rejects.)
fn heap_sort(v: &mut [SeamEdge]) {
    let n = v.len();
    let mut start = n / 2;
    while start > 0 {
        start -= 1;
        sift_down(v, start, n);
    }
    let mut end = n;
    while end > 1 {
        end -= 1;
        swap_in(v, 0, end);
        sift_down(v, 0, end);
    }
}

/// Vertex indices `(start, end)` of local edge `j` of a triangle (`j` mod 3).
#[inline(always)]
fn edge_ends(tri: &[u32; 3], j: usize) -> (u32, u32) {
    let [a, b, c] = *tri;
    match j % 3 {
        0 => (a, b),
        1 => (b, c),
        _ => (c, a),
    }
}

/// `x` with `x_j = 1 − t`, `x_{j+1} = t` (the point at `t` on edge `j`), the third zero.
#[inline(always)]
pub(crate) fn edge_bary(j: usize, t: f64) -> [f64; 3] {
    match j % 3 {
        0 => [1.0 - t, t, 0.0],
        1 => [0.0, 1.0 - t, t],
        _ => [t, 0.0, 1.0 - t],
    }
}

/// The edge curve's unit normal `n*` (eq. (3), as `Patch::edge_point_normal`) and the unit
/// binormal `b̂ = T × n* / |T|` at `t`, local frame; `None` where the tangent `T` vanishes.
#[inline(always)]
pub(crate) fn edge_frame<F: Float>(e: &EdgeView<F>, t: F) -> Option<(V3<F>, V3<F>)> {
    let (c, g) = edge_point::<Dual<F>>(e, Dual::var(t));
    let (_, tan) = split(c);
    let (g, _) = split(g);
    let tt = tan.length2();
    if !(tt > F::ZERO) || !tt.is_fin() {
        return None;
    }
    let n = (g - tan * (tan.dot(g) / tt)).try_normalize()?;
    let b = tan.cross(n) * (F::ONE / tt.sqrt());
    if b.all_finite() { Some((n, b)) } else { None }
}

/// The twist `τ(t) = t(1 − t)·Σ_k c_k (2t − 1)^k`.
#[inline(always)]
pub(crate) fn twist<F: Float>(c: &[F; TWIST_TERMS], t: F) -> F {
    let u = t + t - F::ONE;
    let h = c.iter().rev().fold(F::ZERO, |h, &ck| h * u + ck);
    t * (F::ONE - t) * h
}

/// The least-squares map from the [`FIT_SAMPLES`] samples of a twist to its [`TWIST_TERMS`]
/// coefficients: `c = P·y`, from a modified Gram–Schmidt QR factorisation of the basis matrix
/// (better conditioned than the normal equations; no indexing).
struct FitMatrix {
    p: [[f64; FIT_SAMPLES]; TWIST_TERMS],
}

/// Sample parameter `t_s = (s + ½) / FIT_SAMPLES`.
#[inline(always)]
fn sample_t(s: usize) -> f64 {
    (s as f64 + 0.5) / FIT_SAMPLES as f64
}

fn dot_s(a: &[f64; FIT_SAMPLES], b: &[f64; FIT_SAMPLES]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl FitMatrix {
    fn new() -> Self {
        let mut q = [[0.0f64; FIT_SAMPLES]; TWIST_TERMS];
        let mut g = [[0.0f64; TWIST_TERMS]; TWIST_TERMS];
        for k in 0..TWIST_TERMS {
            // Basis function k at the samples, and its coefficients (the unit vector e_k).
            let mut v: [f64; FIT_SAMPLES] = core::array::from_fn(|s| {
                let t = sample_t(s);
                let u = 2.0 * t - 1.0;
                t * (1.0 - t) * (0..k).fold(1.0, |p, _| p * u)
            });
            let mut gk: [f64; TWIST_TERMS] = core::array::from_fn(|l| f64::from(u8::from(l == k)));
            // Twice (re-orthogonalisation keeps Q orthonormal to rounding).
            for _ in 0..2 {
                for (ql, gl) in q.iter().zip(g.iter()).take(k) {
                    let r = dot_s(ql, &v);
                    v.iter_mut().zip(ql).for_each(|(x, y)| *x -= r * y);
                    gk.iter_mut().zip(gl).for_each(|(x, y)| *x -= r * y);
                }
            }
            let norm = crate::math::sqrt_f64(dot_s(&v, &v));
            let inv = if norm > 0.0 { 1.0 / norm } else { 0.0 };
            v.iter_mut().for_each(|x| *x *= inv);
            gk.iter_mut().for_each(|x| *x *= inv);
            if let (Some(qs), Some(gs)) = (q.get_mut(k), g.get_mut(k)) {
                *qs = v;
                *gs = gk;
            }
        }
        // P = Σ_k g_k q_kᵀ: the fit in the orthonormal basis, mapped back to the coefficients.
        let mut p = [[0.0f64; FIT_SAMPLES]; TWIST_TERMS];
        for (gk, qk) in g.iter().zip(q.iter()) {
            for (row, &gkl) in p.iter_mut().zip(gk) {
                row.iter_mut().zip(qk).for_each(|(x, y)| *x += gkl * y);
            }
        }
        FitMatrix { p }
    }

    /// The coefficients of the samples `y`.
    fn coefficients(&self, y: &[f64; FIT_SAMPLES]) -> [f64; TWIST_TERMS] {
        self.p.map(|row| dot_s(&row, y))
    }
}

/// A patch's geometry widened to `f64`.
pub(crate) fn widen<F: Float>(patch: &Patch<F>) -> (Frame<f64>, Shape<f64>) {
    let v = |v: V3<F>| V3::new(v.x.to_f64(), v.y.to_f64(), v.z.to_f64());
    let frame = Frame {
        origin: v(patch.frame.origin),
        axes: patch.frame.axes.map(v),
    };
    (frame, patch.shape.widen())
}

/// One edge's coefficients for one side: common across, common along, own.
type EdgeFit<F> = [[F; TWIST_TERMS]; 3];

/// The twist `(v·b̂)/(v·n*)` of a local unit vector `v` in the edge frame `(n*, b̂)`, `None` when
/// `v` is (nearly) perpendicular to `n*`.
#[inline(always)]
fn twist_of(v: V3<f64>, n: V3<f64>, b: V3<f64>) -> Option<f64> {
    let den = v.dot(n);
    if !(den > 1e-3) {
        return None;
    }
    let r = v.dot(b) / den;
    if r.is_finite() { Some(r) } else { None }
}

/// Fits the shared edge `ja` of `pa` (from its vertex `ja` to `ja + 1`) and `jb` of `pb` (the
/// same edge, traversed the other way): `None` when the endpoints do not coincide, or a
/// sample or the result is not finite.
fn fit_edge<F: Float>(
    fit: &FitMatrix,
    pa: &Patch<F>,
    ja: usize,
    pb: &Patch<F>,
    jb: usize,
) -> Option<(EdgeFit<F>, EdgeFit<F>)> {
    let (fa, sa) = widen(pa);
    let (fb, sb) = widen(pb);
    let (ea, eb) = (sa.edge(ja), sb.edge(jb));
    // The endpoints must coincide (A runs a → b, B runs b → a).
    let (a0, a1) = (fa.local_to_world(ea.a), fa.local_to_world(ea.b));
    let (b0, b1) = (fb.local_to_world(eb.a), fb.local_to_world(eb.b));
    let len = (a1 - a0).length();
    let tol = crate::math::sqrt_f64(F::EPSILON.to_f64()) * len;
    if !((a0 - b1).length() <= tol && (a1 - b0).length() <= tol) {
        return None;
    }
    let mut ys = [[0.0f64; FIT_SAMPLES]; 6];
    for s in 0..FIT_SAMPLES {
        let t = sample_t(s);
        let tb = 1.0 - t;
        let (_, na) = surface::point_normal_local(&sa, edge_bary(ja, t));
        let (_, nb) = surface::point_normal_local(&sb, edge_bary(jb, tb));
        let (wa, wb) = (fa.local_dir_to_world(na), fb.local_dir_to_world(nb));
        let m = (wa + wb).try_normalize()?;
        let (ma, mb) = (fa.world_dir_to_local(m), fb.world_dir_to_local(m));
        let (nsa, bsa) = edge_frame(&ea, t)?;
        let (nsb, bsb) = edge_frame(&eb, tb)?;
        let (ga, ba, aa) = shared_frame(&ea, t)?;
        let (gb, bb, ab) = shared_frame(&eb, tb)?;
        let vals = [
            twist_of(ma, ga, ba)?,
            twist_of(ma, ga, aa)?,
            twist_of(na, nsa, bsa)?,
            twist_of(mb, gb, bb)?,
            twist_of(mb, gb, ab)?,
            twist_of(nb, nsb, bsb)?,
        ];
        for (y, v) in ys.iter_mut().zip(vals) {
            if let Some(slot) = y.get_mut(s) {
                *slot = v;
            }
        }
    }
    // B's samples lie at its own parameters `1 − t_s = t_{FIT_SAMPLES−1−s}`: reverse them.
    let [ya_c, ya_a, ya_o, mut yb_c, mut yb_a, mut yb_o] = ys;
    yb_c.reverse();
    yb_a.reverse();
    yb_o.reverse();
    let c = [ya_c, ya_a, ya_o, yb_c, yb_a, yb_o].map(|y| fit.coefficients(&y).map(F::from_f64));
    if !c.iter().flatten().all(|x| x.is_fin()) {
        return None;
    }
    let [ca, aa, oa, cb, ab, ob] = c;
    Some(([ca, aa, oa], [cb, ab, ob]))
}

/// The frame of edge `e` at `t` that both neighbours share up to their frames' rounding, built
/// from the edge's shared data alone (its two vertices and their normals, not the patch's own
/// edge curve): `g = normalize((1 − t)·na + t·nb)`, `ĝ = normalize(ê × g)` across the edge
/// (`ê` the chord's direction) and `â = g × ĝ` along it. `None` where it degenerates.
///
/// Seen from the other neighbour (which runs the edge the other way, at `1 − t`), `g` is the
/// same and `ĝ`, `â` change sign, so the tilts fitted by the two sides to the same common
/// normal are each other's negatives, and the common normal they evaluate is the same.
#[inline(always)]
pub(crate) fn shared_frame<F: Float>(e: &EdgeView<F>, t: F) -> Option<(V3<F>, V3<F>, V3<F>)> {
    let g = (e.na * (F::ONE - t) + e.nb * t).try_normalize()?;
    let b = (e.b - e.a).cross(g).try_normalize()?;
    let a = g.cross(b);
    if a.all_finite() {
        Some((g, b, a))
    } else {
        None
    }
}

impl<F: Float> Seam<F> {
    /// Sets edge `j`'s coefficients.
    fn set(&mut self, j: usize, [common, along, own]: EdgeFit<F>) {
        if let (Some(c), Some(a), Some(o)) = (
            self.common.get_mut(j),
            self.common_along.get_mut(j),
            self.own.get_mut(j),
        ) {
            *c = common;
            *a = along;
            *o = own;
        }
    }

    /// `true` when every coefficient is zero: no correction.
    ///
    /// # Panics
    /// Never.
    pub fn is_zero(&self) -> bool {
        self.common
            .iter()
            .chain(self.common_along.iter())
            .chain(self.own.iter())
            .flatten()
            .all(|&c| c == F::ZERO)
    }

    /// The seamless shading normal of `patch` (the patch this seam was fitted for) at
    /// barycentrics `(w1, w2)` (`w0 = 1 − w1 − w2`; projected onto the triangle like
    /// [`Patch::point_normal`]): the geometric normal corrected toward the common edge normals
    /// (see the [module](self) for the formula). World coordinates, unit length, oriented like
    /// the vertex normals.
    ///
    /// Equals [`Patch::point_normal`]'s normal bit for bit where the correction vanishes (a
    /// zero seam, at the vertices), is the vertex normal at the vertices, and on a shared edge
    /// the common edge normal up to the fit's residual, the same from both sides. Work: the
    /// geometric normal plus one edge-curve evaluation (with its derivative) per edge near the
    /// point.
    ///
    /// # Accuracy
    /// Jump across shared edges of meshes whose neighbours share their edge curves within
    /// [`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG) (torus, teapot, sphere-like meshes);
    /// on irregular meshes the neighbours' curves part and the jump is larger
    /// ([`SEAM_JUMP_TEAPOT_DEG`](crate::accuracy::SEAM_JUMP_TEAPOT_DEG)). On a sphere's
    /// patch radial to [`F64_SPHERE_NORMAL`](crate::accuracy::F64_SPHERE_NORMAL) (`f64`) and
    /// [`F32_SPHERE_NORMAL`](crate::accuracy::F32_SPHERE_NORMAL) (`f32`). On the 8×8 torus
    /// within [`TORUS_8X8_SEAMLESS_NORMAL_MAX_DEG`](crate::accuracy::TORUS_8X8_SEAMLESS_NORMAL_MAX_DEG)
    /// of the true normal (the geometric normal: [`TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG`](crate::accuracy::TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG)).
    /// Unit length to [`UNIT_LENGTH_ULPS`](crate::accuracy::UNIT_LENGTH_ULPS) ulps.
    /// # Panics
    /// Never; the result is finite for every accepted patch and any coefficients.
    pub fn shading_normal(&self, patch: &Patch<F>, w1: F, w2: F) -> F::Vec3 {
        let x = project_bary(w1, w2);
        let [_, du1, du2] = surface::point_derivs_local(&patch.shape, x);
        let ng = surface::normal_local(&patch.shape, x, du1, du2);
        let n = self.correct_local(&patch.shape, x, ng).unwrap_or(ng);
        F::to_glam(patch.frame.local_dir_to_world(n))
    }

    /// [`Seam::shading_normal`] from a geometric normal already at hand: `normal` is `patch`'s
    /// geometric normal at `(w1, w2)` (world coordinates, e.g. [`Hit::normal`] with
    /// [`Hit::w1`], [`Hit::w2`]). Saves the derivative evaluation.
    ///
    /// Returns `normal` itself where the correction vanishes, or where `normal` is not a
    /// finite non-zero vector.
    ///
    /// # Accuracy
    /// As [`Seam::shading_normal`] (the frame change of `normal` rounds once more).
    /// # Panics
    /// Never.
    pub fn correct(&self, patch: &Patch<F>, w1: F, w2: F, normal: F::Vec3) -> F::Vec3 {
        let x = project_bary(w1, w2);
        let Some(ng) = patch
            .frame
            .world_dir_to_local(F::from_glam(normal))
            .try_normalize()
        else {
            return normal;
        };
        match self.correct_local(&patch.shape, x, ng) {
            Some(n) => F::to_glam(patch.frame.local_dir_to_world(n)),
            None => normal,
        }
    }

    /// The corrected local-frame normal at barycentrics `x` (projected) from the geometric one
    /// `ng`, or `None` where the correction vanishes.
    #[inline(always)]
    pub(crate) fn correct_local(&self, shape: &Shape<F>, x: [F; 3], ng: V3<F>) -> Option<V3<F>> {
        let [x0, x1, x2] = x;
        let pairs = [(x0, x1), (x1, x2), (x2, x0)];
        let prods = pairs.map(|(a, b)| a * b);
        let big = prods.iter().fold(F::ZERO, |m, &p| m.max(p));
        if !(big > F::ZERO) || !big.is_fin() {
            return None;
        }
        let q = prods.map(|p| {
            let r = p / big;
            r * r
        });
        let sum = q.iter().fold(F::ZERO, |s, &v| s + v);
        let mut acc = V3::<F>::zero();
        let mut any = false;
        let zero = [F::ZERO; TWIST_TERMS];
        for (j, ((((qj, (xa, xb)), common), along), own)) in q
            .iter()
            .zip(pairs)
            .zip(self.common.iter())
            .zip(self.common_along.iter())
            .zip(self.own.iter())
            .enumerate()
        {
            if !(*qj > F::ZERO) || (*common == zero && *along == zero && *own == zero) {
                continue;
            }
            let t = xb / (xa + xb);
            let e = shape.edge(j);
            let (Some((n, b)), Some((g, gb, ga))) = (edge_frame(&e, t), shared_frame(&e, t)) else {
                continue;
            };
            let (tc, ta, to) = (twist(common, t), twist(along, t), twist(own, t));
            let (Some(m), Some(o)) = (
                (g + gb * tc + ga * ta).try_normalize(),
                (n + b * to).try_normalize(),
            ) else {
                continue;
            };
            acc = acc + (m - o) * (*qj / sum);
            any = true;
        }
        if !any {
            return None;
        }
        (ng + acc).try_normalize()
    }
}
