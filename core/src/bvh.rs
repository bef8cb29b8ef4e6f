//! A four-wide bounding volume hierarchy over patches, usable without `std` or `alloc`.
//!
//! The tree itself, [`BoxBvh`], knows only boxes: it is built over any slice of
//! [`Aabb`]s and traversed with a caller's leaf test ([`BoxBvh::closest_with`],
//! [`BoxBvh::any_with`]), so other primitives (flat triangles, other curved patches) are traced
//! with the same builder and traversal. [`Bvh`] is that tree over the patches' boxes with the
//! smooth kernel in its leaves.
//!
//! Built by [`Bvh::build`] (or [`BoxBvh::build`]) into caller-provided storage: binned surface area heuristic (12
//! bins) splits, at most [`MAX_LEAF`] patches per leaf, each node collecting up to
//! [`BVH_WIDTH`] children by splitting its largest child until it has four (as Embree's and
//! tinybvh's wide builders do), split depth at most [`MAX_DEPTH`]. A node stores its children's
//! boxes side by side ([`BvhNode`]), so the traversal tests all four slabs in one four-lane
//! operation (`wide::f32x4` or `f64x4`), visits the children that the ray enters nearest first,
//! and keeps pending children on a fixed-size stack (`heapless`) of [`BVH_STACK`] entries, which
//! the depth bound makes sufficient. Should it ever not be (corrupted storage handed to
//! [`Bvh::from_parts`]), the query returns [`BvhError::StackOverflow`], never a panic or a
//! silent miss.
//!
//! Memory: one [`BvhNode`] is 128 bytes in `f32` (224 in `f64`); a BVH of `n ≥ 2` patches uses
//! at most `n − 1` nodes ([`Bvh::nodes_needed`]; about `n / 8` in practice: leaves of two to four
//! patches in nodes of four children) and `n` `u32` indices.

use heapless::Vec as HVec;

use crate::aabb::Aabb;
use crate::kernel::{self, Crossing, DEFAULT_SAMPLES, KernelStats, WorldRay};
use crate::num::real::{Float, Lane4, LaneOps};
use crate::num::vec::V3;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};
use crate::surface::lanes::Prepared;

/// Children per node: four boxes tested in one four-lane step.
pub const BVH_WIDTH: usize = 4;
/// Maximum depth of the builder's binary splits (a node's children are at least one split
/// deeper than the node, so the tree has fewer than `MAX_DEPTH` levels of nodes).
pub const MAX_DEPTH: usize = 64;
/// Entries of the traversal stack: a node at depth `w` leaves at most `BVH_WIDTH − 1` pending
/// children per ancestor and pushes at most `BVH_WIDTH`, and nodes lie at depth at most
/// `MAX_DEPTH − 2` (their ranges split further), so `3 (MAX_DEPTH − 2) + 4 ≤ 3 MAX_DEPTH`.
pub const BVH_STACK: usize = (BVH_WIDTH - 1) * MAX_DEPTH;
/// The child index of an unused slot of a [`BvhNode`] (its count is 0 and its box empty).
pub const BVH_EMPTY_SLOT: u32 = u32::MAX;
/// Maximum number of patches per leaf, except at [`MAX_DEPTH`] where a leaf takes what is left.
pub const MAX_LEAF: usize = 4;
/// Number of SAH bins per axis.
const BINS: usize = 12;

/// Why a BVH could not be built or traversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhError {
    /// No patches.
    EmptyScene,
    /// The node storage holds fewer than [`Bvh::nodes_needed`] nodes or the index storage
    /// fewer than `n`.
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
    /// The traversal visited more nodes or tested more patches than the tree has, or a node or
    /// index points outside the storage (storage not made by [`Bvh::build`]).
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

/// One BVH node: the boxes of up to [`BVH_WIDTH`] children side by side (structure of arrays,
/// one four-lane load per coordinate), and for each slot `k` either a child node
/// (`count(k) == 0`, node index `child(k)`, always after this node), a leaf of `count(k)`
/// patches (`order[child(k)..child(k) + count(k)]`), or nothing (`child(k) ==`
/// [`BVH_EMPTY_SLOT`], count 0, empty box).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<F: Float> {
    /// `lo[axis][slot]`.
    lo: [[F; BVH_WIDTH]; 3],
    /// `hi[axis][slot]`.
    hi: [[F; BVH_WIDTH]; 3],
    child: [u32; BVH_WIDTH],
    count: [u32; BVH_WIDTH],
}

