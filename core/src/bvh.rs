//! A bounding volume hierarchy over patches, usable without `std` or `alloc`.
//!
//! Built by [`Bvh::build`] into caller-provided storage (binned surface area heuristic, 12 bins,
//! at most [`MAX_LEAF`] patches per leaf, depth at most [`MAX_DEPTH`]); traversed with a
//! fixed-size stack (`heapless`) of [`MAX_DEPTH`] entries, which the depth bound makes
//! sufficient. Should it ever not be (corrupted storage handed to [`Bvh::from_parts`]), the
//! query returns [`BvhError::StackOverflow`], never a panic or a silent miss.
//!
//! Memory: one [`BvhNode`] is 32 bytes in `f32` (56 in `f64`); a BVH of `n` patches uses at most
//! `2n − 1` nodes and `n` `u32` indices: at most 68 bytes per patch in `f32`, besides the
//! patches themselves (228 bytes each).

use heapless::Vec as HVec;

use crate::aabb::Aabb;
use crate::kernel::{self, Crossing, DEFAULT_SAMPLES, KernelStats};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};

/// Maximum tree depth guaranteed by the builder (and size of the traversal stack).
pub const MAX_DEPTH: usize = 64;
/// Maximum number of patches per leaf, except at [`MAX_DEPTH`] where a leaf takes what is left.
pub const MAX_LEAF: usize = 4;
/// Number of SAH bins per axis.
const BINS: usize = 12;

/// Why a BVH could not be built or traversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhError {
    /// No patches.
    EmptyScene,
    /// The node storage holds fewer than `2n − 1` nodes or the index storage fewer than `n`.
    StorageTooSmall {
        /// Nodes needed.
        nodes: usize,
        /// Indices needed.
        indices: usize,
    },
    /// More patches than `u32` can index.
    TooManyPatches,
    /// The traversal stack would overflow (only possible with storage not made by
    /// [`Bvh::build`]).
    StackOverflow,
    /// The traversal visited more nodes than the tree has, or a node or index points outside
    /// the storage (storage not made by [`Bvh::build`]).
    CorruptTree,
    /// An invariant of the builder failed. Not expected for any input: it would be a bug in
    /// this crate (reported as an error rather than a panic or a silently wrong tree).
    Internal,
}

impl core::fmt::Display for BvhError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BvhError::EmptyScene => f.write_str("empty scene: no patches"),
            BvhError::StorageTooSmall { nodes, indices } => {
                write!(
                    f,
                    "BVH storage too small: need {nodes} nodes and {indices} indices"
                )
            }
            BvhError::TooManyPatches => f.write_str("more patches than u32 can index"),
            BvhError::StackOverflow => f.write_str("BVH traversal stack overflow"),
            BvhError::CorruptTree => f.write_str(
                "BVH storage is corrupt (a node is reached twice or points outside the storage)",
            ),
            BvhError::Internal => f.write_str("internal error of the BVH builder (a bug)"),
        }
    }
}

impl core::error::Error for BvhError {}

/// One BVH node: a box and either two children (`count == 0`, children at `first` and
/// `first + 1`) or a leaf of `count` patches (`order[first..first + count]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<F: Float> {
    bounds: Aabb<F>,
    first: u32,
    count: u32,
}

impl<F: Float> BvhNode<F> {
    /// A node from its parts, for owners that store trees themselves (serialised, uploaded and
    /// read back): an interior node (`count == 0`) with children `first` and `first + 1`, or a
    /// leaf of `order[first..first + count]`. [`Bvh::from_parts`] checks what they make.
    ///
    /// # Panics
    /// Never.
    pub fn new(bounds: Aabb<F>, first: u32, count: u32) -> Self {
        BvhNode {
            bounds,
            first,
            count,
        }
    }

    /// The node's box (the union of its patches' shell boxes).
    ///
    /// # Panics
    /// Never.
    pub fn bounds(&self) -> Aabb<F> {
        self.bounds
    }

