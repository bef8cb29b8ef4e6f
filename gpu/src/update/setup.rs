//! The update's set-up ([`GpuUpdate::new`](super::GpuUpdate::new)), step by step: what the
//! passes read that the host makes once ([`Tables`]: the parameters, the patches' triangles,
//! the shared edges, each vertex's corners, the tree's levels), the update's buffers
//! ([`Buffers`]) and each pass's bind group over them ([`pass_binds`], [`level_binds`]).

use smoothtri::internal::{crack_nodes, seam_fit_matrix};
use smoothtri::mesh::SharedEdge;
use smoothtri::{BVH_EMPTY_SLOT, Bvh, NORMAL_CLAMP_DEG};
use wgpu::BufferUsages;
use wgpu::util::DeviceExt;

use super::pipelines::UpdatePipelines;
use crate::device::{bind_entry, plain_buffer};
use crate::records::GpuNode;
use crate::scene::GpuScene;

/// The bytes of `words`, back to back.
fn word_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|i| i.to_ne_bytes()).collect()
}

/// What the passes read that the host makes once, as bytes: the parameters, the patches'
/// triangles, the shared edges, each vertex's corners and the tree's levels.
pub(super) struct Tables {
    /// Patches (one slot each) and shared edges.
    pub(super) slots: u32,
    pub(super) edges: u32,
    build_params: Vec<u8>,
    edge_params: Vec<u8>,
    triangles: Vec<u8>,
    pairs: Vec<u8>,
    incident: Vec<u8>,
    incident_start: Vec<u8>,
    /// The nodes by depth, deepest first, and each depth's `(start, count)` there ([`levels`]).
    level_nodes: Vec<u8>,
    pub(super) levels: Vec<(u32, u32)>,
}

impl Tables {
    /// The tables of the patches' `triangles` with their shared edges `pairs`, over `vertices`
    /// vertices, fitting seams where `seams`, and of the tree of `bvh`.
    pub(super) fn new(
        triangles: &[[u32; 3]],
        pairs: &[SharedEdge],
        vertices: u32,
        seams: bool,
        bvh: &Bvh<'_, f32>,
    ) -> Tables {
        let (slots, edges) = (triangles.len() as u32, pairs.len() as u32);
        let (incident, start) = incident_corners(triangles, vertices as usize);
        let (order, levels) = levels(bvh);
        Tables {
            slots,
            edges,
            build_params: build_params(slots, vertices, seams),
            edge_params: edge_params(edges, seams),
            triangles: word_bytes(triangles.as_flattened()),
            pairs: pairs
                .iter()
                .flat_map(|e| e.sides())
                .flat_map(u32::to_ne_bytes)
                .collect(),
            incident: word_bytes(&incident),
            incident_start: word_bytes(&start),
            level_nodes: word_bytes(&order),
            levels,
        }
    }
}

/// The patch passes' uniform: the patch and vertex counts, whether seams are fitted, then the
/// cosine and sine of each of the CPU's clamp angles (`NORMAL_CLAMP_DEG`).
fn build_params(slots: u32, vertices: u32, seams: bool) -> Vec<u8> {
    let mut bytes = word_bytes(&[slots, 0, vertices, u32::from(seams)]);
    for deg in NORMAL_CLAMP_DEG {
        // As the CPU: sine and cosine in f64, rounded once.
        let (s, c) = deg.to_radians().sin_cos();
        for x in [c as f32, s as f32, 0.0, 0.0] {
            bytes.extend_from_slice(&x.to_ne_bytes());
        }
    }
    bytes
}