impl<F: Float> BvhNode<F> {
    /// A node from its slots, for owners that store trees themselves (serialised, uploaded and
    /// read back): slot `k` has the box `bounds[k]`, and `child[k]`, `count[k]` as described on
    /// [`BvhNode`]. [`Bvh::from_parts`] checks what they make.
    ///
    /// # Panics
    /// Never.
    pub fn new(
        bounds: [Aabb<F>; BVH_WIDTH],
        child: [u32; BVH_WIDTH],
        count: [u32; BVH_WIDTH],
    ) -> Self {
        let mut node = BvhNode {
            lo: [[F::ZERO; BVH_WIDTH]; 3],
            hi: [[F::ZERO; BVH_WIDTH]; 3],
            child,
            count,
        };
        for (k, b) in bounds.iter().enumerate() {
            node.set_box(k, b);
        }
        node
    }

    fn set_box(&mut self, k: usize, b: &Aabb<F>) {
        for (a, (l, h)) in [(b.lo.x, b.hi.x), (b.lo.y, b.hi.y), (b.lo.z, b.hi.z)]
            .into_iter()
            .enumerate()
        {
            if let Some(s) = self.lo.get_mut(a).and_then(|r| r.get_mut(k)) {
                *s = l;
            }
            if let Some(s) = self.hi.get_mut(a).and_then(|r| r.get_mut(k)) {
                *s = h;
            }
        }
    }

    /// The box of slot `k` (the union of its patches' shell boxes; [`Aabb::EMPTY`] for an
    /// unused slot or `k ≥` [`BVH_WIDTH`]).
    ///
    /// # Panics
    /// Never.
    pub fn bounds(&self, k: usize) -> Aabb<F> {
        let at = |m: &[[F; BVH_WIDTH]; 3], a: usize, e: F| {
            m.get(a).and_then(|r| r.get(k)).copied().unwrap_or(e)
        };
        if k >= BVH_WIDTH {
            return Aabb::EMPTY;
        }
        Aabb::from_corners(
            V3::new(
                at(&self.lo, 0, F::MAX),
                at(&self.lo, 1, F::MAX),
                at(&self.lo, 2, F::MAX),
            ),
            V3::new(
                at(&self.hi, 0, F::MIN),
                at(&self.hi, 1, F::MIN),
                at(&self.hi, 2, F::MIN),
            ),
        )
    }

    /// Slot `k`: the child node's index (count 0), the start of the leaf's range in
    /// [`Bvh::order`] (count > 0), or [`BVH_EMPTY_SLOT`] (unused, or `k ≥` [`BVH_WIDTH`]).
    ///
    /// # Panics
    /// Never.
    pub fn child(&self, k: usize) -> u32 {
        self.child.get(k).copied().unwrap_or(BVH_EMPTY_SLOT)
    }

    /// Slot `k`: the number of patches of a leaf (at most [`MAX_LEAF`] except at the depth
    /// limit); 0 for a child node or an unused slot.
    ///
    /// # Panics
    /// Never.
    pub fn count(&self, k: usize) -> u32 {
        self.count.get(k).copied().unwrap_or(0)
    }
}

impl<F: Float> Default for BvhNode<F> {
    /// A node of unused slots: the placeholder for storage that [`Bvh::build`] fills (a BVH of
    /// default nodes finds nothing).
    fn default() -> Self {
        BvhNode {
            lo: [[F::MAX; BVH_WIDTH]; 3],
            hi: [[F::MIN; BVH_WIDTH]; 3],
            child: [BVH_EMPTY_SLOT; BVH_WIDTH],
            count: [0; BVH_WIDTH],
        }
    }
}

/// A BVH over a slice of patches, borrowing its storage: a [`BoxBvh`] over the patches'
/// boxes ([`Patch::bbox`]) with the smooth kernel in its leaves.
#[derive(Clone, Copy, Debug)]
pub struct Bvh<'a, F: Float> {
    patches: &'a [Patch<F>],
    tree: BoxBvh<'a, F>,
}