    /// Interior node: index of the first child (the second is `first + 1`). Leaf: start of
    /// its range in [`Bvh::order`].
    ///
    /// # Panics
    /// Never.
    pub fn first(&self) -> u32 {
        self.first
    }

    /// Number of patches of a leaf (at most [`MAX_LEAF`]); 0 for an interior node.
    ///
    /// # Panics
    /// Never.
    pub fn count(&self) -> u32 {
        self.count
    }
}

impl<F: Float> Default for BvhNode<F> {
    /// A placeholder for storage that [`Bvh::build`] fills (an interior node with an empty box;
    /// a BVH made of default nodes is reported as [`BvhError::CorruptTree`] by queries).
    fn default() -> Self {
        BvhNode {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        }
    }
}

/// A BVH over a slice of patches, borrowing its storage.
#[derive(Clone, Copy, Debug)]
pub struct Bvh<'a, F: Float> {
    patches: &'a [Patch<F>],
    nodes: &'a [BvhNode<F>],
    order: &'a [u32],
}

#[derive(Clone, Copy)]
struct Task {
    node: usize,
    start: usize,
    end: usize,
    depth: usize,
}

#[inline(always)]
fn axis<F: Float>(v: V3<F>, k: usize) -> F {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// The box of patch `i` (an index taken from `order`, which the builder fills with `0..n` and
/// only permutes: out of range would be a builder bug, reported as [`BvhError::Internal`]).
#[inline(always)]
fn patch_box<F: Float>(patches: &[Patch<F>], i: u32) -> Result<Aabb<F>, BvhError> {
    patches
        .get(i as usize)
        .map(|p| p.bbox)
        .ok_or(BvhError::Internal)
}

impl<'a, F: Float> Bvh<'a, F> {
    /// Number of nodes needed to build over `n` patches (`2n − 1`).
    pub const fn nodes_needed(n: usize) -> usize {
        if n == 0 { 0 } else { 2 * n - 1 }
    }

    /// Builds a BVH over `patches` into `nodes` (at least [`Bvh::nodes_needed`]`(n)` long)
    /// and `order` (at least `n` long).
    ///
    /// Returns the BVH, or [`BvhError::EmptyScene`], [`BvhError::StorageTooSmall`],
    /// [`BvhError::TooManyPatches`]. Work: `O(n log n)`; no allocation.
    /// # Panics
    /// Never.
    pub fn build(
        patches: &'a [Patch<F>],
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
    ) -> Result<Self, BvhError> {
        let n = patches.len();
        if n == 0 {
            return Err(BvhError::EmptyScene);
        }
        if n > u32::MAX as usize / 2 {
            return Err(BvhError::TooManyPatches);
        }
        let need = Self::nodes_needed(n);
        if nodes.len() < need || order.len() < n {
            return Err(BvhError::StorageTooSmall {
                nodes: need,
                indices: n,
            });
        }
        for (i, o) in order.iter_mut().enumerate().take(n) {
            *o = i as u32;
        }
        let mut used = 1usize;
        let mut stack: HVec<Task, MAX_DEPTH> = HVec::new();
        // Depth-first: the stack holds at most one pending sibling per level.
        stack
            .push(Task {
                node: 0,
                start: 0,
                end: n,
                depth: 0,
            })
            .map_err(|_| BvhError::Internal)?;
        while let Some(task) = stack.pop() {
            let Task {
                node,
                start,
                end,
                depth,
            } = task;
            // Tasks cover `start < end ≤ n` by construction (splits are strictly inside).
            let range = order.get_mut(start..end).ok_or(BvhError::Internal)?;
            let mut bounds = Aabb::EMPTY;
            let mut centroids = Aabb::EMPTY;
            for &i in range.iter() {
                let b = patch_box(patches, i)?;
                bounds = bounds.union(&b);
                centroids = centroids.grow(b.center());
            }
            let count = end - start;
            let split = if count <= 1 || depth + 1 >= MAX_DEPTH {
                None
            } else {
                match sah_split(patches, range, &bounds, &centroids)? {
                    Some(m) => Some(m),
                    None if count > MAX_LEAF => Some(midpoint_split(patches, range, &centroids)?),
                    None => None,
                }
            };
            let slot = nodes.get_mut(node).ok_or(BvhError::Internal)?;
            match split {
                Some(mid) if mid > 0 && mid < count => {
                    let left = used;
                    used += 2;
                    *slot = BvhNode {
                        bounds,
                        first: left as u32,
                        count: 0,
                    };
                    // Push the larger child first so the smaller is built next (bounded stack).
                    let l = Task {
                        node: left,
                        start,
                        end: start + mid,
                        depth: depth + 1,
                    };
                    let r = Task {
                        node: left + 1,
                        start: start + mid,
                        end,
                        depth: depth + 1,
                    };
                    if stack.push(r).is_err() || stack.push(l).is_err() {
                        return Err(BvhError::StackOverflow);
                    }
                }
                _ => {
                    *slot = BvhNode {
                        bounds,
                        first: start as u32,
                        count: count as u32,
                    };
                }
            }
        }
        let nodes: &'a [BvhNode<F>] = nodes;
        let order: &'a [u32] = order;
        Ok(Bvh {
            patches,
            // A binary tree over n leaves-worth of patches has at most 2n − 1 nodes ≤ len.
            nodes: nodes.get(..used).ok_or(BvhError::Internal)?,
            order: order.get(..n).ok_or(BvhError::Internal)?,
        })
    }

    /// Re-wraps storage filled by an earlier [`Bvh::build`] over the same patches (for owners
    /// that keep the storage in their own structures, or upload and read it back), after
    /// checking it once: every node and leaf range inside the storage, children after their
    /// parent (so the tree has no cycle), depth below [`MAX_DEPTH`], every index below
    /// `patches.len()`. Queries on the result then cannot fail.
    ///
    /// Returns [`BvhError::EmptyScene`] (no node or no patch), [`BvhError::CorruptTree`] or
    /// [`BvhError::StackOverflow`] (too deep). Storage that passes but was not made by `build`
    /// over these patches gives wrong answers, never a panic. Work: `O(nodes)`.
    /// # Panics
    /// Never.
    pub fn from_parts(
        patches: &'a [Patch<F>],
        nodes: &'a [BvhNode<F>],
        order: &'a [u32],
    ) -> Result<Self, BvhError> {
        validate(patches.len(), nodes, order)?;
        Ok(Self::from_built(patches, nodes, order))
    }

    /// Wraps storage that [`Bvh::build`] filled (no check).
    pub(crate) fn from_built(
        patches: &'a [Patch<F>],
        nodes: &'a [BvhNode<F>],
        order: &'a [u32],
    ) -> Self {
        Bvh {
            patches,
            nodes,
            order,
        }
    }

    /// Number of nodes in use.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The patches.
    pub fn patches(&self) -> &'a [Patch<F>] {
        self.patches
    }

    /// The nodes (node 0 is the root; see [`BvhNode`] for the layout), for uploading the tree.
    ///
    /// # Panics
    /// Never.
    pub fn nodes(&self) -> &'a [BvhNode<F>] {
        self.nodes
    }

    /// The patch indices that leaves refer to (`order[first..first + count]`).
    ///
    /// # Panics
    /// Never.
    pub fn order(&self) -> &'a [u32] {
        self.order
    }

    /// Bytes used by the nodes and indices (not the patches).
    pub fn memory_bytes(&self) -> usize {
        core::mem::size_of_val(self.nodes) + core::mem::size_of_val(self.order)
    }

    /// Closest hit of `ray` in `[t_min, t_max]` using the smooth kernel with `N` iterations;
    /// `hit.patch` is the patch's index in the slice given to [`Bvh::build`].
    ///
    /// # Accuracy
    /// As [`Patch::intersect`]; the result equals a brute-force loop over all patches.
    /// # Panics
    /// Never.
    pub fn closest_hit<const N: usize>(&self, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        // Candidates are compared by their crossings; the normal is evaluated once, for the
        // closest (it is finite for every accepted patch, so this equals testing each patch
        // with `Patch::intersect`).
        let (id, c) = self.closest_crossing::<N>(ray, t_min, t_max)?;
        let mut h = kernel::finish(self.patches.get(id as usize)?, ray, &c)?;
        h.patch = id;
        Some(h)
    }

    /// The closest crossing of [`Bvh::closest_hit`] before its normal is evaluated: the
    /// patch's index and where the ray crosses it.
    pub(crate) fn closest_crossing<const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<(u32, Crossing<F>)> {
        let mut stats = KernelStats::default();
        self.traverse(ray, t_min, t_max, false, &mut |p, a, b| {
            kernel::crossing::<F, DEFAULT_SAMPLES, N>(p, ray, a, b, &mut stats)
        })
        .ok()?
    }

    /// Whether anything is hit in `[t_min, t_max]` (shadow rays): stops at the first hit.
    ///
    /// # Panics
    /// Never.
    pub fn any_hit<const N: usize>(&self, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        let mut stats = KernelStats::default();
        let first = self.traverse(ray, t_min, t_max, true, &mut |p, a, b| {
            kernel::crossing::<F, DEFAULT_SAMPLES, N>(p, ray, a, b, &mut stats)
        });
        matches!(first, Ok(Some(_)))
    }

    /// Closest hit with a caller-supplied per-patch test `test(patch, t_min, t_max)` (for
    /// example the flat or Phong baselines of [`flat_hit`](crate::flat_hit) on the patch's vertices,
    /// which lie inside the patch's box). The returned hit's `patch` is set to the patch index.
    ///
    /// # Panics
    /// Never (unless `test` panics).
    pub fn closest_with(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        mut test: impl FnMut(&Patch<F>, F, F) -> Option<Hit<F>>,
    ) -> Option<Hit<F>> {
        let (id, mut h) = self.traverse(ray, t_min, t_max, false, &mut test).ok()??;
        h.patch = id;
        Some(h)
    }

    /// Visits the patches whose boxes the ray enters, nearest box first, testing each with
    /// `test` over the caller's range; returns the candidate with the smallest `t` and its
    /// patch index (with `any`, the first candidate found).
    fn traverse<C: Candidate<F>>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        any: bool,
        test: &mut impl FnMut(&Patch<F>, F, F) -> Option<C>,
    ) -> Result<Option<(u32, C)>, BvhError> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() || t_min.is_nan() || t_max.is_nan() {
            return Ok(None);
        }
        let mut best: Option<(u32, C)> = None;
        let mut tmax = t_max;
        let mut stack: HVec<u32, MAX_DEPTH> = HVec::new();
        // Every node index and leaf range comes from the storage: for storage made by `build`
        // they are always valid; anything else is `CorruptTree`, never a skipped subtree.
        let node_at = |i: u32| self.nodes.get(i as usize).ok_or(BvhError::CorruptTree);
        let enter = |node: &BvhNode<F>, tmax: F| node.bounds.ray_interval(o, d, t_min, tmax);
        let Some(root) = self.nodes.first() else {
            return Ok(None);
        };
        if enter(root, tmax).is_none() {
            return Ok(None);
        }
        let mut current = 0u32;
        // A tree visits each node at most once: the budget bounds the work even for corrupted
        // storage handed to `from_parts`.
        let mut budget = self.nodes.len();
        loop {
            if budget == 0 {
                return Err(BvhError::CorruptTree);
            }
            budget -= 1;
            let node = node_at(current)?;
            if node.count > 0 {
                let first = node.first as usize;
                let ids = self
                    .order
                    .get(first..first.saturating_add(node.count as usize))
                    .ok_or(BvhError::CorruptTree)?;
                for &id in ids {
                    let p = self.patches.get(id as usize).ok_or(BvhError::CorruptTree)?;
                    // Each patch is tested over the caller's whole range, then compared with the
                    // best so far: the kernel's first sign change depends on its interval, so
                    // shortening it to the best `t` could skip a closer crossing pair.
                    if let Some(h) = test(p, t_min, t_max)
                        && (best.is_none() || h.t() < tmax)
                    {
                        tmax = h.t();
                        best = Some((id, h));
                        if any {
                            return Ok(best);
                        }
                    }
                }
            } else {
                let l = node.first;
                let r = node.first.checked_add(1).ok_or(BvhError::CorruptTree)?;
                let tl = enter(node_at(l)?, tmax);
                let tr = enter(node_at(r)?, tmax);
                match (tl, tr) {
                    (Some((a, _)), Some((b, _))) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        if stack.push(far).is_err() {
                            return Err(BvhError::StackOverflow);
                        }
                        current = near;
                        continue;
                    }
                    (Some(_), None) => {
                        current = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        current = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next node still worth visiting (the best hit may have moved closer since
            // it was pushed).
            let mut next = None;
            while let Some(c) = stack.pop() {
                if enter(node_at(c)?, tmax).is_some() {
                    next = Some(c);
                    break;
                }
            }
            match next {
                Some(c) => current = c,
                None => return Ok(best),
            }
        }
    }
}

/// The checks of [`Bvh::from_parts`]: a depth-first walk from the root with the traversal's
/// stack, each node visited once.
fn validate<F: Float>(patches: usize, nodes: &[BvhNode<F>], order: &[u32]) -> Result<(), BvhError> {
    if nodes.is_empty() || patches == 0 {
        return Err(BvhError::EmptyScene);
    }
    let mut stack: HVec<(u32, usize), MAX_DEPTH> = HVec::new();
    let mut current = (0u32, 0usize);
    let mut budget = nodes.len();
    loop {
        let (i, depth) = current;
        if budget == 0 {
            return Err(BvhError::CorruptTree);
        }
        budget -= 1;
        let node = nodes.get(i as usize).ok_or(BvhError::CorruptTree)?;
        if node.count > 0 {
            let first = node.first as usize;
            let ids = order
                .get(first..first.saturating_add(node.count as usize))
                .ok_or(BvhError::CorruptTree)?;
            if ids.iter().any(|&id| id as usize >= patches) {
                return Err(BvhError::CorruptTree);
            }
        } else {
            let l = node.first;
            let r = l.checked_add(1).ok_or(BvhError::CorruptTree)?;
            if l <= i || r as usize >= nodes.len() {
                return Err(BvhError::CorruptTree);
            }
            if depth + 1 >= MAX_DEPTH {
                return Err(BvhError::StackOverflow);
            }
            stack
                .push((r, depth + 1))
                .map_err(|_| BvhError::StackOverflow)?;
            current = (l, depth + 1);
            continue;
        }
        match stack.pop() {
            Some(next) => current = next,
            None => return Ok(()),
        }
    }
}

/// What the traversal compares: anything with a ray parameter.
trait Candidate<F> {
    fn t(&self) -> F;
}

impl<F: Float> Candidate<F> for Hit<F> {
    #[inline(always)]
    fn t(&self) -> F {
        self.t
    }
}

impl<F: Float> Candidate<F> for Crossing<F> {
    #[inline(always)]
    fn t(&self) -> F {
        self.t
    }
}

/// Bin index of a centroid coordinate.
#[inline(always)]
fn bin_of<F: Float>(c: F, cmin: F, scale: F) -> usize {
    let b = ((c - cmin) * scale).to_f64();
    if b >= 0.0 {
        (b as usize).min(BINS - 1)
    } else {
        0
    }
}

/// Binned SAH split of `range` (reordered in place); returns the split position, or `None` when
/// a leaf is cheaper or no binning separates the centroids.
fn sah_split<F: Float>(
    patches: &[Patch<F>],
    range: &mut [u32],
    bounds: &Aabb<F>,
    centroids: &Aabb<F>,
) -> Result<Option<usize>, BvhError> {
    let count = range.len();
    // (cost, axis, first bin of the right side, cmin, scale)
    let mut best: Option<(F, usize, usize, F, F)> = None;
    for k in 0..3 {
        let (cmin, cmax) = (axis(centroids.lo, k), axis(centroids.hi, k));
        let ext = cmax - cmin;
        if !(ext > F::ZERO) {
            continue;
        }
        let scale = F::from_f64(BINS as f64) / ext;
        let mut bins = [(0usize, Aabb::<F>::EMPTY); BINS];
        for &i in range.iter() {
            let b = patch_box(patches, i)?;
            let (c, bb) = bins
                .get_mut(bin_of(axis(b.center(), k), cmin, scale))
                .ok_or(BvhError::Internal)?;
            *c += 1;
            *bb = bb.union(&b);
        }
        // Prefix sweep from the left: count and area of bins [0, s].
        let mut left = [(0usize, F::ZERO); BINS];
        let (mut n, mut acc) = (0usize, Aabb::<F>::EMPTY);
        for (slot, (c, b)) in left.iter_mut().zip(bins.iter()) {
            n += c;
            acc = acc.union(b);
            *slot = (n, acc.half_area());
        }
        // Suffix sweep from the right; a split puts bins [s, BINS) on the right.
        let (mut n, mut acc) = (0usize, Aabb::<F>::EMPTY);
        for s in (1..BINS).rev() {
            let (c, b) = bins.get(s).ok_or(BvhError::Internal)?;
            n += c;
            acc = acc.union(b);
            let &(nl, al) = left.get(s - 1).ok_or(BvhError::Internal)?;
            if nl > 0 && n > 0 {
                let cost = al * F::from_f64(nl as f64) + acc.half_area() * F::from_f64(n as f64);
                if best.is_none_or(|(c, ..)| cost < c) {
                    best = Some((cost, k, s, cmin, scale));
                }
            }
        }
    }
    let Some((cost, k, s, cmin, scale)) = best else {
        return Ok(None);
    };
    // Leaf cost: every patch tested against every ray reaching the node (traversal cost ≈ one
    // box test per child is small beside a patch test).
    let leaf = bounds.half_area() * F::from_f64(count as f64);
    if count <= MAX_LEAF && !(cost < leaf) {
        return Ok(None);
    }
    partition(range, |i| {
        Ok(bin_of(axis(patch_box(patches, i)?.center(), k), cmin, scale) < s)
    })
    .map(Some)
}

/// Midpoint split: partitions `range` at the middle of the widest axis of the centroids' box
/// (when SAH finds no split of a large range). When every centroid falls on one side (e.g. all
/// equal), the range is cut in halves by position instead.
fn midpoint_split<F: Float>(
    patches: &[Patch<F>],
    range: &mut [u32],
    centroids: &Aabb<F>,
) -> Result<usize, BvhError> {
    let e = centroids.hi - centroids.lo;
    let k = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = axis(centroids.center(), k);
    let m = partition(
        range,
        |i| Ok(axis(patch_box(patches, i)?.center(), k) < mid),
    )?;
    Ok(if m == 0 || m == range.len() {
        range.len() / 2
    } else {
        m
    })
}

/// In-place partition; returns the number of elements satisfying `pred` (moved to the front).
fn partition(
    range: &mut [u32],
    pred: impl Fn(u32) -> Result<bool, BvhError>,
) -> Result<usize, BvhError> {
    let mut m = 0usize;
    for j in 0..range.len() {
        // j < len: the split and `tail`'s first element always exist.
        let (head, tail) = range.split_at_mut_checked(j).ok_or(BvhError::Internal)?;
        let x = tail.first_mut().ok_or(BvhError::Internal)?;
        if pred(*x)? {
            // m ≤ j: for m < j swap with the first element not satisfying `pred`; for m = j
            // the element is already in place.
            if let Some(y) = head.get_mut(m) {
                core::mem::swap(x, y);
            }
            m += 1;
        }
    }
    Ok(m)
}
