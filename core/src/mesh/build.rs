//! The scene builder ([`Scene::build`]); the steps are listed in the [mesh
//! module](crate::mesh) documentation.

use core::fmt;

use super::cracks::{CrackReport, apply_gap, clear_reaches, pair_gap};
use super::parallel::{EDGE_WORK_BLOCK, EdgeWork, Executor};
use super::seams::{FitMatrix, Seam, apply_fit, gap_and_fit};
use super::topology::{MeshError, SharedEdge, edge_pair, pair_shared_edges};
use super::vertex_normals::{VertexClamp, VertexClampReport, clamp_vertex_normals};
use crate::bvh::{Bvh, BvhError, BvhNode};
use crate::error::PatchError;
use crate::num::real::Float;
use crate::patch::Patch;
use crate::ray::{Hit, Ray};
use crate::surface::field::LineField;

/// A read-only view of one vertex attribute (three scalars per vertex) in a caller's buffer:
/// vertex `i`'s components are `data[offset + i·stride ..][..3]`, so interleaved vertex
/// buffers (position, normal, uv, …) need no copy. Strides and offsets count scalars, not
/// bytes. For `&[[f32; 3]]` use `Vertices::packed(v.as_flattened())`.
#[derive(Clone, Copy, Debug)]
pub struct Vertices<'a, T> {
    data: &'a [T],
    offset: usize,
    stride: usize,
    count: usize,
}

impl<'a, T: Float> Vertices<'a, T> {
    /// Tightly packed `x, y, z` triples: `data.len() / 3` vertices (a trailing partial triple
    /// is not a vertex).
    ///
    /// # Panics
    /// Never.
    pub const fn packed(data: &'a [T]) -> Self {
        Vertices {
            data,
            offset: 0,
            stride: 3,
            count: data.len() / 3,
        }
    }

    /// `count` vertices whose components start at `offset` and repeat every `stride` scalars.
    ///
    /// Returns [`BuildError::VertexLayout`] when `stride < 3` (with `count > 1`) or when the
    /// last vertex would end past `data`.
    ///
    /// # Panics
    /// Never.
    pub fn strided(
        data: &'a [T],
        offset: usize,
        stride: usize,
        count: usize,
    ) -> Result<Self, BuildError> {
        let bad = BuildError::VertexLayout {
            offset,
            stride,
            count,
            len: data.len(),
        };
        if count > 1 && stride < 3 {
            return Err(bad);
        }
        let end = match count.checked_sub(1) {
            None => offset,
            Some(last) => last
                .checked_mul(stride)
                .and_then(|x| x.checked_add(offset))
                .and_then(|x| x.checked_add(3))
                .ok_or(bad)?,
        };
        if end > data.len() {
            return Err(bad);
        }
        Ok(Vertices {
            data,
            offset,
            stride,
            count,
        })
    }

    /// Number of vertices.
    ///
    /// # Panics
    /// Never.
    pub const fn len(&self) -> usize {
        self.count
    }

    /// `true` when there is no vertex.
    ///
    /// # Panics
    /// Never.
    pub const fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Vertex `i`'s three components, `None` at or beyond [`Vertices::len`].
    ///
    /// # Panics
    /// Never.
    pub fn get(&self, i: usize) -> Option<[T; 3]> {
        if i >= self.count {
            return None;
        }
        let at = i.checked_mul(self.stride)?.checked_add(self.offset)?;
        match self.data.get(at..at.checked_add(3)?)? {
            &[x, y, z] => Some([x, y, z]),
            _ => None,
        }
    }

    /// Vertex `i` rounded to the precision `F` (exact when `T` is `F` or narrower).
    #[inline]
    fn vec3<F: Float>(&self, i: usize) -> Option<F::Vec3> {
        let [x, y, z] = self.get(i)?;
        let c = |v: T| F::from_f64(v.to_f64());
        Some(F::to_glam(crate::num::vec::V3::new(c(x), c(y), c(z))))
    }
}