/// A four-wide BVH over a slice of boxes, borrowing its storage (the nodes and the order of
/// the box indices; the boxes themselves are not kept: the nodes hold them). What a leaf holds
/// is the caller's: [`BoxBvh::closest_with`] and [`BoxBvh::any_with`] call the caller's test
/// with the index of each box the ray reaches, as Embree's user geometries do.
#[derive(Clone, Copy, Debug)]
pub struct BoxBvh<'a, F: Float> {
    nodes: &'a [BvhNode<F>],
    order: &'a [u32],
}

/// Where the builder reads the box of index `i` (an index taken from `order`, which the
/// builder fills with `0..n` and only permutes: out of range would be a builder bug, reported
/// as [`BvhError::Internal`]).
trait Boxes<F: Float> {
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
struct Range<F: Float> {
    start: usize,
    end: usize,
    /// Binary splits above this range.
    depth: usize,
    bounds: Aabb<F>,
    split: Option<usize>,
}

/// A node to fill from a range that splits.
#[derive(Clone, Copy)]
struct Task<F: Float> {
    node: usize,
    range: Range<F>,
}

/// A pending entry of the traversal: a node (`count == 0`) or a leaf, and where the ray enters
/// its box.
#[derive(Clone, Copy)]
struct Pending<F> {
    child: u32,
    count: u32,
    t: F,
}

#[inline(always)]
fn axis<F: Float>(v: V3<F>, k: usize) -> F {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// Bounds `order[start..end]` and decides its split (partitioning it in place): SAH, or the
/// midpoint for ranges too large for a leaf; none for single patches and at the depth limit.
fn examine<F: Float, B: Boxes<F> + ?Sized>(
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

/// The four lanes of `x` (`F::L4` where it carries four values).
#[inline(always)]
fn lanes<F: Float>(x: [F; BVH_WIDTH]) -> F::L4 {
    <F::L4 as Lane4>::from_array4(x)
}

/// The ray as the slab test uses it: per axis the origin, `1/d`, and how the axis is tested.
#[derive(Clone, Copy)]
struct SlabRay<F: Float> {
    o: [F; 3],
    inv: [F; 3],
    /// 0: slabs with `inv`; 1: `d = 0` on this axis, the origin must lie between the planes
    /// (as the kernel's clip); 2: `1/d` is not finite (a subnormal `d`): the axis is not
    /// tested, which keeps the test conservative.
    mode: [u8; 3],
}

impl<F: Float> SlabRay<F> {
    fn new(o: V3<F>, d: V3<F>) -> Self {
        let inv = crate::aabb::reciprocal(d);
        let (o, d, inv) = ([o.x, o.y, o.z], [d.x, d.y, d.z], [inv.x, inv.y, inv.z]);
        let mode = core::array::from_fn(|a| {
            let (c, i) = (d.get(a).copied(), inv.get(a).copied());
            match (c, i) {
                (Some(c), _) if c == F::ZERO => 1,
                (_, Some(i)) if i.is_fin() => 0,
                _ => 2,
            }
        });
        SlabRay { o, inv, mode }
    }

    /// Which slots of `node` the ray enters within `[t_min, t_max]` (bit `k` for slot `k`) and
    /// where it enters each. Conservative with respect to the kernel's clip to a patch's box
    /// (`Aabb::ray_interval`, the same `(plane − o) · (1/d)` per axis): a node's box contains its
    /// patches' boxes, these products are monotone in the plane, and no finiteness is required
    /// here, so every patch whose box the kernel enters lies in a slot reported here.
    #[inline(always)]
    fn enter(&self, node: &BvhNode<F>, t_min: F, t_max: F) -> (u32, [F; BVH_WIDTH]) {
        // The used slots, in one four-lane compare of the child indices.
        let empty = wide::u32x4::new(node.child).simd_eq(wide::u32x4::splat(BVH_EMPTY_SLOT));
        let used = !empty.to_bitmask() & 0b1111;
        if <F::L4 as Lane4>::POINTS == BVH_WIDTH {
            let (hit, near) = self.slabs(&node.lo, &node.hi, t_min, t_max);
            return (used & hit, near);
        }
        // `F::L4` carries one value: the same arithmetic once per slot, the slot moved first.
        let mut hit = 0u32;
        let mut near = [t_min; BVH_WIDTH];
        for (k, t) in near.iter_mut().enumerate() {
            // Lane `j` takes slot `k + j` (mod 4); every index is in range.
            let first = |m: &[[F; BVH_WIDTH]; 3]| {
                m.map(|r| {
                    core::array::from_fn(|j| r.get((k + j) % BVH_WIDTH).copied().unwrap_or(F::ZERO))
                })
            };
            let (h, a) = self.slabs(&first(&node.lo), &first(&node.hi), t_min, t_max);
            hit |= (h & 1) << k;
            *t = a.first().copied().unwrap_or(t_min);
        }
        (used & hit, near)
    }

    /// The slab test of [`SlabRay::enter`] over the lanes of `F::L4`: the lanes the ray
    /// enters (bit per lane) and where it enters each.
    #[inline(always)]
    fn slabs(
        &self,
        lo: &[[F; BVH_WIDTH]; 3],
        hi: &[[F; BVH_WIDTH]; 3],
        t_min: F,
        t_max: F,
    ) -> (u32, [F; BVH_WIDTH]) {
        let mut a = F::L4::splat(t_min);
        let mut b = F::L4::splat(t_max);
        let mut inside = u32::MAX;
        for ((((lo, hi), &o), &inv), &mode) in lo
            .iter()
            .zip(hi)
            .zip(&self.o)
            .zip(&self.inv)
            .zip(&self.mode)
        {
            match mode {
                0 => {
                    // `(plane − o)·(1/d)` is monotone in the plane, increasing where `1/d > 0`,
                    // so the sign picks the near and the far plane (for a box with `lo ≤ hi`;
                    // an empty box, `lo > hi`, is not entered). No NaN can occur (finite
                    // planes, origin and `1/d`), so the one-instruction max and min are exact.
                    let (near, far) = if inv > F::ZERO { (lo, hi) } else { (hi, lo) };
                    let (o, inv) = (F::L4::splat(o), F::L4::splat(inv));
                    a = ((lanes::<F>(*near) - o) * inv).max_fast(a);
                    b = ((lanes::<F>(*far) - o) * inv).min_fast(b);
                }
                1 => {
                    let (lo, hi) = (lanes::<F>(*lo), lanes::<F>(*hi));
                    let o = F::L4::splat(o);
                    inside &= <F::L4 as Lane4>::bits4(F::L4::and(lo.le(o), o.le(hi)));
                }
                _ => {}
            }
        }
        (inside & <F::L4 as Lane4>::bits4(a.le(b)), a.to_array4())
    }
}

/// Builds the tree over the boxes of `boxes` into `nodes` and `order` (the body of
/// [`BoxBvh::build`] and [`Bvh::build`]).
fn build_tree<'a, F: Float, B: Boxes<F> + ?Sized>(
    patches: &B,
    nodes: &'a mut [BvhNode<F>],
    order: &'a mut [u32],
) -> Result<BoxBvh<'a, F>, BvhError> {
    let n = patches.count();
    if n == 0 {
        return Err(BvhError::EmptyScene);
    }
    if n > u32::MAX as usize / 2 {
        return Err(BvhError::TooManyPatches);
    }
    let need = BoxBvh::<F>::nodes_needed(n);
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
    let nodes: &'a [BvhNode<F>] = nodes;
    let order: &'a [u32] = order;
    Ok(BoxBvh {
        // At most `nodes_needed(n)` nodes are used (see there).
        nodes: nodes.get(..used).ok_or(BvhError::Internal)?,
        order: order.get(..n).ok_or(BvhError::Internal)?,
    })
}

impl<'a, F: Float> BoxBvh<'a, F> {
    /// Number of nodes [`BoxBvh::build`] may need for `n` boxes: `n − 1` for `n ≥ 2` (every
    /// node has at least two children, and there are at most `n` leaves), 1 for `n = 1`, 0
    /// for none. Trees use far fewer (about `n / 8`); [`BoxBvh::node_count`] says how many.
    pub const fn nodes_needed(n: usize) -> usize {
        match n {
            0 => 0,
            1 => 1,
            _ => n - 1,
        }
    }

