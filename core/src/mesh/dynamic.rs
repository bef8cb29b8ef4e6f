//! Scenes whose vertices move ([`DynamicScene`]): the same index buffer and the same storage,
//! re-built in place every frame, for skinned and morphed meshes.

use super::build::{Built, Parts, check, start};
use super::input::{BuildOptions, Vertices};
use super::report::{BuildError, BuildObserver, BuildReport};
use super::scene::Scene;
use super::storage::SceneStorage;
use crate::exec::Executor;
use crate::num::real::Float;

/// A scene in caller storage that can be updated in place when its vertices move ([`DynamicScene::update`]):
/// the no_std form of an animated mesh (with the `alloc` feature,
/// [`OwnedScene`](crate::OwnedScene) does the same with storage of its own). Queries go
/// through its view, [`DynamicScene::scene`].
///
/// Storage: what [`SceneSizes::new`](crate::SceneSizes::new) asks for, the scratch included,
/// which the scene keeps between updates (the shared edges of the index buffer are found once,
/// at the build).
#[derive(Debug)]
pub struct DynamicScene<'a, F: Float = f32> {
    parts: Parts<'a, F>,
    built: Built,
    usable: bool,
}

impl<F: Float> core::fmt::Debug for Parts<'_, F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Parts")
            .field("slots", &self.patches.len())
            .finish_non_exhaustive()
    }
}

impl<'a, F: Float> DynamicScene<'a, F> {
    /// [`Scene::build`] into `storage`, keeping what an update needs. Errors as
    /// [`Scene::build`].
    ///
    /// # Panics
    /// Never (unless the observer or the executor panics).
    pub fn build<T: Float, O: BuildObserver, E: Executor>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &mut BuildOptions<O, E>,
        storage: SceneStorage<'a, F>,
    ) -> Result<Self, BuildError> {
        let sizes = check(&positions, &normals, indices, options)?;
        let (parts, built) = start(&positions, &normals, indices, options, storage, &sizes)?;
        Ok(DynamicScene {
            parts,
            built,
            usable: true,
        })
    }

    /// Re-builds the scene in place for moved vertices: `positions` and `normals` of the same
    /// vertices as the build (the same index buffer, kept by the scene), with the same line
    /// field and seams setting in `options` (its observer and executor may differ). The
    /// per-vertex remedy, the patches, crack closure and seams are computed again; the BVH is
    /// refitted to the new boxes, or built anew when a refit no longer serves: when a triangle
    /// the tree left out has become a patch, or when the refitted tree's cost passes
    /// [`REBUILD_COST_RATIO`](crate::mesh::REBUILD_COST_RATIO) times the last built tree's. The
    /// report says which ([`BuildReport::bvh_refitted`]).
    ///
    /// A triangle that degenerates (or whose normals leave the method's domain) becomes its
    /// slot's placeholder ([`Patch::rejected`](crate::Patch::rejected)): no ray reaches it,
    /// the report counts it, the layout is unchanged; when it is a patch again, it is back.
    /// An update with no patch left gives an empty scene: every query misses.
    ///
    /// Errors, with the scene left as it was (the last valid one, queries unchanged):
    /// [`BuildError::OptionsChanged`], [`BuildError::VertexCountMismatch`] (positions and
    /// normals differ in number), [`BuildError::VertexCountChanged`], and
    /// [`BuildError::NonFiniteVertex`] (a NaN or infinite coordinate, or one beyond the range
    /// of `F`), all checked before anything is changed. An error of a later step (not expected
    /// for any input: it would be a bug in this crate) leaves the scene unusable until the next
    /// update succeeds: its queries then miss.
    ///
    /// Work: that of a build without the pairing of the shared edges (a sort) and, when it
    /// refits, without the BVH's build (a refit is one box union per patch and per node slot).
    /// No allocation.
    /// # Accuracy
    /// The patches, their crack reaches and the seams equal those of a fresh build of the
    /// same vertices bit for bit. Where the tree was built anew the hits do too; where it was
    /// refitted its nodes differ, so the traversal may test a patch with another best `t`, and
    /// hits agree within their `t_error`.
    /// # Panics
    /// Never (unless the observer or the executor panics).
    pub fn update<T: Float, O: BuildObserver, E: Executor>(
        &mut self,
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        options: &mut BuildOptions<O, E>,
    ) -> Result<&BuildReport, BuildError> {
        self.built
            .check_update::<T, F, O, E>(&positions, &normals, options)?;
        self.built.rerun(
            &mut self.usable,
            &positions,
            &normals,
            &mut self.parts,
            options,
        )
    }

    /// The scene for queries, as built or last updated (empty, every query missing, while an
    /// update's internal error has left it unusable).
    ///
    /// # Panics
    /// Never.
    pub fn scene(&self) -> Scene<'_, F> {
        let p = &self.parts;
        let built = self.built.in_use(self.usable);
        built.scene(p.patches, p.triangle_ids, p.nodes, p.order, p.seams)
    }

    /// What the build or the last update did.
    ///
    /// # Panics
    /// Never.
    pub fn report(&self) -> &BuildReport {
        &self.built.report
    }
}
