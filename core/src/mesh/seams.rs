//! Seamless shading normals: the fit ([`fit_seams`](super::fit_seams)) and the correction ([`Seam`]); the
//! formula is in the [mesh module](crate::mesh) documentation.

use super::sampling::{FIT_NODES, Nodes, Side, widest_gap};
use super::topology::EdgePair;
use crate::geometry::{EdgeView, Shape};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::surface::lanes::Prepared;
use crate::surface::scalar::{self, project_bary};

#[cfg(doc)]
use crate::ray::Hit;

/// Number of coefficients of each tilt of the common edge normal (`τ(t) = t(1 − t)·
/// Σ_{k<TWIST_TERMS} c_k (2t − 1)^k`), per edge and side.
///
/// The tilts decide only where the common normal lies, not whether it is continuous: both
/// neighbours fit the same samples in frames built from the same data, so their polynomials
/// agree to rounding whatever the number of terms, and the jump across the edge stays at
/// rounding level ([`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG)). Six terms on
/// [`FIT_SAMPLES`] = 8 nodes keep the 8×8 torus's shading normal within 2.897° of the true
/// normal (p99 2.552°; on all 16 edge nodes the same to the third decimal; twelve terms on 16:
/// 2.898°, 2.552°), measured by the repository's test suite. Each term costs 24 bytes per
/// patch in `f32` (two tilts of three edges).
pub const TWIST_TERMS: usize = 6;

/// Samples per shared edge of the least-squares fit: 8 of the 16 Chebyshev nodes
/// `t_s = (1 − cos((2s + 1)π / 32)) / 2` at which crack closure measures the gap
/// ([`CRACK_SAMPLES`](crate::mesh::cracks::CRACK_SAMPLES)), `s = 1, 3, 5, 7, 8, 10, 12, 14`
/// (every other node, symmetric about the middle, so that the neighbour running the edge the
/// other way samples the same points); see [`TWIST_TERMS`] for the choice. [`fit_seams`](super::fit_seams)
/// evaluates `2·FIT_SAMPLES` geometric normals per shared edge (the common normal is their
/// average); the builder evaluates each neighbour once at all 16 nodes for both, the normals'
/// jets only at these 8.
pub const FIT_SAMPLES: usize = FIT_NODES.len();

/// World distance between two unit vertex normals beyond which the two sides of an edge do not
/// share the vertex normal (a per-patch clamp moved one; the same normal differs only by the
/// frames' rounding, below 1e-6 in `f32`).
pub const FREE_END_TOL: f64 = 1e-5;

/// The seam correction of one patch: the common normal of each of its three edges (edge `j`
/// from `Pj` to `Pj+1`, parameter `t` from 0 at `Pj`; see [`crate::mesh`] for the formula). All
/// zeros (the [`Default`]) means no correction: [`Seam::shading_normal`] is then the geometric
/// normal. [`fit_seams`](super::fit_seams) leaves the zeros on boundary and non-manifold edges, on lone
/// triangles and where it declines a fit.
///
/// Memory: 148 bytes in `f32`, 296 in `f64` (checked by a test); with the patch's 304, 452
/// bytes per triangle in `f32`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Seam<F: Float> {
    /// Per edge, the coefficients of the common edge normal's tilt across the edge, `τ_b` (the
    /// same normal, fitted by each neighbour in the frame both build from the edge's vertices
    /// and their normals).
    pub common: [[F; TWIST_TERMS]; 3],
    /// Per edge, the coefficients of the common edge normal's tilt along the edge, `τ_a`.
    pub common_along: [[F; TWIST_TERMS]; 3],
    /// Per edge, whether the two neighbours' vertex normals differ at an end of the edge (a
    /// per-patch clamp moved one). Their frames then differ too, so the edge stores no tilts:
    /// `common[j][0..3]` and `common[j][3..6]` hold the neighbour's normals at this edge's start
    /// and end (this patch's local frame), and the common normal is the average of the two
    /// sides' interpolated vertex normals.
    pub free: [bool; 3],
}

