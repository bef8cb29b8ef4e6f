//! The scene builder: the numbered steps of the [mesh module](crate::mesh)'s documentation,
//! each a function over the one options value ([`BuildOptions`]: what to build, its observer
//! and its executor), run in order by [`Scene::build`] and, in place, by
//! [`DynamicScene::update`](super::DynamicScene::update).
//!
//! Layout: one slot per triangle whose three vertex indices differ (in index order), so the
//! layout of a mesh's storage depends on its index buffer alone, never on its vertices: a
//! triangle the core rejects keeps its slot as a placeholder ([`Patch::rejected`]) that no ray
//! reaches, and a later update can fill it. A triangle that repeats an index has no slot (it can
//! never become a patch).

use super::cracks::CrackReport;
use super::edges::{EdgeSink, Patches, edge_pass};
use super::input::{BuildOptions, Vertices};
use super::parallel::{EDGE_WORK_BLOCK, EdgeWork};
use super::report::{BuildError, BuildObserver, BuildReport, BuildStage};
use super::scene::Scene;
use super::seams::Seam;
use super::storage::{SceneSizes, SceneStorage, take};
use super::topology::{SharedEdge, pair_shared_edges};
use super::vertex_normals::{VertexClamp, VertexClampReport, remedy};
use crate::bvh::{Bvh, BvhNode};
use crate::error::PatchError;
use crate::exec::Executor;
use crate::num::real::Float;
use crate::patch::Patch;
use crate::surface::field::LineField;

/// A refitted BVH is rebuilt by [`DynamicScene::update`](super::DynamicScene::update) once
/// its cost by the surface area heuristic ([`BuildReport::bvh_cost`]) exceeds this many times
/// the cost of the last tree built for the scene.
///
/// Why 1.5: a refit keeps the tree's topology, so as a mesh deforms its boxes overlap more and
/// a ray tests more patches; the cost ratio tracks that expected work (it is the heuristic the
/// builder minimises). A rebuild costs about as much as the patches step, a refit a few
/// percent of it: rebuilding every frame would double an update, never rebuilding lets a
/// twisting mesh's rays slow down without bound. At 1.5 a frame's tracing is at most about
/// half again as slow as with a fresh tree before the tree is rebuilt.
pub const REBUILD_COST_RATIO: f64 = 1.5;

/// Triangles per block of the patches step: the observer hears the progress after each.
const PATCH_BLOCK: usize = EDGE_WORK_BLOCK;

/// The storage of a scene, each slice cut to its size.
pub(crate) struct Parts<'s, F: Float> {
    pub(crate) patches: &'s mut [Patch<F>],
    pub(crate) triangle_ids: &'s mut [u32],
    pub(crate) nodes: &'s mut [BvhNode<F>],
    pub(crate) order: &'s mut [u32],
    pub(crate) seams: &'s mut [Seam<F>],
    pub(crate) triangles: &'s mut [[u32; 3]],
    pub(crate) edges: &'s mut [SharedEdge],
    pub(crate) work: &'s mut [EdgeWork<F>],
    pub(crate) vertex_positions: &'s mut [F::Vec3],
    pub(crate) vertex_normals: &'s mut [F::Vec3],
    pub(crate) clamped: &'s mut [F::Vec3],
    pub(crate) clamps: &'s mut [VertexClamp<F>],
}

impl<'s, F: Float> Parts<'s, F> {
    /// `storage` cut to `sizes` ([`BuildError::StorageTooSmall`] for a short slice).
    pub(crate) fn of(storage: SceneStorage<'s, F>, sizes: &SceneSizes) -> Result<Self, BuildError> {
        Ok(Parts {
            patches: take(storage.patches, sizes.patches, "patches")?,
            triangle_ids: take(storage.triangle_ids, sizes.patches, "triangle_ids")?,
            nodes: take(storage.nodes, sizes.nodes, "nodes")?,
            order: take(storage.order, sizes.patches, "order")?,
            seams: take(storage.seams, sizes.seams, "seams")?,
            triangles: take(storage.triangles, sizes.patches, "triangles")?,
            edges: take(storage.edges, sizes.edges, "edges")?,
            work: take(storage.edge_work, sizes.edge_work, "edge_work")?,
            vertex_positions: take(storage.vertex_positions, sizes.vertices, "vertex_positions")?,
            vertex_normals: take(storage.vertex_normals, sizes.vertices, "vertex_normals")?,
            clamped: take(storage.clamped_normals, sizes.vertices, "clamped_normals")?,
            clamps: take(storage.vertex_clamps, sizes.vertices, "vertex_clamps")?,
        })
    }
}

