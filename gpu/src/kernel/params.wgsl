// smoothtri's bounded-work ray kernel in WGSL: one invocation per ray, closest hit or any hit, BVH
// traversal with a fixed-size stack. The mathematics is the CPU kernel's (docs/METHOD.md §2–§8;
// core/src/kernel/): clip to the patch's box, re-base the ray at the box interval's middle, local
// ray, slab and shell clip (exact wall quadratics), bracketing at 8 points, at most ITERATIONS
// refinement steps of 8 points each and ESTIMATE_STEPS estimate steps of 4 (early stop at
// rounding), the rounding allowance 16 ε L / |f′|, then the exact surface normal once for the
// closest hit (forward-mode derivatives written out below: value and two partials for the surface,
// value and two t-derivatives for the edge curves; no finite differences).
//
// Work per patch test is fixed by WGSL constants: 8 + 8·ITERATIONS height evaluations at most (+
// 4·ESTIMATE_STEPS when ITERATIONS ≥ 1), every loop of the kernel has a constant trip count (a loop
// may stop early, never run longer). The traversal visits each node at most once (a budget of
// node_count visits), tests each index of `order` at most once (a budget of order_count tests) and
// keeps at most STACK pending nodes; anything else is reported through `status`, never a loop
// without end. Every buffer index is checked against the buffer's length before use.
//
// f32 throughout. Finiteness is tested on the bits (`fin`), so that no test depends on how the
// compiler treats NaN or infinity.

// Refinement steps (docs/METHOD.md §8; the CPU's `N`), set when the pipeline is created.
override ITERATIONS: u32 = 4u;
// Refinement stops once the bracket is within this fraction of the rounding allowance
// (`smoothtri::kernel::refine::EARLY_STOP`).
const EARLY_STOP: f32 = 0.25;
// 0: smooth patches; 1: flat triangles (Möller–Trumbore on the same traversal: the baseline).
override FLAT: u32 = 0u;
// 0: closest hit; 1: any hit (shadow rays).
override ANY_HIT: u32 = 0u;
// The shading normal of closest hits and frames: 0 the geometric normal; 1 seamless (smooth
// patches with their seams in `shade_in`); 2 Phong (flat triangles with their vertex normals in
// `shade_in`).
override SHADING: u32 = 0u;
// 1: the scene has patches with tilted sections (the shared line field, core/src/surface/field.rs);
// 0: every section is parallel, and the pipeline compiles without the tilted branches (they
// cost the parallel path about a fifth of its rate when present).
override TILTED: u32 = 1u;

// Interior bracketing samples K (the CPU's DEFAULT_SAMPLES): K + 2 = 8 points.
const SAMPLES: u32 = 6u;
// Traversal stack entries (the CPU's smoothtri::BVH_STACK: three pending children per level of
// four-wide nodes, MAX_DEPTH = 64).
const STACK: u32 = 192u;
// A node's unused slot (the CPU's smoothtri::BVH_EMPTY_SLOT).
const EMPTY_SLOT: u32 = 0xffffffffu;
// f32 machine epsilon.
const EPS: f32 = 1.1920929e-7;
// vec4s per smooth patch record and per flat triangle record (gpu/src/shader.rs `PATCH_VEC4`,
// `FLAT_VEC4`).
const PATCH_VEC4: u32 = 27u;
const FLAT_VEC4: u32 = 3u;
// Refinement parameters (the CPU's kernel/refine.rs).
const INNER_OF_SPREAD: f32 = 0.015625;
const INNER_OF_STOP: f32 = 0.4;
const OUTER_OF_SPREAD: f32 = 2.0;
const OUTER_OF_INNER: f32 = 8.0;
const OUTER_OF_WIDTH: f32 = 0.0625;
// Estimate steps of 4 points per patch test at most, on top of the ITERATIONS steps of 8 (the
// CPU's `refine::ESTIMATE_STEPS`).
const ESTIMATE_STEPS: u32 = 2u;
// Rounding allowance of t_error, in ulps of the patch's extent L (`pt.scale`; the CPU's
// `smoothtri::kernel::ROUNDING_ULPS`); also the snap of f at the shell interval's ends.
const ROUNDING_ULPS: f32 = 16.0;
// Side walls moved outward by this many ulps of L (the CPU's `kernel::WALL_MARGIN_ULPS`), so
// that neighbours' domains overlap at shared edges.
const WALL_MARGIN_ULPS: f32 = 8.0;
// core/src/surface/field.rs SECTION_NEWTON_STEPS.
const SECTION_NEWTON_STEPS: u32 = 6u;
// Coefficients of each tilt of a seam (smoothtri::mesh::TWIST_TERMS) and vec4s per seam record
// (gpu/src/shader.rs `SEAM_VEC4`).
const TWIST_TERMS: u32 = 6u;
const SEAM_VEC4: u32 = 10u;
// A pixel's patch on a miss.
const MISS: u32 = 0xffffffffu;
// Status bits.
const STATUS_CORRUPT: u32 = 1u;
const STATUS_STACK: u32 = 2u;

