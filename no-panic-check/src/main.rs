//! Freestanding `no_std`, `no_main` binary that calls **every public function and type** of the
//! core on opaque inputs, in `f32`, `f64` and `FastF32` (feature `micromath`), plus dual
//! numbers over them.
//!
//! Its panic handler calls `smoothtri_panic_path_survived`, a symbol defined nowhere: if any
//! panic path of the core survives optimisation, the handler is referenced and the link fails
//! with "undefined reference to `smoothtri_panic_path_survived`". A successful link proves the
//! called code cannot panic.
//!
//! Coverage is by construction: [`exercise`] is generic over the precision and is instantiated
//! for each; when a public item is added to the core, add its call here (the list at the top of
//! each function mirrors the core's modules).
#![no_std]
#![no_main]

use core::fmt::Write;
use core::hint::black_box;

use smoothtri::mesh::{
    MeshError, Seam, SharedEdge, VertexClamp, clamp_vertex_normals, close_cracks, fit_seams,
    shared_edges,
};
use smoothtri::{
    Aabb, BoxBvh, BuildError, BuildOptions, Bvh, BvhError, BvhNode, DEFAULT_SAMPLES, DynamicScene,
    EdgeWork, FastF32, Float, Hit, KernelStats, LineField, OnRejected, Patch, PatchError, Ray,
    Scene, SceneSizes, SceneStorage, Vertices, flat_hit, max_height_evals, max_lane_calls,
    moller_trumbore,
};

unsafe extern "C" {
    fn smoothtri_panic_path_survived() -> !;
    fn exit(code: i32) -> !;
}

#[panic_handler]
fn on_panic(_: &core::panic::PanicInfo) -> ! {
    // SAFETY: never executed when the link succeeds; the symbol does not exist.
    unsafe { smoothtri_panic_path_survived() }
}

/// The upper half of the unit octahedron: its four corners on the equator, then its apex
/// (the vertices of [`builder`] and [`dynamic`]).
const UPPER_OCTAHEDRON: [[f64; 3]; 5] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Triangles of the meshes [`builder`] and [`dynamic`] build (the triangle arrays of
/// [`Arrays`]).
const T: usize = 4;

/// The arrays of a [`SceneStorage`] for [`T`] triangles (their ids, BVH order and corner
/// indices, `3 T` shared edges, `3 T / 2` edge-work slots), `P` patches, `N` BVH nodes, `S`
/// seams and `V` vertices (positions, normals, clamped normals and clamps: 0 where the build
/// needs none).
struct Arrays<F: Float, const P: usize, const N: usize, const S: usize, const V: usize> {
    patches: [Patch<F>; P],
    ids: [u32; T],
    nodes: [BvhNode<F>; N],
    order: [u32; T],
    seams: [Seam<F>; S],
    triangles: [[u32; 3]; T],
    edges: [SharedEdge; 3 * T],
    work: [EdgeWork<F>; 3 * T / 2],
    /// Vertex positions, vertex normals and clamped normals.
    vectors: [[F::Vec3; V]; 3],
    clamps: [VertexClamp<F>; V],
}

impl<F: Float, const P: usize, const N: usize, const S: usize, const V: usize>
    Arrays<F, P, N, S, V>
{
    /// Every array filled with defaults (zero vectors).
    fn new() -> Self {
        let zero = v::<F>(0.0, 0.0, 0.0);
        Self {
            patches: [Patch::default(); P],
            ids: [0; T],
            nodes: [BvhNode::default(); N],
            order: [0; T],
            seams: [Seam::default(); S],
            triangles: [[0; 3]; T],
            edges: [SharedEdge::default(); 3 * T],
            work: [EdgeWork::default(); 3 * T / 2],
            vectors: [[zero; V]; 3],
            clamps: [VertexClamp::default(); V],
        }
    }

    /// The storage of a build over these arrays.
    fn storage(&mut self) -> SceneStorage<'_, F> {
        let [positions, normals, clamped] = &mut self.vectors;
        SceneStorage {
            patches: &mut self.patches,
            triangle_ids: &mut self.ids,
            nodes: &mut self.nodes,
            order: &mut self.order,
            seams: &mut self.seams,
            triangles: &mut self.triangles,
            edges: &mut self.edges,
            edge_work: &mut self.work,
            vertex_positions: positions,
            vertex_normals: normals,
            clamped_normals: clamped,
            vertex_clamps: &mut self.clamps,
        }
    }
}

