// smoothtri's bounded-work ray kernel in WGSL: one invocation per ray, closest hit or any hit,
// BVH traversal with a fixed-size stack. The mathematics is the CPU kernel's (docs/METHOD.md
// §2–§8; core/src/kernel/): clip to the patch's box, re-base the ray at the box interval's
// middle, local ray, slab and shell clip (exact wall quadratics), bracketing at 8 points,
// at most ITERATIONS refinement steps of 8 points each and ESTIMATE_STEPS estimate steps of 4 (early stop at
// rounding), the rounding allowance 16 ε L / |f′|,
// then the exact surface normal once for the closest hit (forward-mode derivatives written out
// below: value and two partials for the surface, value and two t-derivatives for the edge
// curves; no finite differences).
//
// Work per patch test is fixed by WGSL constants: 8 + 8·ITERATIONS height evaluations at most
// (+ 4·ESTIMATE_STEPS when ITERATIONS ≥ 1), every loop of the kernel has a constant trip count (a loop may stop early, never run longer).
// The traversal visits each node at most once (a budget of node_count visits), tests each index
// of `order` at most once (a budget of order_count tests) and keeps at most STACK pending nodes;
// anything else is reported through `status`, never a loop without end. Every buffer index is
// checked against the buffer's length before use.
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
// vec4s per smooth patch record and per flat triangle record (see lib.rs, `PATCH_VEC4`).
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
// (lib.rs `SEAM_VEC4`).
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

// The frame's camera (testkit/src/camera.rs `Camera`), light and output (frame.rs `FrameView`).
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

// A four-wide node (core/src/bvh/node.rs `BvhNode`): the four children's boxes by coordinate (lo[axis],
// hi[axis]), and per
// slot a child node (count 0), a leaf `order[child..child + count]`, or EMPTY_SLOT.
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

// ---------------------------------------------------------------------------------------------
// Patch records

// One edge j (from A = Pj to B = Pj+1) with the CPU's per-patch precomputation (Prepared /
// PreparedEdge in core/src/surface/lanes/mod.rs), computed once on the host at upload.
struct Edge {
    a: vec2<f32>,   // A (local z = 0)
    da: vec2<f32>,  // dA (xy; its z is daz)
    e: vec2<f32>,   // e = B − A (z = 0)
    gd: vec2<f32>,  // gd = dB − dA (xy; its z is gdz)
    daz: f32,       // dA.z (1 for parallel sections)
    gdz: f32,       // dB.z − dA.z (0 for parallel sections)
    na: vec3<f32>,  // unit normal at A
    nb: vec3<f32>,  // unit normal at B
    k1: f32,        // κ(S¹): anchor A, axis nA
    k2: f32,        // κ(S²): anchor B, axis nB
    ee: f32,        // |e|²
    eg0: f32,       // e·g(t) = eg0 + t·eg1
    eg1: f32,
    gg0: f32,       // |g(t)|² = gg0 + t·(gg1 + t·gg2)
    gg1: f32,
    gg2: f32,
    ma: vec3<f32>,  // [dA·nA, gd·nA, e·nA]
    mb: vec3<f32>,  // [dA·nB, gd·nB, e·nB]
}

struct Patch {
    origin: vec3<f32>,
    scale: f32,     // 4 × longest edge + |origin|: the rounding allowance's L
    ex: vec3<f32>,
    ey: vec3<f32>,
    ez: vec3<f32>,
    sig_lo: f32,
    sig_hi: f32,
    p1x: f32,
    p2x: f32,
    p2y: f32,
    n0: vec3<f32>,
    n1: vec3<f32>,
    n2: vec3<f32>,
    d0: vec2<f32>,
    d1: vec2<f32>,
    d2: vec2<f32>,
    e0: Edge,
    e1: Edge,
    e2: Edge,
    reach: vec3<f32>, // per wall k (opposite vertex k): core's Patch::reach (close_cracks)
    dz: vec3<f32>,    // the di.z (all 1 for parallel sections, core/src/surface/field.rs)
    tilted: bool,     // some di.z differs from 1: the section of a point is found by Newton
}

fn load_edge(base: u32, a: vec2<f32>, da: vec2<f32>, daz: f32, dbz: f32, na: vec3<f32>,
    nb: vec3<f32>) -> Edge {
    let v0 = patches[base];
    let v1 = patches[base + 1u];
    let v2 = patches[base + 2u];
    let v3 = patches[base + 3u];
    let v4 = patches[base + 4u];
    return Edge(a, da, v0.xy, v0.zw, daz, dbz - daz, na, nb, v1.x, v1.y, v1.z, v1.w, v2.x, v2.y,
        v2.z, v2.w, v3.xyz, v4.xyz);
}

// The caller has checked id < patch_count (so every index below is inside the buffer).
fn load_patch(id: u32) -> Patch {
    let b = id * PATCH_VEC4;
    let v0 = patches[b];
    let v1 = patches[b + 1u];
    let v2 = patches[b + 2u];
    let v3 = patches[b + 3u];
    let v4 = patches[b + 4u];
    let v5 = patches[b + 5u];
    let v6 = patches[b + 6u];
    let v7 = patches[b + 7u];
    let v8 = patches[b + 8u];
    let v9 = patches[b + 9u];
    let p0 = vec2<f32>(0.0, 0.0);
    let p1 = vec2<f32>(v3.w, 0.0);
    let p2 = vec2<f32>(v4.w, v5.w);
    let d0 = vec2<f32>(v6.w, v7.w);
    let d1 = vec2<f32>(v8.w, v9.x);
    let d2 = vec2<f32>(v9.y, v9.z);
    // Without the tilted branches every di.z is 1 (a constant the compiler folds).
    let dz = select(vec3<f32>(patches[b + 14u].w, patches[b + 19u].w, patches[b + 24u].w),
        vec3<f32>(1.0), TILTED == 0u);
    let e0 = load_edge(b + 10u, p0, d0, dz.x, dz.y, v6.xyz, v7.xyz);
    let e1 = load_edge(b + 15u, p1, d1, dz.y, dz.z, v7.xyz, v8.xyz);
    let e2 = load_edge(b + 20u, p2, d2, dz.z, dz.x, v8.xyz, v6.xyz);
    let reach = vec3<f32>(patches[b + 13u].w, patches[b + 18u].w, patches[b + 23u].w);
    let tilted = dz.x != 1.0 || dz.y != 1.0 || dz.z != 1.0;
    return Patch(v0.xyz, v0.w, v1.xyz, v2.xyz, v3.xyz, v1.w, v2.w, v3.w, v4.w, v5.w,
        v6.xyz, v7.xyz, v8.xyz, d0, d1, d2, e0, e1, e2, reach, dz, tilted);
}

// ---------------------------------------------------------------------------------------------
// Boxes

struct Span {
    a: f32,
    b: f32,
    ok: bool,
}

// The interval of t in [t_min, t_max] inside the box (the CPU's Aabb::ray_interval, with
// inv = 1/d per component; a zero component keeps the range when the origin is between the
// slabs and rejects it otherwise).
fn box_span(lo: vec3<f32>, hi: vec3<f32>, o: vec3<f32>, d: vec3<f32>, inv: vec3<f32>,
    t_min: f32, t_max: f32) -> Span {
    var a = t_min;
    var b = t_max;
    for (var k = 0u; k < 3u; k++) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) {
                return Span(0.0, 0.0, false);
            }
        } else {
            let t1 = (lo[k] - o[k]) * inv[k];
            let t2 = (hi[k] - o[k]) * inv[k];
            a = max(a, min(t1, t2));
            b = min(b, max(t1, t2));
        }
    }
    return Span(a, b, a <= b && fin(a) && fin(b));
}

// ---------------------------------------------------------------------------------------------
// The height evaluation f(τ) = z − σS(X) (core/src/surface/lanes/height.rs, one point per call)

struct Root {
    s: f32,
    q: f32,
    sq: f32,
    ok: bool,
}

// Root nearest 0 of qa s² + 2 qb s + qc = 0, c = (qa, qb, qc) (sphere::nearest_root's stable
// form and double-root test; the axis may be scaled, m2 = |m|²).
fn root(c: vec3<f32>, k: f32, w2: f32, g2: f32, m2: f32) -> Root {
    let disc = c.y * c.y - c.x * c.z;
    let sq = sqrt(select(0.0, disc, disc > 0.0));
    let q = select(-c.y - sq, sq - c.y, c.y < 0.0);
    let tol = EPS * 16.0;
    let tol2 = tol * tol;
    let kk = k * k;
    let c_scale = 2.0 * (kk * w2 * w2 + 4.0 * w2 * m2);
    let b_scale = 2.0 * (kk * w2 * g2 + g2 * m2);
    let noise = (c.z * c.z <= tol2 * c_scale) && (c.y * c.y <= tol2 * b_scale);
    let s = c.z / select(1.0, q, q != 0.0);
    let ok = !noise && q != 0.0 && fin(s);
    return Root(select(0.0, s, ok), select(0.0, q, ok), sq, ok);
}

// Derivative s′ of a root from the coefficients' derivatives dc (forward mode; the square root
// has derivative 0 where the discriminant is clamped).
fn root_derivative(r: Root, c: vec3<f32>, dc: vec3<f32>) -> f32 {
    let ddisc = 2.0 * c.y * dc.y - dc.x * c.z - c.x * dc.z;
    let dsq = select(0.0, ddisc / select(1.0, 2.0 * r.sq, r.sq > 0.0), r.sq > 0.0);
    let dq = select(-dc.y - dsq, dsq - dc.y, c.y < 0.0);
    let ds = (dc.z - r.s * dq) / select(1.0, r.q, r.ok);
    return select(0.0, ds, r.ok && fin(ds));
}