    /// Builds a BVH over `boxes` into `nodes` (at least [`BoxBvh::nodes_needed`]`(n)` long)
    /// and `order` (at least `n` long): the same binned-SAH builder as [`Bvh::build`], which
    /// over the patches' boxes gives the same nodes and order as [`Bvh::build`] over the
    /// patches.
    ///
    /// The boxes should be finite (a non-finite or empty box gives a valid tree whose
    /// queries may skip that index). Returns the BVH, or [`BvhError::EmptyScene`],
    /// [`BvhError::StorageTooSmall`], [`BvhError::TooManyPatches`]. Work: `O(n log n)`; no
    /// allocation. Deterministic: the same boxes give the same nodes and order.
    /// # Panics
    /// Never.
    pub fn build(
        boxes: &[Aabb<F>],
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
    ) -> Result<Self, BvhError> {
        build_tree(boxes, nodes, order)
    }

    /// Re-wraps storage filled by an earlier [`BoxBvh::build`] over `count` boxes, after the
    /// checks of [`Bvh::from_parts`] (every index below `count`). Queries on the result then
    /// cannot fail. Returns [`BvhError::EmptyScene`] (no node, `count` 0),
    /// [`BvhError::CorruptTree`] or [`BvhError::StackOverflow`] (too deep). Work: `O(nodes)`.
    /// # Panics
    /// Never.
    pub fn from_parts(
        count: usize,
        nodes: &'a [BvhNode<F>],
        order: &'a [u32],
    ) -> Result<Self, BvhError> {
        validate(count, nodes, order)?;
        Ok(BoxBvh { nodes, order })
    }

