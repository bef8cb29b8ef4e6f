//! The scene update on the device ([`GpuUpdate`], the passes in `gpu/src/update/`): a deforming
//! mesh's vertex normals (where it has none), patches, crack closure, seams and BVH refit
//! re-made by compute passes from vertex buffers that live on the GPU, into an uploaded
//! [`GpuScene`]'s own buffers, with nothing read back per frame.

use std::sync::Arc;

use smoothtri::mesh::{SharedEdge, shared_edges};
use smoothtri::{BVH_EMPTY_SLOT, LineField};

use crate::device::{Gpu, scoped};
use crate::error::GpuError;
use crate::records::GpuNode;
use crate::scene::{GpuScene, SceneKind};
use crate::shader::{Shading, WORKGROUP};

pub(crate) mod pipelines;
mod setup;
use pipelines::UpdatePipelines;
use setup::{Buffers, Tables, bindings, level_binds, pass_binds};

/// The per-frame update of a smooth [`GpuScene`] on the device: given the mesh's index buffer
/// and its vertices in device buffers, [`GpuUpdate::encode`]
/// re-makes what the CPU's `OwnedScene::update` re-makes, as compute passes that write the
/// scene's own buffers:
///
/// 0. where [`GpuUpdate::generate_normals`] is on, the vertex normals from the positions
///    (`vertex_normals`: angle-weighted, for a mesh without normals);
/// 1. every triangle's patch (`build_patches`: the CPU's `Patch::new_or_tilted_with` on the
///    face field, in `f32` with the same operations, the per-patch remedy, and the CPU's
///    placeholder for a triangle that degenerates: an empty box that no ray reaches, the layout
///    unchanged);
/// 2. crack closure and, for a [`GpuScene::smooth_seamless`] scene, the seam fits
///    (`close_edges`: the gap of every shared edge at the CPU's 16 nodes and both walls'
///    reach; both sides' tilts of the common normal at 8 of them, or a free edge's
///    neighbour normals) and each patch's box from its reaches (`fit_boxes`);
/// 3. a refit of the scene's tree (`refit_nodes`, one dispatch per depth, deepest first).
///
/// The records equal the CPU's within rounding (`gpu/tests/device_update.rs`: the shell's
/// heights come from the kernel's height evaluation, equal to the CPU's to rounding; gaps are
/// measured in `f32` relative to the patches' origins where the CPU places its points in
/// `f64`). The tree is always refitted: the CPU's update rebuilds it once a refit's cost passes
/// `smoothtri::REBUILD_COST_RATIO`; [`GpuUpdate::tree_cost`] tells when, and a CPU build
/// uploaded then ([`GpuScene::update`], and a new `GpuUpdate` from its tree) takes over.
///
/// Bad vertices: the device reads nothing back, so it cannot refuse a pose as the CPU's update
/// does (`BuildError::NonFiniteVertex`, the scene kept). A vertex that is not finite makes its
/// triangles placeholders (remedy byte `0x81`, no ray reaches them) and the rest of the scene
/// updates; the next finite pose restores them (`gpu/tests/device_update.rs`). Check poses on
/// the host where a refusal matters.
///
/// Not on the device: the per-vertex remedy of [`LineField::Vertex`] (it runs in triangle
/// order): [`GpuUpdate::new`] refuses that field.
pub struct GpuUpdate {
    gpu: Arc<Gpu>,
    pipelines: Arc<UpdatePipelines>,
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    remedy: wgpu::Buffer,
    /// The vertex normals pass's bind group, and whether it runs ([`GpuUpdate::generate_normals`]).
    normals_bind: wgpu::BindGroup,
    generate_normals: bool,
    binds: [wgpu::BindGroup; 3],
    levels: Vec<(u32, wgpu::BindGroup)>,
    /// Per node, its part of the tree's cost ([`GpuUpdate::tree_cost`]).
    node_cost: wgpu::Buffer,
    /// The scene buffers the passes write and the scene's version, to refuse another scene or
    /// one rewritten since (its tree may have another topology).
    targets: [wgpu::Buffer; 4],
    version: u64,
    slots: u32,
    edges: u32,
    vertices: u32,
}