/// A fixed-size `fmt::Write` sink (the `Display` impls are public functions too).
struct Sink {
    buf: [u8; 128],
    len: usize,
}

impl Write for Sink {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for (slot, b) in self.buf.iter_mut().skip(self.len).zip(s.bytes()) {
            *slot = b;
        }
        self.len = (self.len + s.len()).min(self.buf.len());
        Ok(())
    }
}

fn display_len(x: &dyn core::fmt::Display) -> u32 {
    let mut sink = Sink {
        buf: [0; 128],
        len: 0,
    };
    let _ = write!(sink, "{x}");
    black_box(sink.buf);
    sink.len as u32
}

/// A world vector from `f64` components, opaque to the optimiser.
fn v<F: Float>(x: f64, y: f64, z: f64) -> F::Vec3 {
    black_box(F::from_dvec3(glam::DVec3::new(x, y, z)))
}

/// Whether every component of a vector is finite.
fn fin<F: Float>(v: F::Vec3) -> bool {
    let d = F::to_dvec3(v);
    F::from_f64(d.x).is_fin() && F::from_f64(d.y).is_fin() && F::from_f64(d.z).is_fin()
}

fn c<F: Float>(x: f64) -> F {
    black_box(F::from_f64(x))
}

/// The public scalar face: `Float`'s constants and functions, and the work bound.
fn scalars<F: Float>() -> u32 {
    let x = c::<F>(2.0);
    let y = c::<F>(-0.5);
    let f = x.sqrt() + x.min(y) + x.max(y) + F::from_f64(F::EPSILON.to_f64()) - F::MIN_POSITIVE
        + F::MAX * F::ZERO
        + F::MIN * F::ZERO
        + F::ONE;
    let w = F::to_dvec3(v::<F>(0.3, 0.2, 0.1));
    let a = F::to_array3(F::from_array3([x, y, f]));
    f.is_fin() as u32
        + a[2].is_fin() as u32
        + f.is_nan() as u32
        + (w.x > 0.0) as u32
        + max_lane_calls(black_box(DEFAULT_SAMPLES), black_box(8)) as u32
        + max_height_evals(black_box(DEFAULT_SAMPLES), black_box(8)) as u32
}