struct PointNormal {
    c: vec3<f32>,
    n: vec3<f32>,
}

// Conjugation point c(t) of an edge and its normal n*(t) scaled by |c′|² (eq. (3)).
fn edge_point_normal(ep: Edge, t: f32) -> PointNormal {
    let u = t - 1.0;
    let e = vec3<f32>(ep.e, 0.0);
    let gd = vec3<f32>(ep.gd, select(ep.gdz, 0.0, TILTED == 0u));
    let g = vec3<f32>(ep.da.x + t * gd.x, ep.da.y + t * gd.y,
        select(ep.daz + t * gd.z, 1.0, TILTED == 0u));
    let gg = ep.gg0 + t * (ep.gg1 + t * ep.gg2);
    let dgg = ep.gg1 + 2.0 * t * ep.gg2;
    let eg = ep.eg0 + t * ep.eg1;
    // S¹: anchor A, w = t·e.
    let w2a = t * t * ep.ee;
    let ca = vec3<f32>(ep.k1 * gg, ep.k1 * t * eg - (ep.ma.x + t * ep.ma.y),
        t * (ep.k1 * t * ep.ee - 2.0 * ep.ma.z));
    let dca = vec3<f32>(ep.k1 * dgg, ep.k1 * (eg + t * ep.eg1) - ep.ma.y,
        2.0 * (ep.k1 * t * ep.ee - ep.ma.z));
    let r1 = root(ca, ep.k1, w2a, gg, 1.0);
    let ds1 = root_derivative(r1, ca, dca);
    // S²: anchor B, w = (t − 1)·e.
    let w2b = u * u * ep.ee;
    let cb = vec3<f32>(ep.k2 * gg, ep.k2 * u * eg - (ep.mb.x + t * ep.mb.y),
        u * (ep.k2 * u * ep.ee - 2.0 * ep.mb.z));
    let dcb = vec3<f32>(ep.k2 * dgg, ep.k2 * (eg + u * ep.eg1) - ep.mb.y,
        2.0 * (ep.k2 * u * ep.ee - ep.mb.z));
    let r2 = root(cb, ep.k2, w2b, gg, 1.0);
    let ds2 = root_derivative(r2, cb, dcb);
    let s = t * r2.s - u * r1.s;
    let ds = t * ds2 - u * ds1 + (r2.s - r1.s);
    let cpt = vec3<f32>(ep.a, 0.0) + e * t + g * s;
    // c′ = e + g′·s + g·s′.
    let tng = e + gd * s + g * ds;
    let tt = dot(tng, tng);
    let n = g * tt - tng * dot(tng, g);
    let good = tt > 0.0 && dot(n, n) > 0.0;
    return PointNormal(cpt, select(g, n, good));
}

// The term of vertex i in eq. (5): ½ (Xi·s¹ + ((1 − Xi)/2)·s²), for the line base + s·dir.
fn vertex_term(ep: Edge, pi: vec3<f32>, ni: vec3<f32>, xi: f32, xa: f32, xb: f32,
    base: vec3<f32>, dir: vec3<f32>, dd: f32) -> f32 {
    let den = xa + xb;
    let t = select(0.5, xb / select(1.0, den, den > EPS), den > EPS);
    let en = edge_point_normal(ep, t);
    // Ŝ¹: anchor Pi, unit axis ni, through c; Ŝ²: anchor c, axis n* (scaled), through Pi.
    let wc = en.c - pi;
    let l2 = dot(wc, wc);
    let has = l2 > 0.0;
    let inv = 2.0 / select(1.0, l2, has);
    let k1 = select(0.0, dot(wc, ni) * inv, has);
    let k2 = select(0.0, -(dot(wc, en.n) * inv), has);
    let wa = base - pi;
    let wa2 = dot(wa, wa);
    let r1 = root(vec3<f32>(k1 * dd, k1 * dot(wa, dir) - dot(dir, ni), k1 * wa2 - 2.0 * dot(wa, ni)),
        k1, wa2, dd, 1.0);
    let wb = base - en.c;
    let wb2 = dot(wb, wb);
    let r2 = root(vec3<f32>(k2 * dd, k2 * dot(wb, dir) - dot(dir, en.n),
        k2 * wb2 - 2.0 * dot(wb, en.n)), k2, wb2, dd, dot(en.n, en.n));
    return 0.5 * xi * r1.s + 0.25 * (1.0 - xi) * r2.s;
}

// The line parameter λ of the section through the local point x (core/src/surface/field.rs
// `Section::param`): x.z for parallel sections, else SECTION_NEWTON_STEPS Newton steps on the
// cubic g(λ) = det[A1 − A0, A2 − A0, x − A0] from x.z / mean(di.z).
fn section_param(pt: Patch, x: vec3<f32>) -> f32 {
    if (TILTED == 0u || !pt.tilted) {
        return x.z;
    }
    // (A1 − A0) × (A2 − A0) = k0 + λ·k1 + λ²·k2 (formed here, only for tilted sections, so
    // the parallel path carries none of it).
    let q1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let q2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    let d0 = vec3<f32>(pt.d0, pt.dz.x);
    let c1 = vec3<f32>(pt.d1 - pt.d0, pt.dz.y - pt.dz.x);
    let c2 = vec3<f32>(pt.d2 - pt.d0, pt.dz.z - pt.dz.x);
    let k0 = cross(q1, q2);
    let k1 = cross(q1, c2) + cross(c1, q2);
    let k2 = cross(c1, c2);
    let c0 = dot(k0, x);
    let cc1 = dot(k1, x) - dot(k0, d0);
    let cc2 = dot(k2, x) - dot(k1, d0);
    let c3 = -dot(k2, d0);
    var l = x.z * 3.0 / (pt.dz.x + pt.dz.y + pt.dz.z);
    for (var i = 0u; i < SECTION_NEWTON_STEPS; i++) {
        let g = c0 + l * (cc1 + l * (cc2 + l * c3));
        let dg = cc1 + l * (2.0 * cc2 + 3.0 * l * c3);
        let next = l - g / dg;
        l = select(l, next, fin(next));
    }
    return l;
}

// The barycentric numerators (n0, n1, n2) of the local point x in its section (parameter λ of
// section_param) and their sum, twice the section's projected area (core clip.rs
// `bary_numerators`), with λ in .w of the second.
struct Numerators {
    n: vec3<f32>,
    area: f32,
    s: f32,
}

fn bary_numerators(pt: Patch, x: vec3<f32>) -> Numerators {
    let s = section_param(pt, x);
    let a0x = pt.d0.x * s - x.x;
    let a0y = pt.d0.y * s - x.y;
    let a1x = pt.p1x + pt.d1.x * s - x.x;
    let a1y = pt.d1.y * s - x.y;
    let a2x = pt.p2x + pt.d2.x * s - x.x;
    let a2y = pt.p2y + pt.d2.y * s - x.y;
    let n1 = a2x * a0y - a2y * a0x;
    let n2 = a0x * a1y - a0y * a1x;
    let n0 = a1x * a2y - a1y * a2x;
    return Numerators(vec3<f32>(n0, n1, n2), n0 + n1 + n2, s);
}

// Raw barycentrics (w0, w1, w2) of the local point x in its section (0, 0, 1 where the
// section has no area), with the section's λ in .w.
fn bary_raw(pt: Patch, x: vec3<f32>) -> vec4<f32> {
    let nm = bary_numerators(pt, x);
    let area = nm.area;
    let ar = select(1.0, area, area != 0.0);
    let w1 = select(0.0, nm.n.y / ar, area != 0.0);
    let w2 = select(0.0, nm.n.z / ar, area != 0.0);
    return vec4<f32>(1.0 - w1 - w2, w1, w2, nm.s);
}