/// The edge pass's uniform: the shared edge count and whether seams are fitted, then the
/// CPU's crack closure nodes (`smoothtri::internal::crack_nodes`, with both sides'
/// barycentrics) and the seam fit's map (`seam_fit_matrix`), rounded once from `f64`.
fn edge_params(edges: u32, seams: bool) -> Vec<u8> {
    let mut bytes = word_bytes(&[edges, u32::from(seams), 0, 0]);
    for t in crack_nodes() {
        // The CPU's nodes and the barycentrics of both sides, in f64 and rounded once.
        for x in [t as f32, (1.0 - t) as f32, (1.0 - (1.0 - t)) as f32, 0.0] {
            bytes.extend_from_slice(&x.to_ne_bytes());
        }
    }
    // The seam fit's map, rounded once from the CPU's f64 rows.
    for row in seam_fit_matrix() {
        for x in row {
            bytes.extend_from_slice(&(x as f32).to_ne_bytes());
        }
    }
    bytes
}

/// Each vertex's corners (`3 · triangle + corner`) in triangle order, as the CPU's
/// accumulation visits them, and where each vertex's start in that list (one more entry:
/// the end).
fn incident_corners(triangles: &[[u32; 3]], vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
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
    (incident, start)
}

/// A buffer of `bytes` bytes (at least 16: one is bound even when empty), zeroed. Call
/// inside [`scoped`](crate::device::scoped).
fn zeroed(device: &wgpu::Device, what: &str, bytes: usize, usage: BufferUsages) -> wgpu::Buffer {
    plain_buffer(device, what, bytes.max(16) as u64, usage)
}

/// A buffer holding `bytes` (16 zero bytes where empty). Call inside
/// [`scoped`](crate::device::scoped).
fn init(device: &wgpu::Device, what: &str, bytes: &[u8], usage: BufferUsages) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(what),
        contents: if bytes.is_empty() { &[0; 16] } else { bytes },
        usage,
    })
}

/// The update's own buffers: the vertices, the remedies and the node costs it keeps, and the
/// [`Tables`] the passes read.
pub(super) struct Buffers {
    pub(super) positions: wgpu::Buffer,
    pub(super) normals: wgpu::Buffer,
    pub(super) remedy: wgpu::Buffer,
    pub(super) node_cost: wgpu::Buffer,
    triangles: wgpu::Buffer,
    pairs: wgpu::Buffer,
    build_params: wgpu::Buffer,
    edge_params: wgpu::Buffer,
    level_nodes: wgpu::Buffer,
    incident: wgpu::Buffer,
    incident_start: wgpu::Buffer,
    /// Bound for the seam records of a scene without seams: too short for any record.
    pub(super) no_seams: wgpu::Buffer,
}