impl std::fmt::Debug for GpuUpdate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuUpdate")
            .field("triangles", &self.slots)
            .field("shared_edges", &self.edges)
            .field("vertices", &self.vertices)
            .field("tree_depth", &self.levels.len())
            .finish()
    }
}

impl GpuUpdate {
    /// The update of `scene`, a [`GpuScene::smooth`] or [`GpuScene::smooth_seamless`] upload
    /// of the CPU scene `cpu` (whose tree the passes refit), built from the mesh of `triangles`
    /// (the index buffer as given to the build: `cpu`'s `triangle_ids` pick each patch's) over
    /// `vertex_count` vertices on the line field `field`, with the vertex buffers zeroed.
    ///
    /// Errors: [`GpuError::Unsupported`] for a flat or Phong scene, or for
    /// [`LineField::Vertex`] (its per-vertex remedy runs in triangle order, on the CPU);
    /// [`GpuError::SceneMismatch`] when `cpu` or `triangles` does not match the scene;
    /// [`GpuError::Mesh`] for a vertex index at or above `vertex_count` or repeated in a
    /// triangle; [`GpuError::TooLarge`] beyond the device's limits; [`GpuError::Shader`] or
    /// [`GpuError::Device`] for device errors.
    ///
    /// # Panics
    /// Never.
    pub fn new(
        scene: &GpuScene,
        cpu: &smoothtri::Scene<'_, f32>,
        triangles: &[[u32; 3]],
        vertex_count: usize,
        field: LineField,
    ) -> Result<GpuUpdate, GpuError> {
        let seams = seams_of(scene, field)?;
        let gpu = Arc::clone(&scene.gpu);
        let triangles = patch_triangles(scene, cpu, triangles)?;
        let vertices = vertex_count_of(&gpu, vertex_count)?;
        let mut scratch = vec![SharedEdge::default(); 3 * triangles.len()];
        let pairs = shared_edges(&triangles, vertex_count, &mut scratch).map_err(GpuError::Mesh)?;
        check_workgroups(&gpu, triangles.len(), pairs.len(), vertex_count)?;
        let pipelines = gpu.update_pipelines()?;
        let tables = Tables::new(&triangles, pairs, vertices, seams, cpu.bvh());
        let device = &gpu.device;
        scoped(device, GpuError::Device, || {
            let b = Buffers::new(device, &tables, vertex_count, cpu.bvh().nodes().len());
            // The seam records, or a buffer too short for any record (the passes skip it).
            let seam_out = if seams { &scene.shade_in } else { &b.no_seams };
            let table = bindings(scene, &b, seam_out);
            let (normals_bind, binds) = pass_binds(device, &pipelines, &table);
            let levels = level_binds(device, &pipelines, &table, &tables.levels);
            GpuUpdate {
                gpu: Arc::clone(&gpu),
                pipelines: Arc::clone(&pipelines),
                positions: b.positions,
                normals: b.normals,
                remedy: b.remedy,
                normals_bind,
                generate_normals: false,
                binds,
                levels,
                node_cost: b.node_cost,
                targets: [
                    scene.patches.clone(),
                    scene.nodes.clone(),
                    scene.order.clone(),
                    scene.shade_in.clone(),
                ],
                version: scene.version,
                slots: tables.slots,
                edges: tables.edges,
                vertices,
            }
        })
    }

    /// The vertex positions on the device: three `f32` per vertex, `x y z`, vertex after
    /// vertex. A caller's own pass (skinning, morphing) may write it directly.
    pub fn positions(&self) -> &wgpu::Buffer {
        &self.positions
    }

    /// The vertex normals on the device, laid out as [`GpuUpdate::positions`] (any positive
    /// length: the passes normalise them).
    pub fn normals(&self) -> &wgpu::Buffer {
        &self.normals
    }

