//! The scene update on the device ([`GpuUpdate`], the passes in `gpu/src/update/`): a deforming
//! mesh's vertex normals (where it has none), patches, crack closure, seams and BVH refit
//! re-made by compute passes from vertex buffers that live on the GPU, into an uploaded
//! [`GpuScene`]'s own buffers, with nothing read back per frame.

use std::sync::Arc;

use smoothtri::internal::{crack_nodes, seam_fit_matrix};
use smoothtri::mesh::{SharedEdge, shared_edges};
use smoothtri::{BVH_EMPTY_SLOT, Bvh, LineField, NORMAL_CLAMP_DEG};
use wgpu::util::DeviceExt;

use crate::device::{Gpu, bind_entry, scoped};
use crate::error::GpuError;
use crate::records::GpuNode;
use crate::scene::{GpuScene, SceneKind};
use crate::shader::{Shading, WORKGROUP};

pub(crate) mod pipelines;
use pipelines::UpdatePipelines;

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
        if field != LineField::Face {
            return Err(GpuError::Unsupported(
                "the device builds the face field only (LineField::Face)",
            ));
        }
        let seams = match (scene.kind, scene.shading) {
            (SceneKind::Smooth, Shading::Geometric) => false,
            (SceneKind::Smooth, Shading::Seamless) => true,
            _ => {
                return Err(GpuError::Unsupported(
                    "the device updates smooth scenes (geometric or seamless normal) only",
                ));
            }
        };
        let gpu = Arc::clone(&scene.gpu);
        let n = scene.counts[2] as usize;
        let mismatch = |what, given| GpuError::SceneMismatch {
            what,
            scene: n,
            given,
        };
        let bvh = cpu.bvh();
        if bvh.patches().len() != n {
            return Err(mismatch("patch", bvh.patches().len()));
        }
        // Each patch's triangle, in the patch's vertex order.
        let ids = cpu.triangle_ids();
        let triangles: Vec<[u32; 3]> = ids
            .iter()
            .filter_map(|&t| triangles.get(t as usize).copied())
            .collect();
        if ids.len() != n || triangles.len() != n {
            return Err(mismatch("triangle", triangles.len()));
        }
        let triangles = triangles.as_slice();
        if bvh.nodes().len() != scene.counts[0] as usize {
            return Err(mismatch("node", bvh.nodes().len()));
        }
        let too_large = |what: &'static str, bytes: usize| GpuError::TooLarge {
            what,
            bytes: bytes as u64,
            limit: gpu.buffer_limit(),
        };
        let vertices = u32::try_from(vertex_count).map_err(|_| too_large("vertex", usize::MAX))?;
        if 12 * vertex_count as u64 > gpu.buffer_limit() {
            return Err(too_large("vertex", 12 * vertex_count));
        }
        let mut scratch = vec![SharedEdge::default(); 3 * n];
        let pairs = shared_edges(triangles, vertex_count, &mut scratch).map_err(GpuError::Mesh)?;
        let max_groups = gpu.limits.max_compute_workgroups_per_dimension as usize;
        if n.max(pairs.len())
            .max(vertex_count)
            .div_ceil(WORKGROUP as usize)
            > max_groups
        {
            return Err(too_large("triangle", 12 * n));
        }
        let pipelines = gpu.update_pipelines()?;
        let device = &gpu.device;
        let slots = n as u32;
        let edges = pairs.len() as u32;
        let mut bparams = Vec::new();
        for w in [slots, 0, vertices, u32::from(seams)] {
            bparams.extend_from_slice(&w.to_ne_bytes());
        }
        for deg in NORMAL_CLAMP_DEG {
            // As the CPU: sine and cosine in f64, rounded once.
            let (s, c) = deg.to_radians().sin_cos();
            for x in [c as f32, s as f32, 0.0, 0.0] {
                bparams.extend_from_slice(&x.to_ne_bytes());
            }
        }
        let mut eparams = Vec::new();
        for w in [edges, u32::from(seams), 0, 0] {
            eparams.extend_from_slice(&w.to_ne_bytes());
        }
        for t in crack_nodes() {
            // The CPU's nodes and the barycentrics of both sides, in f64 and rounded once.
            for x in [t as f32, (1.0 - t) as f32, (1.0 - (1.0 - t)) as f32, 0.0] {
                eparams.extend_from_slice(&x.to_ne_bytes());
            }
        }
        // The seam fit's map, rounded once from the CPU's f64 rows.
        for row in seam_fit_matrix() {
            for x in row {
                eparams.extend_from_slice(&(x as f32).to_ne_bytes());
            }
        }
        let pair_bytes: Vec<u8> = pairs
            .iter()
            .flat_map(|e| e.sides())
            .flat_map(u32::to_ne_bytes)
            .collect();
        let tri_bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_ne_bytes())
            .collect();
        // Each vertex's corners, in triangle order (as the CPU's accumulation).
        let mut start = vec![0u32; vertex_count + 1];
        for &i in triangles.iter().flatten() {
            if let Some(c) = start.get_mut(i as usize + 1) {
                *c += 1;
            }
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut incident = vec![0u32; start[vertex_count] as usize];
        let mut next = start.clone();
        for (t, tri) in triangles.iter().enumerate() {
            for (k, &i) in tri.iter().enumerate() {
                if let Some(slot) = next.get_mut(i as usize) {
                    incident[*slot as usize] = (3 * t + k) as u32;
                    *slot += 1;
                }
            }
        }
        let words = |v: &[u32]| -> Vec<u8> { v.iter().flat_map(|i| i.to_ne_bytes()).collect() };
        let (incident, start) = (words(&incident), words(&start));
        let (order, ranges) = levels(bvh);
        let order_bytes: Vec<u8> = order.iter().flat_map(|i| i.to_ne_bytes()).collect();
        scoped(device, GpuError::Device, || {
            use wgpu::BufferUsages as U;
            let zeroed = |what: &'static str, bytes: usize, usage: U| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(what),
                    size: bytes.max(16) as u64,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let init = |what: &'static str, bytes: &[u8], usage: U| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(what),
                    contents: if bytes.is_empty() { &[0; 16] } else { bytes },
                    usage,
                })
            };
            let positions = zeroed("positions", 12 * vertex_count, U::STORAGE | U::COPY_DST);
            let normals = zeroed(
                "normals",
                12 * vertex_count,
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            );
            let remedy = zeroed("remedy", 4 * n, U::STORAGE | U::COPY_SRC);
            let tris = init("triangles", &tri_bytes, U::STORAGE);
            let pairs = init("shared edges", &pair_bytes, U::STORAGE);
            let bparams = init("build params", &bparams, U::UNIFORM);
            let eparams = init("edge params", &eparams, U::UNIFORM);
            let level_nodes = init("tree levels", &order_bytes, U::STORAGE);
            let node_cost = zeroed(
                "node costs",
                4 * bvh.nodes().len(),
                U::STORAGE | U::COPY_SRC,
            );
            let incident = init("incident corners", &incident, U::STORAGE);
            let incident_start = init("incident starts", &start, U::STORAGE);
            // The seam records, or a buffer too short for any record (the passes skip it).
            let no_seams = zeroed("no seams", 16, U::STORAGE);
            let seam_out = if seams { &scene.shade_in } else { &no_seams };
            let group = |p: &wgpu::ComputePipeline, entries: &[wgpu::BindGroupEntry<'_>]| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("smoothtri update"),
                    layout: &p.get_bind_group_layout(0),
                    entries,
                })
            };
            let normals_bind = group(
                &pipelines.normals,
                &[
                    bind_entry(8, &bparams),
                    bind_entry(9, &positions),
                    bind_entry(10, &normals),
                    bind_entry(11, &tris),
                    bind_entry(18, &incident),
                    bind_entry(19, &incident_start),
                ],
            );
            let binds = [
                group(
                    &pipelines.patches,
                    &[
                        bind_entry(1, &scene.patches),
                        bind_entry(8, &bparams),
                        bind_entry(9, &positions),
                        bind_entry(10, &normals),
                        bind_entry(11, &tris),
                        bind_entry(12, &remedy),
                        bind_entry(17, seam_out),
                    ],
                ),
                group(
                    &pipelines.edges,
                    &[
                        bind_entry(1, &scene.patches),
                        bind_entry(12, &remedy),
                        bind_entry(13, &eparams),
                        bind_entry(14, &pairs),
                        bind_entry(17, seam_out),
                    ],
                ),
                group(
                    &pipelines.boxes,
                    &[
                        bind_entry(1, &scene.patches),
                        bind_entry(8, &bparams),
                        bind_entry(12, &remedy),
                        bind_entry(17, seam_out),
                    ],
                ),
            ];
            let levels = ranges
                .iter()
                .map(|&(start, count)| {
                    let mut b = Vec::new();
                    for w in [start, count, 0, 0] {
                        b.extend_from_slice(&w.to_ne_bytes());
                    }
                    let level = init("tree level", &b, U::UNIFORM);
                    let bind = group(
                        &pipelines.refit,
                        &[
                            bind_entry(1, &scene.patches),
                            bind_entry(2, &scene.nodes),
                            bind_entry(3, &scene.order),
                            bind_entry(15, &level),
                            bind_entry(16, &level_nodes),
                            bind_entry(20, &node_cost),
                        ],
                    );
                    (count, bind)
                })
                .collect();
            GpuUpdate {
                gpu: Arc::clone(&gpu),
                pipelines: Arc::clone(&pipelines),
                positions,
                normals,
                remedy,
                normals_bind,
                generate_normals: false,
                binds,
                levels,
                node_cost,
                targets: [
                    scene.patches.clone(),
                    scene.nodes.clone(),
                    scene.order.clone(),
                    scene.shade_in.clone(),
                ],
                version: scene.version,
                slots,
                edges,
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
        let expected = 3 * self.vertices as usize;
        if positions.len() != expected {
            return Err(GpuError::VertexCount {
                expected,
                given: positions.len(),
            });
        }
        if expected > 0 {
            let bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_ne_bytes()).collect();
            self.gpu.queue.write_buffer(&self.positions, 0, &bytes);
        }
        Ok(())
    }

    /// Writes the vertices from the host through the queue (`positions` and `normals`: three
    /// `f32` per vertex). Returns [`GpuError::VertexCount`] when a length is not three per
    /// vertex; the buffers are then unchanged.
    ///
    /// # Panics
    /// Never.
    pub fn write_vertices(&self, positions: &[f32], normals: &[f32]) -> Result<(), GpuError> {
        let expected = 3 * self.vertices as usize;
        for given in [positions.len(), normals.len()] {
            if given != expected {
                return Err(GpuError::VertexCount { expected, given });
            }
        }
        if expected == 0 {
            return Ok(());
        }
        let bytes = |v: &[f32]| v.iter().flat_map(|x| x.to_ne_bytes()).collect::<Vec<u8>>();
        let queue = &self.gpu.queue;
        queue.write_buffer(&self.positions, 0, &bytes(positions));
        queue.write_buffer(&self.normals, 0, &bytes(normals));
        Ok(())
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
        let bytes = self
            .gpu
            .read_buffer(&self.normals, 12 * u64::from(self.vertices))?;
        Ok(bytes
            .chunks_exact(4)
            .map(|c| f32::from_ne_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }

    /// Reads back each triangle's `remedy` byte of the last update (the CPU's
    /// `Patch::remedy`: 0 for the normals as given, the clamp index + 1, or `0x80 |` the
    /// rejection's code for a placeholder). For tests and tools: an update reads nothing back.
    ///
    /// # Panics
    /// Never.
    pub fn read_remedies(&self) -> Result<Vec<u32>, GpuError> {
        let bytes = self
            .gpu
            .read_buffer(&self.remedy, 4 * u64::from(self.slots))?;
        Ok(bytes
            .chunks_exact(4)
            .map(|c| u32::from_ne_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
}

/// The tree's nodes by depth, deepest first, and each depth's `(start, count)` in that list.
fn levels(bvh: &Bvh<'_, f32>) -> (Vec<u32>, Vec<(u32, u32)>) {
    let nodes = bvh.nodes();
    let mut depth = vec![0u32; nodes.len()];
    // Children follow their parents in the storage (Bvh::build): one pass in order.
    for (i, node) in nodes.iter().enumerate() {
        let GpuNode { child, count, .. } = GpuNode::from_node(node);
        for (c, k) in child.into_iter().zip(count) {
            let c = c as usize;
            if c != BVH_EMPTY_SLOT as usize && k == 0 && c > i && c < nodes.len() {
                depth[c] = depth[i] + 1;
            }
        }
    }
    let deepest = depth.iter().copied().max().unwrap_or(0);
    let mut order = Vec::with_capacity(nodes.len());
    let mut ranges = Vec::new();
    for d in (0..=deepest).rev() {
        let start = order.len() as u32;
        order.extend((0..nodes.len() as u32).filter(|&i| depth[i as usize] == d));
        let count = order.len() as u32 - start;
        if count > 0 {
            ranges.push((start, count));
        }
    }
    (order, ranges)
}
