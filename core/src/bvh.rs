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
//! patches themselves (216 bytes each).

use heapless::Vec as HVec;

use crate::kernel::clip::aabb_interval;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};
use crate::real::Float;
use crate::vec::V3;

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
    /// The traversal visited more nodes than the tree has (storage not made by [`Bvh::build`]).
    CorruptTree,
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
            BvhError::CorruptTree => {
                f.write_str("BVH storage is corrupt (a node is reached twice)")
            }
        }
    }
}

impl core::error::Error for BvhError {}

/// One BVH node: a box and either two children (`count == 0`, children at `first` and
/// `first + 1`) or a leaf of `count` patches (`order[first..first + count]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<F: Float> {
    lo: V3<F>,
    hi: V3<F>,
    first: u32,
    count: u32,
}

impl<F: Float> Default for BvhNode<F> {
    fn default() -> Self {
        BvhNode {
            lo: V3::zero(),
            hi: V3::zero(),
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
fn vmin<F: Float>(a: V3<F>, b: V3<F>) -> V3<F> {
    V3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z))
}
#[inline(always)]
fn vmax<F: Float>(a: V3<F>, b: V3<F>) -> V3<F> {
    V3::new(a.x.max(b.x), a.y.max(b.y), a.z.max(b.z))
}
#[inline(always)]
fn axis<F: Float>(v: V3<F>, k: usize) -> F {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}
#[inline(always)]
fn half_area<F: Float>(lo: V3<F>, hi: V3<F>) -> F {
    let e = hi - lo;
    if e.x < F::ZERO {
        return F::ZERO;
    }
    e.x * e.y + e.y * e.z + e.z * e.x
}
fn empty_box<F: Float>() -> (V3<F>, V3<F>) {
    (
        V3::new(F::MAX, F::MAX, F::MAX),
        V3::new(-F::MAX, -F::MAX, -F::MAX),
    )
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
        let centroid = |i: u32| -> V3<F> {
            patches.get(i as usize).map_or(V3::zero(), |p| {
                let [lo, hi] = p.bbox;
                (lo + hi) * F::from_f64(0.5)
            })
        };
        let pbox = |i: u32| -> (V3<F>, V3<F>) {
            patches.get(i as usize).map_or(empty_box(), |p| {
                let [lo, hi] = p.bbox;
                (lo, hi)
            })
        };
        let mut used = 1usize;
        let mut stack: HVec<Task, MAX_DEPTH> = HVec::new();
        // Depth-first: the stack holds at most one pending sibling per level.
        let _ = stack.push(Task {
            node: 0,
            start: 0,
            end: n,
            depth: 0,
        });
        while let Some(task) = stack.pop() {
            let Task {
                node,
                start,
                end,
                depth,
            } = task;
            let Some(range) = order.get_mut(start..end) else {
                break;
            };
            let (mut lo, mut hi) = empty_box::<F>();
            let (mut clo, mut chi) = empty_box::<F>();
            for &i in range.iter() {
                let (a, b) = pbox(i);
                lo = vmin(lo, a);
                hi = vmax(hi, b);
                let c = centroid(i);
                clo = vmin(clo, c);
                chi = vmax(chi, c);
            }
            let count = end - start;
            let make_leaf = count <= 1 || depth + 1 >= MAX_DEPTH;
            let split = if make_leaf {
                None
            } else {
                sah_split(range, lo, hi, clo, chi, &centroid, &pbox)
            };
            let split = match split {
                Some(m) => Some(m),
                None if !make_leaf && count > MAX_LEAF => {
                    Some(median_split(range, clo, chi, &centroid))
                }
                None => None,
            };
            let Some(slot) = nodes.get_mut(node) else {
                break;
            };
            match split {
                Some(mid) if mid > 0 && mid < count => {
                    let left = used;
                    used += 2;
                    *slot = BvhNode {
                        lo,
                        hi,
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
                        lo,
                        hi,
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
            nodes: nodes.get(..used).unwrap_or(nodes),
            order: order.get(..n).unwrap_or(order),
        })
    }

    /// Re-wraps storage filled by an earlier [`Bvh::build`] over the same patches (for owners
    /// that keep the storage in their own structures). Storage not made by `build` gives wrong
    /// answers or [`BvhError::StackOverflow`], never a panic.
    pub fn from_parts(patches: &'a [Patch<F>], nodes: &'a [BvhNode<F>], order: &'a [u32]) -> Self {
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

    /// Bytes used by the nodes and indices (not the patches).
    pub fn memory_bytes(&self) -> usize {
        core::mem::size_of_val(self.nodes) + core::mem::size_of_val(self.order)
    }

    /// Closest hit of `ray` in `[t_min, t_max]` using the smooth kernel with `N` iterations;
    /// `hit.feature` is the patch's index in the slice given to [`Bvh::build`].
    ///
    /// # Accuracy
    /// As [`Patch::intersect`]; the result equals a brute-force loop over all patches.
    /// # Panics
    /// Never.
    pub fn closest_hit<const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Result<Option<Hit<F>>, BvhError> {
        self.closest_with(ray, t_min, t_max, |p, a, b| p.intersect::<N>(ray, a, b))
    }

    /// Whether anything is hit in `[t_min, t_max]` (shadow rays): stops at the first hit.
    ///
    /// # Panics
    /// Never.
    pub fn any_hit<const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Result<bool, BvhError> {
        let mut found = false;
        self.traverse(ray, t_min, t_max, true, &mut |p, _, a, b| {
            let h = p.intersect::<N>(ray, a, b);
            found |= h.is_some();
            h
        })?;
        Ok(found)
    }

    /// Closest hit with a caller-supplied per-patch test `test(patch, t_min, t_max)` (for
    /// example the flat or Phong baselines of [`crate::kernel::flat`] on the patch's vertices,
    /// which lie inside the patch's box). The returned hit's `feature` is set to the patch index.
    ///
    /// # Panics
    /// Never (unless `test` panics).
    pub fn closest_with(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        mut test: impl FnMut(&Patch<F>, F, F) -> Option<Hit<F>>,
    ) -> Result<Option<Hit<F>>, BvhError> {
        self.traverse(ray, t_min, t_max, false, &mut |p, _, a, b| test(p, a, b))
    }

    fn traverse(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        any: bool,
        test: &mut impl FnMut(&Patch<F>, u32, F, F) -> Option<Hit<F>>,
    ) -> Result<Option<Hit<F>>, BvhError> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() || t_min.is_nan() || t_max.is_nan() {
            return Ok(None);
        }
        let mut best: Option<Hit<F>> = None;
        let mut tmax = t_max;
        let mut stack: HVec<u32, MAX_DEPTH> = HVec::new();
        let enter = |node: &BvhNode<F>, tmax: F| aabb_interval(o, d, node.lo, node.hi, t_min, tmax);
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
            let Some(node) = self.nodes.get(current as usize) else {
                break;
            };
            if node.count > 0 {
                let first = node.first as usize;
                let ids = self
                    .order
                    .get(first..first + node.count as usize)
                    .unwrap_or(&[]);
                for &id in ids {
                    // Each patch is tested over the caller's whole range, then compared with the
                    // best so far: the kernel's first sign change depends on its interval, so
                    // shortening it to the best `t` could skip a closer crossing pair.
                    if let Some(p) = self.patches.get(id as usize)
                        && let Some(mut h) = test(p, id, t_min, t_max)
                        && (best.is_none() || h.t < tmax)
                    {
                        h.feature = id;
                        tmax = h.t;
                        best = Some(h);
                        if any {
                            return Ok(best);
                        }
                    }
                }
            } else {
                let l = node.first;
                let r = node.first + 1;
                let tl = self.nodes.get(l as usize).and_then(|n| enter(n, tmax));
                let tr = self.nodes.get(r as usize).and_then(|n| enter(n, tmax));
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
            // Pop the next node still worth visiting.
            let mut next = None;
            while let Some(c) = stack.pop() {
                if self
                    .nodes
                    .get(c as usize)
                    .and_then(|n| enter(n, tmax))
                    .is_some()
                {
                    next = Some(c);
                    break;
                }
            }
            match next {
                Some(c) => current = c,
                None => break,
            }
        }
        Ok(best)
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
/// a leaf is cheaper.
fn sah_split<F: Float>(
    range: &mut [u32],
    lo: V3<F>,
    hi: V3<F>,
    clo: V3<F>,
    chi: V3<F>,
    centroid: &impl Fn(u32) -> V3<F>,
    pbox: &impl Fn(u32) -> (V3<F>, V3<F>),
) -> Option<usize> {
    let count = range.len();
    // (cost, axis, first bin of the right side, cmin, scale)
    let mut best: Option<(F, usize, usize, F, F)> = None;
    for k in 0..3 {
        let (cmin, cmax) = (axis(clo, k), axis(chi, k));
        let ext = cmax - cmin;
        if !(ext > F::ZERO) {
            continue;
        }
        let scale = F::from_f64(BINS as f64) / ext;
        let mut bins = [(0usize, empty_box::<F>()); BINS];
        for &i in range.iter() {
            let b = bin_of(axis(centroid(i), k), cmin, scale);
            if let Some((c, (blo, bhi))) = bins.get_mut(b) {
                let (a, z) = pbox(i);
                *c += 1;
                *blo = vmin(*blo, a);
                *bhi = vmax(*bhi, z);
            }
        }
        // Prefix sweep from the left: count and area of bins [0, s].
        let mut left = [(0usize, F::ZERO); BINS];
        let (mut n, (mut bl, mut bh)) = (0usize, empty_box::<F>());
        for (slot, (c, (a, z))) in left.iter_mut().zip(bins.iter()) {
            n += c;
            bl = vmin(bl, *a);
            bh = vmax(bh, *z);
            *slot = (n, half_area(bl, bh));
        }
        // Suffix sweep from the right; a split puts bins [s, BINS) on the right.
        let (mut n, (mut bl, mut bh)) = (0usize, empty_box::<F>());
        for s in (1..BINS).rev() {
            if let Some((c, (a, z))) = bins.get(s) {
                n += c;
                bl = vmin(bl, *a);
                bh = vmax(bh, *z);
            }
            if let Some(&(nl, al)) = left.get(s - 1)
                && nl > 0
                && n > 0
            {
                let cost = al * F::from_f64(nl as f64) + half_area(bl, bh) * F::from_f64(n as f64);
                if best.is_none_or(|(c, ..)| cost < c) {
                    best = Some((cost, k, s, cmin, scale));
                }
            }
        }
    }
    let (cost, k, s, cmin, scale) = best?;
    // Leaf cost: every patch tested against every ray reaching the node (traversal cost ≈ one
    // box test per child is small beside a patch test).
    let leaf = half_area(lo, hi) * F::from_f64(count as f64);
    if count <= MAX_LEAF && !(cost < leaf) {
        return None;
    }
    Some(partition(range, |i| {
        bin_of(axis(centroid(i), k), cmin, scale) < s
    }))
}

/// Median split along the widest centroid axis (when SAH finds no split of a large range,
/// e.g. all centroids equal): the range is split in halves by position.
fn median_split<F: Float>(
    range: &mut [u32],
    clo: V3<F>,
    chi: V3<F>,
    centroid: &impl Fn(u32) -> V3<F>,
) -> usize {
    let e = chi - clo;
    let k = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = clo + e * F::from_f64(0.5);
    let m = partition(range, |i| axis(centroid(i), k) < axis(mid, k));
    if m == 0 || m == range.len() {
        range.len() / 2
    } else {
        m
    }
}

/// In-place partition; returns the number of elements satisfying `pred` (moved to the front).
fn partition(range: &mut [u32], pred: impl Fn(u32) -> bool) -> usize {
    let mut m = 0usize;
    for j in 0..range.len() {
        if let Some((head, tail)) = range.split_at_mut_checked(j)
            && let Some(x) = tail.first_mut()
            && pred(*x)
        {
            if let Some(y) = head.get_mut(m) {
                core::mem::swap(x, y);
            }
            m += 1;
        }
    }
    m
}