// Raw barycentrics projected onto the triangle (negative or non-finite components 0,
// renormalised; the centroid if all vanish).
fn project(w: vec3<f32>) -> vec3<f32> {
    let a = select(0.0, w.x, fin(w.x) && w.x > 0.0);
    let b = select(0.0, w.y, fin(w.y) && w.y > 0.0);
    let c = select(0.0, w.z, fin(w.z) && w.z > 0.0);
    let m = max(max(a, b), c);
    if (!(m > 0.0) || !fin(m)) {
        return vec3<f32>(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
    }
    let an = a / m;
    let bn = b / m;
    let cn = c / m;
    let inv = 1.0 / (an + bn + cn);
    return vec3<f32>(an * inv, bn * inv, cn * inv);
}

// Barycentrics of the local point x in the cross-section at its height, projected onto the
// triangle.
fn bary(pt: Patch, x: vec3<f32>) -> vec3<f32> {
    return project(bary_raw(pt, x).xyz);
}

// The height change of the surface's continuation beyond the triangle's edges, from the
// projected point q to the raw barycentrics w in the cross-section at height s, along the
// plane normal to the interpolated vertex normal (core/src/surface/lanes/height.rs `beyond_edge`); 0 inside.
fn beyond_edge(pt: Patch, w: vec3<f32>, q: vec3<f32>, s: f32) -> f32 {
    let e = w - q;
    let ox = e.y * pt.p1x + e.z * pt.p2x + s * (e.x * pt.d0.x + e.y * pt.d1.x + e.z * pt.d2.x);
    let oy = e.z * pt.p2y + s * (e.x * pt.d0.y + e.y * pt.d1.y + e.z * pt.d2.y);
    let nx = q.x * pt.n0.x + q.y * pt.n1.x + q.z * pt.n2.x;
    let ny = q.x * pt.n0.y + q.y * pt.n1.y + q.z * pt.n2.y;
    let nz = q.x * pt.n0.z + q.y * pt.n1.z + q.z * pt.n2.z;
    let dx = q.x * pt.d0.x + q.y * pt.d1.x + q.z * pt.d2.x;
    let dy = q.x * pt.d0.y + q.y * pt.d1.y + q.z * pt.d2.y;
    var dh = 0.0;
    if (TILTED != 0u && pt.tilted) {
        // The point is o.z above the section point of q (core height.rs `beyond_edge`).
        let oz = s * dot(e, pt.dz);
        let vz = dot(q, pt.dz);
        let nd = (nx * dx + ny * dy) / vz + nz;
        dh = oz - (nx * ox + ny * oy + nz * oz) / nd;
    } else {
        let nd = nx * dx + ny * dy + nz;
        dh = 0.0 - (nx * ox + ny * oy) / nd;
    }
    let outside = w.x < 0.0 || w.y < 0.0 || w.z < 0.0;
    return select(0.0, dh, outside && fin(dh));
}

// Height σS(X) at barycentrics x (summing to one, inside the triangle).
fn height_at(pt: Patch, x: vec3<f32>) -> f32 {
    let base = vec3<f32>(x.y * pt.p1x + x.z * pt.p2x, x.z * pt.p2y, 0.0);
    var dir = vec3<f32>(x.x * pt.d0.x + x.y * pt.d1.x + x.z * pt.d2.x,
        x.x * pt.d0.y + x.y * pt.d1.y + x.z * pt.d2.y, x.x + x.y + x.z);
    if (TILTED != 0u && pt.tilted) {
        // Unit height (core/src/surface/field.rs `unit_height_dir`).
        let inv = 1.0 / dot(x, pt.dz);
        dir = vec3<f32>(dir.x * inv, dir.y * inv, 1.0);
    }
    let dd = dot(dir, dir);
    let p0 = vec3<f32>(0.0, 0.0, 0.0);
    let p1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let p2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    return vertex_term(pt.e1, p0, pt.n0, x.x, x.y, x.z, base, dir, dd)
        + vertex_term(pt.e2, p1, pt.n1, x.y, x.z, x.x, base, dir, dd)
        + vertex_term(pt.e0, p2, pt.n2, x.z, x.x, x.y, base, dir, dd);
}

// f(τ) at the local point lo + τ·lr.
fn f_at(pt: Patch, lo: vec3<f32>, lr: vec3<f32>, tau: f32) -> f32 {
    let x = lo + lr * tau;
    let w = bary_raw(pt, x);
    let q = project(w.xyz);
    return x.z - (height_at(pt, q) + beyond_edge(pt, w.xyz, q, w.w));
}

// ---------------------------------------------------------------------------------------------
// The shell clip (core/src/kernel/clip.rs)

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

fn cross2_poly(u0: vec2<f32>, u1: vec2<f32>, v0: vec2<f32>, v1: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(cross2(u0, v0), cross2(u0, v1) + cross2(u1, v0), cross2(u1, v1));
}

struct Roots {
    r: vec2<f32>,
    ok: vec2<bool>,
}

// Real roots of c0 + c1·x + c2·x² (numerically careful, up to two).
fn quadratic_roots(c: vec3<f32>) -> Roots {
    let none = Roots(vec2<f32>(0.0, 0.0), vec2<bool>(false, false));
    let scale = max(abs(c.y), abs(c.x));
    if (abs(c.z) <= EPS * 1e-3 * scale || c.z == 0.0) {
        if (c.y != 0.0) {
            let x = -c.x / c.y;
            return Roots(vec2<f32>(x, 0.0), vec2<bool>(fin(x), false));
        }
        return none;
    }
    let disc = c.y * c.y - 4.0 * c.z * c.x;
    if (!(disc >= 0.0) || !fin(disc)) {
        return none;
    }
    let sq = sqrt(disc);
    let q = select(-0.5 * (c.y + sq), -0.5 * (c.y - sq), c.y < 0.0);
    let r1 = q / c.z;
    let r2 = select(r1, c.x / select(1.0, q, q != 0.0), q != 0.0);
    return Roots(vec2<f32>(r1, r2), vec2<bool>(fin(r1), fin(r2)));
}

// Whether the ray point at τ is inside the walls Xk = −m_k: the wall polynomials for parallel
// sections, the point's barycentrics in its section for tilted ones.
fn inside(pt: Patch, polys: array<vec3<f32>, 3>, m: vec3<f32>, o: vec3<f32>, r: vec3<f32>,
    tau: f32) -> bool {
    if (TILTED != 0u && pt.tilted) {
        let nm = bary_numerators(pt, o + r * tau);
        return nm.n.x + m.x * nm.area >= 0.0 && nm.n.y + m.y * nm.area >= 0.0
            && nm.n.z + m.z * nm.area >= 0.0;
    }
    var ok_all = true;
    for (var k = 0u; k < 3u; k++) {
        let c = polys[k];
        ok_all = ok_all && (c.x + tau * (c.y + tau * c.z) >= 0.0);
    }
    return ok_all;
}

// Base point and direction of the line over the barycentrics x (local frame).
struct Line {
    p: vec3<f32>,
    g: vec3<f32>,
}

fn line_at(pt: Patch, x: vec3<f32>) -> Line {
    let p = vec3<f32>(x.y * pt.p1x + x.z * pt.p2x, x.z * pt.p2y, 0.0);
    let g = vec3<f32>(x.x * pt.d0 + x.y * pt.d1 + x.z * pt.d2, dot(x, pt.dz));
    return Line(p, g);
}

// Where the ray o + τ·r meets wall k (walls moved out by m3) of a shell with
// tilted sections (core clip.rs `ruled_wall_crossings`): the Plücker side product of the ray
// with the wall's line at t, a quadratic in t; each root's ray parameter, or not ok.
fn ruled_crossings(pt: Patch, m3: vec3<f32>, k: u32, o: vec3<f32>, r: vec3<f32>) -> Roots {
    // The moved corners' lines (core shell.rs `moved_corners`): corner i has Xj = −m_j for
    // the two other vertices j; wall k runs from corner k+1 to corner k+2.
    let corner = array<vec3<f32>, 3>(vec3<f32>(1.0 + m3.y + m3.z, -m3.y, -m3.z),
        vec3<f32>(-m3.x, 1.0 + m3.x + m3.z, -m3.z), vec3<f32>(-m3.x, -m3.y, 1.0 + m3.x + m3.y));
    let la = line_at(pt, corner[(k + 1u) % 3u]);
    let lb = line_at(pt, corner[(k + 2u) % 3u]);
    let pe = lb.p - la.p;
    let ge = lb.g - la.g;
    let m = cross(o, r);
    let q = vec3<f32>(dot(r, cross(la.p, la.g)) + dot(la.g, m),
        dot(r, cross(la.p, ge) + cross(pe, la.g)) + dot(ge, m), dot(r, cross(pe, ge)));
    let ts = quadratic_roots(q);
    var out = Roots(vec2<f32>(0.0, 0.0), vec2<bool>(false, false));
    for (var j = 0u; j < 2u; j++) {
        if (ts.ok[j]) {
            let t = ts.r[j];
            let p = la.p + pe * t;
            let g = la.g + ge * t;
            let rg = cross(r, g);
            let tau = dot(cross(p - o, g), rg) / dot(rg, rg);
            out.r[j] = tau;
            out.ok[j] = fin(tau);
        }
    }
    return out;
}

// [τa, τb]: the hull of the sub-intervals of [τ_lo, τ_hi] inside all three walls (at most 8
// breakpoints, a fixed sorting network, 7 midpoint tests).
// The walls Xk = −margin (core/src/kernel/clip.rs `wall_margin`): the margin's world width
// WALL_MARGIN_ULPS·ε·L over the triangle's smallest altitude 2·area / longest edge; each wall
// also moves out by its crack reach (`wall_margins`).
fn wall_margins(pt: Patch) -> vec3<f32> {
    let longest = sqrt(max(max(pt.p1x * pt.p1x, pt.p2x * pt.p2x + pt.p2y * pt.p2y),
        (pt.p2x - pt.p1x) * (pt.p2x - pt.p1x) + pt.p2y * pt.p2y));
    var margin = WALL_MARGIN_ULPS * EPS * pt.scale * longest / (pt.p1x * pt.p2y);
    if (!fin(margin)) {
        margin = 0.0;
    }
    return pt.reach + vec3<f32>(margin, margin, margin);
}

// The barycentrics of the local (x, y) in the triangle; `lin` for a direction (core
// band.rs `bary_xy`).
fn band_bary(pt: Patch, xy: vec2<f32>, lin: bool) -> vec3<f32> {
    let b2 = xy.y / pt.p2y;
    let b1 = (xy.x - pt.p2x * b2) / pt.p1x;
    let b0 = select(1.0 - b1 - b2, -b1 - b2, lin);
    return vec3<f32>(b0, b1, b2);
}

// q(β) = c0·β1β2 + c1·β2β0 + c2·β0β1 (core band.rs `q`).
fn band_q(c: vec3<f32>, x: vec3<f32>) -> f32 {
    return c.x * (x.y * x.z) + c.y * (x.z * x.x) + c.z * (x.x * x.y);
}

// Whether the local ray o + τ·r, τ in [a, b], misses the patch's band (core/src/kernel/clip.rs
// `misses`): h(τ) = z − q(β) stays above hi or below lo, widened by per_reach times the largest
// wall offset. The band rides in the record's last two vec4s: (c0, c1, c2, lo), (hi, per_reach).
fn band_misses(pt: Patch, base: u32, o: vec3<f32>, r: vec3<f32>, a: f32, b: f32) -> bool {
    let v0 = patches[base + 25u];
    let v1 = patches[base + 26u];
    let m = wall_margins(pt);
    let widen = v1.y * max(max(m.x, m.y), m.z);
    let lo = v0.w - widen;
    let hi = v1.x + widen;
    let bo = band_bary(pt, o.xy, false);
    let br = band_bary(pt, r.xy, true);
    let ha = o.z + r.z * a - band_q(v0.xyz, bo + br * a);
    let hb = o.z + r.z * b - band_q(v0.xyz, bo + br * b);
    let h2 = -band_q(v0.xyz, br);
    let w = b - a;
    let bow = h2 * w * w * 0.25;
    let hmin = min(ha, hb) - max(bow, 0.0);
    let hmax = max(ha, hb) - min(bow, 0.0);
    return fin(hmin) && fin(hmax) && ((hmin > hi) || (hmax < lo));
}

fn shell_interval(pt: Patch, o: vec3<f32>, r: vec3<f32>, tau_lo: f32, tau_hi: f32) -> Span {
    // a_i(τ) − q(τ) = (p_i + o.z·d_i − o) + τ (r.z·d_i − r), in the xy-plane.
    let u0 = vec2<f32>(0.0, 0.0) + pt.d0 * o.z - o.xy;
    let u1 = vec2<f32>(pt.p1x, 0.0) + pt.d1 * o.z - o.xy;
    let u2 = vec2<f32>(pt.p2x, pt.p2y) + pt.d2 * o.z - o.xy;
    let v0 = pt.d0 * r.z - r.xy;
    let v1 = pt.d1 * r.z - r.xy;
    let v2 = pt.d2 * r.z - r.xy;
    let w0 = cross2_poly(u1, v1, u2, v2);
    let w1 = cross2_poly(u2, v2, u0, v0);
    let w2 = cross2_poly(u0, v0, u1, v1);
    let sum = w0 + w1 + w2;
    let m = wall_margins(pt);
    let polys = array<vec3<f32>, 3>(w0 + m.x * sum, w1 + m.y * sum, w2 + m.z * sum);
    var brk = array<f32, 8>(tau_lo, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi);
    var count = 1u;
    for (var k = 0u; k < 3u; k++) {
        var rs: Roots;
        if (TILTED != 0u && pt.tilted) {
            rs = ruled_crossings(pt, m, k, o, r);
        } else {
            rs = quadratic_roots(polys[k]);
        }
        for (var m = 0u; m < 2u; m++) {
            let x = rs.r[m];
            if (rs.ok[m] && x > tau_lo && x < tau_hi && count < 8u) {
                brk[count] = x;
                count += 1u;
            }
        }
    }
    // Fixed insertion network over all slots (unused slots hold τ_hi, which sorts last).
    for (var i = 1u; i < 8u; i++) {
        for (var j = i; j >= 1u; j--) {
            let x = brk[j - 1u];
            let y = brk[j];
            if (y < x) {
                brk[j - 1u] = y;
                brk[j] = x;
            }
        }
    }
    var first = 0.0;
    var last = 0.0;
    var has = false;
    for (var k = 0u; k < 7u; k++) {
        let a = brk[k];
        let b = brk[k + 1u];
        if (b > a && inside(pt, polys, m, o, r, 0.5 * (a + b))) {
            if (!has) {
                first = a;
            }
            has = true;
            last = b;
        }
    }
    if (has) {
        return Span(first, last, true);
    }
    // A ray that only touches the shell at a point can still cross the surface there.
    if (tau_hi <= tau_lo && inside(pt, polys, m, o, r, tau_lo)) {
        return Span(tau_lo, tau_lo, true);
    }
    return Span(0.0, 0.0, false);
}

// ---------------------------------------------------------------------------------------------
// Bracketing and refinement (core/src/kernel/refine.rs)

struct Bracket {
    a: f32,
    b: f32,
    fa: f32,
    fb: f32,
}

// Regula falsi point of the bracket, clamped inside it (the midpoint if degenerate).
fn estimate(br: Bracket) -> f32 {
    if (br.fa == 0.0) {
        return br.a;
    }
    if (br.fb == 0.0) {
        return br.b;
    }
    let den = br.fb - br.fa;
    let x = (br.fb * br.a - br.fa * br.b) / select(1.0, den, den != 0.0);
    if (den != 0.0 && fin(x) && x >= br.a && x <= br.b) {
        return x;
    }
    return 0.5 * (br.a + br.b);
}

// Bracketing sample j of the shell interval: shell.a + j·stp, the last (j = SAMPLES + 1)
// exactly shell.b.
fn sample_at(shell: Span, stp: f32, j: u32) -> f32 {
    return select(shell.a + stp * f32(j), shell.b, j >= SAMPLES + 1u);
}

// A sample (x, f(x)) beside a bracket, for the start estimate; `ok` false where there is none.
struct Side {
    ok: bool,
    x: f32,
    f: f32,
}

// The CPU's `refine::start_estimate`: the zero of the inverse interpolation x(f) through the
// bracket's ends and the samples before and after it where f is strictly monotone over them
// (cubic, quadratic), else regula falsi.
fn start_estimate(br: Bracket, before: Side, after: Side) -> f32 {
    let rf = estimate(br);
    if (br.fa == 0.0 || br.fb == 0.0) {
        return rf;
    }
    let rising = br.fb > br.fa;
    let use_p = before.ok && select((before.f > br.fa), (before.f < br.fa), rising);
    // (The comparisons in parentheses: `a < b, c > d` would parse as a template list.)
    let use_q = after.ok && select((after.f < br.fb), (after.f > br.fb), rising);
    var xs: array<f32, 4>;
    var fs: array<f32, 4>;
    var m = 0u;
    if (use_p) {
        xs[m] = before.x;
        fs[m] = before.f;
        m++;
    }
    xs[m] = br.a;
    fs[m] = br.fa;
    m++;
    xs[m] = br.b;
    fs[m] = br.fb;
    m++;
    if (use_q) {
        xs[m] = after.x;
        fs[m] = after.f;
        m++;
    }
    if (m == 2u) {
        return rf;
    }
    // Lagrange: Σ_i x_i Π_{j≠i} f_j / (f_j − f_i).
    var x = 0.0;
    for (var i = 0u; i < m; i++) {
        var w = 1.0;
        for (var j = 0u; j < m; j++) {
            if (j != i) {
                w = w * (fs[j] / (fs[j] - fs[i]));
            }
        }
        x = x + xs[i] * w;
    }
    if (fin(x) && x > br.a && x < br.b) {
        return x;
    }
    return rf;
}

struct Crossing {
    ok: bool,
    t: f32,
    t_error: f32,
    bary: vec3<f32>,
}

fn no_crossing() -> Crossing {
    return Crossing(false, 0.0, 0.0, vec3<f32>(0.0, 0.0, 0.0));
}

// The search part of the kernel for one patch (clip, bracket, refine): where the ray crosses
// it in [t_min, t_max].
fn smooth_crossing(id: u32, o: vec3<f32>, d: vec3<f32>, inv: vec3<f32>, t_min: f32,
    t_max: f32) -> Crossing {
    let b = id * PATCH_VEC4;
    let bx = box_span(patches[b + 4u].xyz, patches[b + 5u].xyz, o, d, inv, t_min, t_max);
    if (!bx.ok) {
        return no_crossing();
    }
    let pt = load_patch(id);
    // Local ray re-based at the middle of the box interval.
    let t0 = 0.5 * (bx.a + bx.b);
    let w = o + d * t0 - pt.origin;
    let lo = vec3<f32>(dot(w, pt.ex), dot(w, pt.ey), dot(w, pt.ez));
    let lr = vec3<f32>(dot(d, pt.ex), dot(d, pt.ey), dot(d, pt.ez));
    // Slab σmin ≤ σ ≤ σmax.
    var a = bx.a - t0;
    var bb = bx.b - t0;
    if (lr.z != 0.0) {
        let iz = 1.0 / lr.z;
        let u = (pt.sig_lo - lo.z) * iz;
        let v = (pt.sig_hi - lo.z) * iz;
        a = max(a, min(u, v));
        bb = min(bb, max(u, v));
    } else if (lo.z < pt.sig_lo || lo.z > pt.sig_hi) {
        return no_crossing();
    }
    if (!(a <= bb) || !fin(a) || !fin(bb)) {
        return no_crossing();
    }
    // The band, first over the slab's interval (before the wall quadratics), as on the CPU.
    if (band_misses(pt, b, lo, lr, a, bb)) {
        return no_crossing();
    }
    let shell = shell_interval(pt, lo, lr, a, bb);
    if (!shell.ok || !(shell.b >= shell.a)) {
        return no_crossing();
    }
    // The band: no surface point on the interval, nothing to sample.
    if (band_misses(pt, b, lo, lr, shell.a, shell.b)) {
        return no_crossing();
    }
    // Bracketing: the ends and SAMPLES interior points, the first sign change.
    let stp = (shell.b - shell.a) / f32(SAMPLES + 1u);
    var found = false;
    var br = Bracket(0.0, 0.0, 0.0, 0.0);
    var x0 = shell.a;
    var f0 = 0.0;
    // f at the interval's ends within the rounding of f counts as zero (the CPU's
    // `refine::bracket_step`): neighbours decide a crossing at their shared wall alike.
    let snap = ROUNDING_ULPS * EPS * pt.scale;
    var before = Side(false, 0.0, 0.0);
    var at = 0u;
    for (var j = 0u; j < SAMPLES + 2u; j++) {
        let x1 = sample_at(shell, stp, j);
        var f1 = f_at(pt, lo, lr, x1);
        if ((j == 0u || j == SAMPLES + 1u) && abs(f1) <= snap) {
            f1 = 0.0;
        }
        if (j > 0u && (f0 == 0.0 || f1 == 0.0 || (f1 > 0.0) != (f0 > 0.0))) {
            br = Bracket(x0, x1, f0, f1);
            found = true;
            at = j;
            break;
        }
        if (j > 0u) {
            before = Side(true, x0, f0);
        }
        x0 = x1;
        f0 = f1;
    }
    if (!found) {
        return no_crossing();
    }
    // The sample after the bracket (the CPU's lane call computes it with the others), for the
    // start estimate; none after the last.
    var after = Side(false, 0.0, 0.0);
    if (at < SAMPLES + 1u && br.fa != 0.0 && br.fb != 0.0) {
        let x2 = sample_at(shell, stp, at + 1u);
        after = Side(true, x2, f_at(pt, lo, lr, x2));
    }
    let first = br;
    // Early stop, as on the CPU: once the bracket is within EARLY_STOP of the rounding
    // allowance computed from the sampling bracket's secant (a lower bound of the final one).
    var stop = 0.0;
    if (first.b > first.a) {
        let s0 = abs(first.fb - first.fa) / (first.b - first.a);
        let floor = ROUNDING_ULPS * EPS * pt.scale / select(1.0, s0, s0 > 0.0);
        if (s0 > 0.0 && fin(floor)) {
            stop = EARLY_STOP * floor;
        }
    }
    // Refinement: at most ITERATIONS steps of 8 points (fewer once the bracket has collapsed
    // onto an exact zero or is within `stop`) and at most ESTIMATE_STEPS estimate steps of the
    // 4 points around a trusted estimate (the CPU's `refine::refine`, "Estimate steps").
    var x = start_estimate(br, before, after);
    var estimate_steps = ESTIMATE_STEPS;
    var steps = 0u;
    for (var it = 0u; it < ITERATIONS + ESTIMATE_STEPS; it++) {
        if (br.fa == 0.0 || br.fb == 0.0 || !(br.b - br.a > stop)) {
            break;
        }
        let wd = br.b - br.a;
        // Radii around the estimate from its distance e to regula falsi's (the CPU's
        // `refine::refine`).
        let e = abs(x - estimate(br));
        var r_in = max(e * INNER_OF_SPREAD, stop * INNER_OF_STOP);
        if (!(e > 0.0)) {
            r_in = max(r_in, wd * (OUTER_OF_WIDTH / OUTER_OF_INNER));
        }
        let r_out = max(max(e * OUTER_OF_SPREAD, r_in * OUTER_OF_INNER), wd * OUTER_OF_WIDTH);
        // Trusted: a root caught within r_in ends the refinement; then only the 4 points
        // around the estimate (at most ESTIMATE_STEPS times), else a uniform step (at most
        // ITERATIONS of them).
        var first_k = 0u;
        if (ITERATIONS > 0u && estimate_steps > 0u && e > 0.0 && r_in + r_in <= stop) {
            estimate_steps -= 1u;
            first_k = 4u;
        } else {
            if (steps == ITERATIONS) {
                break;
            }
            steps++;
        }
        let neg_a = br.fa < 0.0;
        var nb = br.b;
        var fnb = br.fb;
        var xs: array<f32, 8>;
        var fs: array<f32, 8>;
        for (var k = 0u; k < 8u; k++) {
            if (k < first_k) {
                // Not evaluated: a copy of the bracket's start, which no search below takes.
                xs[k] = br.a;
                fs[k] = br.fa;
                continue;
            }
            var xk: f32;
            switch k {
                case 0u, 1u, 2u, 3u: {
                    xk = br.a + wd * (0.2 * f32(k + 1u));
                }
                case 4u: {
                    xk = x - r_out;
                }
                case 5u: {
                    xk = x - r_in;
                }
                case 6u: {
                    xk = x + r_in;
                }
                default: {
                    xk = x + r_out;
                }
            }
            xk = min(max(xk, br.a), br.b);
            let fk = f_at(pt, lo, lr, xk);
            xs[k] = xk;
            fs[k] = fk;
            // b′: the smallest point whose sign differs from f(a)'s (or is zero).
            if ((fk == 0.0 || (fk < 0.0) != neg_a) && xk < nb) {
                nb = xk;
                fnb = fk;
            }
        }
        // a′: the largest point below b′ (all of them have f(a)'s sign).
        var na = br.a;
        var fna = br.fa;
        for (var k = 0u; k < 8u; k++) {
            if (xs[k] < nb && xs[k] > na) {
                na = xs[k];
                fna = fs[k];
            }
        }
        // The nearest samples outside the new bracket, for the next estimate.
        var bef = Side(false, 0.0, 0.0);
        var aft = Side(false, 0.0, 0.0);
        for (var k = 0u; k < 10u; k++) {
            var xk: f32;
            var fk: f32;
            if (k < 8u) {
                xk = xs[k];
                fk = fs[k];
            } else if (k == 8u) {
                xk = br.a;
                fk = br.fa;
            } else {
                xk = br.b;
                fk = br.fb;
            }
            if (xk < na && (!bef.ok || xk > bef.x)) {
                bef = Side(true, xk, fk);
            }
            if (xk > nb && (!aft.ok || xk < aft.x)) {
                aft = Side(true, xk, fk);
            }
        }
        if (fnb == 0.0) {
            br = Bracket(nb, nb, fnb, fnb);
        } else {
            br = Bracket(na, nb, fna, fnb);
        }
        // A bracket within `stop` ends the refinement and takes the regula falsi point below.
        if (br.b - br.a > stop) {
            x = start_estimate(br, bef, aft);
        }
    }
    // The estimate inside the final bracket (the CPU's `refine` returns it with the bracket):
    // regula falsi once the bracket is within `stop`, where the samples are rounding noise.
    if (!(br.b - br.a > stop)) {
        x = estimate(br);
    }
    let tau = x;
    let bc = bary(pt, lo + lr * tau);
    // Re-basing can round the hit an ulp outside the caller's range: clamp it.
    let t = min(max(t0 + tau, t_min), t_max);
    // Rounding allowance ROUNDING_ULPS ε L / |f′|, f′ the smaller of the sampling bracket's and
    // the final bracket's secants (near convergence the final bracket's end values are rounding
    // noise and its secant alone can be far too steep), as on the CPU.
    var slope: f32 = 0.0;
    var s_first: f32 = 0.0;
    if (first.b > first.a) {
        s_first = abs(first.fb - first.fa) / (first.b - first.a);
    }
    if (br.b > br.a) {
        let s_fin = abs(br.fb - br.fa) / (br.b - br.a);
        slope = select(s_fin, min(s_fin, s_first), first.b > first.a);
    } else {
        slope = s_first;
    }
    var rounding = ROUNDING_ULPS * EPS * pt.scale / select(1.0, slope, slope > 0.0);
    if (!(slope > 0.0) || !fin(rounding)) {
        rounding = 0.0;
    }
    // A zero at an end of the bracket is the root up to the rounding of f (as on the CPU).
    let width = select(br.b - br.a, 0.0, br.fa == 0.0 || br.fb == 0.0);
    let t_error = width + rounding;
    if (fin(t) && fin(t_error)) {
        return Crossing(true, t, t_error, bc);
    }
    return no_crossing();
}

// ---------------------------------------------------------------------------------------------
// The exact surface normal (docs/METHOD.md §5; core/src/surface/scalar.rs point_derivs_local and
// normal_local), by forward-mode derivatives written out: a "G" value is vec3(value, ∂/∂w1,
// ∂/∂w2) with w0 = 1 − w1 − w2; a GV is a vector with its two partials. The edge curve enters
// through its parameter t(X): c and n* need c(t), c′(t) (for n*) and c″(t) (for n*′), carried
// as "J" values vec3(value, d/dt, d²/dt²).

fn g_mul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.x * b.x, a.yz * b.x + a.x * b.yz);
}