    /// With `on`, each update first computes the vertex normals from the positions
    /// (angle-weighted, as `smoothtri_io::angle_weighted_normals` does for a mesh without
    /// normals: each vertex's triangles' unit face normals weighted by their angles there, in
    /// `f32`), overwriting [`GpuUpdate::normals`]; then only the positions need writing
    /// ([`GpuUpdate::write_positions`]). Off by default.
    pub fn generate_normals(&mut self, on: bool) {
        self.generate_normals = on;
    }

    /// Whether each update generates the vertex normals ([`GpuUpdate::generate_normals`]).
    pub fn generates_normals(&self) -> bool {
        self.generate_normals
    }

    /// Writes the positions from the host through the queue (three `f32` per vertex), for an
    /// update that generates its normals ([`GpuUpdate::generate_normals`]). Returns
    /// [`GpuError::VertexCount`] when the length is not three per vertex; the buffer is then
    /// unchanged.
    ///
    /// # Panics
    /// Never.
    pub fn write_positions(&self, positions: &[f32]) -> Result<(), GpuError> {
        self.check_vertex_floats(positions.len())?;
        self.write_floats(&self.positions, positions);
        Ok(())
    }

    /// Writes the vertices from the host through the queue (`positions` and `normals`: three
    /// `f32` per vertex). Returns [`GpuError::VertexCount`] when a length is not three per
    /// vertex; the buffers are then unchanged.
    ///
    /// # Panics
    /// Never.
    pub fn write_vertices(&self, positions: &[f32], normals: &[f32]) -> Result<(), GpuError> {
        self.check_vertex_floats(positions.len())?;
        self.check_vertex_floats(normals.len())?;
        self.write_floats(&self.positions, positions);
        self.write_floats(&self.normals, normals);
        Ok(())
    }

    /// [`GpuError::VertexCount`] unless `given` floats are three per vertex.
    fn check_vertex_floats(&self, given: usize) -> Result<(), GpuError> {
        let expected = 3 * self.vertices as usize;
        if given != expected {
            return Err(GpuError::VertexCount { expected, given });
        }
        Ok(())
    }