fn exercise<F: Float>() -> u32 {
    let mut acc = scalars::<F>();
    let p = [
        v::<F>(1.0, 0.0, 0.0),
        v::<F>(0.0, 1.0, 0.0),
        v::<F>(0.0, 0.0, 1.0),
    ];
    let n = black_box(p);
    // Construction: both constructors and every error's Display.
    let steep = [v::<F>(1.0, 0.0, -0.2), n[1], n[2]];
    for r in [
        Patch::<F>::new(p, n),
        Patch::<F>::new(p, steep),
        Patch::<F>::new_or_tilted(p, steep),
    ] {
        match r {
            Ok(patch) => acc += patch.normal_clamp().is_some() as u32,
            Err(e) => acc += display_len(&e),
        }
    }
    acc += display_len(&black_box(PatchError::ZeroNormal { vertex: 1 }));
    // The shared line field: a patch with tilted sections (normals at unequal angles to the
    // face), its evaluation and its kernel (the section's Newton steps, the ruled walls).
    let uneven = [v::<F>(0.3, 0.3, 0.9), n[1], n[2]];
    for field in [LineField::Face, black_box(LineField::Vertex)] {
        for r in [
            Patch::<F>::with_field(p, uneven, field),
            Patch::<F>::new_or_tilted_with(p, steep, field),
        ] {
            if let Ok(q) = r {
                let ray = Ray::<F>::new(v::<F>(2.0, 2.0, 2.0), v::<F>(-1.0, -1.0, -1.0));
                let h = q.closest_hit(&ray, c::<F>(0.0), c::<F>(f64::INFINITY), 4);
                acc += h.map_or(0, |h| h.t.is_fin() as u32);
                acc += fin::<F>(q.point(c::<F>(0.1), c::<F>(0.7))) as u32;
            }
        }
    }
    let Ok(patch) = Patch::<F>::new_or_tilted(p, n) else {
        return acc;
    };
    // Evaluation.
    let (w1, w2) = (c::<F>(0.2), c::<F>(0.3));
    let x = patch.point(w1, w2);
    let h = patch.height(w1, w2);
    let (xn, nn) = patch.point_normal(w1, w2);
    let (d1, d2) = patch.derivatives(w1, w2);
    let (ce, cn) = patch.edge_point_normal(black_box(4), w1);
    let [v0, _, _] = patch.vertices();
    let [n0, _, _] = patch.normals();
    let nf = patch.face_normal();
    let (lo, hi) = patch.height_range();
    acc += patch.roots_certified() as u32;
    let vs = [x, xn, nn, d1, d2, ce, cn, v0, n0, nf];
    acc += vs.iter().filter(|q| fin::<F>(**q)).count() as u32;
    acc += (h + lo + hi).is_fin() as u32;
    // Boxes.
    let b = patch.bounds();
    let u = b.union(&Aabb::new(b.min(), b.max())).union(&Aabb::EMPTY);
    let e = Aabb::<F>::default();
    acc += fin::<F>(u.max()) as u32 + (e == Aabb::EMPTY) as u32;
    let data = patch.data();
    acc += (data.sigma[1].is_fin() && data == black_box(patch).data()) as u32;
    // Rays and the per-patch kernels.
    let ray = Ray::<F>::new(v::<F>(2.0, 2.0, 2.0), v::<F>(-1.0, -1.0, -1.0));
    let at = ray.at(c::<F>(0.5));
    acc += fin::<F>(at) as u32;
    let (t0, t1) = (c::<F>(0.0), c::<F>(f64::INFINITY));
    let hit: Option<Hit<F>> = patch.closest_hit(&ray, t0, t1, 8);
    // The study of the predicted search (smoothtri::internal).
    for s in smoothtri::internal::search_study(&patch, &ray, t0, t1, black_box(4)) {
        acc += s.evals + s.crossing.is_some() as u32;
    }
    if let Some([e, b]) = smoothtri::internal::predictor_error(&patch, black_box(8)) {
        acc += (e <= b) as u32;
    }
    let (hit2, stats): (_, KernelStats) =
        patch.closest_hit_stats::<DEFAULT_SAMPLES>(&ray, t0, t1, 5);
    let (hit3, _) = patch.closest_hit_stats::<0>(&ray, t0, t1, 0);
    let verts = patch.vertices();
    let mt = moller_trumbore(&verts, &ray, t0, t1);
    let flat = flat_hit(&verts, None, &ray, t0, t1);
    let phong = flat_hit(&verts, Some(&patch.normals()), &ray, t0, t1);
    acc += hit.map_or(0, |h| {
        h.patch + h.front_face as u32 + h.t_error.is_fin() as u32
    });
    acc += hit2.is_some() as u32 + hit3.is_some() as u32 + mt.is_some() as u32;
    acc += flat.is_some() as u32 + phong.is_some() as u32;
    acc += stats.height_evals + stats.normal_evals;
    // BVH over a few copies, in caller-provided storage, every query.
    const COUNT: usize = 8;
    let patches = [patch; COUNT];
    let mut nodes = [BvhNode::<F>::default(); COUNT - 1];
    let mut order = [0u32; COUNT];
    match Bvh::build(black_box(&patches), &mut nodes, &mut order) {
        Ok(bvh) => {
            acc += bvh.node_count() as u32 + bvh.memory_bytes() as u32;
            acc += bvh.patches().len() as u32;
            let root = bvh.nodes().first().copied().unwrap_or_default();
            let k = black_box(2usize);
            acc += root.child(k) + root.count(k) + bvh.order().len() as u32;
            acc += fin::<F>(root.bounds(k).min()) as u32;
            if let Some(h) = bvh.closest_hit(&ray, t0, t1, 8) {
                acc += h.patch;
            }
            acc += bvh.any_hit(&ray, t0, t1, 4) as u32;
            let with = bvh.closest_with(&ray, t0, t1, |_, p, a, b| {
                flat_hit(&p.vertices(), Some(&p.normals()), &ray, a, b)
            });
            acc += with.is_some() as u32;
            // Re-wrapped storage, checked once.
            if let Ok(again) = Bvh::from_parts(&patches, bvh.nodes(), bvh.order()) {
                acc += again.closest_hit(&ray, t0, t1, 2).is_some() as u32;
            }
        }
        Err(e) => acc += display_len(&e),
    }
    // Storage not made by `build`: typed errors, never a panic.
    let junk = [BvhNode::<F>::default(); 3];
    let b = [junk[1].bounds(black_box(9)); 4];
    let junk = [
        junk[0],
        BvhNode::new(b, black_box([1, 2, 0, 7]), [0, 0, 0, 3]),
        BvhNode::new([Aabb::EMPTY; 4], black_box([0; 4]), black_box([9; 4])),
    ];
    match Bvh::from_parts(black_box(&patches), black_box(&junk), black_box(&order)) {
        Ok(raw) => acc += raw.closest_hit(&ray, t0, t1, 2).is_some() as u32,
        Err(e) => acc += display_len(&e),
    }
    let mut few = [BvhNode::<F>::default(); 1];
    if let Err(e) = Bvh::build(black_box(&patches), &mut few, &mut order) {
        acc += display_len(&e);
    }
    // The tree over caller boxes, with caller leaf tests.
    let boxes = patches.map(|p| black_box(p.bounds()));
    let mut nodes = [BvhNode::<F>::default(); COUNT - 1];
    acc += BoxBvh::<F>::nodes_needed(black_box(COUNT)) as u32;
    match BoxBvh::build(black_box(&boxes), &mut nodes, &mut order) {
        Ok(tree) => {
            acc += tree.node_count() as u32 + tree.memory_bytes() as u32;
            acc += tree.order().len() as u32 + tree.nodes().len() as u32;
            let with = tree.closest_with(&ray, t0, t1, |i, a, b| {
                let p = patches.get(i as usize)?;
                flat_hit(&p.vertices(), None, &ray, a, b)
            });
            acc += with.is_some() as u32;
            acc += tree.any_with(&ray, t0, t1, |i, a, b| {
                patches
                    .get(i as usize)
                    .and_then(|p| moller_trumbore(&p.vertices(), &ray, a, b))
                    .is_some()
            }) as u32;
            if let Ok(again) = BoxBvh::from_parts(COUNT, tree.nodes(), tree.order()) {
                acc += again.node_count() as u32;
            }
            if let Ok(bvh) = Bvh::from_parts(&patches, tree.nodes(), tree.order()) {
                acc += bvh.tree().node_count() as u32;
            }
        }
        Err(e) => acc += display_len(&e),
    }
    if let Err(e) = BoxBvh::from_parts(black_box(COUNT), black_box(&junk), black_box(&order)) {
        acc += display_len(&e);
    }
    acc += display_len(&black_box(BvhError::Internal));
    acc += seams(&patches, &ray);
    acc
}