/// What a build leaves beside its storage: the counts that say which parts are in use, what
/// the scene was built with, and what the last build or update did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Built {
    /// Vertices of the mesh.
    pub(crate) vertices: usize,
    /// Slots in use (triangles with distinct indices).
    pub(crate) slots: usize,
    /// Shared edges at the front of the edge storage (the pairs of the index buffer).
    pub(crate) shared: usize,
    /// BVH nodes in use (0: no patch, every query misses).
    pub(crate) nodes: usize,
    /// Entries of the BVH's order in use (the patches in the tree).
    pub(crate) kept: usize,
    /// The cost of the last tree built ([`REBUILD_COST_RATIO`]).
    pub(crate) cost_built: f64,
    /// The line field built with.
    pub(crate) field: LineField,
    /// Whether seams were fitted.
    pub(crate) seams: bool,
    /// What the last build or update did.
    pub(crate) report: BuildReport,
}

impl Built {
    /// The checks an update makes before it changes anything ([`DynamicScene::update`] and
    /// [`OwnedScene::update`](crate::OwnedScene::update)): the options are the build's, and
    /// the vertices fit ([`check_vertices`]).
    ///
    /// [`DynamicScene::update`]: super::DynamicScene::update
    pub(crate) fn check_update<T: Float, F: Float, O, E>(
        &self,
        positions: &Vertices<'_, T>,
        normals: &Vertices<'_, T>,
        options: &BuildOptions<O, E>,
    ) -> Result<(), BuildError> {
        if options.field != self.field || options.seams != self.seams {
            return Err(BuildError::OptionsChanged);
        }
        check_vertices::<T, F>(positions, normals, self.vertices)
    }

    /// An update's steps after [`Built::check_update`]: [`run`] over `parts` with these counts
    /// known. On success the counts become the update's and the scene `usable`; an error of a
    /// step leaves it unusable (its queries miss) until an update succeeds.
    pub(crate) fn rerun<T: Float, F: Float, O: BuildObserver, E: Executor>(
        &mut self,
        usable: &mut bool,
        positions: &Vertices<'_, T>,
        normals: &Vertices<'_, T>,
        parts: &mut Parts<'_, F>,
        options: &mut BuildOptions<O, E>,
    ) -> Result<&BuildReport, BuildError> {
        let result = run(
            positions,
            normals,
            self.report.triangles,
            parts,
            options,
            self.slots,
            Some(self),
        );
        *usable = result.is_ok();
        *self = result?;
        Ok(&self.report)
    }

    /// The counts queries see: these, or an empty tree (every query misses) when not `usable`.
    pub(crate) fn in_use(self, usable: bool) -> Built {
        if usable {
            self
        } else {
            Built {
                nodes: 0,
                kept: 0,
                ..self
            }
        }
    }

    /// The scene these counts describe in `parts`.
    pub(crate) fn scene<'v, F: Float>(
        &self,
        patches: &'v [Patch<F>],
        triangle_ids: &'v [u32],
        nodes: &'v [BvhNode<F>],
        order: &'v [u32],
        seams: &'v [Seam<F>],
    ) -> Scene<'v, F> {
        let cut = |n: usize, len: usize| n.min(len);
        let patches = patches.get(..cut(self.slots, patches.len())).unwrap_or(&[]);
        let seams = if self.seams {
            seams.get(..cut(self.slots, seams.len())).unwrap_or(&[])
        } else {
            &[]
        };
        Scene {
            bvh: Bvh::from_built(
                patches,
                nodes.get(..cut(self.nodes, nodes.len())).unwrap_or(&[]),
                order.get(..cut(self.kept, order.len())).unwrap_or(&[]),
            ),
            triangle_ids: triangle_ids
                .get(..cut(self.slots, triangle_ids.len()))
                .unwrap_or(&[]),
            seams,
            report: self.report,
        }
    }
}

