//! What a build did ([`BuildReport`]), why it failed ([`BuildError`]), and what it tells an
//! observer while it runs ([`BuildObserver`], [`BuildStage`]).

use core::fmt;

use super::cracks::CrackReport;
use super::topology::MeshError;
use super::vertex_normals::VertexClampReport;
use crate::bvh::BvhError;
use crate::error::PatchError;

#[cfg(doc)]
use super::{
    BuildOptions, DynamicScene, Scene, SceneSizes, SceneStorage, Vertices, clamp_vertex_normals,
};
#[cfg(doc)]
use crate::patch::Patch;
#[cfg(doc)]
use crate::surface::field::LineField;

/// Counts of rejected triangles by [`PatchError`] variant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rejections {
    /// [`PatchError::NonFinite`].
    pub non_finite: usize,
    /// [`PatchError::DegenerateTriangle`].
    pub degenerate: usize,
    /// [`PatchError::ZeroNormal`].
    pub zero_normal: usize,
    /// [`PatchError::BackFacingNormal`].
    pub back_facing: usize,
    /// [`PatchError::InvalidShell`].
    pub invalid_shell: usize,
    /// [`PatchError::OutOfRange`].
    pub out_of_range: usize,
}

impl Rejections {
    /// Counts `e`.
    pub(super) fn count(&mut self, e: PatchError) {
        let slot = match e {
            PatchError::NonFinite => &mut self.non_finite,
            PatchError::DegenerateTriangle => &mut self.degenerate,
            PatchError::ZeroNormal { .. } => &mut self.zero_normal,
            PatchError::BackFacingNormal { .. } => &mut self.back_facing,
            PatchError::InvalidShell => &mut self.invalid_shell,
            PatchError::OutOfRange => &mut self.out_of_range,
        };
        *slot += 1;
    }

    /// Each reason with its count, in the order of the fields (for reports).
    ///
    /// # Panics
    /// Never.
    pub fn by_reason(&self) -> [(&'static str, usize); 6] {
        [
            ("non-finite vertex or normal", self.non_finite),
            ("degenerate triangle", self.degenerate),
            ("zero normal", self.zero_normal),
            ("back-facing normal", self.back_facing),
            ("invalid shell", self.invalid_shell),
            ("coordinates out of range", self.out_of_range),
        ]
    }
}

/// What [`Scene::build`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BuildReport {
    /// Triangles given.
    pub triangles: usize,
    /// Patches built (triangles accepted).
    pub patches: usize,
    /// Triangles rejected, by reason (`rejected.by_reason()`); their sum is
    /// `triangles − patches`.
    pub rejected: Rejections,
    /// The first rejected triangle and why.
    pub first_rejected: Option<(u32, PatchError)>,
    /// Patches whose normals the per-patch remedy clamped ([`Patch::normal_clamp`]).
    pub remedied: usize,
    /// The first remedied triangle.
    pub first_remedied: Option<u32>,
    /// The per-vertex remedy ([`LineField::Vertex`] only).
    pub vertex_clamps: Option<VertexClampReport>,
    /// What crack closure measured.
    pub cracks: CrackReport,
    /// Shared edges whose seams were fitted ([`BuildOptions::seams`]; `None` without).
    pub seam_edges: Option<usize>,
    /// BVH nodes in use.
    pub bvh_nodes: usize,
    /// Whether the BVH was refitted to the patches' new boxes ([`DynamicScene::update`])
    /// rather than built anew.
    pub bvh_refitted: bool,
    /// The BVH's cost by the surface area heuristic relative to its root's box (what a ray
    /// entering the root is expected to test); an update rebuilds the tree once a refit has
    /// raised it past [`REBUILD_COST_RATIO`](crate::mesh::REBUILD_COST_RATIO) times the cost of
    /// the last tree built.
    pub bvh_cost: f64,
}

