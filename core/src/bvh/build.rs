//! The builder: binned surface area heuristic splits ([`BINS`] bins per axis), at most
//! [`MAX_LEAF`] boxes per leaf, each node collecting up to [`BVH_WIDTH`] children by splitting
//! its largest child until it has four, depth at most [`MAX_DEPTH`]; caller storage, no
//! allocation, deterministic.

use core::sync::atomic::{AtomicBool, Ordering};

use heapless::Vec as HVec;

use super::error::BvhError;
use super::node::{BVH_EMPTY_SLOT, BVH_STACK, BVH_WIDTH, BvhNode, MAX_DEPTH, MAX_LEAF, axis};
use super::parts::{Merge, SUBTREE_MIN, in_parts, partition, partition_in_parts};
use crate::aabb::Aabb;
use crate::exec::Executor;
use crate::num::real::Float;
use crate::patch::Patch;

/// Number of SAH bins per axis.
pub(super) const BINS: usize = 12;

/// Where the builder reads the box of index `i` (an index taken from `order`, which the
/// builder fills with `0..n` and only permutes: out of range would be a builder bug, reported
/// as [`BvhError::Internal`]).
pub(super) trait Boxes<F: Float> {
    fn count(&self) -> usize;
    fn box_of(&self, i: u32) -> Result<Aabb<F>, BvhError>;
}

impl<F: Float> Boxes<F> for [Patch<F>] {
    fn count(&self) -> usize {
        self.len()
    }
    #[inline(always)]
    fn box_of(&self, i: u32) -> Result<Aabb<F>, BvhError> {
        self.get(i as usize)
            .map(|p| p.bbox)
            .ok_or(BvhError::Internal)
    }
}

impl<F: Float> Boxes<F> for [Aabb<F>] {
    fn count(&self) -> usize {
        self.len()
    }
    #[inline(always)]
    fn box_of(&self, i: u32) -> Result<Aabb<F>, BvhError> {
        self.get(i as usize).copied().ok_or(BvhError::Internal)
    }
}

/// A range of `order` the builder has examined: its boxes, and where it splits (already
/// partitioned) or `None` for a leaf.
#[derive(Clone, Copy)]
pub(super) struct Range<F: Float> {
    pub(super) start: usize,
    pub(super) end: usize,
    /// Binary splits above this range.
    pub(super) depth: usize,
    pub(super) bounds: Aabb<F>,
    pub(super) split: Option<usize>,
}

/// A node to fill from a range that splits.
#[derive(Clone, Copy)]
pub(super) struct Task<F: Float> {
    pub(super) node: usize,
    pub(super) range: Range<F>,
}

/// A range's box and its centroids' box.
#[derive(Clone, Copy)]
struct Extent<F: Float> {
    bounds: Aabb<F>,
    centroids: Aabb<F>,
}

impl<F: Float> Default for Extent<F> {
    fn default() -> Self {
        Extent {
            bounds: Aabb::EMPTY,
            centroids: Aabb::EMPTY,
        }
    }
}

impl<F: Float> Merge for Extent<F> {
    fn merge(&mut self, other: &Self) {
        self.bounds = self.bounds.union(&other.bounds);
        self.centroids = self.centroids.union(&other.centroids);
    }
}

/// The three axes' SAH bins: each bin's count and the union of its boxes.
type Bins<F> = [[(usize, Aabb<F>); BINS]; 3];

impl<F: Float> Merge for Bins<F> {
    fn merge(&mut self, other: &Self) {
        for (axis, theirs) in self.iter_mut().zip(other.iter()) {
            for ((c, b), (oc, ob)) in axis.iter_mut().zip(theirs.iter()) {
                *c += oc;
                *b = b.union(ob);
            }
        }
    }
}