/// Seamless shading normals: the fit over an opaque index buffer (shared, boundary and
/// non-manifold edges, and every error), both normal functions, with fitted and opaque
/// coefficients.
fn seams<F: Float>(patches: &[Patch<F>], ray: &Ray<F>) -> u32 {
    const COUNT: usize = 8;
    let mut acc = 0;
    let tris: [[u32; 3]; COUNT] = black_box([
        [0, 1, 2],
        [2, 1, 3],
        [1, 2, 4],
        [3, 4, 5],
        [5, 4, 3],
        [0, 2, 5],
        [6, 7, 8],
        [8, 7, 6],
    ]);
    let mut scratch = [SharedEdge::default(); 3 * COUNT];
    let mut out = [Seam::<F>::default(); COUNT];
    let Some(ps) = patches.get(..COUNT) else {
        return acc;
    };
    match fit_seams(ps, &tris, black_box(9), &mut scratch, &mut out) {
        Ok(n) => acc += n as u32,
        Err(e) => acc += display_len(&e),
    }
    for bad in [
        fit_seams(ps, &tris, black_box(3), &mut scratch, &mut out),
        fit_seams(ps, &tris, 9, &mut scratch[..5], &mut out),
        fit_seams(ps, &tris[..2], 9, &mut scratch, &mut out),
    ] {
        if let Err(e) = bad {
            acc += display_len(&e);
        }
    }
    acc += display_len(&black_box(MeshError::TooManyTriangles));
    // The pairing a port of the edge pass reads, and its errors.
    match shared_edges(&tris, black_box(9), &mut scratch) {
        Ok(pairs) => {
            acc += pairs
                .iter()
                .map(|e| e.sides()[0] ^ e.sides()[1])
                .sum::<u32>()
        }
        Err(e) => acc += display_len(&e),
    }
    if let Err(e) = shared_edges(&tris, 9, &mut scratch[..5]) {
        acc += display_len(&e);
    }
    // The crack nodes and the seam fit's map a port of the update uploads.
    acc += smoothtri::internal::crack_nodes()
        .iter()
        .filter(|t| (0.0..=1.0).contains(*t))
        .count() as u32;
    acc += smoothtri::internal::seam_fit_matrix()
        .iter()
        .flatten()
        .filter(|x| x.is_finite())
        .count() as u32;
    // Crack closing on a copy (it widens the patches' walls and boxes), and its errors.
    let mut sealed = [ps[0]; COUNT];
    sealed.copy_from_slice(ps);
    match close_cracks(&mut sealed, &tris, black_box(9), &mut scratch) {
        Ok(r) => {
            acc += r.shared_edges as u32 + r.open_edges as u32 + (r.widest_gap > 0.0) as u32;
            if let Some(h) = sealed[1].closest_hit(ray, c::<F>(0.0), c::<F>(f64::INFINITY), 4) {
                acc += h.t.is_fin() as u32;
            }
            acc += sealed[2].data().reach.iter().filter(|r| r.is_fin()).count() as u32;
        }
        Err(e) => acc += display_len(&e),
    }
    for bad in [
        close_cracks(&mut sealed, &tris, black_box(3), &mut scratch),
        close_cracks(&mut sealed, &tris, 9, &mut scratch[..5]),
        close_cracks(&mut sealed, &tris[..2], 9, &mut scratch),
    ] {
        if let Err(e) = bad {
            acc += display_len(&e);
        }
    }
    let mut wild = black_box(out[0]);
    wild.common[1][3] = c::<F>(f64::NAN);
    wild.common_along[0][5] = c::<F>(-1e30);
    wild.common[2][0] = c::<F>(1e30);
    let (w1, w2) = (c::<F>(0.25), c::<F>(0.5));
    for (seam, patch) in out.iter().chain([&wild]).zip(ps.iter().cycle()) {
        let n = seam.shading_normal(patch, w1, w2);
        let g = patch.point_normal(w1, w2).1;
        let m = seam.correct(patch, w1, w2, g);
        acc += fin::<F>(n) as u32 + fin::<F>(m) as u32;
        acc += seam.is_zero() as u32 + (seam == &wild) as u32;
    }
    if let Some(p) = ps.first() {
        if let Some(h) = p.closest_hit(ray, c::<F>(0.0), c::<F>(f64::INFINITY), 4) {
            let n = wild.correct(p, h.w1, h.w2, h.normal);
            acc += fin::<F>(n) as u32;
        }
    }
    acc
}

