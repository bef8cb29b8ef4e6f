//! The builder: binned surface area heuristic splits ([`BINS`] bins per axis), at most
//! [`MAX_LEAF`] boxes per leaf, each node collecting up to [`BVH_WIDTH`] children by splitting
//! its largest child until it has four, depth at most [`MAX_DEPTH`]; caller storage, no
//! allocation, deterministic.

use heapless::Vec as HVec;

use super::error::BvhError;
use super::node::{BVH_STACK, BVH_WIDTH, BvhNode, MAX_DEPTH, MAX_LEAF, axis};
use crate::aabb::Aabb;
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

/// Bounds `order[start..end]` and decides its split (partitioning it in place): SAH, or the
/// midpoint for ranges too large for a leaf; none for single patches and at the depth limit.
pub(super) fn examine<F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
    order: &mut [u32],
    start: usize,
    end: usize,
    depth: usize,
) -> Result<Range<F>, BvhError> {
    // Ranges cover `start < end ≤ n` by construction (splits are strictly inside).
    let range = order.get_mut(start..end).ok_or(BvhError::Internal)?;
    let mut bounds = Aabb::EMPTY;
    let mut centroids = Aabb::EMPTY;
    for &i in range.iter() {
        let b = patches.box_of(i)?;
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

/// Builds the tree over the boxes of `patches` into `nodes` and `order` (the body of
/// `BoxBvh::build` and `Bvh::build`); returns the number of nodes used (at most
/// [`nodes_needed`]).
pub(super) fn build_tree<F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
    nodes: &mut [BvhNode<F>],
    order: &mut [u32],
) -> Result<usize, BvhError> {
    let n = patches.count();
    if n == 0 {
        return Err(BvhError::EmptyScene);
    }
    if n > u32::MAX as usize / 2 {
        return Err(BvhError::TooManyPatches);
    }
    let need = nodes_needed(n);
    if nodes.len() < need || order.len() < n {
        return Err(BvhError::StorageTooSmall {
            nodes: need,
            indices: n,
        });
    }
    for (i, o) in order.iter_mut().enumerate().take(n) {
        *o = i as u32;
    }
    let root = examine(patches, order, 0, n, 0)?;
    let mut used = 1usize;
    // Depth first; each node leaves at most three pending siblings per level. A root that
    // does not split becomes one leaf, like any range that does not.
    let mut stack: HVec<Task<F>, { BVH_STACK + BVH_WIDTH }> = HVec::new();
    stack
        .push(Task {
            node: 0,
            range: root,
        })
        .map_err(|_| BvhError::Internal)?;
    while let Some(Task { node, range }) = stack.pop() {
        // The node's children: split the range, then keep splitting the child of largest
        // area (then most patches) that splits, until there are four.
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
            let left = examine(patches, order, c.start, mid, c.depth + 1)?;
            let right = examine(patches, order, mid, c.end, c.depth + 1)?;
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
                let at = used;
                used += 1;
                tasks
                    .push(Task {
                        node: at,
                        range: *c,
                    })
                    .map_err(|_| BvhError::Internal)?;
                (at as u32, 0)
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
    Ok(used)
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
pub(super) fn sah_split<F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
    range: &mut [u32],
    bounds: &Aabb<F>,
    centroids: &Aabb<F>,
) -> Result<Option<usize>, BvhError> {
    let count = range.len();
    // Per axis with extent: the centroids' minimum and the bins per unit.
    let frames: [Option<(F, F)>; 3] = core::array::from_fn(|k| {
        let (cmin, cmax) = (axis(centroids.lo, k), axis(centroids.hi, k));
        let ext = cmax - cmin;
        (ext > F::ZERO).then(|| (cmin, F::from_f64(BINS as f64) / ext))
    });
    // All three axes' bins in one pass over the patches' boxes.
    let mut bins = [[(0usize, Aabb::<F>::EMPTY); BINS]; 3];
    for &i in range.iter() {
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
    partition(range, |i| {
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

/// In-place partition; returns the number of elements satisfying `pred` (moved to the front).
pub(super) fn partition(
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
