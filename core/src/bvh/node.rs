//! The four-wide node: its children's boxes side by side, the limits that bound a tree's depth
//! and its traversal stack, and the ray's slab test of all four children in one step.

use crate::aabb::Aabb;
use crate::kernel::WorldRay;
use crate::num::real::{Float, Lane4, LaneOps};
use crate::num::vec::V3;

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

/// One BVH node: the boxes of up to [`BVH_WIDTH`] children side by side (structure of arrays,
/// one four-lane load per coordinate), and for each slot `k` either a child node
/// (`count(k) == 0`, node index `child(k)`, always after this node), a leaf of `count(k)`
/// patches (`order[child(k)..child(k) + count(k)]`), or nothing (`child(k) ==`
/// [`BVH_EMPTY_SLOT`], count 0, empty box).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<F: Float> {
    /// `lo[axis][slot]`.
    pub(super) lo: [[F; BVH_WIDTH]; 3],
    /// `hi[axis][slot]`.
    pub(super) hi: [[F; BVH_WIDTH]; 3],
    pub(super) child: [u32; BVH_WIDTH],
    pub(super) count: [u32; BVH_WIDTH],
}

impl<F: Float> BvhNode<F> {
    /// A node from its slots, for owners that store trees themselves (serialised, uploaded and
    /// read back): slot `k` has the box `bounds[k]`, and `child[k]`, `count[k]` as described on
    /// [`BvhNode`]. [`Bvh::from_parts`](crate::Bvh::from_parts) checks what they make.
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

    pub(super) fn set_box(&mut self, k: usize, b: &Aabb<F>) {
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
    /// [`Bvh::order`](crate::Bvh::order) (count > 0), or [`BVH_EMPTY_SLOT`] (unused, or `k ≥` [`BVH_WIDTH`]).
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
    /// A node of unused slots: the placeholder for storage that [`Bvh::build`](crate::Bvh::build) fills (a BVH of
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

#[inline(always)]
pub(super) fn axis<F: Float>(v: V3<F>, k: usize) -> F {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// The four lanes of `x` (`F::L4` where it carries four values).
#[inline(always)]
pub(super) fn lanes<F: Float>(x: [F; BVH_WIDTH]) -> F::L4 {
    <F::L4 as Lane4>::from_array4(x)
}

/// The ray as the slab test uses it: per axis the origin, `1/d`, and how the axis is tested.
#[derive(Clone, Copy)]
pub(super) struct SlabRay<F: Float> {
    pub(super) o: [F; 3],
    pub(super) inv: [F; 3],
    /// 0: slabs with `inv`; 1: `d = 0` on this axis, the origin must lie between the planes
    /// (as the kernel's clip); 2: `1/d` is not finite (a subnormal `d`): the axis is not
    /// tested, which keeps the test conservative.
    pub(super) mode: [u8; 3],
}

impl<F: Float> SlabRay<F> {
    /// The slab ray of origin `o` and direction `d` (any values).
    pub(super) fn new(o: V3<F>, d: V3<F>) -> Self {
        Self::with_reciprocals(o, d, crate::aabb::reciprocal(d))
    }

    /// The slab ray of a world ray the kernel has prepared: its reciprocals, computed once
    /// per ray for the traversal and every patch's box test.
    #[inline(always)]
    pub(super) fn of_world(ray: &WorldRay<F>) -> Self {
        Self::with_reciprocals(ray.o, ray.d, ray.inv)
    }

    /// The slab ray with `inv = reciprocal(d)` given.
    #[inline(always)]
    fn with_reciprocals(o: V3<F>, d: V3<F>, inv: V3<F>) -> Self {
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
    pub(super) fn enter(&self, node: &BvhNode<F>, t_min: F, t_max: F) -> (u32, [F; BVH_WIDTH]) {
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
    pub(super) fn slabs(
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