    /// Writes `values` into `buffer` through the queue (nothing where there are none).
    fn write_floats(&self, buffer: &wgpu::Buffer, values: &[f32]) {
        if !values.is_empty() {
            let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_ne_bytes()).collect();
            self.gpu.queue.write_buffer(buffer, 0, &bytes);
        }
    }

    /// Records the update's passes into `enc`: `3 + depth` dispatches (patches, edges, boxes,
    /// then one per depth of the tree; one more first for generated normals), in that order,
    /// so that commands recorded after them (a frame, a query) see the updated scene. Returns
    /// [`GpuError::SceneMismatch`] when `scene` is not the scene this update was made for, or
    /// was rewritten since by [`GpuScene::update`] (whose tree may have another topology: make
    /// a new `GpuUpdate` from its `Bvh`); nothing is recorded then.
    ///
    /// Work: one invocation per vertex for generated normals (one angle per incident
    /// triangle), one per triangle (at most 7 patch constructions, 19 height evaluations
    /// each), one per shared edge (32 height evaluations; with seams 16 exact normals), one per
    /// triangle for the box and its seam flag, one per node.
    ///
    /// # Panics
    /// Never.
    pub fn encode(&self, scene: &GpuScene, enc: &mut wgpu::CommandEncoder) -> Result<(), GpuError> {
        if [&scene.patches, &scene.nodes, &scene.order, &scene.shade_in] != self.targets.each_ref()
            || scene.version != self.version
        {
            return Err(GpuError::SceneMismatch {
                what: "buffer",
                scene: scene.counts[2] as usize,
                given: self.slots as usize,
            });
        }
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("smoothtri update"),
            timestamp_writes: None,
        });
        let p = &self.pipelines;
        if self.generate_normals && self.vertices > 0 {
            pass.set_pipeline(&p.normals);
            pass.set_bind_group(0, &self.normals_bind, &[]);
            pass.dispatch_workgroups(self.vertices.div_ceil(WORKGROUP), 1, 1);
        }
        for (pipeline, bind, count) in [
            (&p.patches, &self.binds[0], self.slots),
            (&p.edges, &self.binds[1], self.edges),
            (&p.boxes, &self.binds[2], self.slots),
        ] {
            if count > 0 {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, bind, &[]);
                pass.dispatch_workgroups(count.div_ceil(WORKGROUP), 1, 1);
            }
        }
        pass.set_pipeline(&p.refit);
        for (count, bind) in &self.levels {
            pass.set_bind_group(0, bind, &[]);
            pass.dispatch_workgroups(count.div_ceil(WORKGROUP), 1, 1);
        }
        Ok(())
    }

    /// Updates `scene` from the vertex buffers' current contents ([`GpuUpdate::encode`]),
    /// submits and waits for the device.
    ///
    /// # Panics
    /// Never.
    pub fn run(&self, scene: &GpuScene) -> Result<(), GpuError> {
        let device = &self.gpu.device;
        scoped(device, GpuError::Device, || {
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("smoothtri update"),
            });
            self.encode(scene, &mut enc)?;
            self.gpu.queue.submit([enc.finish()]);
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map(|_| ())
                .map_err(|e| GpuError::Device(e.to_string()))
        })?
    }

    /// The refitted tree's cost by the surface area heuristic after the last update, relative
    /// to its root's box, as the CPU's `BuildReport::bvh_cost` measures it (the per-node parts
    /// computed by the refit pass, read back and summed here in `f64`). The CPU's update
    /// rebuilds its tree once this passes `smoothtri::REBUILD_COST_RATIO` times the built
    /// tree's cost; the device only refits, so a renderer that plays long or wild animations
    /// checks this now and then and uploads a CPU build when it is past that ratio. 0 before
    /// the first update; `+∞` for a root of no area.
    ///
    /// # Panics
    /// Never.
    pub fn tree_cost(&self) -> Result<f64, GpuError> {
        let parts = self
            .gpu
            .read_buffer(&self.node_cost, self.node_cost.size())?;
        let root = self
            .gpu
            .read_buffer(&self.targets[1], size_of::<GpuNode>() as u64)?;
        let word = |b: &[u8], k: usize| {
            b.get(4 * k..4 * k + 4)
                .map_or(0.0, |w| f32::from_ne_bytes([w[0], w[1], w[2], w[3]]))
        };
        let sum: f64 = (0..parts.len() / 4)
            .map(|k| f64::from(word(&parts, k)))
            .sum();
        let child = |s: usize| {
            root.get(96 + 4 * s..100 + 4 * s)
                .map_or(BVH_EMPTY_SLOT, |w| {
                    u32::from_ne_bytes([w[0], w[1], w[2], w[3]])
                })
        };
        // The root's box: the union of its used slots (the CPU's `tree_cost`, in f32).
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for s in (0..4).filter(|&s| child(s) != BVH_EMPTY_SLOT) {
            for a in 0..3 {
                lo[a] = lo[a].min(word(&root, 4 * a + s));
                hi[a] = hi[a].max(word(&root, 12 + 4 * a + s));
            }
        }
        let e = [0, 1, 2].map(|a| hi[a] - lo[a]);
        let area = if e.iter().all(|&x| x >= 0.0) {
            f64::from(e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
        } else {
            0.0
        };
        Ok(if self.levels.is_empty() {
            0.0
        } else if area > 0.0 {
            sum / area
        } else {
            f64::INFINITY
        })
    }

    /// Reads back the vertex normals buffer (three `f32` per vertex): what the last update
    /// built the patches from, generated or written. For tests and tools.
    ///
    /// # Panics
    /// Never.
    pub fn read_normals(&self) -> Result<Vec<f32>, GpuError> {
        let bytes = 12 * u64::from(self.vertices);
        self.gpu
            .read_words(&self.normals, bytes, f32::from_ne_bytes)
    }

    /// Reads back each triangle's `remedy` byte of the last update (the CPU's
    /// `Patch::remedy`: 0 for the normals as given, the clamp index + 1, or `0x80 |` the
    /// rejection's code for a placeholder). For tests and tools: an update reads nothing back.
    ///
    /// # Panics
    /// Never.
    pub fn read_remedies(&self) -> Result<Vec<u32>, GpuError> {
        let bytes = 4 * u64::from(self.slots);
        self.gpu.read_words(&self.remedy, bytes, u32::from_ne_bytes)
    }
}

