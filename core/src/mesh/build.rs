//! The scene builder ([`Scene::build`]); the steps are listed in the [mesh
//! module](crate::mesh) documentation.

use super::cracks::{CrackReport, apply_gap, clear_reaches, pair_gap};
use super::input::{BuildOptions, Vertices};
use super::parallel::{EDGE_WORK_BLOCK, EdgeWork, Executor};
use super::report::{BuildError, BuildObserver, BuildReport, BuildStage, Rejected};
use super::scene::Scene;
use super::seams::{FitMatrix, Seam, apply_fit, gap_and_fit};
use super::storage::{SceneSizes, SceneStorage, take};
use super::topology::{SharedEdge, edge_pair, pair_shared_edges};
use super::vertex_normals::clamp_vertex_normals;
use crate::bvh::{Bvh, BvhNode};
use crate::error::PatchError;
use crate::num::real::Float;
use crate::patch::Patch;
use crate::surface::field::LineField;

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
}
