//! [`OwnedScene`]: the builder's storage in `Vec`s (feature `alloc`).

use alloc::vec;
use alloc::vec::Vec;

use super::input::{BuildOptions, Vertices};
use super::parallel::{EdgeWork, Executor};
use super::report::{BuildError, BuildObserver, BuildReport, Rejected};
use super::scene::Scene;
use super::seams::Seam;
use super::storage::{SceneSizes, SceneStorage};
use super::topology::SharedEdge;
use super::vertex_normals::VertexClamp;
use crate::bvh::{Bvh, BvhNode};
use crate::error::PatchError;
use crate::num::real::Float;
use crate::patch::Patch;

/// A [`Scene`] that owns its storage (feature `alloc`): [`OwnedScene::build`] allocates what
/// [`SceneSizes::new`] asks for, runs [`Scene::build`] and keeps the used parts (the scratch
/// is freed). [`OwnedScene::scene`] borrows it as a [`Scene`] for queries.
#[derive(Clone, Debug)]
pub struct OwnedScene<F: Float = f32> {
    patches: Vec<Patch<F>>,
    triangle_ids: Vec<u32>,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
    seams: Vec<Seam<F>>,
    report: BuildReport,
}

impl<F: Float> OwnedScene<F> {
    /// [`Scene::build`] into storage of its own. Errors as [`Scene::build`].
    ///
    /// # Panics
    /// Never (allocation failure aborts, as in `alloc`).
    pub fn build<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
    ) -> Result<Self, BuildError> {
        Self::build_reporting(positions, normals, indices, options, |_, _| {})
    }

    /// [`Scene::build_reporting`] into storage of its own.
    ///
    /// # Panics
    /// Never (unless `rejected` panics).
    pub fn build_reporting<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        rejected: impl FnMut(u32, PatchError),
    ) -> Result<Self, BuildError> {
        let mut observer = Rejected(rejected);
        Self::build_observed(positions, normals, indices, options, &mut observer)
    }

    /// [`Scene::build_observed`] into storage of its own.
    ///
    /// # Panics
    /// Never (unless `observer` panics).
    pub fn build_observed<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        observer: &mut impl BuildObserver,
    ) -> Result<Self, BuildError> {
        Self::build_parallel(positions, normals, indices, options, observer, &())
    }

    /// [`Scene::build_parallel`] into storage of its own.
    ///
    /// # Panics
    /// Never (unless `observer` or `executor` panics).
    pub fn build_parallel<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        observer: &mut impl BuildObserver,
        executor: &impl Executor,
    ) -> Result<Self, BuildError> {
        let sizes =
            SceneSizes::new(positions.len(), indices.len(), options).ok_or(BuildError::TooLarge)?;
        // Storage the allocator could not describe (more than `isize::MAX` bytes) is refused
        // here rather than by `Vec`'s capacity-overflow panic.
        if sizes
            .bytes::<F>()
            .is_none_or(|b| isize::try_from(b).is_err())
        {
            return Err(BuildError::TooLarge);
        }
        let mut patches = vec![Patch::<F>::default(); sizes.patches];
        let mut triangle_ids = vec![0u32; sizes.patches];
        let mut nodes = vec![BvhNode::<F>::default(); sizes.nodes];
        let mut order = vec![0u32; sizes.patches];
        let mut seams = vec![Seam::<F>::default(); sizes.seams];
        let mut triangles = vec![[0u32; 3]; sizes.patches];
        let mut edges = vec![SharedEdge::default(); sizes.edges];
        let mut edge_work = vec![EdgeWork::<F>::default(); sizes.edge_work];
        let zero = F::to_glam(crate::num::vec::V3::zero());
        let mut vpos = vec![zero; sizes.vertices];
        let mut vnrm = vec![zero; sizes.vertices];
        let mut clamped = vec![zero; sizes.vertices];
        let mut clamps = vec![VertexClamp::<F>::default(); sizes.vertices];
        let storage = SceneStorage {
            patches: &mut patches,
            triangle_ids: &mut triangle_ids,
            nodes: &mut nodes,
            order: &mut order,
            seams: &mut seams,
            triangles: &mut triangles,
            edges: &mut edges,
            edge_work: &mut edge_work,
            vertex_positions: &mut vpos,
            vertex_normals: &mut vnrm,
            clamped_normals: &mut clamped,
            vertex_clamps: &mut clamps,
        };
        let report = *Scene::build_parallel(
            positions, normals, indices, options, storage, observer, executor,
        )?
        .report();
        patches.truncate(report.patches);
        triangle_ids.truncate(report.patches);
        order.truncate(report.patches);
        nodes.truncate(report.bvh_nodes);
        seams.truncate(if options.seams { report.patches } else { 0 });
        Ok(OwnedScene {
            patches,
            triangle_ids,
            nodes,
            order,
            seams,
            report,
        })
    }

    /// The scene, borrowed for queries.
    ///
    /// # Panics
    /// Never.
    pub fn scene(&self) -> Scene<'_, F> {
        Scene::from_built(
            Bvh::from_built(&self.patches, &self.nodes, &self.order),
            &self.triangle_ids,
            &self.seams,
            self.report,
        )
    }
}