/// Bounds `order[start..end]` (absolute positions; `order` holds the positions from `base`) and
/// decides its split (partitioning it in place): SAH, or the midpoint for ranges too large for
/// a leaf; none for single patches and at the depth limit.
///
/// A range of at least [`PARALLEL_MIN`](super::parts::PARALLEL_MIN) boxes is bounded, binned
/// and partitioned in [`PARTS`](super::parts::PARTS) parts on `executor` (the top of the tree;
/// subtrees pass `&()`); unions of boxes and counts are exact and the partition's order does
/// not depend on the executor, so the result is the one-thread result bit for bit.
pub(super) fn examine<F: Float, B: Boxes<F> + Sync + ?Sized>(
    patches: &B,
    order: &mut [u32],
    base: usize,
    (start, end): (usize, usize),
    depth: usize,
    executor: &impl Executor,
) -> Result<Range<F>, BvhError> {
    // Ranges cover `base ≤ start < end ≤ base + order.len()` by construction (splits are
    // strictly inside).
    let local = start.checked_sub(base).ok_or(BvhError::Internal)?;
    let range = order.get_mut(local..end - base).ok_or(BvhError::Internal)?;
    let (bounds, centroids) = in_parts(range, executor, Extent::default, &|acc, part| {
        for &i in part {
            let b = patches.box_of(i)?;
            acc.bounds = acc.bounds.union(&b);
            acc.centroids = acc.centroids.grow(b.center());
        }
        Ok(())
    })
    .map(|e| (e.bounds, e.centroids))?;
    let count = end - start;
    let split = if count <= 1 || depth + 1 >= MAX_DEPTH {
        None
    } else {
        match sah_split(patches, range, &bounds, &centroids, executor)? {
            Some(m) => Some(m),
            None if count > MAX_LEAF => Some(midpoint_split(patches, range, &centroids)?),
            None => None,
        }
    };
    Ok(Range {
        start,
        end,
        depth,
        bounds,
        split: split.filter(|&m| m > 0 && m < count).map(|m| start + m),
    })
}

/// Number of nodes a tree of `n` boxes may need: `n − 1` for `n ≥ 2` (every node has at least
/// two children, and there are at most `n` leaves), 1 for `n = 1`, 0 for none.
pub(super) const fn nodes_needed(n: usize) -> usize {
    match n {
        0 => 0,
        1 => 1,
        _ => n - 1,
    }
}

/// The most subtrees of one build: a range that would be one more is built with the top of
/// the tree instead. Bounds the task list the builder keeps on its stack.
pub(super) const MAX_SUBTREES: usize = 64;

/// A child range of the top of the tree left for a subtree task: the node and slot that will
/// point to the subtree's root.
#[derive(Clone, Copy)]
struct Deferred<F: Float> {
    parent: usize,
    slot: usize,
    range: Range<F>,
}

/// One subtree task: its root range, the node region it may fill (node `j` of the region is
/// node `base + j` of the tree) and its part of `order`.
struct Subtree<'s, F: Float> {
    nodes: &'s mut [BvhNode<F>],
    base: usize,
    order: &'s mut [u32],
    range: Range<F>,
    used: usize,
    result: Result<(), BvhError>,
}