/// Step 0: the input against itself and the options: the storage sizes it needs.
///
/// Errors: [`BuildError::VertexCountMismatch`], [`BuildError::NoTriangles`],
/// [`BuildError::TooLarge`], [`BuildError::IndexOutOfRange`].
pub(crate) fn check<T: Float, O, E>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    indices: &[[u32; 3]],
    options: &BuildOptions<O, E>,
) -> Result<SceneSizes, BuildError> {
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
    let plain = BuildOptions {
        field: options.field,
        seams: options.seams,
        ..BuildOptions::default()
    };
    let sizes = SceneSizes::new(vertex_count, indices.len(), &plain).ok_or(BuildError::TooLarge)?;
    for (t, tri) in indices.iter().enumerate() {
        if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(BuildError::IndexOutOfRange { triangle: t, index });
        }
    }
    Ok(sizes)
}

/// The checks of an update's vertices: as many positions as normals, as many as `count`, every
/// coordinate finite in `T` and in `F`.
fn check_vertices<T: Float, F: Float>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    count: usize,
) -> Result<(), BuildError> {
    if positions.len() != normals.len() {
        return Err(BuildError::VertexCountMismatch {
            positions: positions.len(),
            normals: normals.len(),
        });
    }
    if positions.len() != count {
        return Err(BuildError::VertexCountChanged {
            built: count,
            given: positions.len(),
        });
    }
    for vertex in 0..count {
        let finite = |v: &Vertices<'_, T>| {
            v.vec3::<F>(vertex)
                .is_some_and(|p| F::from_glam(p).all_finite())
        };
        if !finite(positions) || !finite(normals) {
            return Err(BuildError::NonFiniteVertex { vertex });
        }
    }
    Ok(())
}

/// Step 1: the slots, the triangles of `indices` whose indices differ, in order: their index
/// triples into `triangles`, their input indices into `triangle_ids`. Returns the slot count.
pub(crate) fn slots(indices: &[[u32; 3]], triangles: &mut [[u32; 3]], ids: &mut [u32]) -> usize {
    let mut n = 0usize;
    for (t, tri) in indices.iter().enumerate() {
        let [a, b, c] = *tri;
        if a == b || b == c || a == c {
            continue;
        }
        if let (Some(slot), Some(id)) = (triangles.get_mut(n), ids.get_mut(n)) {
            *slot = *tri;
            *id = t as u32;
            n += 1;
        }
    }
    n
}

/// Step 2, on [`LineField::Vertex`]: the per-vertex remedy
/// ([`clamp_vertex_normals`](super::clamp_vertex_normals)) over the slots' triangles, into
/// `parts.clamped`, its patch constructions on `executor` when `order_free` (the BVH's order
/// holds no tree to refit, so it can lend its room to the remedy's per-triangle flags), serial
/// otherwise; both give the same bits.
fn vertex_normals<T: Float, F: Float>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    parts: &mut Parts<'_, F>,
    slots: usize,
    executor: &impl Executor,
    order_free: bool,
) -> Result<VertexClampReport, BuildError> {
    for (i, (p, n)) in parts
        .vertex_positions
        .iter_mut()
        .zip(parts.vertex_normals.iter_mut())
        .enumerate()
    {
        if let (Some(a), Some(b)) = (positions.vec3::<F>(i), normals.vec3::<F>(i)) {
            *p = a;
            *n = b;
        }
    }
    let triangles = parts.triangles.get(..slots).ok_or(BuildError::TooLarge)?;
    // The BVH's order, when no refit will read it, holds the remedy's per-triangle flags.
    let pool = order_free.then_some((&mut *parts.order, executor));
    Ok(remedy(
        parts.vertex_positions,
        parts.vertex_normals,
        triangles,
        parts.clamped,
        parts.clamps,
        pool,
    )?)
}

