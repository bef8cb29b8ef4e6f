//! A built scene ([`Scene`]): its queries and its parts.

use super::report::BuildReport;
use super::seams::Seam;
use crate::bvh::Bvh;
use crate::kernel::Heights;
use crate::kernel::heights::target;
use crate::num::real::Float;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};

#[cfg(doc)]
use super::{BuildOptions, SceneStorage};

/// A closest hit of a [`Scene`]: the kernel's [`Hit`] with the input triangle and the
/// shading normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit<F: Float = f32> {
    /// The hit (`hit.patch` is the patch's index in [`Scene::patches`]).
    pub hit: Hit<F>,
    /// The input triangle that was hit (an index into the index buffer given to
    /// [`Scene::build`]).
    pub triangle: u32,
    /// The seamless shading normal ([`Seam::correct`]) when the scene was built with
    /// [`BuildOptions::seams`], else `hit.normal`. Unit length, oriented like the vertex
    /// normals.
    pub shading_normal: F::Vec3,
}

/// A traceable scene: the accepted patches, their BVH and seams, borrowed from the
/// [`SceneStorage`] it was built in. Immutable; queries take `&self` and are thread-safe.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a, F: Float = f32> {
    pub(super) bvh: Bvh<'a, F>,
    pub(super) triangle_ids: &'a [u32],
    pub(super) seams: &'a [Seam<F>],
    pub(super) report: BuildReport,
}

impl<'a, F: Float> Scene<'a, F> {
    /// The closest hit of `ray` with `t` in `[t_min, t_max]`, the smooth kernel with a
    /// refinement budget of `n` steps (eight height evaluations each; `n = 0` brackets only;
    /// any `n`, run as [`iterations`](crate::iterations)`(n)`, at most
    /// [`MAX_ITERATIONS`](crate::MAX_ITERATIONS)), or `None`. The lane code is compiled for
    /// the build's target; [`crate::isa`] has the same query with a kernel chosen at run time
    /// (the same hit, bit for bit).
    ///
    /// With seams, the hit's normal and the seamless shading normal come from one height
    /// evaluation over four lanes of jets (the point and the three edge points), from the
    /// patch preparation of the search: less work than [`Bvh::closest_hit`] then
    /// [`Scene::scene_hit`], with the same result bit for bit (the repository's builder tests).
    ///
    /// # Accuracy
    /// As [`Patch::closest_hit`]: `t` within the hit's `t_error`; the same hit as a loop over
    /// every patch. The shading normal as [`Seam::correct`].
    /// # Panics
    /// Never. Non-finite rays miss.
    pub fn closest_hit(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> Option<SceneHit<F>> {
        self.closest_hit_with(ray, [t_min, t_max], n, &target())
    }

    /// [`Scene::closest_hit`] with the lane calls of `heights`.
    #[inline(always)]
    pub(crate) fn closest_hit_with(
        &self,
        ray: &Ray<F>,
        range: [F; 2],
        n: usize,
        heights: &impl Heights<F>,
    ) -> Option<SceneHit<F>> {
        let mut slots = [None, None];
        let (id, c, prepared) = self
            .bvh
            .closest_crossing(ray, range, n, &mut slots, heights)?;
        let patch = self.bvh.patches().get(id as usize)?;
        // With a seam, the hit's normal and the shading normal come from one evaluation over
        // four lanes, bit for bit what `Bvh::closest_hit` and `Scene::scene_hit` give.
        let (mut hit, shading_normal) = match self.seams.get(id as usize) {
            Some(seam) if !seam.is_zero() => {
                let (normal, shading) = seam.hit_normals(patch, prepared, c.bary);
                let hit = c.hit_with_normal(patch, ray, normal)?;
                (hit, F::to_glam(shading))
            }
            _ => {
                let hit = c.hit(patch, prepared, ray)?;
                (hit, hit.normal)
            }
        };
        hit.patch = id;
        Some(SceneHit {
            triangle: self.triangle_of(id),
            shading_normal,
            hit,
        })
    }

    /// The input triangle of patch `id`, or `u32::MAX` for an index not of this scene.
    fn triangle_of(&self, id: u32) -> u32 {
        self.triangle_ids
            .get(id as usize)
            .copied()
            .unwrap_or(u32::MAX)
    }

    /// Whether `ray` hits anything with `t` in `[t_min, t_max]` (shadow rays), with a
    /// refinement budget of `n` steps (as [`Scene::closest_hit`]): stops at the first crossing
    /// found and evaluates no normal.
    ///
    /// # Panics
    /// Never. Non-finite rays miss.
    pub fn any_hit(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> bool {
        self.bvh.any_hit(ray, t_min, t_max, n)
    }

    /// [`Scene::any_hit`] with the lane calls of `heights`.
    #[inline(always)]
    pub(crate) fn any_hit_with(
        &self,
        ray: &Ray<F>,
        range: [F; 2],
        n: usize,
        heights: &impl Heights<F>,
    ) -> bool {
        self.bvh.any_hit_with(ray, range, n, heights)
    }

    /// `hit` (from this scene's patches, e.g. by a query of [`Scene::bvh`]) with its triangle
    /// and shading normal. A hit whose `patch` is not of this scene keeps its normal and gets
    /// triangle `u32::MAX`.
    ///
    /// # Panics
    /// Never.
    pub fn scene_hit(&self, hit: Hit<F>) -> SceneHit<F> {
        SceneHit {
            triangle: self.triangle_of(hit.patch),
            shading_normal: self.shading_normal(&hit),
            hit,
        }
    }

    /// The normal to shade `hit` with: the seamless shading normal when the scene has seams
    /// ([`Seam::correct`]), else `hit.normal`.
    ///
    /// # Panics
    /// Never.
    pub fn shading_normal(&self, hit: &Hit<F>) -> F::Vec3 {
        let i = hit.patch as usize;
        match (self.seams.get(i), self.bvh.patches().get(i)) {
            (Some(seam), Some(patch)) => seam.correct(patch, hit.w1, hit.w2, hit.normal),
            _ => hit.normal,
        }
    }

    /// The patch built for input triangle `triangle`, `None` when it was rejected (or out of
    /// range). Binary search over [`Scene::triangle_ids`] (`O(log n)`).
    ///
    /// # Panics
    /// Never.
    pub fn patch_of_triangle(&self, triangle: u32) -> Option<&'a Patch<F>> {
        self.bvh.patches().get(self.patch_index(triangle)?)
    }

    /// The index in [`Scene::patches`] of input triangle `triangle`'s patch, `None` when it
    /// was rejected (or out of range). Binary search over [`Scene::triangle_ids`].
    ///
    /// # Panics
    /// Never.
    pub fn patch_index(&self, triangle: u32) -> Option<usize> {
        let i = self.triangle_ids.binary_search(&triangle).ok()?;
        let patch = self.bvh.patches().get(i)?;
        patch.rejected().is_none().then_some(i)
    }

    /// The BVH (for the baselines of [`Bvh::closest_with`] and uploads).
    ///
    /// # Panics
    /// Never.
    pub fn bvh(&self) -> &Bvh<'a, F> {
        &self.bvh
    }