/// Builds the tree over the non-empty boxes of `patches` into `nodes` and `order` (the body of
/// `BoxBvh::build` and `Bvh::build`; boxes that are empty, or not finite, are left out: no ray
/// can enter them); returns the number of nodes used (at most [`nodes_needed`] of the boxes
/// kept) and of indices (the boxes kept, `order[..m]`).
///
/// In three phases, the same tree for any `executor`: the top of the tree is built on the
/// calling thread down to child ranges of at most `max(m / 32, SUBTREE_MIN)` boxes, which are
/// left for subtrees (at most [`MAX_SUBTREES`]), its ranges of at least
/// [`PARALLEL_MIN`](super::parts::PARALLEL_MIN) boxes bounded, binned and partitioned in
/// [`PARTS`](super::parts::PARTS) parts on the executor; the executor builds the subtrees, each
/// in its
/// own region of `nodes` and its own part of `order`; the regions are then moved together.
/// Every node is split as a build on one thread splits it, so the tree is that build's up to
/// the numbering of its nodes (top first, then each subtree in turn).
pub(super) fn build_tree<F: Float, B: Boxes<F> + Sync + ?Sized>(
    patches: &B,
    nodes: &mut [BvhNode<F>],
    order: &mut [u32],
    executor: &impl Executor,
) -> Result<(usize, usize), BvhError> {
    let total = patches.count();
    if total > u32::MAX as usize / 2 {
        return Err(BvhError::TooManyPatches);
    }
    if order.len() < total {
        return Err(BvhError::StorageTooSmall {
            nodes: nodes_needed(total),
            indices: total,
        });
    }
    let mut n = 0usize;
    for i in 0..total as u32 {
        if !patches.box_of(i)?.is_empty() {
            *order.get_mut(n).ok_or(BvhError::Internal)? = i;
            n += 1;
        }
    }
    if n == 0 {
        return Err(BvhError::EmptyScene);
    }
    let need = nodes_needed(n);
    if nodes.len() < need {
        return Err(BvhError::StorageTooSmall {
            nodes: need,
            indices: total,
        });
    }
    let order = order.get_mut(..n).ok_or(BvhError::Internal)?;
    let root = examine(patches, order, 0, (0, n), 0, executor)?;
    // The top, with its subtrees deferred (none for small trees: one phase).
    let limit = if n > 2 * SUBTREE_MIN {
        (n / 32).max(SUBTREE_MIN)
    } else {
        0
    };
    let mut deferred: HVec<Deferred<F>, MAX_SUBTREES> = HVec::new();
    let mut used = 1usize;
    let top = Task {
        node: 0,
        range: root,
    };
    grow(
        patches,
        nodes,
        0,
        &mut used,
        order,
        0,
        top,
        (limit, &mut deferred),
        executor,
    )?;
    if deferred.is_empty() {
        return Ok((used, n));
    }
    // The subtrees: node regions after the top in deferral order, each as large as its range
    // may need; parts of `order` by position.
    let mut bases = [0usize; MAX_SUBTREES];
    let mut next = used;
    for (b, d) in bases.iter_mut().zip(deferred.iter()) {
        *b = next;
        next += nodes_needed(d.range.end - d.range.start);
    }
    if next > nodes.len() {
        return Err(BvhError::Internal);
    }
    let mut by_start: [usize; MAX_SUBTREES] = core::array::from_fn(|i| i);
    let count = deferred.len();
    let by_start = by_start.get_mut(..count).ok_or(BvhError::Internal)?;
    // Insertion sort of at most MAX_SUBTREES indices by range start.
    for i in 1..count {
        let mut j = i;
        while j > 0 {
            let (Some(&a), Some(&b)) = (by_start.get(j - 1), by_start.get(j)) else {
                break;
            };
            let (Some(da), Some(db)) = (deferred.get(a), deferred.get(b)) else {
                break;
            };
            if da.range.start <= db.range.start {
                break;
            }
            if let Some([x, y]) = by_start.get_mut(j - 1..=j) {
                core::mem::swap(x, y);
            }
            j -= 1;
        }
    }
    let mut parts: [Option<&mut [u32]>; MAX_SUBTREES] = core::array::from_fn(|_| None);
    let (mut rest, mut at) = (&mut *order, 0usize);
    for &d in by_start.iter() {
        let r = deferred.get(d).ok_or(BvhError::Internal)?.range;
        let (_, tail) = rest
            .split_at_mut_checked(r.start.checked_sub(at).ok_or(BvhError::Internal)?)
            .ok_or(BvhError::Internal)?;
        let (part, tail) = tail
            .split_at_mut_checked(r.end - r.start)
            .ok_or(BvhError::Internal)?;
        *parts.get_mut(d).ok_or(BvhError::Internal)? = Some(part);
        rest = tail;
        at = r.end;
    }
    let (_, mut free) = nodes.split_at_mut_checked(used).ok_or(BvhError::Internal)?;
    let mut tasks: HVec<Subtree<'_, F>, MAX_SUBTREES> = HVec::new();
    for ((d, base), part) in deferred.iter().zip(bases).zip(parts.iter_mut()) {
        let size = nodes_needed(d.range.end - d.range.start);
        let (region, tail) = free.split_at_mut_checked(size).ok_or(BvhError::Internal)?;
        free = tail;
        let task = Subtree {
            nodes: region,
            base,
            order: part.take().ok_or(BvhError::Internal)?,
            range: d.range,
            used: 1,
            result: Ok(()),
        };
        if tasks.push(task).is_err() {
            return Err(BvhError::Internal);
        }
    }
    executor.run_chunks(&mut tasks, 1, &|_, chunk| {
        for t in chunk.iter_mut() {
            let root = Task {
                node: 0,
                range: t.range,
            };
            let start = t.range.start;
            t.result = grow(
                patches,
                t.nodes,
                t.base,
                &mut t.used,
                t.order,
                start,
                root,
                (0, &mut HVec::new()),
                &(),
            );
        }
    });
    // Each subtree's nodes moved down to follow the previous one, its node children renumbered,
    // and its parent's slot pointed at its root.
    let mut results: HVec<(usize, usize), MAX_SUBTREES> = HVec::new();
    for task in tasks.iter() {
        task.result?;
        results
            .push((task.base, task.used))
            .map_err(|_| BvhError::Internal)?;
    }
    drop(tasks);
    let mut at = used;
    for ((old, count), d) in results.into_iter().zip(deferred.iter()) {
        if old != at {
            // Down by `old − at` (the regions only move down): each node read before it can be
            // overwritten.
            for i in 0..count {
                let node = *nodes.get(old + i).ok_or(BvhError::Internal)?;
                *nodes.get_mut(at + i).ok_or(BvhError::Internal)? = node;
            }
            let shift = (old - at) as u32;
            for node in nodes.get_mut(at..at + count).ok_or(BvhError::Internal)? {
                for k in 0..BVH_WIDTH {
                    if node.count(k) == 0 && node.child(k) != BVH_EMPTY_SLOT {
                        *node.child.get_mut(k).ok_or(BvhError::Internal)? -= shift;
                    }
                }
            }
        }
        let parent = nodes.get_mut(d.parent).ok_or(BvhError::Internal)?;
        *parent.child.get_mut(d.slot).ok_or(BvhError::Internal)? = at as u32;
        at += count;
    }
    Ok((at, n))
}