/// The gap and the fits of shared edge `pair`, from both neighbours' surfaces at the same
/// nodes (each side widened and prepared once, one jet evaluation per node): the gap bit for
/// bit [`edge_gap`](super::cracks::edge_gap)'s, the fits [`fit_sides`]'; `(0, None)` when an
/// index is out of range.
#[inline]
pub(crate) fn gap_and_fit<F: Float>(
    fit: &FitMatrix,
    patches: &[Patch<F>],
    pair: EdgePair,
) -> (f64, Option<EdgeFits<F>>) {
    let (Some(pa), Some(pb)) = (patches.get(pair.ta), patches.get(pair.tb)) else {
        return (0.0, None);
    };
    let (a, b) = (Side::new(pa, pair.ja, false), Side::new(pb, pair.jb, true));
    let (pa, na) = a.points_normals(&fit.nodes);
    let (pb, nb) = b.points_normals(&fit.nodes);
    (widest_gap(&pa, &pb), fit_sides(fit, &a, &na, &b, &nb))
}

/// Stores the fits of shared edge `pair` in both neighbours' seams; `true` when there were
/// fits to store.
pub(crate) fn apply_fit<F: Float>(
    seams: &mut [Seam<F>],
    pair: EdgePair,
    sides: Option<(EdgeFit<F>, EdgeFit<F>)>,
) -> bool {
    let Some((sa, sb)) = sides else {
        return false;
    };
    if let Some(seam) = seams.get_mut(pair.ta) {
        seam.set(pair.ja, sa);
    }
    if let Some(seam) = seams.get_mut(pair.tb) {
        seam.set(pair.jb, sb);
    }
    true
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
pub(crate) struct FitMatrix {
    p: [[f64; FIT_SAMPLES]; TWIST_TERMS],
    /// The sample parameters.
    pub(crate) nodes: Nodes,
}

fn dot_s(a: &[f64; FIT_SAMPLES], b: &[f64; FIT_SAMPLES]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl FitMatrix {
    pub(crate) fn new() -> Self {
        let nodes = Nodes::new();
        FitMatrix {
            p: Self::solve(&nodes),
            nodes,
        }
    }

    fn solve(nodes: &Nodes) -> [[f64; FIT_SAMPLES]; TWIST_TERMS] {
        let sample_t = |s: usize| nodes.fit_t(s);
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
            let norm = crate::num::math::sqrt_f64(dot_s(&v, &v));
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
        p
    }

    /// The map's rows (one per coefficient).
    pub(crate) fn rows(&self) -> [[f64; FIT_SAMPLES]; TWIST_TERMS] {
        self.p
    }

    /// The coefficients of the samples `y`.
    fn coefficients(&self, y: &[f64; FIT_SAMPLES]) -> [f64; TWIST_TERMS] {
        self.p.map(|row| dot_s(&row, y))
    }
}

/// One edge's coefficients for one side: the common normal's tilts across and along the edge,
/// and whether the edge is free ([`Seam::free`]: then the first holds the neighbour's normals).
pub(crate) type EdgeFit<F> = ([[F; TWIST_TERMS]; 2], bool);

/// Both sides' fits of one shared edge (the first side's, the second's).
pub(crate) type EdgeFits<F> = (EdgeFit<F>, EdgeFit<F>);

/// The tilt `(v·b)/(v·n)` of a local unit vector `v` toward `b` in the frame `(n, b)` (the
/// shared frame's `g` and `ĝ` or `â`), `None` when `v` is (nearly) perpendicular to `n`.
#[inline(always)]
fn twist_of(v: V3<f64>, n: V3<f64>, b: V3<f64>) -> Option<f64> {
    let den = v.dot(n);
    if !(den > 1e-3) {
        return None;
    }
    let r = v.dot(b) / den;
    if r.is_finite() { Some(r) } else { None }
}

/// Fits a shared edge from its two [`Side`]s (the first runs the edge forwards, the second
/// backwards) and their local geometric normals `na`, `nb` at the nodes: `None` when the
/// endpoints do not coincide, or a sample or the result is not finite.
pub(crate) fn fit_sides<F: Float>(
    fit: &FitMatrix,
    a: &Side<F>,
    na: &[V3<f64>; FIT_SAMPLES],
    b: &Side<F>,
    nb: &[V3<f64>; FIT_SAMPLES],
) -> Option<(EdgeFit<F>, EdgeFit<F>)> {
    let (fa, fb) = (&a.frame, &b.frame);
    let (ea, eb) = (a.shape.edge(a.edge), b.shape.edge(b.edge));
    // The endpoints must coincide (A runs a → b, B runs b → a).
    let (a0, a1) = (fa.local_to_world(ea.a), fa.local_to_world(ea.b));
    let (b0, b1) = (fb.local_to_world(eb.a), fb.local_to_world(eb.b));
    let len = (a1 - a0).length();
    let tol = crate::num::math::sqrt_f64(F::EPSILON.to_f64()) * len;
    if !((a0 - b1).length() <= tol && (a1 - b0).length() <= tol) {
        return None;
    }
    // Where the two sides' vertex normals differ at an end (a per-patch clamp), their frames
    // differ too: each side stores the other's two vertex normals (in its own local frame)
    // and takes for the common normal the average of both sides' interpolated vertex normals.
    let to_a = |v: V3<f64>| fa.world_dir_to_local(fb.local_dir_to_world(v));
    let to_b = |v: V3<f64>| fb.world_dir_to_local(fa.local_dir_to_world(v));
    let (sa, sb) = ((to_a(eb.nb), to_a(eb.na)), (to_b(ea.nb), to_b(ea.na)));
    if (sa.0 - ea.na).length() > FREE_END_TOL || (sa.1 - ea.nb).length() > FREE_END_TOL {
        let side = |(s0, s1): (V3<f64>, V3<f64>)| {
            let mut c = [F::ZERO; TWIST_TERMS];
            for (slot, v) in c.iter_mut().zip([s0.x, s0.y, s0.z, s1.x, s1.y, s1.z]) {
                *slot = F::from_f64(v);
            }
            ([c, [F::ZERO; TWIST_TERMS]], true)
        };
        let (ca, cb) = (side(sa), side(sb));
        let ok = ca.0.iter().chain(cb.0.iter()).flatten().all(|x| x.is_fin());
        return if ok { Some((ca, cb)) } else { None };
    }
    let mut ys = [[0.0f64; FIT_SAMPLES]; 4];
    for (s, (&na, &nb)) in na.iter().zip(nb.iter()).enumerate() {
        let t = fit.nodes.fit_t(s);
        let tb = b.own_t(t);
        let (ga, ba, aa) = shared_frame(&ea, t)?;
        let (gb, bb, ab) = shared_frame(&eb, tb)?;
        let (wa, wb) = (fa.local_dir_to_world(na), fb.local_dir_to_world(nb));
        let m = (wa + wb).try_normalize()?;
        let (ma, mb) = (fa.world_dir_to_local(m), fb.world_dir_to_local(m));
        let vals = [
            twist_of(ma, ga, ba)?,
            twist_of(ma, ga, aa)?,
            twist_of(mb, gb, bb)?,
            twist_of(mb, gb, ab)?,
        ];
        for (y, v) in ys.iter_mut().zip(vals) {
            if let Some(slot) = y.get_mut(s) {
                *slot = v;
            }
        }
    }
    // B's samples lie at its own parameters `1 − t_s = t_{FIT_SAMPLES−1−s}`: reverse them.
    let [ya_c, ya_a, mut yb_c, mut yb_a] = ys;
    yb_c.reverse();
    yb_a.reverse();
    let c = [ya_c, ya_a, yb_c, yb_a].map(|y| fit.coefficients(&y).map(F::from_f64));
    if !c.iter().flatten().all(|x| x.is_fin()) {
        return None;
    }
    let [ca, aa, cb, ab] = c;
    Some((([ca, aa], false), ([cb, ab], false)))
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

/// The points of the three edges seen from barycentrics `x` (edge `j` from `Pj` to `Pj+1`),
/// where the correction takes the patch's own geometric normal: for edge `j` the opposite
/// vertex's weight `xc` moved onto the edge's two in proportion,
/// `y = (xa + xc·xa/s, xb + xc·xb/s, 0)` with `s = xa + xb`, so that on the edge (`xc = 0`) the
/// point is `x` itself, bit for bit, and the correction there is exactly the common normal.
/// Not finite where `s = 0` (at the opposite vertex, where that edge's weight vanishes).
#[inline(always)]
fn edge_points<F: Float>([x0, x1, x2]: [F; 3]) -> [[F; 3]; 3] {
    let z = F::ZERO;
    let moved = |xa: F, xb: F, xc: F| {
        let s = xa + xb;
        (xa + xc * (xa / s), xb + xc * (xb / s))
    };
    let (a0, b0) = moved(x0, x1, x2);
    let (a1, b1) = moved(x1, x2, x0);
    let (a2, b2) = moved(x2, x0, x1);
    [[a0, b0, z], [z, a1, b1], [b2, z, a2]]
}

/// The patch's own geometric normals (local frame) at the three [`edge_points`] of `x`, and
/// its geometric normal at `at` (`x` itself, or the kernel's barycentrics of a hit): four
/// exact normals from one height evaluation over jets of four lanes
/// ([`Prepared::derivatives_x4`], bit for bit four one-point evaluations).
#[inline(always)]
fn own_normals<F: Float>(
    shape: &Shape<F>,
    pr: &Prepared<F>,
    x: [F; 3],
    at: [F; 3],
) -> ([V3<F>; 3], V3<F>) {
    let [y0, y1, y2] = edge_points(x);
    let [d0, d1, d2, dx] = pr.derivatives_x4(shape, [y0, y1, y2, at]);
    let normal = |y: [F; 3], [du1, du2]: [V3<F>; 2]| scalar::normal_local(shape, y, du1, du2);
    (
        [normal(y0, d0), normal(y1, d1), normal(y2, d2)],
        normal(at, dx),
    )
}

impl<F: Float> Seam<F> {
    /// Sets edge `j`'s coefficients.
    fn set(&mut self, j: usize, ([common, along], free): EdgeFit<F>) {
        if let (Some(c), Some(a), Some(f)) = (
            self.common.get_mut(j),
            self.common_along.get_mut(j),
            self.free.get_mut(j),
        ) {
            *c = common;
            *a = along;
            *f = free;
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
            .flatten()
            .all(|&c| c == F::ZERO)
    }

    /// The seamless shading normal of `patch` (the patch this seam was fitted for) at
    /// barycentrics `(w1, w2)` (`w0 = 1 − w1 − w2`; projected onto the triangle like
    /// [`Patch::point_normal`]): the geometric normal corrected toward the common edge normals
    /// (see [`crate::mesh`] for the formula). World coordinates, unit length, oriented like
    /// the vertex normals.
    ///
    /// Equals [`Patch::point_normal`]'s normal bit for bit for a zero seam, is this patch's
    /// vertex normal at the vertices, and on a fitted edge the common edge normal, the same from
    /// both sides to rounding. Work: the geometric normal and this patch's exact normal at the
    /// three edge points `t_j`, in one height evaluation over jets of four lanes (bit for bit
    /// four of the kernel's hit-normal evaluations) and one precomputation, less than
    /// [`Patch::point_normal`] (the repository's instruction-count benchmark,
    /// `seam_shading_teapot4_f32`).
    ///
    /// # Accuracy
    /// Jump across every fitted edge within [`SEAM_JUMP_DEG`](crate::accuracy::SEAM_JUMP_DEG),
    /// where neighbours' edge curves part, next to clamped and folded patches (measured by the
    /// repository's test suite on the teapot, stress meshes and real files). Where a per-patch
    /// clamp moved a vertex normal, the shading normal at that vertex itself is each side's own
    /// (the correction vanishes there): continuous across the edges, not at that point. On a sphere's
    /// patch radial to [`F64_SPHERE_NORMAL`](crate::accuracy::F64_SPHERE_NORMAL) (`f64`) and
    /// [`F32_SPHERE_NORMAL`](crate::accuracy::F32_SPHERE_NORMAL) (`f32`). On the 8×8 torus
    /// within 2.90° of the true normal (the geometric normal: 5.80°; both pinned by the
    /// repository's test suite).
    /// Unit length to [`UNIT_LENGTH_ULPS`](crate::accuracy::UNIT_LENGTH_ULPS) ulps.
    /// # Panics
    /// Never; the result is finite for every accepted patch and any coefficients.
    pub fn shading_normal(&self, patch: &Patch<F>, w1: F, w2: F) -> F::Vec3 {
        let x = project_bary(w1, w2);
        let shape = &patch.shape;
        if self.is_zero() {
            let [_, du1, du2] = scalar::point_derivs_local(shape, x);
            return F::to_glam(
                patch
                    .frame
                    .local_dir_to_world(scalar::normal_local(shape, x, du1, du2)),
            );
        }
        // The kernel's hit normal and the edges' own normals, in one evaluation over four
        // lanes of jets.
        let (own, ng) = own_normals(shape, &Prepared::new(shape), x, x);
        let n = self.correct_local(shape, x, ng, &own).unwrap_or(ng);
        F::to_glam(patch.frame.local_dir_to_world(n))
    }

    /// [`Seam::shading_normal`] from a geometric normal already at hand: `normal` is `patch`'s
    /// geometric normal at `(w1, w2)` (world coordinates, e.g. [`Hit::normal`] with
    /// [`Hit::w1`], [`Hit::w2`]). Saves the derivative evaluation.
    ///
    /// Returns `normal` itself for a zero seam, where the correction vanishes, or where `normal`
    /// is not a finite non-zero vector. Work: the three edge points' exact normals (one
    /// height evaluation over jets of four lanes and one precomputation; the repository's
    /// instruction-count benchmark, `seam_correct_teapot4_f32`).
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
        if self.is_zero() {
            return normal;
        }
        let (own, _) = own_normals(&patch.shape, &Prepared::new(&patch.shape), x, x);
        match self.correct_local(&patch.shape, x, ng, &own) {
            Some(n) => F::to_glam(patch.frame.local_dir_to_world(n)),
            None => normal,
        }
    }

    /// Both normals of a hit on `patch` at the kernel's barycentrics `bary` (a crossing's,
    /// with the patch's `prepared` height evaluation that the crossing carries): the
    /// geometric normal in the local frame, bit for bit the kernel's (the crossing's hit),
    /// and the shading normal in world coordinates, bit for bit [`Seam::correct`] given the
    /// hit's normal. One height evaluation over four lanes of jets serves both (lane four is
    /// the hit's point), where `Bvh::closest_hit` then `correct` take two: a one-point
    /// evaluation for the hit's normal, then one over four lanes for the edge points.
    #[inline(always)]
    pub(crate) fn hit_normals(
        &self,
        patch: &Patch<F>,
        prepared: &Prepared<F>,
        bary: [F; 3],
    ) -> (V3<F>, V3<F>) {
        let shape = &patch.shape;
        let [_, w1, w2] = bary;
        // `correct` takes the hit's projected (w1, w2).
        let x = project_bary(w1, w2);
        let (own, ng_local) = own_normals(shape, prepared, x, bary);
        let world = patch.frame.local_dir_to_world(ng_local);
        // As `correct` receives it: the hit's world normal, back in the local frame.
        let shading = match patch.frame.world_dir_to_local(world).try_normalize() {
            Some(ng) if !self.is_zero() => self
                .correct_local(shape, x, ng, &own)
                .map_or(world, |n| patch.frame.local_dir_to_world(n)),
            _ => world,
        };
        (ng_local, shading)
    }

    /// The corrected local-frame normal at barycentrics `x` (projected) from the geometric one
    /// `ng` and the patch's own normals at the three edge points ([`own_normals`]), or `None`
    /// where the correction vanishes.
    #[inline(always)]
    fn correct_local(
        &self,
        shape: &Shape<F>,
        x: [F; 3],
        ng: V3<F>,
        own: &[V3<F>; 3],
    ) -> Option<V3<F>> {
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
        for (j, (((((qj, (xa, xb)), common), along), &free), &o)) in q
            .iter()
            .zip(pairs)
            .zip(self.common.iter())
            .zip(self.common_along.iter())
            .zip(self.free.iter())
            .zip(own)
            .enumerate()
        {
            if !(*qj > F::ZERO) || (*common == zero && *along == zero) {
                continue;
            }
            let s = xa + xb;
            let t = xb / s;
            let e = shape.edge(j);
            let Some((g, gb, ga)) = shared_frame(&e, t) else {
                continue;
            };
            let m = if free {
                // The neighbour's vertex normals, interpolated, averaged with this side's.
                let [c0, c1, c2, c3, c4, c5, ..] = *common;
                let other = V3::new(c0, c1, c2) * (F::ONE - t) + V3::new(c3, c4, c5) * t;
                other.try_normalize().and_then(|o| (g + o).try_normalize())
            } else {
                (g + gb * twist(common, t) + ga * twist(along, t)).try_normalize()
            };
            let Some(m) = m else {
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