/// Step 3: one patch per slot, with the per-patch remedy ([`Patch::new_or_tilted_with`]), or
/// the slot's placeholder ([`Patch::rejected`]); in blocks of [`PATCH_BLOCK`] slots, each
/// spread over `executor`. Each patch depends only on its own triangle.
#[allow(clippy::too_many_arguments)]
fn patches<T: Float, F: Float>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    clamped: &[F::Vec3],
    triangles: &[[u32; 3]],
    field: LineField,
    patches: &mut [Patch<F>],
    executor: &impl Executor,
    mut progress: impl FnMut(usize, usize),
) {
    let n = patches.len();
    for (b, block) in patches.chunks_mut(PATCH_BLOCK).enumerate() {
        let first = b * PATCH_BLOCK;
        executor.run_chunks(block, 16, &|start, chunk| {
            for (k, slot) in chunk.iter_mut().enumerate() {
                let tri = triangles.get(first + start + k).copied();
                *slot = match tri.map(|t| patch_of(positions, normals, clamped, t, field)) {
                    Some(Ok(p)) => p,
                    Some(Err(e)) => Patch::placeholder(e),
                    None => Patch::placeholder(PatchError::DegenerateTriangle),
                };
            }
        });
        progress((first + block.len()).min(n), n);
    }
}

/// The patch of triangle `tri` on `field` (its normals from `clamped` on the shared field).
#[inline]
fn patch_of<T: Float, F: Float>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    clamped: &[F::Vec3],
    tri: [u32; 3],
    field: LineField,
) -> Result<Patch<F>, PatchError> {
    let corner = |i: u32| -> Option<(F::Vec3, F::Vec3)> {
        let i = i as usize;
        let n = match field {
            LineField::Vertex => *clamped.get(i)?,
            LineField::Face => normals.vec3::<F>(i)?,
        };
        Some((positions.vec3::<F>(i)?, n))
    };
    let [a, b, c] = tri;
    let (Some(a), Some(b), Some(c)) = (corner(a), corner(b), corner(c)) else {
        return Err(PatchError::NonFinite);
    };
    Patch::<F>::new_or_tilted_with([a.0, b.0, c.0], [a.1, b.1, c.1], field)
}

/// Step 3's report, in index order: the rejected triangles (the slots' placeholders and the
/// triangles without a slot, which repeat an index: degenerate), told to `observer`, counted in
/// `report` with the remedied patches.
fn tally<F: Float>(
    triangles: usize,
    ids: &[u32],
    patches: &[Patch<F>],
    report: &mut BuildReport,
    observer: &mut impl BuildObserver,
) {
    let mut slots = ids.iter().zip(patches).peekable();
    for t in 0..triangles as u32 {
        let why = match slots.peek() {
            Some(&(&id, p)) if id == t => {
                slots.next();
                match p.rejected() {
                    Some(e) => e,
                    None => {
                        report.patches += 1;
                        if p.normal_clamp().is_some() {
                            report.remedied += 1;
                            report.first_remedied.get_or_insert(t);
                        }
                        continue;
                    }
                }
            }
            _ => PatchError::DegenerateTriangle,
        };
        report.rejected.count(why);
        report.first_rejected.get_or_insert((t, why));
        observer.rejected(t, why);
    }
}