/// Fills the nodes of the tree below `root` (a node whose range is examined), depth first:
/// each node's children, by splitting its range, then the child of largest area (then most
/// boxes) that splits, until there are four; a child that still splits becomes a node, unless a
/// leaf holds it. `nodes` is the region of node indices from `base` (node `base + j` at `j`),
/// `*used` the region's nodes in use; `order` holds the positions from `order_base`. With
/// `limit > 0`, a child node of at most `limit` boxes is left to `deferred` (its slot to be
/// pointed at its subtree's root), while the list has room. Large ranges are bounded, binned
/// and partitioned on `executor` ([`examine`]).
#[allow(clippy::too_many_arguments)]
fn grow<F: Float, B: Boxes<F> + Sync + ?Sized>(
    patches: &B,
    nodes: &mut [BvhNode<F>],
    base: usize,
    used: &mut usize,
    order: &mut [u32],
    order_base: usize,
    root: Task<F>,
    (limit, deferred): (usize, &mut HVec<Deferred<F>, MAX_SUBTREES>),
    executor: &impl Executor,
) -> Result<(), BvhError> {
    // Depth first; each node leaves at most three pending siblings per level. A root that
    // does not split becomes one leaf, like any range that does not.
    let mut stack: HVec<Task<F>, { BVH_STACK + BVH_WIDTH }> = HVec::new();
    stack.push(root).map_err(|_| BvhError::Internal)?;
    while let Some(Task { node, range }) = stack.pop() {
        let mut kids: HVec<Range<F>, BVH_WIDTH> = HVec::new();
        kids.push(range).map_err(|_| BvhError::Internal)?;
        while kids.len() < BVH_WIDTH {
            let mut pick: Option<(usize, F, usize)> = None;
            for (k, c) in kids.iter().enumerate() {
                let (area, count) = (c.bounds.half_area(), c.end - c.start);
                if c.split.is_some()
                    && pick.is_none_or(|(_, a, n)| area > a || (area == a && count > n))
                {
                    pick = Some((k, area, count));
                }
            }
            let Some((k, ..)) = pick else { break };
            let c = *kids.get(k).ok_or(BvhError::Internal)?;
            let mid = c.split.ok_or(BvhError::Internal)?;
            let depth = c.depth + 1;
            let left = examine(patches, order, order_base, (c.start, mid), depth, executor)?;
            let right = examine(patches, order, order_base, (mid, c.end), depth, executor)?;
            *kids.get_mut(k).ok_or(BvhError::Internal)? = left;
            kids.insert(k + 1, right).map_err(|_| BvhError::Internal)?;
        }
        let mut out = BvhNode::default();
        let mut tasks: HVec<Task<F>, BVH_WIDTH> = HVec::new();
        for (k, c) in kids.iter().enumerate() {
            out.set_box(k, &c.bounds);
            // A range that still splits becomes a child node, unless a leaf holds it: a
            // node of a few leaves costs a visit more than testing those patches (each
            // test starts with its own box).
            let (child, count) = if c.split.is_some() && c.end - c.start > MAX_LEAF {
                let later = Deferred {
                    parent: base + node,
                    slot: k,
                    range: *c,
                };
                if c.end - c.start <= limit && deferred.push(later).is_ok() {
                    (BVH_EMPTY_SLOT, 0)
                } else {
                    let at = *used;
                    *used += 1;
                    tasks
                        .push(Task {
                            node: at,
                            range: *c,
                        })
                        .map_err(|_| BvhError::Internal)?;
                    ((base + at) as u32, 0)
                }
            } else {
                (c.start as u32, (c.end - c.start) as u32)
            };
            *out.child.get_mut(k).ok_or(BvhError::Internal)? = child;
            *out.count.get_mut(k).ok_or(BvhError::Internal)? = count;
        }
        *nodes.get_mut(node).ok_or(BvhError::Internal)? = out;
        // Push in reverse so the first child is built next.
        while let Some(t) = tasks.pop() {
            stack.push(t).map_err(|_| BvhError::StackOverflow)?;
        }
    }
    Ok(())
}