/// Why [`Scene::build`] (or [`Vertices::strided`], or an update: [`DynamicScene::update`])
/// failed. After a failed build the storage is unspecified and no scene exists; after a failed
/// update, see [`DynamicScene::update`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildError {
    /// The index buffer is empty.
    NoTriangles,
    /// An update's vertex `vertex` has a position or normal coordinate that is NaN or
    /// infinite (a build rejects the triangles around such a vertex instead).
    NonFiniteVertex {
        /// The vertex.
        vertex: usize,
    },
    /// An update's vertices are not as many as the scene was built with.
    VertexCountChanged {
        /// Vertices the scene was built with.
        built: usize,
        /// Vertices given.
        given: usize,
    },
    /// An update's options ask for another line field or another seams setting than the scene
    /// was built with (its storage is laid out for those).
    OptionsChanged,
    /// Every triangle was rejected; the first one's reason.
    NoUsableTriangles {
        /// Triangles given.
        triangles: usize,
        /// Why the first was rejected.
        first: PatchError,
    },
    /// A vertex index is at or beyond the vertex count.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The offending index.
        index: u32,
    },
    /// The positions and the normals hold different numbers of vertices.
    VertexCountMismatch {
        /// Vertices of the positions.
        positions: usize,
        /// Vertices of the normals.
        normals: usize,
    },
    /// A strided vertex view does not fit its buffer ([`Vertices::strided`]).
    VertexLayout {
        /// First scalar.
        offset: usize,
        /// Scalars per vertex.
        stride: usize,
        /// Vertices.
        count: usize,
        /// Scalars in the buffer.
        len: usize,
    },
    /// A slice of [`SceneStorage`] is shorter than [`SceneSizes::new`] says.
    StorageTooSmall {
        /// The field of [`SceneStorage`].
        buffer: &'static str,
        /// Slots needed.
        needed: usize,
        /// Slots given.
        given: usize,
    },
    /// More triangles or vertices than `u32` indices (or the sizes) can address.
    TooLarge,
    /// A mesh-level step failed on input the builder had checked: not expected for any input
    /// (it would be a bug in this crate), reported rather than a panic.
    Mesh(MeshError),
    /// The BVH builder failed on patches the builder made: not expected for any input (a bug
    /// in this crate), reported rather than a panic.
    Bvh(BvhError),
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::NoTriangles => f.write_str("no triangles"),
            BuildError::NonFiniteVertex { vertex } => {
                write!(f, "vertex {vertex} has a non-finite position or normal")
            }
            BuildError::VertexCountChanged { built, given } => write!(
                f,
                "the scene was built with {built} vertices, the update gives {given}"
            ),
            BuildError::OptionsChanged => f.write_str(
                "an update must use the line field and seams setting the scene was built with",
            ),
            BuildError::NoUsableTriangles { triangles, first } => write!(
                f,
                "no usable triangles: all {triangles} triangles were rejected (first: {first})"
            ),
            BuildError::IndexOutOfRange { triangle, index } => write!(
                f,
                "triangle {triangle}: vertex index {index} is out of range"
            ),
            BuildError::VertexCountMismatch { positions, normals } => {
                write!(f, "{positions} positions but {normals} normals")
            }
            BuildError::VertexLayout {
                offset,
                stride,
                count,
                len,
            } => write!(
                f,
                "{count} vertices at offset {offset}, stride {stride} do not fit a buffer of {len} scalars"
            ),
            BuildError::StorageTooSmall {
                buffer,
                needed,
                given,
            } => write!(f, "storage '{buffer}' holds {given} slots, needs {needed}"),
            BuildError::TooLarge => f.write_str("too many triangles or vertices"),
            BuildError::Mesh(e) => write!(f, "internal error of the scene builder: {e}"),
            BuildError::Bvh(e) => write!(f, "internal error of the scene builder: {e}"),
        }
    }
}

impl core::error::Error for BuildError {}

impl From<MeshError> for BuildError {
    fn from(e: MeshError) -> Self {
        match e {
            MeshError::TooManyTriangles => BuildError::TooLarge,
            e => BuildError::Mesh(e),
        }
    }
}

impl From<BvhError> for BuildError {
    fn from(e: BvhError) -> Self {
        match e {
            BvhError::TooManyPatches => BuildError::TooLarge,
            e => BuildError::Bvh(e),
        }
    }
}

/// The steps of [`Scene::build`], in the order they run (the first only on
/// [`LineField::Vertex`], seams only with [`BuildOptions::seams`]), as told to a
/// [`BuildObserver`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BuildStage {
    /// The per-vertex remedy ([`clamp_vertex_normals`]).
    VertexNormals,
    /// One patch per triangle.
    Patches,
    /// The shared edges: crack closure ([`close_cracks`](super::close_cracks)) and, with [`BuildOptions::seams`],
    /// the seamless shading normals ([`fit_seams`](super::fit_seams)), both from one evaluation of the two
    /// neighbours' surfaces per edge (the heights for the gap, with seams their jets for the
    /// normals too).
    Edges,
    /// The BVH.
    Bvh,
    /// The scene is built.
    Done,
}

impl BuildStage {
    /// Lower-case name, for reports.
    ///
    /// # Panics
    /// Never.
    pub fn name(self) -> &'static str {
        match self {
            BuildStage::VertexNormals => "vertex normals",
            BuildStage::Patches => "patches",
            BuildStage::Edges => "edges",
            BuildStage::Bvh => "BVH",
            BuildStage::Done => "done",
        }
    }
}

/// What a build ([`Scene::build`], [`DynamicScene::update`]) tells the observer of its
/// [`BuildOptions`] while it runs; both methods do nothing
/// by default.
pub trait BuildObserver {
    /// Triangle `triangle` was rejected for `why` (called in index order).
    fn rejected(&mut self, triangle: u32, why: PatchError) {
        let _ = (triangle, why);
    }
    /// `stage` starts now (and [`BuildStage::Done`] once at the end of a successful build).
    fn stage(&mut self, stage: BuildStage) {
        let _ = stage;
    }
    /// `done` of `total` items of `stage` are finished (shared edges for
    /// [`BuildStage::Edges`], triangles for [`BuildStage::Patches`]); called after each block,
    /// for progress bars.
    fn progress(&mut self, stage: BuildStage, done: usize, total: usize) {
        let _ = (stage, done, total);
    }
}

/// Nothing to observe.
impl BuildObserver for () {}

/// An observer by reference (so the caller keeps what it learns).
impl<T: BuildObserver + ?Sized> BuildObserver for &mut T {
    fn rejected(&mut self, triangle: u32, why: PatchError) {
        (**self).rejected(triangle, why);
    }
    fn stage(&mut self, stage: BuildStage) {
        (**self).stage(stage);
    }
    fn progress(&mut self, stage: BuildStage, done: usize, total: usize) {
        (**self).progress(stage, done, total);
    }
}

/// An observer of rejected triangles only: `OnRejected(|triangle, why| …)` (for reports that
/// list them all).
#[derive(Clone, Copy, Debug)]
pub struct OnRejected<R>(pub R);

impl<R: FnMut(u32, PatchError)> BuildObserver for OnRejected<R> {
    fn rejected(&mut self, triangle: u32, why: PatchError) {
        (self.0)(triangle, why);
    }
}
