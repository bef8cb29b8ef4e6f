//! The caller's storage of a scene: its sizes from the counts alone ([`SceneSizes`]) and the
//! slices the builder fills ([`SceneStorage`]).

use super::input::BuildOptions;
use super::parallel::{EDGE_WORK_BLOCK, EdgeWork};
use super::report::BuildError;
use super::seams::Seam;
use super::topology::SharedEdge;
use super::vertex_normals::VertexClamp;
use crate::bvh::{Bvh, BvhNode};
use crate::num::real::Float;
use crate::patch::Patch;
use crate::surface::field::LineField;

#[cfg(doc)]
use super::Scene;

/// The length of every slice of [`SceneStorage`] for a mesh of given counts: what
/// [`Scene::build`] needs at most, whatever the data (rejected triangles leave slots unused).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneSizes {
    /// Slots of [`SceneStorage::patches`], [`SceneStorage::triangle_ids`],
    /// [`SceneStorage::order`] and [`SceneStorage::triangles`]: one per triangle.
    pub patches: usize,
    /// Slots of [`SceneStorage::nodes`]: [`Bvh::nodes_needed`]`(triangles)`, `triangles − 1`.
    pub nodes: usize,
    /// Slots of [`SceneStorage::seams`]: one per triangle with [`BuildOptions::seams`], else 0.
    pub seams: usize,
    /// Slots of [`SceneStorage::edges`]: three per triangle.
    pub edges: usize,
    /// Slots of [`SceneStorage::edge_work`]: the shared edges computed per block (at most
    /// [`EDGE_WORK_BLOCK`], and no more than a mesh of this size can share; 0 without
    /// triangles). The scene does not depend on it.
    pub edge_work: usize,
    /// Slots of each per-vertex slice of [`SceneStorage`]: one per vertex on
    /// [`LineField::Vertex`], else 0.
    pub vertices: usize,
}

impl SceneSizes {
    /// The sizes for `vertex_count` vertices and `triangle_count` triangles built with
    /// `options`; `None` when a size overflows `usize`.
    ///
    /// # Panics
    /// Never.
    pub const fn new(
        vertex_count: usize,
        triangle_count: usize,
        options: &BuildOptions,
    ) -> Option<Self> {
        let Some(edges) = triangle_count.checked_mul(3) else {
            return None;
        };
        let nodes = Bvh::<f32>::nodes_needed(triangle_count);
        Some(SceneSizes {
            patches: triangle_count,
            nodes,
            seams: if options.seams { triangle_count } else { 0 },
            edges,
            edge_work: {
                let shared = edges / 2;
                let block = if shared < EDGE_WORK_BLOCK {
                    shared
                } else {
                    EDGE_WORK_BLOCK
                };
                if block == 0 && triangle_count > 0 {
                    1
                } else {
                    block
                }
            },
            vertices: match options.field {
                LineField::Vertex => vertex_count,
                LineField::Face => 0,
            },
        })
    }

    /// Total bytes of the storage of these sizes in precision `F` (scratch included); `None`
    /// on overflow.
    ///
    /// # Panics
    /// Never.
    pub fn bytes<F: Float>(&self) -> Option<usize> {
        use core::mem::size_of;
        let per_patch = size_of::<Patch<F>>() + 2 * size_of::<u32>() + size_of::<[u32; 3]>();
        let per_vertex = 3 * size_of::<F::Vec3>() + size_of::<VertexClamp<F>>();
        [
            self.patches.checked_mul(per_patch)?,
            self.nodes.checked_mul(size_of::<BvhNode<F>>())?,
            self.seams.checked_mul(size_of::<Seam<F>>())?,
            self.edges.checked_mul(size_of::<SharedEdge>())?,
            self.edge_work.checked_mul(size_of::<EdgeWork<F>>())?,
            self.vertices.checked_mul(per_vertex)?,
        ]
        .iter()
        .try_fold(0usize, |a, &b| a.checked_add(b))
    }
}

/// The caller's storage for [`Scene::build`], each slice at least as long as
/// [`SceneSizes::new`] says (longer is fine; contents on entry are ignored). The first five
/// slices hold the scene and are borrowed by it; the rest is scratch, free again once `build`
/// returns (their contents are then unspecified).
pub struct SceneStorage<'a, F: Float> {
    /// The accepted patches ([`SceneSizes::patches`]).
    pub patches: &'a mut [Patch<F>],
    /// The input triangle of each patch ([`SceneSizes::patches`]).
    pub triangle_ids: &'a mut [u32],
    /// The BVH's nodes ([`SceneSizes::nodes`]).
    pub nodes: &'a mut [BvhNode<F>],
    /// The BVH's patch order ([`SceneSizes::patches`]).
    pub order: &'a mut [u32],
    /// The patches' seams ([`SceneSizes::seams`]; may be empty without
    /// [`BuildOptions::seams`]).
    pub seams: &'a mut [Seam<F>],
    /// Scratch: the accepted triangles' index buffer ([`SceneSizes::patches`]).
    pub triangles: &'a mut [[u32; 3]],
    /// Scratch: the shared-edge sort ([`SceneSizes::edges`]).
    pub edges: &'a mut [SharedEdge],
    /// Scratch: one block of per-edge results ([`SceneSizes::edge_work`]).
    pub edge_work: &'a mut [EdgeWork<F>],
    /// Scratch, [`LineField::Vertex`] only: positions in `F` ([`SceneSizes::vertices`]).
    pub vertex_positions: &'a mut [F::Vec3],
    /// Scratch, [`LineField::Vertex`] only: normals in `F` ([`SceneSizes::vertices`]).
    pub vertex_normals: &'a mut [F::Vec3],
    /// Scratch, [`LineField::Vertex`] only: the remedied normals ([`SceneSizes::vertices`]).
    pub clamped_normals: &'a mut [F::Vec3],
    /// Scratch, [`LineField::Vertex`] only: the remedy's state ([`SceneSizes::vertices`]).
    pub vertex_clamps: &'a mut [VertexClamp<F>],
}

/// Checks that `slice` holds `needed` slots and returns the first `needed`.
pub(super) fn take<'a, T>(
    slice: &'a mut [T],
    needed: usize,
    buffer: &'static str,
) -> Result<&'a mut [T], BuildError> {
    let given = slice.len();
    slice.get_mut(..needed).ok_or(BuildError::StorageTooSmall {
        buffer,
        needed,
        given,
    })
}