/// Recomputes the child boxes of every node in use from the boxes of `patches` (the tree's
/// structure and `order` unchanged: a refit); returns the tree's cost ([`tree_cost`]). The
/// leaf slots first, on `executor` in ranges of nodes (each slot's box a union of its
/// patches' boxes: the bulk of the work), then the inner slots children before parents (a
/// node's children follow it) on the calling thread. Work: one box union per index of `order`
/// and per node slot; the boxes are the same whatever the executor (unions are exact).
pub(super) fn refit<F: Float, B: Boxes<F> + Sync + ?Sized>(
    patches: &B,
    nodes: &mut [BvhNode<F>],
    order: &[u32],
    executor: &impl Executor,
) -> Result<f64, BvhError> {
    let corrupt = AtomicBool::new(false);
    executor.run_chunks(nodes, 64, &|_, chunk| {
        for node in chunk.iter_mut() {
            if refit_leaves(patches, node, order).is_err() {
                corrupt.store(true, Ordering::Relaxed);
            }
        }
    });
    if corrupt.load(Ordering::Relaxed) {
        return Err(BvhError::CorruptTree);
    }
    for i in (0..nodes.len()).rev() {
        let mut node = *nodes.get(i).ok_or(BvhError::Internal)?;
        for k in 0..BVH_WIDTH {
            let (child, count) = (node.child(k), node.count(k));
            if child == BVH_EMPTY_SLOT || count > 0 {
                continue;
            }
            let c = child as usize;
            if c <= i {
                return Err(BvhError::CorruptTree);
            }
            let sub = nodes.get(c).ok_or(BvhError::CorruptTree)?;
            let mut b = Aabb::EMPTY;
            for s in 0..BVH_WIDTH {
                if sub.child(s) != BVH_EMPTY_SLOT {
                    b = b.union(&sub.bounds(s));
                }
            }
            node.set_box(k, &b);
        }
        *nodes.get_mut(i).ok_or(BvhError::Internal)? = node;
    }
    Ok(tree_cost(nodes))
}

/// Sets the box of each leaf slot of `node` (a slot with patches) to the union of its
/// patches' boxes; inner slots are left as they are.
#[inline]
fn refit_leaves<F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
    node: &mut BvhNode<F>,
    order: &[u32],
) -> Result<(), BvhError> {
    for k in 0..BVH_WIDTH {
        let (child, count) = (node.child(k), node.count(k));
        if child == BVH_EMPTY_SLOT || count == 0 {
            continue;
        }
        let first = child as usize;
        let ids = order
            .get(first..first + count as usize)
            .ok_or(BvhError::CorruptTree)?;
        let mut b = Aabb::EMPTY;
        for &id in ids {
            b = b.union(&patches.box_of(id)?);
        }
        node.set_box(k, &b);
    }
    Ok(())
}