fn g_div(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = a.x / b.x;
    return vec3<f32>(q, (a.yz - q * b.yz) / b.x);
}

fn g_sqrt0(a: vec3<f32>) -> vec3<f32> {
    if (a.x > 0.0) {
        let r = sqrt(a.x);
        if (r > 0.0) {
            return vec3<f32>(r, a.yz / (r + r));
        }
    }
    return vec3<f32>(0.0, 0.0, 0.0);
}

struct GV {
    v: vec3<f32>,
    d1: vec3<f32>,
    d2: vec3<f32>,
}

fn gv_const(v: vec3<f32>) -> GV {
    return GV(v, vec3<f32>(0.0), vec3<f32>(0.0));
}

fn gv_sub(a: GV, b: GV) -> GV {
    return GV(a.v - b.v, a.d1 - b.d1, a.d2 - b.d2);
}

fn gv_dot(a: GV, b: GV) -> vec3<f32> {
    return vec3<f32>(dot(a.v, b.v), dot(a.d1, b.v) + dot(a.v, b.d1), dot(a.d2, b.v) + dot(a.v, b.d2));
}

// Root nearest 0 of the line base + s·g (w = base − anchor) and the sphere with axis m
// (|m|² = m2, value only: the double-root test's scale) and curvature kappa.
fn root_g(w: GV, g: GV, m: GV, m2: f32, kappa: vec3<f32>) -> vec3<f32> {
    let zero = vec3<f32>(0.0);
    let g2 = gv_dot(g, g);
    let w2 = gv_dot(w, w);
    let qa = g_mul(kappa, g2);
    let qb = g_mul(kappa, gv_dot(w, g)) - gv_dot(g, m);
    let qc = g_mul(kappa, w2) - 2.0 * gv_dot(w, m);
    var disc = g_mul(qb, qb) - g_mul(qa, qc);
    if (!(disc.x > 0.0)) {
        disc = zero;
    }
    let sq = g_sqrt0(disc);
    let q = select(-qb - sq, sq - qb, qb.x < 0.0);
    let tol = EPS * 16.0;
    let kk = kappa.x * kappa.x;
    let c_scale = 2.0 * (kk * w2.x * w2.x + 4.0 * w2.x * m2);
    let b_scale = 2.0 * (kk * w2.x * g2.x + g2.x * m2);
    if ((qc.x * qc.x <= tol * tol * c_scale && qb.x * qb.x <= tol * tol * b_scale) || q.x == 0.0) {
        return zero;
    }
    let s = g_div(qc, q);
    if (fin3(s)) {
        return s;
    }
    return zero;
}