    /// Number of nodes in use.
    ///
    /// # Panics
    /// Never.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nodes (node 0 is the root; see [`BvhNode`] for the layout).
    ///
    /// # Panics
    /// Never.
    pub fn nodes(&self) -> &'a [BvhNode<F>] {
        self.nodes
    }

    /// The box indices that leaves refer to (`order[child..child + count]`).
    ///
    /// # Panics
    /// Never.
    pub fn order(&self) -> &'a [u32] {
        self.order
    }

    /// Bytes used by the nodes and indices.
    ///
    /// # Panics
    /// Never.
    pub fn memory_bytes(&self) -> usize {
        core::mem::size_of_val(self.nodes) + core::mem::size_of_val(self.order)
    }

    /// Closest hit with the caller's leaf test `test(index, t_min, t_max)`, `index` the box's
    /// index in the slice given to [`BoxBvh::build`]: leaves are visited nearest box first,
    /// each index whose leaf box the ray enters is tested over the caller's whole range, and
    /// the hit of smallest `t` is returned with its `patch` set to the index. The test must
    /// return hits with `t` in `[t_min, t_max]` (as [`moller_trumbore`](crate::moller_trumbore)
    /// does); a hit outside its box may be missed or kept.
    ///
    /// # Accuracy
    /// The same as a loop over every index that keeps the smallest `t` (the boxes must contain
    /// what the test hits).
    /// # Panics
    /// Never (unless `test` panics).
    pub fn closest_with(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        mut test: impl FnMut(u32, F, F) -> Option<Hit<F>>,
    ) -> Option<Hit<F>> {
        let (id, mut h) = self
            .traverse(ray, t_min, t_max, false, &mut |id, a, b, _| test(id, a, b))
            .ok()??;
        h.patch = id;
        Some(h)
    }

    /// Whether the caller's test `test(index, t_min, t_max)` reports a hit for any index whose
    /// box the ray enters within `[t_min, t_max]` (shadow rays): stops at the first.
    ///
    /// # Panics
    /// Never (unless `test` panics).
    pub fn any_with(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        mut test: impl FnMut(u32, F, F) -> bool,
    ) -> bool {
        let first = self.traverse(ray, t_min, t_max, true, &mut |id, a, b, _| {
            test(id, a, b).then_some(AnyHit(t_min))
        });
        matches!(first, Ok(Some(_)))
    }

    /// Visits the leaves whose boxes the ray enters, nearest box first, testing each index
    /// with `test` over the caller's range; returns the candidate with the smallest `t` and its
    /// index (with `any`, the first candidate found). The test's last argument is the
    /// best candidate's `t` once there is one: a candidate at or beyond it is discarded, so
    /// the test may skip an index whose crossings all lie there.
    fn traverse<C: Candidate<F>>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        any: bool,
        test: &mut impl FnMut(u32, F, F, Option<F>) -> Option<C>,
    ) -> Result<Option<(u32, C)>, BvhError> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() || t_min.is_nan() || t_max.is_nan() {
            return Ok(None);
        }
        let slab = SlabRay::new(o, d);
        let mut best: Option<(u32, C)> = None;
        let mut tmax = t_max;
        let mut stack: HVec<Pending<F>, BVH_STACK> = HVec::new();
        // The entry taken next: the nearest child of the node just visited, without a trip
        // through the stack (the one it would have been popped next from), or the root.
        let mut next = Some(Pending {
            child: 0,
            count: 0,
            t: t_min,
        });
        // A tree visits each node at most once and tests each index of `order` at most once:
        // the budgets bound the work even for corrupted storage handed to `from_parts`.
        let mut visits = self.nodes.len();
        let mut tests = self.order.len();
        while let Some(e) = next.take().or_else(|| stack.pop()) {
            // Skip what the best hit has moved in front of since it was pushed (the ray enters
            // its box at `e.t`, after the best hit).
            if e.t > tmax {
                continue;
            }
            if e.count > 0 {
                let first = e.child as usize;
                let ids = self
                    .order
                    .get(first..first.saturating_add(e.count as usize))
                    .ok_or(BvhError::CorruptTree)?;
                tests = tests.checked_sub(ids.len()).ok_or(BvhError::CorruptTree)?;
                for &id in ids {
                    // Each index is tested over the caller's whole range, then compared with the
                    // best so far: the kernel's first sign change depends on its interval, so
                    // shortening it to the best `t` could skip a closer crossing pair.
                    let beyond = best.as_ref().map(|_| tmax);
                    if let Some(h) = test(id, t_min, t_max, beyond)
                        && (best.is_none() || h.t() < tmax)
                    {
                        tmax = h.t();
                        best = Some((id, h));
                        if any {
                            return Ok(best);
                        }
                    }
                }
                continue;
            }
            visits = visits.checked_sub(1).ok_or(BvhError::CorruptTree)?;
            let node = self
                .nodes
                .get(e.child as usize)
                .ok_or(BvhError::CorruptTree)?;
            let (hit, near) = slab.enter(node, t_min, tmax);
            if hit == 0 {
                continue;
            }
            // The entered slots, farthest first onto the stack, the nearest taken next (of
            // equal entries, the later slot). One or two slots (most visits) without the sort.
            let entry = |k: usize, t: F| Pending {
                child: node.child(k),
                count: node.count(k),
                t,
            };
            let at = |k: usize| near.get(k).copied().unwrap_or(t_min);
            let k0 = hit.trailing_zeros() as usize;
            let rest = hit & (hit - 1);
            if rest == 0 {
                next = Some(entry(k0, at(k0)));
                continue;
            }
            let k1 = rest.trailing_zeros() as usize;
            if rest & (rest - 1) == 0 {
                let (t0, t1) = (at(k0), at(k1));
                let (far, near_one) = if t1 <= t0 {
                    (entry(k0, t0), entry(k1, t1))
                } else {
                    (entry(k1, t1), entry(k0, t0))
                };
                stack.push(far).map_err(|_| BvhError::StackOverflow)?;
                next = Some(near_one);
                continue;
            }
            let mut order: [(F, usize); BVH_WIDTH] = [(F::ZERO, 0); BVH_WIDTH];
            let mut m = 0usize;
            for (k, &t) in near.iter().enumerate() {
                if hit & (1 << k) == 0 {
                    continue;
                }
                let mut j = m;
                while j > 0 {
                    let Some(&prev) = order.get(j - 1) else { break };
                    if prev.0 >= t {
                        break;
                    }
                    if let Some(s) = order.get_mut(j) {
                        *s = prev;
                    }
                    j -= 1;
                }
                if let Some(s) = order.get_mut(j) {
                    *s = (t, k);
                }
                m += 1;
            }
            for (i, &(t, k)) in order.iter().take(m).enumerate() {
                if i + 1 == m {
                    next = Some(entry(k, t));
                } else {
                    stack
                        .push(entry(k, t))
                        .map_err(|_| BvhError::StackOverflow)?;
                }
            }
        }
        Ok(best)
    }
}