/// Whether the update of `scene` fits seams ([`GpuScene::smooth_seamless`]), or
/// [`GpuError::Unsupported`] for a scene or a line `field` the device does not update.
fn seams_of(scene: &GpuScene, field: LineField) -> Result<bool, GpuError> {
    if field != LineField::Face {
        return Err(GpuError::Unsupported(
            "the device builds the face field only (LineField::Face)",
        ));
    }
    match (scene.kind, scene.shading) {
        (SceneKind::Smooth, Shading::Geometric) => Ok(false),
        (SceneKind::Smooth, Shading::Seamless) => Ok(true),
        _ => Err(GpuError::Unsupported(
            "the device updates smooth scenes (geometric or seamless normal) only",
        )),
    }
}

/// Each patch's triangle of `triangles` (`cpu`'s `triangle_ids` pick them), in the patch's
/// vertex order; [`GpuError::SceneMismatch`] unless `cpu`'s patches, triangles and nodes are
/// the scene's.
fn patch_triangles(
    scene: &GpuScene,
    cpu: &smoothtri::Scene<'_, f32>,
    triangles: &[[u32; 3]],
) -> Result<Vec<[u32; 3]>, GpuError> {
    let n = scene.counts[2] as usize;
    let bvh = cpu.bvh();
    if bvh.patches().len() != n {
        return Err(scene.mismatch("patch", bvh.patches().len()));
    }
    let ids = cpu.triangle_ids();
    let triangles: Vec<[u32; 3]> = ids
        .iter()
        .filter_map(|&t| triangles.get(t as usize).copied())
        .collect();
    if ids.len() != n || triangles.len() != n {
        return Err(scene.mismatch("triangle", triangles.len()));
    }
    if bvh.nodes().len() != scene.counts[0] as usize {
        return Err(scene.mismatch("node", bvh.nodes().len()));
    }
    Ok(triangles)
}

/// [`GpuError::TooLarge`]: `bytes` of `what` beyond the device's buffer limit.
fn too_large(gpu: &Gpu, what: &'static str, bytes: usize) -> GpuError {
    GpuError::TooLarge {
        what,
        bytes: bytes as u64,
        limit: gpu.buffer_limit(),
    }
}

/// `vertex_count` as the passes count it, when its vertex buffers fit the device.
fn vertex_count_of(gpu: &Gpu, vertex_count: usize) -> Result<u32, GpuError> {
    let vertices = u32::try_from(vertex_count).map_err(|_| too_large(gpu, "vertex", usize::MAX))?;
    if 12 * vertex_count as u64 > gpu.buffer_limit() {
        return Err(too_large(gpu, "vertex", 12 * vertex_count));
    }
    Ok(vertices)
}

/// [`GpuError::TooLarge`] when a pass over the `triangles`, the `edges` or the vertices would
/// need more workgroups than the device dispatches.
fn check_workgroups(
    gpu: &Gpu,
    triangles: usize,
    edges: usize,
    vertex_count: usize,
) -> Result<(), GpuError> {
    let max_groups = gpu.limits.max_compute_workgroups_per_dimension as usize;
    let most = triangles.max(edges).max(vertex_count);
    if most.div_ceil(WORKGROUP as usize) > max_groups {
        return Err(too_large(gpu, "triangle", 12 * triangles));
    }
    Ok(())
}