fn j_mul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.x * b.x, a.y * b.x + a.x * b.y, a.z * b.x + 2.0 * a.y * b.y + a.x * b.z);
}

fn j_div(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = a.x / b.x;
    let q1 = (a.y - q * b.y) / b.x;
    let q2 = (a.z - 2.0 * q1 * b.y - q * b.z) / b.x;
    return vec3<f32>(q, q1, q2);
}

fn j_sqrt0(a: vec3<f32>) -> vec3<f32> {
    if (a.x > 0.0) {
        let r = sqrt(a.x);
        if (r > 0.0) {
            let r1 = a.y / (r + r);
            let r2 = (a.z - 2.0 * r1 * r1) / (r + r);
            return vec3<f32>(r, r1, r2);
        }
    }
    return vec3<f32>(0.0, 0.0, 0.0);
}

struct JV {
    v: vec3<f32>,
    d: vec3<f32>,
    dd: vec3<f32>,
}

fn jv_dot(a: JV, b: JV) -> vec3<f32> {
    return vec3<f32>(dot(a.v, b.v), dot(a.d, b.v) + dot(a.v, b.d),
        dot(a.dd, b.v) + 2.0 * dot(a.d, b.d) + dot(a.v, b.dd));
}

fn jv_dot_c(a: JV, m: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(a.v, m), dot(a.d, m), dot(a.dd, m));
}