    /// The patches, one per slot in input order: a slot for each triangle whose three indices
    /// differ ([`Scene::triangle_ids`] says which), holding its patch, or a placeholder
    /// ([`Patch::rejected`]) where the triangle was rejected (no ray reaches it; skip it when
    /// iterating).
    ///
    /// # Panics
    /// Never.
    pub fn patches(&self) -> &'a [Patch<F>] {
        self.bvh.patches()
    }

    /// The input triangle of each slot of [`Scene::patches`] (strictly increasing; the
    /// triangles that repeat an index have no slot).
    ///
    /// # Panics
    /// Never.
    pub fn triangle_ids(&self) -> &'a [u32] {
        self.triangle_ids
    }

    /// The seam of each patch; empty without [`BuildOptions::seams`].
    ///
    /// # Panics
    /// Never.
    pub fn seams(&self) -> &'a [Seam<F>] {
        self.seams
    }

    /// What the build did.
    ///
    /// # Panics
    /// Never.
    pub fn report(&self) -> &BuildReport {
        &self.report
    }

    /// Bytes the scene holds (patches, triangle ids, seams, BVH nodes and order; not the
    /// scratch).
    ///
    /// # Panics
    /// Never.
    pub fn memory_bytes(&self) -> usize {
        core::mem::size_of_val(self.bvh.patches())
            + core::mem::size_of_val(self.triangle_ids)
            + core::mem::size_of_val(self.seams)
            + self.bvh.memory_bytes()
    }
}