struct Params {
    ray_count: u32,
    node_count: u32,
    order_count: u32,
    patch_count: u32,
}

struct RayIn {
    o: vec3<f32>,
    t_min: f32,
    d: vec3<f32>,
    t_max: f32,
}

struct HitOut {
    t: f32,
    t_error: f32,
    w1: f32,
    w2: f32,
    point: vec3<f32>,
    patch_id: u32,
    normal: vec3<f32>,
    flags: u32,
    shading: vec3<f32>, // the shading normal (SHADING), else the normal
    pad: u32,
}

// The frame's camera (host/src/camera.rs `Camera`), light and output (gpu/src/frame.rs
// `FrameView`).
struct View {
    eye: vec3<f32>,
    tan_half: f32,
    forward: vec3<f32>,
    aspect: f32,
    right: vec3<f32>,
    eps: f32,        // the shadow ray's offset along the primary ray, and its t_min
    up: vec3<f32>,
    heat_scale: f32, // > 0: the heat map of t_error · heat_scale; 0: shaded
    light: vec3<f32>,
    width: u32,
    height: u32,
}

// One pixel's primary hit (patch MISS on a miss).
struct PixelOut {
    point: vec3<f32>,
    patch_id: u32,
    t_error: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// A four-wide node (core/src/bvh/node.rs `BvhNode`): the four children's boxes by coordinate
// (lo[axis], hi[axis]), and per slot a child node (count 0), a leaf `order[child..child + count]`,
// or EMPTY_SLOT.
struct Node {
    lo: array<vec4<f32>, 3>,
    hi: array<vec4<f32>, 3>,
    child: vec4<u32>,
    count: vec4<u32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> patches: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> nodes: array<Node>;
@group(0) @binding(3) var<storage, read> order: array<u32>;
@group(0) @binding(4) var<storage, read> rays: array<RayIn>;
@group(0) @binding(5) var<storage, read_write> hits: array<HitOut>;
@group(0) @binding(6) var<storage, read_write> status: array<atomic<u32>>;
// Per patch: its seam record (SHADING = 1) or its three world vertex normals (SHADING = 2).
@group(0) @binding(7) var<storage, read> shade_in: array<vec4<f32>>;
@group(1) @binding(0) var<uniform> view: View;
// Per pixel, row-major: the colour (r | g << 8 | b << 16 | 255 << 24) and the primary hit.
@group(1) @binding(1) var<storage, read_write> image: array<u32>;
@group(1) @binding(2) var<storage, read_write> pixels: array<PixelOut>;
// [shadow rays traced, the largest t_error's bits]
@group(1) @binding(3) var<storage, read_write> frame_stats: array<atomic<u32>, 4>;

fn fin(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn fin3(v: vec3<f32>) -> bool {
    return fin(v.x) && fin(v.y) && fin(v.z);
}