// Edge-sphere root with its first two t-derivatives (unit axis m, constant curvature kappa).
fn root_j(w: JV, g: JV, m: vec3<f32>, kappa: f32) -> vec3<f32> {
    let zero = vec3<f32>(0.0);
    let g2 = jv_dot(g, g);
    let w2 = jv_dot(w, w);
    let qa = kappa * g2;
    let qb = kappa * jv_dot(w, g) - jv_dot_c(g, m);
    let qc = kappa * w2 - 2.0 * jv_dot_c(w, m);
    var disc = j_mul(qb, qb) - j_mul(qa, qc);
    if (!(disc.x > 0.0)) {
        disc = zero;
    }
    let sq = j_sqrt0(disc);
    let q = select(-qb - sq, sq - qb, qb.x < 0.0);
    let tol = EPS * 16.0;
    let kk = kappa * kappa;
    let c_scale = 2.0 * (kk * w2.x * w2.x + 4.0 * w2.x);
    let b_scale = 2.0 * (kk * w2.x * g2.x + g2.x);
    if ((qc.x * qc.x <= tol * tol * c_scale && qb.x * qb.x <= tol * tol * b_scale) || q.x == 0.0) {
        return zero;
    }
    let s = j_div(qc, q);
    if (fin3(s)) {
        return s;
    }
    return zero;
}

struct EdgeJet {
    c: vec3<f32>,   // c(t)
    dc: vec3<f32>,  // c′(t)
    n: vec3<f32>,   // n*(t) scaled by |c′|²
    dn: vec3<f32>,  // its t-derivative
}

fn edge_jet(ep: Edge, t: f32) -> EdgeJet {
    let zero = vec3<f32>(0.0);
    let e = vec3<f32>(ep.e, 0.0);
    let gd = vec3<f32>(ep.gd, select(ep.gdz, 0.0, TILTED == 0u));
    let g = JV(vec3<f32>(ep.da + ep.gd * t, select(ep.daz + t * gd.z, 1.0, TILTED == 0u)), gd,
        zero);
    let w1 = JV(e * t, e, zero);
    let w2 = JV(e * (t - 1.0), e, zero);
    let s1 = root_j(w1, g, ep.na, ep.k1);
    let s2 = root_j(w2, g, ep.nb, ep.k2);
    let s = j_mul(vec3<f32>(1.0 - t, -1.0, 0.0), s1) + j_mul(vec3<f32>(t, 1.0, 0.0), s2);
    let c = vec3<f32>(ep.a, 0.0) + e * t + g.v * s.x;
    let tng = e + gd * s.x + g.v * s.y;
    let dtan = 2.0 * gd * s.y + g.v * s.z;
    let tt = dot(tng, tng);
    let dtt = 2.0 * dot(tng, dtan);
    let tg = dot(tng, g.v);
    let n = g.v * tt - tng * tg;
    let dn = gd * tt + g.v * dtt - dtan * tg - tng * (dot(dtan, g.v) + dot(tng, gd));
    if (tt > 0.0 && dot(n, n) > 0.0) {
        return EdgeJet(c, tng, n, dn);
    }
    return EdgeJet(c, tng, g.v, gd);
}

fn vertex_term_g(ep: Edge, pi: vec3<f32>, ni: vec3<f32>, xi: vec3<f32>, xa: vec3<f32>,
    xb: vec3<f32>, base: GV, dir: GV) -> vec3<f32> {
    let den = xa + xb;
    var t = vec3<f32>(0.5, 0.0, 0.0);
    if (den.x > EPS) {
        t = g_div(xb, den);
    }
    let ej = edge_jet(ep, t.x);
    let c = GV(ej.c, ej.dc * t.y, ej.dc * t.z);
    let nc = GV(ej.n, ej.dn * t.y, ej.dn * t.z);
    let wc = gv_sub(c, gv_const(pi));
    let l2 = gv_dot(wc, wc);
    var k1 = vec3<f32>(0.0);
    var k2 = vec3<f32>(0.0);
    if (l2.x > 0.0) {
        k1 = g_div(2.0 * gv_dot(wc, gv_const(ni)), l2);
        k2 = g_div(-2.0 * gv_dot(wc, nc), l2);
    }
    let s1 = root_g(gv_sub(base, gv_const(pi)), dir, gv_const(ni), 1.0, k1);
    let s2 = root_g(gv_sub(base, c), dir, nc, dot(nc.v, nc.v), k2);
    return 0.5 * g_mul(xi, s1) + 0.25 * g_mul(vec3<f32>(1.0, 0.0, 0.0) - xi, s2);
}

fn try_normalize(v: vec3<f32>) -> vec4<f32> {
    let l = length(v);
    if (l > 0.0 && fin(l)) {
        let u = v * (1.0 / l);
        if (fin3(u)) {
            return vec4<f32>(u, 1.0);
        }
    }
    return vec4<f32>(0.0);
}

// Unit surface normal (local frame) at the projected barycentrics x, oriented like the vertex
// normals; the normalised interpolated vertex normal where the derivatives degenerate.
fn normal_local(pt: Patch, x: vec3<f32>) -> vec3<f32> {
    let x0 = vec3<f32>(x.x, -1.0, -1.0);
    let x1 = vec3<f32>(x.y, 1.0, 0.0);
    let x2 = vec3<f32>(x.z, 0.0, 1.0);
    let p0 = vec3<f32>(0.0, 0.0, 0.0);
    let p1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let p2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    let d0 = vec3<f32>(pt.d0, pt.dz.x);
    let d1 = vec3<f32>(pt.d1, pt.dz.y);
    let d2 = vec3<f32>(pt.d2, pt.dz.z);
    let base = GV(p0 * x.x + p1 * x.y + p2 * x.z, p1 - p0, p2 - p0);
    var dir = GV(d0 * x.x + d1 * x.y + d2 * x.z, d1 - d0, d2 - d0);
    if (TILTED != 0u && pt.tilted) {
        // D = V / Vz: ∂D/∂Xk = ((dk − d0) − D·(dk.z − d0.z)) / Vz.
        let inv = 1.0 / dir.v.z;
        let dv = dir.v * inv;
        dir = GV(dv, (dir.d1 - dv * dir.d1.z) * inv, (dir.d2 - dv * dir.d2.z) * inv);
    }
    let h = vertex_term_g(pt.e1, p0, pt.n0, x0, x1, x2, base, dir)
        + vertex_term_g(pt.e2, p1, pt.n1, x1, x2, x0, base, dir)
        + vertex_term_g(pt.e0, p2, pt.n2, x2, x0, x1, base, dir);
    let du1 = base.d1 + dir.d1 * h.x + dir.v * h.y;
    let du2 = base.d2 + dir.d2 * h.x + dir.v * h.z;
    let phong = pt.n0 * x.x + pt.n1 * x.y + pt.n2 * x.z;
    var fallback = vec3<f32>(0.0, 0.0, 1.0);
    let fb = try_normalize(phong);
    if (fb.w > 0.0) {
        fallback = fb.xyz;
    }
    let n = try_normalize(cross(du1, du2));
    if (n.w > 0.0) {
        return select(n.xyz, -n.xyz, dot(n.xyz, phong) < 0.0);
    }
    return fallback;
}

// ---------------------------------------------------------------------------------------------
// The flat baseline: Möller–Trumbore on the record's three world vertices
// (core/src/kernel/flat.rs).

