//! [`OwnedScene`]: the builder's storage in `Vec`s (feature `alloc`).

use alloc::vec;
use alloc::vec::Vec;

use super::build::{Built, Parts, check, start};
use super::input::{BuildOptions, Vertices};
use super::parallel::EdgeWork;
use super::report::{BuildError, BuildObserver, BuildReport};
use super::scene::Scene;
use super::seams::Seam;
use super::storage::{SceneSizes, SceneStorage};
use super::topology::{SharedEdge, pair_shared_edges};
use super::vertex_normals::VertexClamp;
use crate::bvh::{Bvh, BvhNode};
use crate::exec::Executor;
use crate::num::real::Float;
use crate::patch::Patch;

/// A [`Scene`] that owns its storage (feature `alloc`): [`OwnedScene::build`] allocates what
/// [`SceneSizes::new`] asks for, runs [`Scene::build`] and keeps the parts in use (the scratch
/// is freed); [`OwnedScene::update`] re-builds it in place for moved vertices, as
/// [`DynamicScene::update`](crate::DynamicScene::update) does (the first update allocates the
/// scratch again and finds the shared edges once more). [`OwnedScene::scene`] borrows it as a
/// [`Scene`] for queries.
#[derive(Clone, Debug)]
pub struct OwnedScene<F: Float = f32> {
    arrays: Arrays<F>,
    scratch: Option<Scratch<F>>,
    built: Built,
    usable: bool,
}

/// The scene's own arrays: what queries read, and the triangles an update rebuilds from.
#[derive(Clone, Debug)]
struct Arrays<F: Float> {
    patches: Vec<Patch<F>>,
    triangle_ids: Vec<u32>,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
    seams: Vec<Seam<F>>,
    triangles: Vec<[u32; 3]>,
}

impl<F: Float> Arrays<F> {
    /// These arrays and `scratch` as the builder's storage, whole.
    fn storage<'s>(&'s mut self, scratch: &'s mut Scratch<F>) -> SceneStorage<'s, F> {
        SceneStorage {
            patches: &mut self.patches,
            triangle_ids: &mut self.triangle_ids,
            nodes: &mut self.nodes,
            order: &mut self.order,
            seams: &mut self.seams,
            triangles: &mut self.triangles,
            edges: &mut scratch.edges,
            edge_work: &mut scratch.edge_work,
            vertex_positions: &mut scratch.vertex_positions,
            vertex_normals: &mut scratch.vertex_normals,
            clamped_normals: &mut scratch.clamped_normals,
            vertex_clamps: &mut scratch.vertex_clamps,
        }
    }
}

/// The storage an update needs beside the scene's own.
#[derive(Clone, Debug)]
struct Scratch<F: Float> {
    edges: Vec<SharedEdge>,
    edge_work: Vec<EdgeWork<F>>,
    vertex_positions: Vec<F::Vec3>,
    vertex_normals: Vec<F::Vec3>,
    clamped_normals: Vec<F::Vec3>,
    vertex_clamps: Vec<VertexClamp<F>>,
}

impl<F: Float> Scratch<F> {
    fn new(sizes: &SceneSizes) -> Self {
        let zero = F::to_glam(crate::num::vec::V3::zero());
        Scratch {
            edges: vec![SharedEdge::default(); sizes.edges],
            edge_work: vec![EdgeWork::default(); sizes.edge_work],
            vertex_positions: vec![zero; sizes.vertices],
            vertex_normals: vec![zero; sizes.vertices],
            clamped_normals: vec![zero; sizes.vertices],
            vertex_clamps: vec![VertexClamp::default(); sizes.vertices],
        }
    }
}

impl<F: Float> OwnedScene<F> {
    /// [`Scene::build`] into storage of its own. Errors as [`Scene::build`].
    ///
    /// # Panics
    /// Never (allocation failure aborts, as in `alloc`; unless the observer or the executor
    /// panics).
    pub fn build<T: Float, O: BuildObserver, E: Executor>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &mut BuildOptions<O, E>,
    ) -> Result<Self, BuildError> {
        let sizes = check(&positions, &normals, indices, options)?;
        // Storage the allocator could not describe (more than `isize::MAX` bytes) is refused
        // here rather than by `Vec`'s capacity-overflow panic.
        if sizes
            .bytes::<F>()
            .is_none_or(|b| isize::try_from(b).is_err())
        {
            return Err(BuildError::TooLarge);
        }
        let mut arrays = Arrays {
            patches: vec![Patch::<F>::default(); sizes.patches],
            triangle_ids: vec![0u32; sizes.patches],
            nodes: vec![BvhNode::<F>::default(); sizes.nodes],
            order: vec![0u32; sizes.patches],
            seams: vec![Seam::<F>::default(); sizes.seams],
            triangles: vec![[0u32; 3]; sizes.patches],
        };
        let mut scratch = Scratch::new(&sizes);
        let storage = arrays.storage(&mut scratch);
        let (_, built) = start(&positions, &normals, indices, options, storage, &sizes)?;
        let count = built.slots;
        let a = &mut arrays;
        for v in [&mut a.triangle_ids, &mut a.order] {
            v.truncate(count);
        }
        a.patches.truncate(count);
        a.triangles.truncate(count);
        a.order.truncate(built.kept);
        a.nodes.truncate(built.nodes);
        a.seams.truncate(if built.seams { count } else { 0 });
        Ok(OwnedScene {
            arrays,
            scratch: None,
            built,
            usable: true,
        })
    }

    /// Re-builds the scene in place for moved vertices, as
    /// [`DynamicScene::update`](crate::DynamicScene::update) does (the same errors, the same
    /// scene after an error, the same results bit for bit). The first update allocates the
    /// builder's scratch again (kept until the scene is dropped) and pairs the shared edges.
    ///
    /// # Panics
    /// Never (allocation failure aborts, as in `alloc`; unless the observer or the executor
    /// panics).
    pub fn update<T: Float, O: BuildObserver, E: Executor>(
        &mut self,
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        options: &mut BuildOptions<O, E>,
    ) -> Result<&BuildReport, BuildError> {
        self.built
            .check_update::<T, F, O, E>(&positions, &normals, options)?;
        let slots = self.built.slots;
        let plain = BuildOptions {
            field: self.built.field,
            seams: self.built.seams,
            ..BuildOptions::default()
        };
        let sizes =
            SceneSizes::new(self.built.vertices, slots, &plain).ok_or(BuildError::TooLarge)?;
        if self.scratch.is_none() {
            let mut scratch = Scratch::new(&sizes);
            pair_shared_edges(
                &self.arrays.triangles,
                self.built.vertices,
                &mut scratch.edges,
            )?;
            self.scratch = Some(scratch);
            self.arrays.order.resize(slots, 0);
            self.arrays
                .nodes
                .resize(Bvh::<F>::nodes_needed(slots), BvhNode::default());
        }
        let Some(scratch) = self.scratch.as_mut() else {
            return Err(BuildError::TooLarge);
        };
        let mut parts = Parts::of(self.arrays.storage(scratch), &sizes)?;
        self.built
            .rerun(&mut self.usable, &positions, &normals, &mut parts, options)
    }

    /// The scene, borrowed for queries (empty, every query missing, while an update's internal
    /// error has left it unusable).
    ///
    /// # Panics
    /// Never.
    pub fn scene(&self) -> Scene<'_, F> {
        let a = &self.arrays;
        self.built.in_use(self.usable).scene(
            &a.patches,
            &a.triangle_ids,
            &a.nodes,
            &a.order,
            &a.seams,
        )
    }
}