/// Runs the steps after the slots over `parts`: the per-vertex remedy, the patches, the shared
/// edges (paired anew, or `known` pairs kept from the build) and the BVH (built, or with
/// `refit` refitted when it may be, see [`REBUILD_COST_RATIO`]). Returns the scene's counts.
///
/// A scene with no patch left is an error for a build ([`BuildError::NoUsableTriangles`]) and
/// an empty scene (every query misses) for an update.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run<T: Float, F: Float, O: BuildObserver, E: Executor>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    triangles: usize,
    parts: &mut Parts<'_, F>,
    options: &mut BuildOptions<O, E>,
    slots: usize,
    known: Option<&Built>,
) -> Result<Built, BuildError> {
    let vertex_count = positions.len();
    let observer = &mut options.observer;
    let executor = &options.executor;
    let mut report = BuildReport {
        triangles,
        ..BuildReport::default()
    };
    // 2. The per-vertex remedy (shared field only).
    if options.field == LineField::Vertex {
        observer.stage(BuildStage::VertexNormals);
        // An update may refit the tree whose order `parts.order` holds: keep it intact.
        let order_free = known.is_none_or(|b| b.nodes == 0);
        report.vertex_clamps = Some(vertex_normals(
            positions, normals, parts, slots, executor, order_free,
        )?);
    }
    // 3. One patch per slot.
    observer.stage(BuildStage::Patches);
    let cut = BuildError::TooLarge;
    let tris = parts.triangles.get(..slots).ok_or(cut)?;
    let ps = parts.patches.get_mut(..slots).ok_or(cut)?;
    patches(
        positions,
        normals,
        parts.clamped,
        tris,
        options.field,
        ps,
        executor,
        |done, total| observer.progress(BuildStage::Patches, done, total),
    );
    let ids = parts.triangle_ids.get(..slots).ok_or(cut)?;
    tally(triangles, ids, ps, &mut report, observer);
    if report.patches == 0
        && known.is_none()
        && let Some((_, first)) = report.first_rejected
    {
        return Err(BuildError::NoUsableTriangles { triangles, first });
    }
    // 4 and 5. The shared edges: crack closure and, with seams, the fits, from one evaluation
    // of both neighbours' surfaces per edge.
    observer.stage(BuildStage::Edges);
    let shared = match known {
        Some(b) => b.shared,
        None => pair_shared_edges(tris, vertex_count, parts.edges)?,
    };
    let pairs = parts.edges.get(..shared).ok_or(cut)?;
    let seams = if options.seams {
        Some(parts.seams.get_mut(..slots).ok_or(cut)?)
    } else {
        None
    };
    let mut sink = EdgeSink {
        patches: Patches::Close(ps),
        seams,
        cracks: CrackReport::default(),
        fitted: 0,
    };
    edge_pass(&mut sink, pairs, parts.work, executor, |done, total| {
        observer.progress(BuildStage::Edges, done, total)
    });
    report.cracks = sink.cracks;
    report.seam_edges = options.seams.then_some(sink.fitted);
    // 6. The BVH: refitted where the last tree still serves, else built.
    observer.stage(BuildStage::Bvh);
    let ps: &[Patch<F>] = parts.patches.get(..slots).ok_or(cut)?;
    let (nodes, kept, cost_built) = match known.filter(|b| b.nodes > 0) {
        Some(b) if refit_serves(ps, parts.order.get(..b.kept).ok_or(cut)?) => {
            let order = parts.order.get(..b.kept).ok_or(cut)?;
            let nodes = parts.nodes.get_mut(..b.nodes).ok_or(cut)?;
            let cost = Bvh::refit_in(ps, nodes, order, executor)?;
            if cost <= REBUILD_COST_RATIO * b.cost_built {
                report.bvh_refitted = true;
                report.bvh_cost = cost;
                (b.nodes, b.kept, b.cost_built)
            } else {
                build_bvh(ps, parts.nodes, parts.order, executor, &mut report)?
            }
        }
        _ => build_bvh(ps, parts.nodes, parts.order, executor, &mut report)?,
    };
    report.bvh_nodes = nodes;
    observer.stage(BuildStage::Done);
    Ok(Built {
        vertices: vertex_count,
        slots,
        shared,
        nodes,
        kept,
        cost_built,
        field: options.field,
        seams: options.seams,
        report,
    })
}