fn flat_crossing(id: u32, o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32) -> Crossing {
    let b = id * FLAT_VEC4;
    let p0 = patches[b].xyz;
    let p1 = patches[b + 1u].xyz;
    let p2 = patches[b + 2u].xyz;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if (det == 0.0 || !fin(det)) {
        return no_crossing();
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = dot(tv, pv) * inv;
    if (!(u >= 0.0 && u <= 1.0)) {
        return no_crossing();
    }
    let qv = cross(tv, e1);
    let v = dot(d, qv) * inv;
    if (!(v >= 0.0 && u + v <= 1.0)) {
        return no_crossing();
    }
    let t = dot(e2, qv) * inv;
    if (t >= t_min && t <= t_max && fin(t)) {
        return Crossing(true, t, 0.0, vec3<f32>(1.0 - u - v, u, v));
    }
    return no_crossing();
}

// ---------------------------------------------------------------------------------------------
// Traversal (core/src/bvh/tree.rs `traverse`: four-wide nodes, entered children pushed farthest first
// so the nearest is visited next, leaves tested when popped)

struct Traced {
    found: bool,
    err: u32,
    best: Crossing,
    id: u32,
}

// The closest crossing of the ray in [t_min, t_max] (any crossing when `any`), its patch, and
// the status bits of a corrupt tree or a full stack (then nothing is found).
fn trace(o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32, any: bool) -> Traced {
    var none = Traced(false, 0u, no_crossing(), 0u);
    // The host marks rays that the CPU rejects (non-finite, zero direction, NaN or reversed
    // range) with t_min > t_max; the checks here only repeat that.
    if (!(t_min <= t_max) || !fin3(o) || !fin3(d) || !fin(t_min) || !fin(t_max)
        || dot(d, d) == 0.0) {
        return none;
    }
    let node_count = min(params.node_count, arrayLength(&nodes));
    let order_count = min(params.order_count, arrayLength(&order));
    var patch_count = min(params.patch_count, arrayLength(&patches) / PATCH_VEC4);
    if (FLAT != 0u) {
        patch_count = min(params.patch_count, arrayLength(&patches) / FLAT_VEC4);
    }
    if (node_count == 0u) {
        return none;
    }
    let inv = vec3<f32>(select(0.0, 1.0 / d.x, d.x != 0.0), select(0.0, 1.0 / d.y, d.y != 0.0),
        select(0.0, 1.0 / d.z, d.z != 0.0));
    var tmax = t_max;
    var found = false;
    var best = no_crossing();
    var best_id = 0u;
    var err = 0u;
    // Pending nodes and leaves (child, count as in Node) with where the ray enters their box.
    var st_child: array<u32, STACK>;
    var st_count: array<u32, STACK>;
    var st_t: array<f32, STACK>;
    st_child[0] = 0u;
    st_count[0] = 0u;
    st_t[0] = t_min;
    var sp = 1u;
    // Slab test per axis as core/src/bvh/node.rs `SlabRay`: 1/d where finite; d = 0: the origin
    // between the planes; 1/d not finite: the axis is not tested (conservative).
    let slab = vec3<bool>(d.x != 0.0 && fin(inv.x), d.y != 0.0 && fin(inv.y),
        d.z != 0.0 && fin(inv.z));
    var visits = node_count;
    var tests = order_count;
    loop {
        if (sp == 0u) {
            break;
        }
        sp -= 1u;
        let ec = st_child[sp];
        let en = st_count[sp];
        // Skip what the best hit has moved in front of since it was pushed.
        if (st_t[sp] > tmax) {
            continue;
        }
        if (en > 0u) {
            if (ec > order_count || en > order_count - ec || en > tests) {
                err |= STATUS_CORRUPT;
                break;
            }
            tests -= en;
            var stop = false;
            for (var k = 0u; k < en; k++) {
                let id = order[ec + k];
                if (id >= patch_count) {
                    err |= STATUS_CORRUPT;
                    stop = true;
                    break;
                }
                // Each patch is tested over the caller's whole range (the first sign change
                // depends on the interval), then compared with the best so far.
                var c: Crossing;
                if (FLAT != 0u) {
                    c = flat_crossing(id, o, d, t_min, t_max);
                } else {
                    c = smooth_crossing(id, o, d, inv, t_min, t_max);
                }
                if (c.ok && (!found || c.t < tmax)) {
                    tmax = c.t;
                    best = c;
                    best_id = id;
                    found = true;
                    if (any) {
                        stop = true;
                        break;
                    }
                }
            }
            if (stop) {
                break;
            }
            continue;
        }
        if (visits == 0u || ec >= node_count) {
            err |= STATUS_CORRUPT;
            break;
        }
        visits -= 1u;
        let node = nodes[ec];
        var a = vec4<f32>(t_min);
        var b = vec4<f32>(tmax);
        var inside = node.child != vec4<u32>(EMPTY_SLOT);
        for (var q = 0u; q < 3u; q++) {
            if (slab[q]) {
                let t1 = (node.lo[q] - o[q]) * inv[q];
                let t2 = (node.hi[q] - o[q]) * inv[q];
                a = max(a, min(t1, t2));
                b = min(b, max(t1, t2));
            } else if (d[q] == 0.0) {
                inside = inside & (node.lo[q] <= vec4<f32>(o[q])) & (vec4<f32>(o[q]) <= node.hi[q]);
            }
        }
        let enter = inside & (a <= b);
        // The entered slots sorted farthest first (insertion sort; equal entries keep slot
        // order), pushed so that the nearest is popped next.
        var sorted_t: array<f32, 4>;
        var sorted_k: array<u32, 4>;
        var m = 0u;
        for (var k = 0u; k < 4u; k++) {
            if (!enter[k]) {
                continue;
            }
            let t = a[k];
            var j = m;
            for (var q = 0u; q < 4u; q++) {
                if (j == 0u || sorted_t[j - 1u] >= t) {
                    break;
                }
                sorted_t[j] = sorted_t[j - 1u];
                sorted_k[j] = sorted_k[j - 1u];
                j -= 1u;
            }
            sorted_t[j] = t;
            sorted_k[j] = k;
            m += 1u;
        }
        if (sp + m > STACK) {
            err |= STATUS_STACK;
            break;
        }
        for (var q = 0u; q < m; q++) {
            let k = sorted_k[q];
            st_child[sp] = node.child[k];
            st_count[sp] = node.count[k];
            st_t[sp] = sorted_t[q];
            sp += 1u;
        }
    }
    if (err != 0u) {
        none.err = err;
        return none;
    }
    return Traced(found, 0u, best, best_id);
}

// The geometric normal (world, unit) of a crossing of patch `id` (checked by `trace`);
// w = 0 where it is not finite (the CPU then reports no hit).
fn hit_normal(id: u32, c: Crossing) -> vec4<f32> {
    if (FLAT != 0u) {
        let b = id * FLAT_VEC4;
        let p0 = patches[b].xyz;
        return try_normalize(cross(patches[b + 1u].xyz - p0, patches[b + 2u].xyz - p0));
    }
    let pt = load_patch(id);
    let nl = normal_local(pt, c.bary);
    let normal = pt.ex * nl.x + pt.ey * nl.y + pt.ez * nl.z;
    return vec4<f32>(normal, select(0.0, 1.0, fin3(normal)));
}

// ---------------------------------------------------------------------------------------------
// Shading normals (SHADING): the seamless normal of core/src/mesh/seams.rs `Seam::correct`,
// or the Phong normal of the flat triangles (the interpolated vertex normals).

// The tilt τ(t) = t(1 − t)·Σ_k c_k (2t − 1)^k (seams.rs `twist`).
fn twist(c: array<f32, TWIST_TERMS>, t: f32) -> f32 {
    let u = t + t - 1.0;
    var h = 0.0;
    for (var k = 0u; k < TWIST_TERMS; k++) {
        h = h * u + c[TWIST_TERMS - 1u - k];
    }
    return t * (1.0 - t) * h;
}

fn edge_of(pt: Patch, j: u32) -> Edge {
    if (j == 0u) {
        return pt.e0;
    }
    if (j == 1u) {
        return pt.e1;
    }
    return pt.e2;
}

// Edge j's point seen from barycentrics x (seams.rs `edge_points`): the opposite vertex's
// weight moved onto the edge's two in proportion.
fn edge_point(x: vec3<f32>, j: u32) -> vec3<f32> {
    if (j == 0u) {
        let s = x.x + x.y;
        return vec3<f32>(x.x + x.z * (x.x / s), x.y + x.z * (x.y / s), 0.0);
    }
    if (j == 1u) {
        let s = x.y + x.z;
        return vec3<f32>(0.0, x.y + x.x * (x.y / s), x.z + x.x * (x.z / s));
    }
    let s = x.z + x.x;
    return vec3<f32>(x.x + x.y * (x.x / s), 0.0, x.z + x.y * (x.z / s));
}

// The seamless normal (local frame) at projected barycentrics x from the geometric one ng
// (seams.rs `Seam::correct_local`); w = 0 where the correction vanishes. `s` is the patch's
// seam record (SEAM_VEC4 vec4s, lib.rs `seam_record`).
fn seam_correct(pt: Patch, s: u32, x: vec3<f32>, ng: vec3<f32>) -> vec4<f32> {
    let prods = vec3<f32>(x.x * x.y, x.y * x.z, x.z * x.x);
    let big = max(max(prods.x, prods.y), prods.z);
    if (!(big > 0.0) || !fin(big)) {
        return vec4<f32>(0.0);
    }
    let r = prods / big;
    let q = r * r;
    let sum = q.x + q.y + q.z;
    let flags = shade_in[s + 9u];
    var acc = vec3<f32>(0.0);
    var touched = false;
    for (var j = 0u; j < 3u; j++) {
        let v0 = shade_in[s + 3u * j];
        let v1 = shade_in[s + 3u * j + 1u];
        let v2 = shade_in[s + 3u * j + 2u];
        let across = array<f32, TWIST_TERMS>(v0.x, v0.y, v0.z, v0.w, v1.x, v1.y);
        let along = array<f32, TWIST_TERMS>(v1.z, v1.w, v2.x, v2.y, v2.z, v2.w);
        let zero = all(v0 == vec4<f32>(0.0)) && all(v1 == vec4<f32>(0.0))
            && all(v2 == vec4<f32>(0.0));
        if (!(q[j] > 0.0) || zero) {
            continue;
        }
        let xa = x[j];
        let xb = x[(j + 1u) % 3u];
        let t = xb / (xa + xb);
        let e = edge_of(pt, j);
        // The frame both neighbours build from the edge (seams.rs `shared_frame`).
        let g = try_normalize(e.na * (1.0 - t) + e.nb * t);
        let gb = try_normalize(cross(vec3<f32>(e.e, 0.0), g.xyz));
        let ga = cross(g.xyz, gb.xyz);
        if (g.w == 0.0 || gb.w == 0.0 || !fin3(ga)) {
            continue;
        }
        var m: vec4<f32>;
        if (flags[j] != 0.0) {
            // The neighbour's vertex normals, interpolated, averaged with this side's.
            let other = try_normalize(v0.xyz * (1.0 - t) + vec3<f32>(v0.w, v1.x, v1.y) * t);
            m = select(vec4<f32>(0.0), try_normalize(g.xyz + other.xyz), other.w != 0.0);
        } else {
            m = try_normalize(g.xyz + gb.xyz * twist(across, t) + ga * twist(along, t));
        }
        if (m.w == 0.0) {
            continue;
        }
        let own = normal_local(pt, edge_point(x, j));
        acc = acc + (m.xyz - own) * (q[j] / sum);
        touched = true;
    }
    if (!touched) {
        return vec4<f32>(0.0);
    }
    return try_normalize(ng + acc);
}

// The shading normal (world) of the closest crossing c of patch id with geometric normal
// `normal` (SHADING: 0 the geometric normal itself; 1 seamless, as the CPU's
// `Scene::shading_normal`; 2 Phong, the flat scene's interpolated vertex normals).
fn shading_normal(id: u32, c: Crossing, normal: vec3<f32>) -> vec3<f32> {
    let w1 = c.bary.y;
    let w2 = c.bary.z;
    if (SHADING == 2u) {
        let b = id * 3u;
        if (b + 2u >= arrayLength(&shade_in)) {
            return normal;
        }
        let w0 = 1.0 - w1 - w2;
        let n = try_normalize(shade_in[b].xyz * w0 + shade_in[b + 1u].xyz * w1
            + shade_in[b + 2u].xyz * w2);
        return select(normal, n.xyz, n.w != 0.0);
    }
    if (SHADING != 1u || FLAT != 0u) {
        return normal;
    }
    let s = id * SEAM_VEC4;
    if (s + SEAM_VEC4 > arrayLength(&shade_in) || shade_in[s + 9u].w == 0.0) {
        return normal;
    }
    let pt = load_patch(id);
    let ng = try_normalize(vec3<f32>(dot(normal, pt.ex), dot(normal, pt.ey), dot(normal, pt.ez)));
    if (ng.w == 0.0) {
        return normal;
    }
    let x = project(vec3<f32>(1.0 - w1 - w2, w1, w2));
    let n = seam_correct(pt, s, x, ng.xyz);
    if (n.w == 0.0) {
        return normal;
    }
    return pt.ex * n.x + pt.ey * n.y + pt.ez * n.z;
}

// ---------------------------------------------------------------------------------------------
// Entry point of the batch queries (lib.rs `GpuScene::closest_hit`, `any_hit`): one ray per
// invocation, from `rays` to `hits`.

fn miss(i: u32) {
    hits[i] = HitOut(0.0, 0.0, 0.0, 0.0, vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0),
        0u);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= params.ray_count || i >= arrayLength(&rays) || i >= arrayLength(&hits)) {
        return;
    }
    let ray = rays[i];
    let tr = trace(ray.o, ray.d, ray.t_min, ray.t_max, ANY_HIT != 0u);
    if (tr.err != 0u) {
        atomicOr(&status[0], tr.err);
    }
    if (!tr.found) {
        miss(i);
        return;
    }
    let best = tr.best;
    if (ANY_HIT != 0u) {
        hits[i] = HitOut(best.t, best.t_error, best.bary.y, best.bary.z, vec3<f32>(0.0),
            tr.id, vec3<f32>(0.0), 1u, vec3<f32>(0.0), 0u);
        return;
    }
    // The normal, once, for the closest crossing.
    let n = hit_normal(tr.id, best);
    if (n.w == 0.0) {
        miss(i);
        return;
    }
    let front = dot(n.xyz, ray.d) < 0.0;
    hits[i] = HitOut(best.t, best.t_error, best.bary.y, best.bary.z, ray.o + ray.d * best.t,
        tr.id, n.xyz, select(1u, 3u, front), shading_normal(tr.id, best, n.xyz), 0u);
}