/// The tree's cost by the surface area heuristic, relative to its root's box: each slot's
/// half area times what a ray entering it tests (one node, or the leaf's boxes), summed and
/// divided by the root's half area (`+∞` for a root of no area). Compared across refits to
/// decide when a refitted tree has degraded enough to rebuild.
pub(super) fn tree_cost<F: Float>(nodes: &[BvhNode<F>]) -> f64 {
    let Some(root) = nodes.first() else {
        return 0.0;
    };
    let mut root_box = Aabb::EMPTY;
    for k in 0..BVH_WIDTH {
        if root.child(k) != BVH_EMPTY_SLOT {
            root_box = root_box.union(&root.bounds(k));
        }
    }
    let mut sum = 0.0f64;
    for node in nodes {
        for k in 0..BVH_WIDTH {
            if node.child(k) == BVH_EMPTY_SLOT {
                continue;
            }
            let weight = f64::from(node.count(k).max(1));
            sum += node.bounds(k).half_area().to_f64() * weight;
        }
    }
    let area = root_box.half_area().to_f64();
    if area > 0.0 {
        sum / area
    } else {
        f64::INFINITY
    }
}

/// Bin index of a centroid coordinate.
#[inline(always)]
pub(super) fn bin_of<F: Float>(c: F, cmin: F, scale: F) -> usize {
    let b = ((c - cmin) * scale).to_f64();
    if b >= 0.0 {
        (b as usize).min(BINS - 1)
    } else {
        0
    }
}

/// Binned SAH split of `range` (reordered in place); returns the split position, or `None` when
/// a leaf is cheaper or no binning separates the centroids.
pub(super) fn sah_split<F: Float, B: Boxes<F> + Sync + ?Sized>(
    patches: &B,
    range: &mut [u32],
    bounds: &Aabb<F>,
    centroids: &Aabb<F>,
    executor: &impl Executor,
) -> Result<Option<usize>, BvhError> {
    let count = range.len();
    // Per axis with extent: the centroids' minimum and the bins per unit.
    let frames: [Option<(F, F)>; 3] = core::array::from_fn(|k| {
        let (cmin, cmax) = (axis(centroids.lo, k), axis(centroids.hi, k));
        let ext = cmax - cmin;
        (ext > F::ZERO).then(|| (cmin, F::from_f64(BINS as f64) / ext))
    });
    // All three axes' bins in one pass over the patches' boxes.
    let empty: fn() -> Bins<F> = || [[(0usize, Aabb::<F>::EMPTY); BINS]; 3];
    let bins = in_parts(range, executor, empty, &|bins, part| {
        for &i in part {
            let b = patches.box_of(i)?;
            let center = b.center();
            for (k, (frame, bins)) in frames.iter().zip(bins.iter_mut()).enumerate() {
                if let Some((cmin, scale)) = *frame {
                    let (c, bb) = bins
                        .get_mut(bin_of(axis(center, k), cmin, scale))
                        .ok_or(BvhError::Internal)?;
                    *c += 1;
                    *bb = bb.union(&b);
                }
            }
        }
        Ok(())
    })?;
    // (cost, axis, first bin of the right side, cmin, scale)
    let mut best: Option<(F, usize, usize, F, F)> = None;
    for (k, (frame, bins)) in frames.iter().zip(bins.iter()).enumerate() {
        let Some((cmin, scale)) = *frame else {
            continue;
        };
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
    partition_in_parts(range, executor, &|i| {
        Ok(bin_of(axis(patches.box_of(i)?.center(), k), cmin, scale) < s)
    })
    .map(Some)
}

/// Midpoint split: partitions `range` at the middle of the widest axis of the centroids' box
/// (when SAH finds no split of a large range). When every centroid falls on one side (e.g. all
/// equal), the range is cut in halves by position instead.
pub(super) fn midpoint_split<F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
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
    let m = partition(range, |i| Ok(axis(patches.box_of(i)?.center(), k) < mid))?;
    Ok(if m == 0 || m == range.len() {
        range.len() / 2
    } else {
        m
    })
}