/// What [`Scene::build`] builds beside the patches and the BVH.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildOptions {
    /// The line field of the patches: [`LineField::Face`] (the paper's construction, the
    /// default) or [`LineField::Vertex`] (neighbours share their edges' lines, so their edge
    /// curves meet; adds the per-vertex remedy and its storage).
    pub field: LineField,
    /// Fit the seamless shading normals ([`SceneHit::shading_normal`] then differs from the
    /// geometric normal; costs `2·FIT_SAMPLES` = 16 normal evaluations per shared edge and
    /// [`SceneSizes::seams`] storage). Without it the shading normal is the geometric one.
    pub seams: bool,
}

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
    fn count(&mut self, e: PatchError) {
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
}

/// Why [`Scene::build`] (or [`Vertices::strided`]) failed. Storage is then unspecified; no
/// scene exists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildError {
    /// The index buffer is empty.
    NoTriangles,
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

/// What [`Scene::build_observed`] tells its caller while it builds; both methods do nothing
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

/// The observer of [`Scene::build_reporting`]: rejected triangles only.
pub(crate) struct Rejected<R>(pub(crate) R);

impl<R: FnMut(u32, PatchError)> BuildObserver for Rejected<R> {
    fn rejected(&mut self, triangle: u32, why: PatchError) {
        (self.0)(triangle, why);
    }
}

/// Calls `run(start, block)` for consecutive blocks of `work` covering the shared edges
/// `pairs` (`block` the first `min(work.len(), rest)` entries, for the edges from `start`),
/// and tells `observer` the progress of [`BuildStage::Edges`] after each.
fn for_each_block<F: Float>(
    pairs: &[SharedEdge],
    work: &mut [EdgeWork<F>],
    observer: &mut impl BuildObserver,
    mut run: impl FnMut(usize, &mut [EdgeWork<F>]),
) {
    let n = pairs.len();
    let step = work.len().max(1);
    let mut start = 0usize;
    while start < n {
        let len = step.min(n - start);
        let Some(block) = work.get_mut(..len) else {
            return;
        };
        run(start, block);
        start += len;
        observer.progress(BuildStage::Edges, start, n);
    }
}

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
    bvh: Bvh<'a, F>,
    triangle_ids: &'a [u32],
    seams: &'a [Seam<F>],
    report: BuildReport,
}

/// Checks that `slice` holds `needed` slots and returns the first `needed`.
fn take<'a, T>(
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