// ---------------------------------------------------------------------------------------------
// Entry point of whole frames (lib.rs `GpuScene::render_frame`): one invocation per pixel
// generates the camera ray, traces it, shades the closest hit with the shading normal, Lambert
// and ambient light and one shadow ray, and writes the pixel's colour and hit. The demo's
// renderer (host-demo/src/renderer.rs `render`, `shade`, `background`, and the heat map of
// `view`) in f32.

fn to_u8(x: f32) -> u32 {
    let c = clamp(x, 0.0, 1.0);
    return u32(select(0.0, pow(c, 1.0 / 2.2), c > 0.0) * 255.0 + 0.5);
}

fn pack(c: vec3<u32>) -> u32 {
    return min(c.x, 255u) | (min(c.y, 255u) << 8u) | (min(c.z, 255u) << 16u) | (255u << 24u);
}

// host-demo/src/image.rs `heat`.
fn heat(l: f32) -> vec3<u32> {
    let t = clamp(l, 0.0, 1.0);
    var a = 0.0;
    var b = 0.33;
    var ca = vec3<f32>(20.0, 20.0, 90.0);
    var cb = vec3<f32>(30.0, 170.0, 200.0);
    if (t > 0.66) {
        a = 0.66;
        b = 1.0;
        ca = vec3<f32>(240.0, 220.0, 60.0);
        cb = vec3<f32>(220.0, 30.0, 30.0);
    } else if (t > 0.33) {
        a = 0.33;
        b = 0.66;
        ca = cb;
        cb = vec3<f32>(240.0, 220.0, 60.0);
    }
    return vec3<u32>(ca + (cb - ca) * ((t - a) / (b - a)));
}

@compute @workgroup_size(8, 8)
fn frame(@builtin(global_invocation_id) gid: vec3<u32>) {
    let x = gid.x;
    let y = gid.y;
    let w = view.width;
    let h = view.height;
    if (x >= w || y >= h) {
        return;
    }
    let i = y * w + x;
    if (i >= arrayLength(&image) || i >= arrayLength(&pixels)) {
        return;
    }
    // testkit/src/camera.rs `Camera::ray` through the pixel's centre.
    let sx = (2.0 * (f32(x) + 0.5) / f32(w) - 1.0) * view.tan_half * view.aspect;
    let sy = (1.0 - 2.0 * (f32(y) + 0.5) / f32(h)) * view.tan_half;
    let d = normalize(view.forward + view.right * sx + view.up * sy);
    let o = view.eye;
    let tr = trace(o, d, 0.0, 3.4028235e38, false);
    if (tr.err != 0u) {
        atomicOr(&status[0], tr.err);
    }
    var n = vec4<f32>(0.0);
    if (tr.found) {
        n = hit_normal(tr.id, tr.best);
    }
    if (n.w == 0.0) {
        let s = f32(y) / f32(max(h, 1u));
        var bg = vec3<u32>(vec3<f32>(48.0 - 24.0 * s, 54.0 - 26.0 * s, 66.0 - 30.0 * s));
        if (view.heat_scale > 0.0) {
            bg = vec3<u32>(0u);
        }
        image[i] = pack(bg);
        pixels[i] = PixelOut(vec3<f32>(0.0), MISS, 0.0, 0u, 0u, 0u);
        return;
    }
    let best = tr.best;
    let p = o + d * best.t;
    var nn = shading_normal(tr.id, best, n.xyz);
    if (dot(nn, d) > 0.0) {
        nn = -nn;
    }
    let lambert = max(dot(nn, view.light), 0.0);
    var vis = 0.0;
    if (lambert > 0.0) {
        atomicAdd(&frame_stats[0], 1u);
        let shadow = trace(p - d * view.eps, view.light, view.eps, 3.4028235e38, true);
        if (shadow.err != 0u) {
            atomicOr(&status[0], shadow.err);
        }
        vis = select(1.0, 0.0, shadow.found);
    }
    var c: vec3<u32>;
    if (view.heat_scale > 0.0) {
        let rel = max(best.t_error * view.heat_scale, 1e-12);
        c = heat((log2(rel) * 0.30103 + 9.0) / 6.0);
    } else {
        let front = dot(n.xyz, d) < 0.0;
        let albedo = select(vec3<f32>(0.25, 0.45, 0.80), vec3<f32>(0.85, 0.50, 0.22), front);
        let s = 0.12 + (1.0 - 0.12) * lambert * vis;
        c = vec3<u32>(to_u8(albedo.x * s), to_u8(albedo.y * s), to_u8(albedo.z * s));
    }
    image[i] = pack(c);
    pixels[i] = PixelOut(p, tr.id, best.t_error, 0u, 0u, 0u);
    atomicMax(&frame_stats[1], bitcast<u32>(best.t_error));
}