/// The remedy per vertex: a square pyramid whose apex normal is steep for every face, its
/// report, and its three error paths.
fn vertex_clamps<F: Float>() -> u32 {
    let pos = [
        v::<F>(0.0, 0.0, 0.0),
        v::<F>(1.0, 0.0, 0.0),
        v::<F>(1.0, 1.0, 0.0),
        v::<F>(0.0, 1.0, 0.0),
        v::<F>(0.5, 0.5, 0.2),
    ];
    let nrm = [
        v::<F>(-1.0, -1.0, 1.0),
        v::<F>(1.0, -1.0, 1.0),
        v::<F>(1.0, 1.0, 1.0),
        v::<F>(-1.0, 1.0, 1.0),
        black_box(v::<F>(1.0, 0.0, 0.05)),
    ];
    let tris = [[0u32, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    let mut out = nrm;
    let mut scratch = [VertexClamp::<F>::default(); 5];
    let mut acc = 0;
    match clamp_vertex_normals(&pos, &nrm, &tris, &mut out, &mut scratch) {
        Ok(r) => acc += (r.clamped + r.unresolved) as u32 + fin::<F>(out[4]) as u32,
        Err(e) => acc += display_len(&e),
    }
    for r in [
        clamp_vertex_normals(&pos, &nrm, &[[0, 1, 9]], &mut out, &mut scratch),
        clamp_vertex_normals(&pos, &nrm, &tris, &mut out, &mut scratch[..2]),
        clamp_vertex_normals(&pos, &nrm[..2], &tris, &mut out, &mut scratch),
    ] {
        if let Err(e) = r {
            acc += display_len(&e);
        }
    }
    acc
}

/// The scene builder into caller storage: both fields, with and without seams, every query and
/// report, and its errors (short storage, bad indices, bad layouts, nothing usable).
fn builder<F: Float>() -> u32 {
    const V: usize = 6;
    // An octahedron's upper half plus a degenerate triangle (the apex again), interleaved
    // position + normal.
    let mut buf = [0.0f64; 6 * V];
    let apex = UPPER_OCTAHEDRON[4];
    let corners = UPPER_OCTAHEDRON.iter().chain([&apex]);
    for (slot, p) in buf.chunks_exact_mut(6).zip(corners) {
        for (k, x) in p.iter().enumerate() {
            if let Some(s) = slot.get_mut(k) {
                *s = *x;
            }
            if let Some(s) = slot.get_mut(k + 3) {
                *s = *x;
            }
        }
    }
    let buf = black_box(buf);
    let tris: [[u32; 3]; T] = black_box([[0, 1, 4], [1, 2, 4], [2, 3, 4], [4, 5, 4]]);
    let mut acc = 0;
    let (Ok(pos), Ok(nrm)) = (
        Vertices::strided(&buf, 0, 6, V),
        Vertices::strided(&buf, 3, 6, V),
    ) else {
        return acc;
    };
    acc += pos.len() as u32 + pos.is_empty() as u32 + pos.get(black_box(9)).is_none() as u32;
    let packed = Vertices::packed(black_box(&buf));
    acc += packed.get(2).map_or(0, |p| (p[0] > 0.0) as u32);
    if let Err(e) = Vertices::strided(&buf, black_box(5), 6, V) {
        acc += display_len(&e);
    }
    for field in [LineField::Face, black_box(LineField::Vertex)] {
        for seams in [false, black_box(true)] {
            let options = BuildOptions {
                field,
                seams,
                ..BuildOptions::default()
            };
            let Some(sizes) = SceneSizes::new(V, T, &options) else {
                continue;
            };
            acc += sizes.bytes::<F>().map_or(0, |b| b as u32);
            let mut arrays = Arrays::<F, T, { 2 * T - 1 }, T, V>::new();
            let storage = arrays.storage();
            let mut rejected = 0u32;
            let mut observed = options.with_observer(OnRejected(|t: u32, e: PatchError| {
                rejected += t + display_len(&e)
            }));
            let built = Scene::<F>::build(pos, nrm, &tris, &mut observed, storage);
            match built {
                Ok(scene) => {
                    let ray = Ray::<F>::new(v::<F>(0.2, 0.3, 3.0), v::<F>(0.0, 0.0, -1.0));
                    let (t0, t1) = (c::<F>(0.0), c::<F>(f64::INFINITY));
                    if let Some(h) = scene.closest_hit(&ray, t0, t1, 4) {
                        acc += h.triangle + fin::<F>(h.shading_normal) as u32;
                        acc += fin::<F>(scene.shading_normal(&h.hit)) as u32;
                        acc += scene.scene_hit(h.hit).triangle;
                    }
                    acc += scene.any_hit(&ray, t0, t1, 4) as u32;
                    acc += scene.patch_of_triangle(black_box(3)).is_some() as u32;
                    acc += scene.patch_index(black_box(2)).map_or(0, |i| i as u32);
                    acc += scene.bvh().node_count() as u32 + scene.patches().len() as u32;
                    acc += scene.triangle_ids().len() as u32 + scene.seams().len() as u32;
                    acc += scene.memory_bytes() as u32;
                    let r = scene.report();
                    acc += (r.patches + r.remedied + r.bvh_nodes) as u32;
                    acc += r
                        .rejected
                        .by_reason()
                        .iter()
                        .map(|(_, n)| *n as u32)
                        .sum::<u32>();
                    acc += r.seam_edges.unwrap_or(0) as u32 + r.cracks.shared_edges as u32;
                    acc += r.first_rejected.map_or(0, |(t, e)| t + display_len(&e));
                    acc += r.vertex_clamps.map_or(0, |c| c.clamped as u32);
                }
                Err(e) => acc += display_len(&e),
            }
            acc += rejected;
        }
    }
    // Errors: an index out of range, nothing usable, no triangles, short storage.
    let mut options = BuildOptions::default();
    let mut arrays = Arrays::<F, 1, { 2 * T - 1 }, 0, 0>::new();
    let bad: [&[[u32; 3]]; 4] = black_box([&[[0, 1, 9]], &[[4, 5, 4]], &[], &tris]);
    for tris in bad {
        let storage = arrays.storage();
        match Scene::<F>::build(pos, nrm, tris, &mut options, storage) {
            Ok(s) => acc += s.patches().len() as u32,
            Err(e) => acc += display_len(&e),
        }
    }
    acc += display_len(&black_box(BuildError::TooLarge));
    acc
}

/// A scene updated in place ([`DynamicScene`]): a build, an update with moved vertices (a
/// triangle collapsed), its queries, and the update's errors (a NaN vertex, a count change,
/// other options).
fn dynamic<F: Float>() -> u32 {
    const V: usize = 5;
    let p = UPPER_OCTAHEDRON;
    let flat = |q: [[f64; 3]; V]| {
        let mut out = [0.0f64; 3 * V];
        for (o, x) in out.iter_mut().zip(q.iter().flatten()) {
            *o = *x;
        }
        out
    };
    let pos = black_box(flat(p));
    let mut moved = p;
    moved[1] = moved[0];
    let moved = black_box(flat(moved));
    let mut nan = pos;
    nan[4] = black_box(f64::NAN);
    let tris: [[u32; 3]; T] = black_box([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]);
    let mut options = BuildOptions {
        seams: black_box(true),
        ..BuildOptions::default()
    };
    let mut arrays = Arrays::<F, T, T, T, 0>::new();
    let storage = arrays.storage();
    let pk = Vertices::packed;
    let mut acc = 0;
    let mut scene = match DynamicScene::<F>::build(pk(&pos), pk(&pos), &tris, &mut options, storage)
    {
        Ok(s) => s,
        Err(e) => return display_len(&e),
    };
    let short: &[f64] = pos.get(..6).unwrap_or(&[]);
    let cases: [(&[f64], &[f64]); 4] = [(&moved, &pos), (&nan, &pos), (&pos, &pos), (short, short)];
    for (q, n) in cases {
        match scene.update(pk(q), pk(n), &mut options) {
            Ok(r) => acc += (r.patches + r.bvh_nodes) as u32 + r.bvh_refitted as u32,
            Err(e) => acc += display_len(&e),
        }
        let s = scene.scene();
        let ray = Ray::<F>::new(v::<F>(0.2, 0.3, 3.0), v::<F>(0.0, 0.0, -1.0));
        let (t0, t1) = (c::<F>(0.0), c::<F>(f64::INFINITY));
        if let Some(h) = s.closest_hit(&ray, t0, t1, 4) {
            acc += h.triangle;
        }
        acc += s.any_hit(&ray, t0, t1, 4) as u32;
        acc += s
            .patches()
            .iter()
            .filter(|p| p.rejected().is_some())
            .count() as u32;
        acc += (s.report().bvh_cost > 1.0) as u32;
    }
    if let Err(e) = scene.update(pk(&pos), pk(&pos), &mut BuildOptions::default()) {
        acc += display_len(&e);
    }
    acc + scene.report().patches as u32
}

/// Entry point: aligns the stack as the C ABI expects, then calls [`main`].
#[cfg(target_arch = "x86_64")]
#[unsafe(naked)]
#[unsafe(no_mangle)]
pub extern "C" fn _start() -> ! {
    core::arch::naked_asm!("xor ebp, ebp", "and rsp, -16", "call {main}", "ud2", main = sym main)
}

extern "C" fn main() -> ! {
    let r = exercise::<f32>() + exercise::<f64>() + exercise::<FastF32>();
    let r = r + builder::<f32>() + builder::<f64>() + builder::<FastF32>();
    let r = r + dynamic::<f32>() + dynamic::<f64>() + dynamic::<FastF32>();
    let r = r + vertex_clamps::<f32>() + vertex_clamps::<f64>() + vertex_clamps::<FastF32>();
    // SAFETY: libc's exit, linked from the C library (only the start files are left out).
    unsafe { exit(if black_box(r) >= 3 { 0 } else { 1 }) }
}