impl<'a, F: Float> Scene<'a, F> {
    /// Builds the scene of a triangle mesh: `positions` and `normals` per vertex (any
    /// consistent length unit; normals of any positive length, pointing to the side from which
    /// the triangles are counter-clockwise), `indices` three vertex indices per triangle, into
    /// `storage` (sizes from [`SceneSizes::new`]). The steps are those of the
    /// [mesh module](crate::mesh); the [`BuildReport`] says what each did.
    ///
    /// Input in `f32` or `f64` (`T`) for patches in `F`: each scalar is rounded to `F` once.
    ///
    /// Errors: [`BuildError::NoTriangles`], [`BuildError::VertexCountMismatch`],
    /// [`BuildError::IndexOutOfRange`], [`BuildError::StorageTooSmall`],
    /// [`BuildError::TooLarge`], and [`BuildError::NoUsableTriangles`] when every triangle is
    /// rejected. A rejected triangle is otherwise only counted.
    ///
    /// Work: `O(n log n)` in the triangles, dominated by crack closure (32 surface points per
    /// shared edge) and, with seams, the fit (16 normals per shared edge); the patch
    /// constructions (at most 7 per triangle, and the per-vertex remedy's on the shared field)
    /// and the BVH cost less (`smoothtri inspect` prints the time of each step). No allocation.
    /// # Accuracy
    /// Every patch, hit and normal is bit for bit what the steps give when called one by one.
    /// # Panics
    /// Never.
    pub fn build<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        storage: SceneStorage<'a, F>,
    ) -> Result<Self, BuildError> {
        Self::build_reporting(positions, normals, indices, options, storage, |_, _| {})
    }

    /// [`Scene::build`], calling `rejected(triangle, why)` for every rejected triangle in
    /// index order (for reports that list them all).
    ///
    /// # Panics
    /// Never (unless `rejected` panics).
    pub fn build_reporting<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        storage: SceneStorage<'a, F>,
        rejected: impl FnMut(u32, PatchError),
    ) -> Result<Self, BuildError> {
        let mut observer = Rejected(rejected);
        Self::build_observed(positions, normals, indices, options, storage, &mut observer)
    }

    /// [`Scene::build`], telling `observer` each rejected triangle (in index order) and the
    /// start of each step ([`BuildStage`]), so a caller can time the steps or show progress.
    ///
    /// # Panics
    /// Never (unless `observer` panics).
    pub fn build_observed<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        storage: SceneStorage<'a, F>,
        observer: &mut impl BuildObserver,
    ) -> Result<Self, BuildError> {
        Self::build_parallel(positions, normals, indices, options, storage, observer, &())
    }

    /// [`Scene::build_observed`], with the per-edge work of crack closure and the seam fit
    /// spread over `executor`'s threads ([`Executor`]; `&()` runs on the calling thread).
    /// The scene is bit for bit the same whatever the executor (each edge's result is a pure
    /// function of its two patches, applied in edge order on the calling thread).
    ///
    /// # Panics
    /// Never (unless `observer` or `executor` panics).
    pub fn build_parallel<T: Float>(
        positions: Vertices<'_, T>,
        normals: Vertices<'_, T>,
        indices: &[[u32; 3]],
        options: &BuildOptions,
        storage: SceneStorage<'a, F>,
        observer: &mut impl BuildObserver,
        executor: &impl Executor,
    ) -> Result<Self, BuildError> {
        let vertex_count = positions.len();
        if normals.len() != vertex_count {
            return Err(BuildError::VertexCountMismatch {
                positions: vertex_count,
                normals: normals.len(),
            });
        }
        if indices.is_empty() {
            return Err(BuildError::NoTriangles);
        }
        if u32::try_from(indices.len()).is_err() || u32::try_from(vertex_count).is_err() {
            return Err(BuildError::TooLarge);
        }
        let sizes =
            SceneSizes::new(vertex_count, indices.len(), options).ok_or(BuildError::TooLarge)?;
        for (t, tri) in indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(BuildError::IndexOutOfRange { triangle: t, index });
            }
        }
        let patches = take(storage.patches, sizes.patches, "patches")?;
        let triangle_ids = take(storage.triangle_ids, sizes.patches, "triangle_ids")?;
        let nodes = take(storage.nodes, sizes.nodes, "nodes")?;
        let order = take(storage.order, sizes.patches, "order")?;
        let seams = take(storage.seams, sizes.seams, "seams")?;
        let triangles = take(storage.triangles, sizes.patches, "triangles")?;
        let edges = take(storage.edges, sizes.edges, "edges")?;
        let work = take(storage.edge_work, sizes.edge_work, "edge_work")?;
        let vpos = take(storage.vertex_positions, sizes.vertices, "vertex_positions")?;
        let vnrm = take(storage.vertex_normals, sizes.vertices, "vertex_normals")?;
        let clamped = take(storage.clamped_normals, sizes.vertices, "clamped_normals")?;
        let clamps = take(storage.vertex_clamps, sizes.vertices, "vertex_clamps")?;

        let mut report = BuildReport {
            triangles: indices.len(),
            ..BuildReport::default()
        };
        // 1. The per-vertex remedy (shared field only).
        if options.field == LineField::Vertex {
            observer.stage(BuildStage::VertexNormals);
            for (i, (p, n)) in vpos.iter_mut().zip(vnrm.iter_mut()).enumerate() {
                if let (Some(a), Some(b)) = (positions.vec3::<F>(i), normals.vec3::<F>(i)) {
                    *p = a;
                    *n = b;
                }
            }
            // Triangles that repeat an index (zero area: rejected as patches below) have no
            // face normal to clamp toward; the remedy runs over the others.
            let mut distinct = 0;
            for tri in indices {
                let [a, b, c] = *tri;
                if a != b && b != c && a != c {
                    if let Some(slot) = triangles.get_mut(distinct) {
                        *slot = *tri;
                    }
                    distinct += 1;
                }
            }
            let distinct = triangles.get(..distinct).ok_or(BuildError::TooLarge)?;
            report.vertex_clamps =
                Some(clamp_vertex_normals(vpos, vnrm, distinct, clamped, clamps)?);
        }
        // 2. One patch per triangle, in index order.
        observer.stage(BuildStage::Patches);
        let mut count = 0usize;
        for (t, tri) in indices.iter().enumerate() {
            let corner = |k: usize| -> Option<(F::Vec3, F::Vec3)> {
                let i = *tri.get(k)? as usize;
                let n = match options.field {
                    LineField::Vertex => *clamped.get(i)?,
                    LineField::Face => normals.vec3::<F>(i)?,
                };
                Some((positions.vec3::<F>(i)?, n))
            };
            let (Some(a), Some(b), Some(c)) = (corner(0), corner(1), corner(2)) else {
                return Err(BuildError::TooLarge);
            };
            match Patch::<F>::new_or_tilted_with([a.0, b.0, c.0], [a.1, b.1, c.1], options.field) {
                Ok(patch) => {
                    if patch.normal_clamp().is_some() {
                        report.remedied += 1;
                        report.first_remedied.get_or_insert(t as u32);
                    }
                    let (Some(ps), Some(id), Some(tr)) = (
                        patches.get_mut(count),
                        triangle_ids.get_mut(count),
                        triangles.get_mut(count),
                    ) else {
                        return Err(BuildError::TooLarge);
                    };
                    *ps = patch;
                    *id = t as u32;
                    *tr = *tri;
                    count += 1;
                }
                Err(e) => {
                    report.rejected.count(e);
                    report.first_rejected.get_or_insert((t as u32, e));
                    observer.rejected(t as u32, e);
                }
            }
            if (t + 1) % EDGE_WORK_BLOCK == 0 || t + 1 == indices.len() {
                observer.progress(BuildStage::Patches, t + 1, indices.len());
            }
        }
        if let (0, Some((_, first))) = (count, report.first_rejected) {
            return Err(BuildError::NoUsableTriangles {
                triangles: indices.len(),
                first,
            });
        }
        Self::finish(
            patches,
            triangle_ids,
            nodes,
            order,
            seams,
            triangles,
            (edges, work),
            count,
            vertex_count,
            options,
            report,
            (observer, executor),
        )
    }

    /// Steps 3 to 5 over the first `count` patches.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        patches: &'a mut [Patch<F>],
        triangle_ids: &'a mut [u32],
        nodes: &'a mut [BvhNode<F>],
        order: &'a mut [u32],
        seams: &'a mut [Seam<F>],
        triangles: &mut [[u32; 3]],
        (edges, work): (&mut [SharedEdge], &mut [EdgeWork<F>]),
        count: usize,
        vertex_count: usize,
        options: &BuildOptions,
        mut report: BuildReport,
        (observer, executor): (&mut impl BuildObserver, &impl Executor),
    ) -> Result<Self, BuildError> {
        let short = BuildError::TooLarge;
        let patches = patches.get_mut(..count).ok_or(short)?;
        let triangle_ids: &'a [u32] = triangle_ids.get(..count).ok_or(short)?;
        let triangles = triangles.get(..count).ok_or(short)?;
        report.patches = count;
        // 3 and 4. The shared edges once, then block by block each edge's gap (crack closure)
        // and, with seams, its fits, from one evaluation of both neighbours' surfaces.
        observer.stage(BuildStage::Edges);
        let shared = pair_shared_edges(triangles, vertex_count, edges)?;
        let pairs: &[SharedEdge] = edges.get(..shared).ok_or(short)?;
        clear_reaches(patches);
        let mut cracks = CrackReport::default();
        let fit = FitMatrix::new();
        let mut seams = if options.seams {
            let seams = seams.get_mut(..count).ok_or(short)?;
            for s in seams.iter_mut() {
                *s = Seam::default();
            }
            Some(seams)
        } else {
            None
        };
        let with_seams = seams.is_some();
        let mut fitted = 0usize;
        for_each_block(pairs, work, observer, |start, block| {
            let view: &[Patch<F>] = patches;
            executor.run_chunks(block, &|first, chunk| {
                for (k, w) in chunk.iter_mut().enumerate() {
                    let Some(e) = edge_pair(pairs, start + first + k) else {
                        continue;
                    };
                    (w.gap, w.fit) = if with_seams {
                        gap_and_fit(&fit, view, e)
                    } else {
                        (pair_gap(&fit.nodes, view, e), None)
                    };
                }
            });
            for (k, w) in block.iter().enumerate() {
                if let Some(e) = edge_pair(pairs, start + k) {
                    apply_gap(patches, e, w.gap, &mut cracks);
                    if let Some(seams) = seams.as_deref_mut() {
                        fitted += usize::from(apply_fit(seams, e, w.fit));
                    }
                }
            }
        });
        report.cracks = cracks;
        let patches: &'a [Patch<F>] = patches;
        let seams: &'a [Seam<F>] = match seams {
            Some(seams) => {
                report.seam_edges = Some(fitted);
                seams
            }
            None => &[],
        };
        // 5. The BVH.
        observer.stage(BuildStage::Bvh);
        let bvh = Bvh::build(patches, nodes, order)?;
        report.bvh_nodes = bvh.node_count();
        observer.stage(BuildStage::Done);
        Ok(Scene {
            bvh,
            triangle_ids,
            seams,
            report,
        })
    }

    /// A scene over parts kept by an owner that built them with [`Scene::build`] (the BVH
    /// already validated).
    #[cfg(feature = "alloc")]
    pub(crate) fn from_built(
        bvh: Bvh<'a, F>,
        triangle_ids: &'a [u32],
        seams: &'a [Seam<F>],
        report: BuildReport,
    ) -> Self {
        Scene {
            bvh,
            triangle_ids,
            seams,
            report,
        }
    }

    /// The closest hit of `ray` with `t` in `[t_min, t_max]`, the smooth kernel at `N`
    /// refinement steps (eight height evaluations each; `N = 0` brackets only), or `None`.
    ///
    /// With seams, the hit's normal and the seamless shading normal come from one height
    /// evaluation over four lanes of jets (the point and the three edge points), from the
    /// patch preparation of the search: less work than [`Bvh::closest_hit`] then
    /// [`Scene::scene_hit`], with the same result bit for bit (the repository's builder tests).
    ///
    /// # Accuracy
    /// As [`Patch::intersect`]: `t` within the hit's `t_error`; the same hit as a loop over
    /// every patch. The shading normal as [`Seam::correct`].
    /// # Panics
    /// Never. Non-finite rays miss.
    pub fn closest_hit<const N: usize>(
        &self,
        ray: &Ray<F>,
        t_min: F,
        t_max: F,
    ) -> Option<SceneHit<F>> {
        let mut slots = [None, None];
        let (id, c, prepared) = self
            .bvh
            .closest_crossing::<N>(ray, t_min, t_max, &mut slots)?;
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

    /// Whether `ray` hits anything with `t` in `[t_min, t_max]` (shadow rays): stops at the
    /// first crossing found and evaluates no normal.
    ///
    /// # Panics
    /// Never. Non-finite rays miss.
    pub fn any_hit<const N: usize>(&self, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        self.bvh.any_hit::<N>(ray, t_min, t_max)
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
        self.triangle_ids.binary_search(&triangle).ok()
    }

    /// The BVH (for the baselines of [`Bvh::closest_with`] and uploads).
    ///
    /// # Panics
    /// Never.
    pub fn bvh(&self) -> &Bvh<'a, F> {
        &self.bvh
    }

    /// The accepted patches, in input order.
    ///
    /// # Panics
    /// Never.
    pub fn patches(&self) -> &'a [Patch<F>] {
        self.bvh.patches()
    }

    /// The input triangle of each patch (strictly increasing).
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