impl<'a, F: Float> Bvh<'a, F> {
    /// Number of nodes [`Bvh::build`] may need for `n` patches: `n − 1` for `n ≥ 2` (every
    /// node has at least two children, and there are at most `n` leaves), 1 for `n = 1`, 0
    /// for none. Trees use far fewer (about `n / 8`); [`Bvh::node_count`] says how many.
    pub const fn nodes_needed(n: usize) -> usize {
        BoxBvh::<F>::nodes_needed(n)
    }

    /// Builds a BVH over `patches` into `nodes` (at least [`Bvh::nodes_needed`]`(n)` long)
    /// and `order` (at least `n` long).
    ///
    /// Returns the BVH, or [`BvhError::EmptyScene`], [`BvhError::StorageTooSmall`],
    /// [`BvhError::TooManyPatches`]. Work: `O(n log n)`; no allocation. Deterministic: the same
    /// patches give the same nodes and order.
    /// # Panics
    /// Never.
    pub fn build(
        patches: &'a [Patch<F>],
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
    ) -> Result<Self, BvhError> {
        let tree = build_tree(patches, nodes, order)?;
        Ok(Bvh { patches, tree })
    }

    /// Re-wraps storage filled by an earlier [`Bvh::build`] over the same patches (for owners
    /// that keep the storage in their own structures, or upload and read it back), after
    /// checking it once: every node and leaf range inside the storage, children after their
    /// parent (so the tree has no cycle), nodes no deeper than `MAX_DEPTH − 2`, every index
    /// below `patches.len()`. Queries on the result then cannot fail.
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
        let tree = BoxBvh::from_parts(patches.len(), nodes, order)?;
        Ok(Bvh { patches, tree })
    }

    /// Wraps storage that [`Bvh::build`] filled (no check).
    #[cfg(feature = "alloc")]
    pub(crate) fn from_built(
        patches: &'a [Patch<F>],
        nodes: &'a [BvhNode<F>],
        order: &'a [u32],
    ) -> Self {
        Bvh {
            patches,
            tree: BoxBvh { nodes, order },
        }
    }

    /// The tree over the patches' boxes, for queries with a caller's leaf test
    /// ([`BoxBvh::closest_with`], [`BoxBvh::any_with`]: the index is the patch's).
    ///
    /// # Panics
    /// Never.
    pub fn tree(&self) -> BoxBvh<'a, F> {
        self.tree
    }

    /// Number of nodes in use.
    pub fn node_count(&self) -> usize {
        self.tree.node_count()
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
        self.tree.nodes
    }

    /// The patch indices that leaves refer to (`order[child..child + count]`).
    ///
    /// # Panics
    /// Never.
    pub fn order(&self) -> &'a [u32] {
        self.tree.order
    }

    /// Bytes used by the nodes and indices (not the patches).
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
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
        let mut slots = [None, None];
        let (id, c, prepared) = self.closest_crossing::<N>(ray, t_min, t_max, &mut slots)?;
        let mut h = c.hit(self.patches.get(id as usize)?, prepared, ray)?;
        h.patch = id;
        Some(h)
    }

    /// The closest crossing of [`Bvh::closest_hit`] before its normal is evaluated: the
    /// patch's index, where the ray crosses it and the patch prepared for the height
    /// evaluation (in one of the two `slots`: each candidate is prepared into the slot the
    /// best crossing so far does not hold).
    pub(crate) fn closest_crossing<'s, const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        slots: &'s mut [Option<Prepared<F>>; 2],
    ) -> Option<(u32, Crossing<F>, &'s Prepared<F>)> {
        let mut stats = KernelStats::default();
        let world = WorldRay::new(ray)?;
        let patches = self.patches;
        let [s0, s1] = slots;
        let mut free = 0usize;
        let (id, c) = self
            .tree
            .traverse(ray, t_min, t_max, false, &mut |id, a, b, beyond| {
                let p = patches.get(id as usize)?;
                let slot = if free == 0 { &mut *s0 } else { &mut *s1 };
                let c = kernel::crossing::<F, DEFAULT_SAMPLES, N>(
                    p, &world, a, b, beyond, &mut stats, slot,
                )?;
                // The traversal keeps a crossing iff it precedes the best so far (`beyond`):
                // then its slot holds the best, and the next candidate takes the other.
                if beyond.is_none_or(|t| c.t < t) {
                    free ^= 1;
                }
                Some(c)
            })
            .ok()??;
        let best = if free == 0 { s1 } else { s0 };
        Some((id, c, best.as_ref()?))
    }

    /// Whether anything is hit in `[t_min, t_max]` (shadow rays): stops at the first hit.
    ///
    /// # Panics
    /// Never.
    pub fn any_hit<const N: usize>(&self, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        let mut stats = KernelStats::default();
        let Some(world) = WorldRay::new(ray) else {
            return false;
        };
        let patches = self.patches;
        let mut scratch = None;
        let first = self
            .tree
            .traverse(ray, t_min, t_max, true, &mut |id, a, b, _| {
                let p = patches.get(id as usize)?;
                kernel::crossing::<F, DEFAULT_SAMPLES, N>(
                    p,
                    &world,
                    a,
                    b,
                    None,
                    &mut stats,
                    &mut scratch,
                )
            });
        matches!(first, Ok(Some(_)))
    }

    /// Closest hit with a caller-supplied per-patch test `test(index, patch, t_min, t_max)`,
    /// where `index` is the patch's index in the slice given to [`Bvh::build`] (for example the
    /// flat or Phong baselines of [`flat_hit`](crate::flat_hit) on the patch's vertices, which
    /// lie inside the patch's box, or on the caller's own triangle array: an Embree-style user
    /// geometry). The returned hit's `patch` is set to the patch index.
    ///
    /// # Panics
    /// Never (unless `test` panics).
    pub fn closest_with(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        mut test: impl FnMut(u32, &Patch<F>, F, F) -> Option<Hit<F>>,
    ) -> Option<Hit<F>> {
        let patches = self.patches;
        self.tree.closest_with(ray, t_min, t_max, |id, a, b| {
            test(id, patches.get(id as usize)?, a, b)
        })
    }
}

