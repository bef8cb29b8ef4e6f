//! The tree over boxes, [`BoxBvh`]: building it into caller storage, checking storage handed
//! back, and the one traversal (nearest child first, a fixed-size stack, work bounded by the
//! tree's size) that every query runs with its leaf test.

use heapless::Vec as HVec;

use super::build::{Boxes, build_tree, nodes_needed};
use super::error::BvhError;
use super::node::{BVH_EMPTY_SLOT, BVH_STACK, BVH_WIDTH, BvhNode, MAX_DEPTH, SlabRay};
use crate::aabb::Aabb;
use crate::exec::Executor;
use crate::kernel::Crossing;
use crate::num::real::Float;
use crate::ray::{Hit, Ray};

/// A four-wide BVH over a slice of boxes, borrowing its storage (the nodes and the order of
/// the box indices; the boxes themselves are not kept: the nodes hold them). What a leaf holds
/// is the caller's: [`BoxBvh::closest_with`] and [`BoxBvh::any_with`] call the caller's test
/// with the index of each box the ray reaches, as Embree's user geometries do.
#[derive(Clone, Copy, Debug)]
pub struct BoxBvh<'a, F: Float> {
    pub(super) nodes: &'a [BvhNode<F>],
    pub(super) order: &'a [u32],
}

/// A pending entry of the traversal: a node (`count == 0`) or a leaf, and where the ray enters
/// its box.
#[derive(Clone, Copy)]
pub(super) struct Pending<F> {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) t: F,
}

impl<'a, F: Float> BoxBvh<'a, F> {
    /// Number of nodes [`BoxBvh::build`] may need for `n` boxes: `n − 1` for `n ≥ 2` (every
    /// node has at least two children, and there are at most `n` leaves), 1 for `n = 1`, 0
    /// for none. Trees use far fewer (about `n / 8`); [`BoxBvh::node_count`] says how many.
    pub const fn nodes_needed(n: usize) -> usize {
        nodes_needed(n)
    }

    /// Builds a BVH over `boxes` into `nodes` (at least [`BoxBvh::nodes_needed`]`(n)` long)
    /// and `order` (at least `n` long): the same binned-SAH builder as [`Bvh::build`](crate::Bvh::build), which
    /// over the patches' boxes gives the same nodes and order as [`Bvh::build`](crate::Bvh::build) over the
    /// patches.
    ///
    /// Empty boxes (and boxes with a NaN corner) are left out of the tree: no ray can enter
    /// them, so their indices are never tested; [`BoxBvh::order`] lists the indices kept. Returns the BVH, or [`BvhError::EmptyScene`],
    /// [`BvhError::StorageTooSmall`], [`BvhError::TooManyPatches`]. Work: `O(n log n)`; no
    /// allocation. Deterministic: the same boxes give the same nodes and order.
    /// # Panics
    /// Never.
    pub fn build(
        boxes: &[Aabb<F>],
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
    ) -> Result<Self, BvhError> {
        Self::build_from(boxes, nodes, order, &())
    }

    /// [`BoxBvh::build`] over any source of boxes (an [`Aabb`] slice or the patches'), its
    /// subtrees on `executor`: the nodes used and the indices of the boxes kept.
    pub(super) fn build_from<B: Boxes<F> + Sync + ?Sized>(
        boxes: &B,
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
        executor: &impl Executor,
    ) -> Result<Self, BvhError> {
        let (used, kept) = build_tree(boxes, nodes, order, executor)?;
        let nodes: &'a [BvhNode<F>] = nodes;
        let order: &'a [u32] = order;
        Ok(BoxBvh {
            nodes: nodes.get(..used).ok_or(BvhError::Internal)?,
            order: order.get(..kept).ok_or(BvhError::Internal)?,
        })
    }

    /// Re-wraps storage filled by an earlier [`BoxBvh::build`] over `count` boxes, after the
    /// checks of [`Bvh::from_parts`](crate::Bvh::from_parts) (every index below `count`). Queries on the result then
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
    pub(super) fn traverse<C: Candidate<F>>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
        any: bool,
        test: &mut impl FnMut(u32, F, F, Option<F>) -> Option<C>,
    ) -> Result<Option<(u32, C)>, BvhError> {
        let o = F::from_glam(ray.origin);
        let d = F::from_glam(ray.dir);
        if !o.all_finite() || !d.all_finite() {
            return Ok(None);
        }
        self.traverse_slab(&SlabRay::new(o, d), t_min, t_max, any, test)
    }

    /// [`BoxBvh::traverse`] for a ray already prepared ([`SlabRay`], finite origin and
    /// direction): the kernel's queries pass their [`WorldRay`](crate::kernel::WorldRay)'s
    /// reciprocals instead of computing them again.
    pub(super) fn traverse_slab<C: Candidate<F>>(
        &self,
        slab: &SlabRay<F>,
        t_min: F,
        t_max: F,
        any: bool,
        test: &mut impl FnMut(u32, F, F, Option<F>) -> Option<C>,
    ) -> Result<Option<(u32, C)>, BvhError> {
        if t_min.is_nan() || t_max.is_nan() {
            return Ok(None);
        }
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

/// The checks of [`Bvh::from_parts`](crate::Bvh::from_parts): a depth-first walk from the root, each node visited
/// once.
pub(super) fn validate<F: Float>(
    patches: usize,
    nodes: &[BvhNode<F>],
    order: &[u32],
) -> Result<(), BvhError> {
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
pub(super) trait Candidate<F> {
    fn t(&self) -> F;
}

impl<F: Float> Candidate<F> for Hit<F> {
    #[inline(always)]
    fn t(&self) -> F {
        self.t
    }
}

/// What [`BoxBvh::any_with`] reports: that its test hit (the ray's `t_min` as its `t`).
pub(super) struct AnyHit<F>(F);

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
