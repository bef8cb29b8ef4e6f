//! A four-wide bounding volume hierarchy over patches, usable without `std` or `alloc`.
//!
//! The tree itself, [`BoxBvh`], knows only boxes: it is built over any slice of
//! [`Aabb`](crate::Aabb)s and traversed with a caller's leaf test ([`BoxBvh::closest_with`],
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

mod build;
mod error;
mod node;
mod parts;
mod tree;

pub use error::BvhError;
pub use node::{BVH_EMPTY_SLOT, BVH_STACK, BVH_WIDTH, BvhNode, MAX_DEPTH, MAX_LEAF};
pub use tree::BoxBvh;

use crate::exec::Executor;
use build::{build_tree, refit, tree_cost};
use node::SlabRay;

use crate::kernel::heights::target;
use crate::kernel::{
    self, Budget, Crossing, DEFAULT_SAMPLES, Heights, KernelStats, Test, WorldRay,
};
use crate::num::real::Float;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};
use crate::surface::lanes::Prepared;

/// A BVH over a slice of patches, borrowing its storage: a [`BoxBvh`] over the patches'
/// boxes ([`Patch::bounds`]) with the smooth kernel in its leaves.
#[derive(Clone, Copy, Debug)]
pub struct Bvh<'a, F: Float> {
    patches: &'a [Patch<F>],
    tree: BoxBvh<'a, F>,
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
        let tree = BoxBvh::build_from(patches, nodes, order, &())?;
        Ok(Bvh { patches, tree })
    }

    /// Builds the tree over `patches` into `nodes` and `order` as [`Bvh::build`] does, its
    /// subtrees and the binning of its top's large ranges on `executor` (the same tree
    /// whatever the executor); placeholders
    /// ([`Patch::rejected`]) are left out. Returns the nodes used, the patches in the tree and
    /// the tree's cost (`tree_cost`).
    pub(crate) fn build_in(
        patches: &[Patch<F>],
        nodes: &mut [BvhNode<F>],
        order: &mut [u32],
        executor: &impl Executor,
    ) -> Result<(usize, usize, f64), BvhError> {
        let (used, kept) = build_tree(patches, nodes, order, executor)?;
        let cost = tree_cost(nodes.get(..used).ok_or(BvhError::Internal)?);
        Ok((used, kept, cost))
    }

    /// Refits the tree in `nodes` (in use) over `order` (its patches) to the patches' boxes
    /// now: the same structure, every box recomputed, the leaves' on `executor`. Returns the
    /// tree's cost.
    pub(crate) fn refit_in(
        patches: &[Patch<F>],
        nodes: &mut [BvhNode<F>],
        order: &[u32],
        executor: &impl Executor,
    ) -> Result<f64, BvhError> {
        refit(patches, nodes, order, executor)
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

    /// Closest hit of `ray` in `[t_min, t_max]` using the smooth kernel with a refinement
    /// budget of `n` steps (any `n`; it runs [`iterations`](crate::iterations)`(n)`, at most
    /// [`MAX_ITERATIONS`](crate::MAX_ITERATIONS)); `hit.patch` is the patch's index in the
    /// slice given to [`Bvh::build`]. The lane code is compiled for the build's target; the
    /// same query with a kernel chosen at run time is [`crate::isa`]'s (the same hit, bit for
    /// bit).
    ///
    /// # Accuracy
    /// As [`Patch::closest_hit`]; the result equals a brute-force loop over all patches.
    /// # Panics
    /// Never.
    pub fn closest_hit(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> Option<Hit<F>> {
        self.closest_hit_with(ray, [t_min, t_max], n, &target())
    }

    /// [`Bvh::closest_hit`] with the lane calls of `heights`.
    #[inline(always)]
    pub(crate) fn closest_hit_with(
        &self,
        ray: &Ray<F>,
        range: [F; 2],
        n: usize,
        heights: &impl Heights<F>,
    ) -> Option<Hit<F>> {
        // Candidates are compared by their crossings; the normal is evaluated once, for the
        // closest (it is finite for every accepted patch, so this equals testing each patch
        // with `Patch::closest_hit`).
        let mut slots = [None, None];
        let (id, c, prepared) = self.closest_crossing(ray, range, n, &mut slots, heights)?;
        let mut h = c.hit(self.patches.get(id as usize)?, prepared, ray)?;
        h.patch = id;
        Some(h)
    }

    /// The closest crossing of [`Bvh::closest_hit`] before its normal is evaluated: the
    /// patch's index, where the ray crosses it and the patch prepared for the height
    /// evaluation (in one of the two `slots`: each candidate is prepared into the slot the
    /// best crossing so far does not hold).
    #[inline(always)]
    pub(crate) fn closest_crossing<'s>(
        &self,
        ray: &Ray<F>,
        [t_min, t_max]: [F; 2],
        n: usize,
        slots: &'s mut [Option<Prepared<F>>; 2],
        heights: &impl Heights<F>,
    ) -> Option<(u32, Crossing<F>, &'s Prepared<F>)> {
        let mut stats = KernelStats::default();
        let world = WorldRay::new(ray)?;
        let n = Budget::new(n);
        let patches = self.patches;
        let [s0, s1] = slots;
        let mut free = 0usize;
        let (id, c) = self
            .tree
            .traverse_slab(
                &SlabRay::of_world(&world),
                t_min,
                t_max,
                false,
                &mut |id, a, b, beyond| {
                    let p = patches.get(id as usize)?;
                    let slot = if free == 0 { &mut *s0 } else { &mut *s1 };
                    let test = Test {
                        t_min: a,
                        t_max: b,
                        beyond,
                        n,
                        predict: true,
                    };
                    let c = kernel::crossing::<F, DEFAULT_SAMPLES>(
                        p, &world, test, &mut stats, slot, heights,
                    )?;
                    // The traversal keeps a crossing iff it precedes the best so far (`beyond`):
                    // then its slot holds the best, and the next candidate takes the other.
                    if beyond.is_none_or(|t| c.t < t) {
                        free ^= 1;
                    }
                    Some(c)
                },
            )
            .ok()??;
        let best = if free == 0 { s1 } else { s0 };
        Some((id, c, best.as_ref()?))
    }

    /// Whether anything is hit in `[t_min, t_max]` (shadow rays), with a refinement budget of
    /// `n` steps (as [`Bvh::closest_hit`]): stops at the first hit.
    ///
    /// # Panics
    /// Never.
    pub fn any_hit(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> bool {
        self.any_hit_with(ray, [t_min, t_max], n, &target())
    }

    /// [`Bvh::any_hit`] with the lane calls of `heights`.
    #[inline(always)]
    pub(crate) fn any_hit_with(
        &self,
        ray: &Ray<F>,
        [t_min, t_max]: [F; 2],
        n: usize,
        heights: &impl Heights<F>,
    ) -> bool {
        let mut stats = KernelStats::default();
        let Some(world) = WorldRay::new(ray) else {
            return false;
        };
        let n = Budget::new(n);
        let patches = self.patches;
        let mut scratch = None;
        let first = self.tree.traverse_slab(
            &SlabRay::of_world(&world),
            t_min,
            t_max,
            true,
            &mut |id, a, b, _| {
                let p = patches.get(id as usize)?;
                let test = Test {
                    t_min: a,
                    t_max: b,
                    beyond: None,
                    n,
                    predict: true,
                };
                kernel::crossing::<F, DEFAULT_SAMPLES>(
                    p,
                    &world,
                    test,
                    &mut stats,
                    &mut scratch,
                    heights,
                )
            },
        );
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