/// The checks of [`Bvh::from_parts`]: a depth-first walk from the root, each node visited
/// once.
fn validate<F: Float>(patches: usize, nodes: &[BvhNode<F>], order: &[u32]) -> Result<(), BvhError> {
    if nodes.is_empty() || patches == 0 {
        return Err(BvhError::EmptyScene);
    }
    let mut stack: HVec<(u32, usize), { BVH_STACK + BVH_WIDTH }> = HVec::new();
    let mut current = Some((0u32, 0usize));
    let mut budget = nodes.len();
    let mut tests = order.len();
    while let Some((i, depth)) = current {
        budget = budget.checked_sub(1).ok_or(BvhError::CorruptTree)?;
        let node = nodes.get(i as usize).ok_or(BvhError::CorruptTree)?;
        for k in 0..BVH_WIDTH {
            let (child, count) = (node.child(k), node.count(k));
            if child == BVH_EMPTY_SLOT {
                continue;
            }
            if count > 0 {
                let first = child as usize;
                let ids = order
                    .get(first..first.saturating_add(count as usize))
                    .ok_or(BvhError::CorruptTree)?;
                if ids.iter().any(|&id| id as usize >= patches) {
                    return Err(BvhError::CorruptTree);
                }
                tests = tests.checked_sub(ids.len()).ok_or(BvhError::CorruptTree)?;
            } else {
                if child <= i || child as usize >= nodes.len() {
                    return Err(BvhError::CorruptTree);
                }
                if depth + 1 > MAX_DEPTH - 2 {
                    return Err(BvhError::StackOverflow);
                }
                stack
                    .push((child, depth + 1))
                    .map_err(|_| BvhError::StackOverflow)?;
            }
        }
        current = stack.pop();
    }
    Ok(())
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

/// What [`BoxBvh::any_with`] reports: that its test hit (the ray's `t_min` as its `t`).
struct AnyHit<F>(F);

impl<F: Float> Candidate<F> for AnyHit<F> {
    #[inline(always)]
    fn t(&self) -> F {
        self.0
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
fn sah_split<F: Float, B: Boxes<F> + ?Sized>(
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
fn midpoint_split<F: Float, B: Boxes<F> + ?Sized>(
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