/// Whether refitting the tree over `order` (the patches the tree holds) keeps every patch in
/// the tree: no placeholder has become a patch since the tree was built.
fn refit_serves<F: Float>(patches: &[Patch<F>], order: &[u32]) -> bool {
    let in_tree = order
        .iter()
        .filter(|&&i| {
            patches
                .get(i as usize)
                .is_some_and(|p| p.rejected().is_none())
        })
        .count();
    let real = patches.iter().filter(|p| p.rejected().is_none()).count();
    in_tree == real
}

/// The BVH built anew over `patches` (their placeholders left out), its subtrees on
/// `executor`: the nodes used, the patches kept and the tree's cost. No patch: an empty tree.
fn build_bvh<F: Float>(
    patches: &[Patch<F>],
    nodes: &mut [BvhNode<F>],
    order: &mut [u32],
    executor: &impl Executor,
    report: &mut BuildReport,
) -> Result<(usize, usize, f64), BuildError> {
    if patches.iter().all(|p| p.rejected().is_some()) {
        report.bvh_cost = 0.0;
        return Ok((0, 0, 0.0));
    }
    let (nodes, kept, cost) = Bvh::build_in(patches, nodes, order, executor)?;
    report.bvh_cost = cost;
    Ok((nodes, kept, cost))
}

/// The start every build shares ([`Scene::build`], [`DynamicScene::build`] and
/// [`OwnedScene::build`](crate::OwnedScene::build)): `storage` laid out for `sizes` (what
/// [`check`] returned for this input), one slot per triangle, then the steps ([`run`]).
/// Returns the parts in use and the scene's counts.
///
/// [`DynamicScene::build`]: super::DynamicScene::build
pub(crate) fn start<'s, T: Float, F: Float, O: BuildObserver, E: Executor>(
    positions: &Vertices<'_, T>,
    normals: &Vertices<'_, T>,
    indices: &[[u32; 3]],
    options: &mut BuildOptions<O, E>,
    storage: SceneStorage<'s, F>,
    sizes: &SceneSizes,
) -> Result<(Parts<'s, F>, Built), BuildError> {
    let mut parts = Parts::of(storage, sizes)?;
    let slots = slots(indices, parts.triangles, parts.triangle_ids);
    let built = run(
        positions,
        normals,
        indices.len(),
        &mut parts,
        options,
        slots,
        None,
    )?;
    Ok((parts, built))
}

impl<'a, F: Float> Scene<'a, F> {
    /// Builds the scene of a triangle mesh: `positions` and `normals` per vertex (any
    /// consistent length unit; normals of any positive length, pointing to the side from which
    /// the triangles are counter-clockwise), `indices` three vertex indices per triangle, into
    /// `storage` (sizes from [`SceneSizes::new`]), as `options` say (line field, seams,
    /// observer, executor). The steps are those of the [mesh module](crate::mesh); the
    /// [`BuildReport`] says what each did.
    ///
    /// Input in `f32` or `f64` (`T`) for patches in `F`: each scalar is rounded to `F` once.
    ///
    /// Errors: [`BuildError::NoTriangles`], [`BuildError::VertexCountMismatch`],
    /// [`BuildError::IndexOutOfRange`], [`BuildError::StorageTooSmall`],
    /// [`BuildError::TooLarge`], and [`BuildError::NoUsableTriangles`] when every triangle is
    /// rejected. A rejected triangle is otherwise only counted, its slot kept as a
    /// placeholder ([`Patch::rejected`]).
    ///
    /// Work: `O(n log n)` in the triangles, dominated by the shared edges (32 surface points
    /// per shared edge, and with seams 16 normals); the patch constructions (at most 7 per
    /// triangle, and the per-vertex remedy's on the shared field) and the BVH cost less
    /// (`smoothtri inspect` prints the time of each step). The patches, the edges and the
    /// BVH's subtrees run on `options.executor`. No allocation.
    /// # Accuracy
    /// Every patch, hit and normal is bit for bit what the steps give when called one by one,
    /// whatever the executor.
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
        let Parts {
            patches,
            triangle_ids,
            nodes,
            order,
            seams,
            ..
        } = parts;
        Ok(built.scene(patches, triangle_ids, nodes, order, seams))
    }
}