impl Buffers {
    /// The buffers of `t`, for `vertex_count` vertices and a tree of `nodes` nodes. Call
    /// inside [`scoped`](crate::device::scoped).
    pub(super) fn new(
        device: &wgpu::Device,
        t: &Tables,
        vertex_count: usize,
        nodes: usize,
    ) -> Buffers {
        use BufferUsages as U;
        let vertex_bytes = 12 * vertex_count;
        Buffers {
            positions: zeroed(device, "positions", vertex_bytes, U::STORAGE | U::COPY_DST),
            normals: zeroed(
                device,
                "normals",
                vertex_bytes,
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
            remedy: zeroed(
                device,
                "remedy",
                4 * t.slots as usize,
                U::STORAGE | U::COPY_SRC,
            ),
            node_cost: zeroed(device, "node costs", 4 * nodes, U::STORAGE | U::COPY_SRC),
            triangles: init(device, "triangles", &t.triangles, U::STORAGE),
            pairs: init(device, "shared edges", &t.pairs, U::STORAGE),
            build_params: init(device, "build params", &t.build_params, U::UNIFORM),
            edge_params: init(device, "edge params", &t.edge_params, U::UNIFORM),
            level_nodes: init(device, "tree levels", &t.level_nodes, U::STORAGE),
            incident: init(device, "incident corners", &t.incident, U::STORAGE),
            incident_start: init(device, "incident starts", &t.incident_start, U::STORAGE),
            no_seams: zeroed(device, "no seams", 16, U::STORAGE),
        }
    }
}

/// The bindings of group 0 that each pass uses (its entry point's in `gpu/src/update/`): the
/// vertex normals, the patches, the shared edges, the boxes and the refit of one depth.
const NORMALS_USE: [u32; 6] = [8, 9, 10, 11, 18, 19];
const PATCHES_USE: [u32; 7] = [1, 8, 9, 10, 11, 12, 17];
const EDGES_USE: [u32; 5] = [1, 12, 13, 14, 17];
const BOXES_USE: [u32; 4] = [1, 8, 12, 17];
const REFIT_USE: [u32; 6] = [1, 2, 3, 15, 16, 20];

/// The buffers of the update shader's group 0 by binding number, but the refit's depth (15,
/// one per depth): `scene`'s records, nodes and order, the update's own [`Buffers`] and the
/// seam records `seam_out`.
pub(super) fn bindings<'a>(
    scene: &'a GpuScene,
    b: &'a Buffers,
    seam_out: &'a wgpu::Buffer,
) -> Vec<(u32, &'a wgpu::Buffer)> {
    vec![
        (1, &scene.patches),
        (2, &scene.nodes),
        (3, &scene.order),
        (8, &b.build_params),
        (9, &b.positions),
        (10, &b.normals),
        (11, &b.triangles),
        (12, &b.remedy),
        (13, &b.edge_params),
        (14, &b.pairs),
        (16, &b.level_nodes),
        (17, seam_out),
        (18, &b.incident),
        (19, &b.incident_start),
        (20, &b.node_cost),
    ]
}

/// The bind group of `pipeline`'s group 0 (the layout its shader implies): the buffers of
/// `bindings` at the binding numbers it `uses`. Call inside [`scoped`](crate::device::scoped).
fn group(
    device: &wgpu::Device,
    pipeline: &wgpu::ComputePipeline,
    bindings: &[(u32, &wgpu::Buffer)],
    uses: &[u32],
) -> wgpu::BindGroup {
    let entries: Vec<_> = uses
        .iter()
        .filter_map(|u| bindings.iter().find(|(k, _)| k == u))
        .map(|&(k, buffer)| bind_entry(k, buffer))
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("smoothtri update"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// The bind groups of the vertex normals pass and of the patch, edge and box passes over
/// `bindings` ([`bindings`]). Call inside [`scoped`](crate::device::scoped).
pub(super) fn pass_binds(
    device: &wgpu::Device,
    p: &UpdatePipelines,
    bindings: &[(u32, &wgpu::Buffer)],
) -> (wgpu::BindGroup, [wgpu::BindGroup; 3]) {
    (
        group(device, &p.normals, bindings, &NORMALS_USE),
        [
            group(device, &p.patches, bindings, &PATCHES_USE),
            group(device, &p.edges, bindings, &EDGES_USE),
            group(device, &p.boxes, bindings, &BOXES_USE),
        ],
    )
}

/// Per depth of the tree (`levels`: each depth's `(start, count)` in the buffer of nodes by
/// depth), its node count and the refit pass's bind group over `bindings` ([`bindings`]) and
/// the depth's uniform. Call inside [`scoped`](crate::device::scoped).
pub(super) fn level_binds(
    device: &wgpu::Device,
    p: &UpdatePipelines,
    bindings: &[(u32, &wgpu::Buffer)],
    levels: &[(u32, u32)],
) -> Vec<(u32, wgpu::BindGroup)> {
    levels
        .iter()
        .map(|&(start, count)| {
            let bytes = word_bytes(&[start, count, 0, 0]);
            let level = init(device, "tree level", &bytes, BufferUsages::UNIFORM);
            let with_level: Vec<_> = bindings.iter().copied().chain([(15, &level)]).collect();
            (count, group(device, &p.refit, &with_level, &REFIT_USE))
        })
        .collect()
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
