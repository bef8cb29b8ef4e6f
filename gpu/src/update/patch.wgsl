// The scene update's passes (gpu/src/update.rs `GpuUpdate`), one file each, compiled after the
// kernel's shader (gpu/src/kernel/; its height evaluation samples the surface) with `patches` and
// `nodes` bound read_write: this file (the bindings and constants they share, and the patches),
// cracks.wgsl (crack closure and the boxes), seams.wgsl (the seam fits), tree.wgsl (the refit) and
// normals.wgsl (vertex normals of a mesh without any).
//
// The per-patch step: one invocation per triangle slot builds the patch of its triangle from
// vertex buffers already on the device and writes its record in the layout `load_patch` reads
// (gpu/src/records.rs `smooth_record`).
//
// The mathematics is the CPU's `Patch::new_or_tilted_with` in f32 (core/src/patch.rs: frame,
// local normals and line field, core/src/surface/edge.rs sphere curvatures,
// core/src/surface/shell.rs samples, height range, validity and box, core/src/surface/band.rs
// culling band), the same operations in the same order; the per-patch remedy tries the
// clamps of `NORMAL_CLAMP_DEG` (uploaded as cosines and sines) in order. A triangle the CPU
// rejects gets the CPU's placeholder record (empty box, no surface) and its reason in
// `slot_remedy`, so a mesh's layout never depends on its data. Reaches are 0 here: crack
// closure is a later pass.

struct BuildParams {
    count: u32,         // triangle slots
    vertex_field: u32,  // 1: LineField::Vertex (one scale for the three normals)
    vertices: u32,      // entries of the position and normal buffers (xyz each)
    seams: u32,         // 1: the scene carries seam records (seam_out) to fit
    clamp: array<vec4<f32>, 6>, // (cos, sin) of NORMAL_CLAMP_DEG, in order
}

@group(0) @binding(8) var<uniform> bparams: BuildParams;
@group(0) @binding(9) var<storage, read> b_positions: array<f32>;
@group(0) @binding(10) var<storage, read_write> b_normals: array<f32>;
@group(0) @binding(11) var<storage, read> b_triangles: array<u32>;
// The scene's seam records (gpu/src/records.rs `seam_record`, SEAM_VEC4 per patch) where
// `seams` is set; otherwise a dummy buffer that no pass touches.
@group(0) @binding(17) var<storage, read_write> seam_out: array<vec4<f32>>;
// Per slot: the CPU's `Patch::remedy` byte (0: as given; k + 1: clamp k; 0x80 | reason: the
// placeholder of a rejected triangle).
@group(0) @binding(12) var<storage, read_write> slot_remedy: array<u32>;

// core/src/patch.rs MIN_NORMAL_COS, `degenerate_ratio` (√ε of f32), and f32::MIN_POSITIVE.
const MIN_NORMAL_COS: f32 = 1.0e-3;
const DEGENERATE_RATIO: f32 = 3.4526698e-4;
const MIN_POSITIVE: f32 = 1.1754944e-38;
const F32_MAX: f32 = 3.4028235e38;
// core/src/surface/shell.rs MARGIN_REL / MARGIN_ABS; core/src/kernel/budget.rs EXTENT_EDGES,
// MAX_CRACK_REACH; core/src/surface/band.rs BAND_MIN_NORMAL_COS.
const MARGIN_REL: f32 = 0.5;
const MARGIN_ABS: f32 = 1.0e-4;
const EXTENT_EDGES: f32 = 4.0;
const MAX_CRACK_REACH: f32 = 0.25;
const BAND_MIN_NORMAL_COS: f32 = 0.70710677;

const REJECTED: u32 = 0x80u;
const E_NON_FINITE: u32 = 1u;
const E_DEGENERATE: u32 = 2u;
const E_ZERO_NORMAL: u32 = 3u;   // + vertex
const E_BACK_FACING: u32 = 6u;   // + vertex
const E_INVALID_SHELL: u32 = 9u;
const E_OUT_OF_RANGE: u32 = 10u;

// The patch in its local frame, as the CPU's Frame and Shape (P0 = 0, P1 = (p1x, 0, 0),
// P2 = (p2x, p2y, 0)).
struct Local {
    origin: vec3<f32>,
    ex: vec3<f32>,
    ey: vec3<f32>,
    ez: vec3<f32>,
    p1x: f32,
    p2x: f32,
    p2y: f32,
    n0: vec3<f32>,
    n1: vec3<f32>,
    n2: vec3<f32>,
    d0: vec3<f32>,
    d1: vec3<f32>,
    d2: vec3<f32>,
}

struct Constructed {
    code: u32,  // 0 or the error of core/src/error.rs PatchError (the placeholder's code)
    l: Local,
}

// V3::try_normalize: (unit vector, 1) or (0, 0).
fn unit_or_zero(v: vec3<f32>) -> vec4<f32> {
    let l = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (l > 0.0 && fin(l)) {
        let u = v * (1.0 / l);
        if (fin3(u)) {
            return vec4<f32>(u, 1.0);
        }
    }
    return vec4<f32>(0.0);
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

fn all_zero(v: vec3<f32>) -> bool {
    return v.x == 0.0 && v.y == 0.0 && v.z == 0.0;
}

// One vertex normal in the local frame (x: the unit normal; w: 0 or the error code).
struct LocalNormal {
    n: vec3<f32>,
    code: u32,
}

fn local_normal(src: vec3<f32>, ex: vec3<f32>, ey: vec3<f32>, nf: vec3<f32>, vertex: u32)
    -> LocalNormal {
    let len2 = dot3(src, src);
    var u = vec4<f32>(0.0);
    if (!fin(len2)) {
        // Overflowing normal: rescale first.
        let m = max(max(abs(src.x), abs(src.y)), abs(src.z));
        u = unit_or_zero(src * (1.0 / m));
    } else if (len2 < MIN_POSITIVE) {
        return LocalNormal(vec3<f32>(0.0), E_ZERO_NORMAL + vertex);
    } else {
        u = unit_or_zero(src);
    }
    if (u.w == 0.0) {
        return LocalNormal(vec3<f32>(0.0), E_ZERO_NORMAL + vertex);
    }
    let n = vec3<f32>(dot3(u.xyz, ex), dot3(u.xyz, ey), dot3(u.xyz, nf));
    if (n.z < MIN_NORMAL_COS || !fin(n.z)) {
        return LocalNormal(n, E_BACK_FACING + vertex);
    }
    return LocalNormal(n, 0u);
}

fn line_dir(n: vec3<f32>) -> vec3<f32> {
    let d = n * (1.0 / n.z);
    return vec3<f32>(d.x, d.y, 1.0);
}

// core/src/patch.rs `Patch::with_field` up to the shell: the frame, the local vertices, normals
// and line field, or the error.
fn construct(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, m0: vec3<f32>, m1: vec3<f32>,
    m2: vec3<f32>) -> Constructed {
    var out: Constructed;
    out.code = 0u;
    if (!(fin3(p0) && fin3(p1) && fin3(p2) && fin3(m0) && fin3(m1) && fin3(m2))) {
        out.code = E_NON_FINITE;
        return out;
    }
    let e = p1 - p0;
    let f = p2 - p0;
    let c = cross3(e, f);
    let g = p2 - p1;
    let lmax2 = max(max(dot3(e, e), dot3(f, f)), dot3(g, g));
    let c2 = dot3(c, c);
    let c_len = sqrt(c2);
    if (!fin(lmax2) || !fin(c_len)) {
        out.code = E_OUT_OF_RANGE;
        return out;
    }
    if (!(all_zero(e) && all_zero(f)) && lmax2 * lmax2 < MIN_POSITIVE / EPS) {
        out.code = E_OUT_OF_RANGE;
        return out;
    }
    if (c_len <= DEGENERATE_RATIO * lmax2 || c_len <= 0.0) {
        out.code = E_DEGENERATE;
        return out;
    }
    if (c2 < MIN_POSITIVE / EPS) {
        out.code = E_OUT_OF_RANGE;
        return out;
    }
    let nf0 = c * (1.0 / c_len);
    let ex = unit_or_zero(e);
    if (ex.w == 0.0) {
        out.code = E_DEGENERATE;
        return out;
    }
    // Re-orthogonalise, as the CPU.
    let nf = unit_or_zero(nf0 - ex.xyz * dot3(nf0, ex.xyz));
    if (nf.w == 0.0) {
        out.code = E_DEGENERATE;
        return out;
    }
    let ey = cross3(nf.xyz, ex.xyz);
    let l0 = local_normal(m0, ex.xyz, ey, nf.xyz, 0u);
    if (l0.code != 0u) {
        out.code = l0.code;
        return out;
    }
    let l1 = local_normal(m1, ex.xyz, ey, nf.xyz, 1u);
    if (l1.code != 0u) {
        out.code = l1.code;
        return out;
    }
    let l2 = local_normal(m2, ex.xyz, ey, nf.xyz, 2u);
    if (l2.code != 0u) {
        out.code = l2.code;
        return out;
    }
    var d0 = line_dir(l0.n);
    var d1 = line_dir(l1.n);
    var d2 = line_dir(l2.n);
    if (bparams.vertex_field != 0u) {
        // One scale for the three normals unless they make equal angles with the face.
        let lo = min(min(l0.n.z, l1.n.z), l2.n.z);
        let hi = max(max(l0.n.z, l1.n.z), l2.n.z);
        if (hi - lo > 4.0 * EPS * hi) {
            let inv = 1.0 / hi;
            d0 = l0.n * inv;
            d1 = l1.n * inv;
            d2 = l2.n * inv;
        }
    }
    out.l = Local(p0, ex.xyz, ey, nf.xyz, dot3(e, ex.xyz), dot3(f, ex.xyz), dot3(f, ey), l0.n,
        l1.n, l2.n, d0, d1, d2);
    return out;
}

// core/src/surface/sphere.rs `curvature`.
fn curvature(a: vec3<f32>, m: vec3<f32>, b: vec3<f32>) -> f32 {
    let w = b - a;
    let l2 = dot3(w, w);
    if (l2 > 0.0) {
        return 2.0 * dot3(w, m) / l2;
    }
    return 0.0;
}

fn lp(l: Local, i: u32) -> vec3<f32> {
    switch i {
        case 0u: { return vec3<f32>(0.0); }
        case 1u: { return vec3<f32>(l.p1x, 0.0, 0.0); }
        default: { return vec3<f32>(l.p2x, l.p2y, 0.0); }
    }
}

fn ln(l: Local, i: u32) -> vec3<f32> {
    switch i {
        case 0u: { return l.n0; }
        case 1u: { return l.n1; }
        default: { return l.n2; }
    }
}

fn ld(l: Local, i: u32) -> vec3<f32> {
    switch i {
        case 0u: { return l.d0; }
        case 1u: { return l.d1; }
        default: { return l.d2; }
    }
}

// The record of `l` (gpu/src/records.rs `smooth_record`) with height range `sigma`, box
// `lo`/`hi`, reaches 0 and band `band0`/`band1`, into patches[id].
fn write_record(id: u32, l: Local, sigma: vec2<f32>, lo: vec3<f32>, hi: vec3<f32>,
    band0: vec4<f32>, band1: vec4<f32>) {
    let b = id * PATCH_VEC4;
    let p1 = lp(l, 1u);
    let p2 = lp(l, 2u);
    let longest = sqrt(max(max(dot3(p1, p1), dot3(p2 - p1, p2 - p1)), dot3(p2, p2)));
    let scale = longest * 4.0 + sqrt(dot3(l.origin, l.origin));
    patches[b] = vec4<f32>(l.origin, scale);
    patches[b + 1u] = vec4<f32>(l.ex, sigma.x);
    patches[b + 2u] = vec4<f32>(l.ey, sigma.y);
    patches[b + 3u] = vec4<f32>(l.ez, l.p1x);
    patches[b + 4u] = vec4<f32>(lo, l.p2x);
    patches[b + 5u] = vec4<f32>(hi, l.p2y);
    patches[b + 6u] = vec4<f32>(l.n0, l.d0.x);
    patches[b + 7u] = vec4<f32>(l.n1, l.d0.y);
    patches[b + 8u] = vec4<f32>(l.n2, l.d1.x);
    patches[b + 9u] = vec4<f32>(l.d1.y, l.d2.x, l.d2.y, 0.0);
    for (var j = 0u; j < 3u; j++) {
        let k = (j + 1u) % 3u;
        let a = lp(l, j);
        let da = ld(l, j);
        let db = ld(l, k);
        let na = ln(l, j);
        let nb = ln(l, k);
        let e = lp(l, k) - a;
        let gd = db - da;
        let k1 = curvature(a, na, lp(l, k));
        let k2 = curvature(lp(l, k), nb, a);
        let r = b + 10u + 5u * j;
        patches[r] = vec4<f32>(e.x, e.y, gd.x, gd.y);
        patches[r + 1u] = vec4<f32>(k1, k2, dot3(e, e), dot3(e, da));
        patches[r + 2u] = vec4<f32>(dot3(e, gd), dot3(da, da), 2.0 * dot3(da, gd), dot3(gd, gd));
        patches[r + 3u] = vec4<f32>(dot3(da, na), dot3(gd, na), dot3(e, na), 0.0);
        patches[r + 4u] = vec4<f32>(dot3(da, nb), dot3(gd, nb), dot3(e, nb), da.z);
    }
    patches[b + 25u] = band0;
    patches[b + 26u] = band1;
}

// The placeholder's record (the CPU's `Patch::default()` through `smooth_record`): zeros, an
// empty box, the unbounded band.
fn write_placeholder(id: u32) {
    let b = id * PATCH_VEC4;
    for (var k = 0u; k < PATCH_VEC4; k++) {
        patches[b + k] = vec4<f32>(0.0);
    }
    patches[b + 4u] = vec4<f32>(F32_MAX, F32_MAX, F32_MAX, 0.0);
    patches[b + 5u] = vec4<f32>(-F32_MAX, -F32_MAX, -F32_MAX, 0.0);
    patches[b + 25u] = vec4<f32>(0.0, 0.0, 0.0, -F32_MAX);
    patches[b + 26u] = vec4<f32>(F32_MAX, 0.0, 0.0, 0.0);
}

// core/src/surface/shell.rs: the sample barycentrics (15 on the edges at EDGE_T, 4 inside).
const SHELL_SAMPLES: u32 = 19u;
const EDGE_T = array<f32, 5>(0.1, 0.25, 0.5, 0.75, 0.9);

fn sample_bary(i: u32) -> vec3<f32> {
    if (i < 15u) {
        let t = EDGE_T[i % 5u];
        switch i / 5u {
            case 0u: { return vec3<f32>(1.0 - t, t, 0.0); }
            case 1u: { return vec3<f32>(0.0, 1.0 - t, t); }
            default: { return vec3<f32>(t, 0.0, 1.0 - t); }
        }
    }
    switch i - 15u {
        case 0u: { return vec3<f32>(2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0); }
        case 1u: { return vec3<f32>(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0); }
        case 2u: { return vec3<f32>(1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0); }
        default: { return vec3<f32>(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0); }
    }
}

// shell.rs `longest_edge`.
fn longest_edge(l: Local) -> f32 {
    let dx = l.p2x - l.p1x;
    return sqrt(max(max(l.p1x * l.p1x, dx * dx + l.p2y * l.p2y), l.p2x * l.p2x + l.p2y * l.p2y));
}

fn parallel_sections(l: Local) -> bool {
    return l.d0.z == 1.0 && l.d1.z == 1.0 && l.d2.z == 1.0;
}

fn cross_z(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// shell.rs `quadratic_min` over [lo, hi].
fn quadratic_min(c: vec3<f32>, lo: f32, hi: f32) -> f32 {
    var m = min(c.x + lo * (c.y + lo * c.z), c.x + hi * (c.y + hi * c.z));
    if (c.z != 0.0) {
        let v = -c.y / (c.z + c.z);
        if (v > lo && v < hi) {
            m = min(m, c.x + v * (c.y + v * c.z));
        }
    }
    return m;
}

// shell.rs `is_valid`: every section through the shell is a proper triangle.
fn shell_valid(l: Local, sigma: vec2<f32>) -> bool {
    let p1 = lp(l, 1u);
    let p2 = lp(l, 2u);
    if (parallel_sections(l)) {
        let u1 = l.d1 - l.d0;
        let v1 = l.d2 - l.d0;
        let c = vec3<f32>(cross_z(p1, p2), cross_z(p1, v1) + cross_z(u1, p2), cross_z(u1, v1));
        return quadratic_min(c, sigma.x, sigma.y) >= 0.25 * c.x && c.x > 0.0;
    }
    let c1 = l.d1 - l.d0;
    let c2 = l.d2 - l.d0;
    let k0 = cross3(p1, p2);
    let k1 = cross3(p1, c2) + cross3(c1, p2);
    let k2 = cross3(c1, c2);
    let dz = min(min(l.d0.z, l.d1.z), l.d2.z);
    let lo = sigma.x / dz;
    let hi = sigma.y / dz;
    for (var i = 0u; i < 3u; i++) {
        let d = ld(l, i);
        let c = vec3<f32>(dot3(k0, d), dot3(k1, d), dot3(k2, d));
        if (!(fin(lo) && fin(hi) && c.x > 0.0 && quadratic_min(c, lo, hi) >= 0.25 * c.x)) {
            return false;
        }
    }
    return true;
}

struct Box {
    lo: vec3<f32>,
    hi: vec3<f32>,
}

// shell.rs `aabb`: the world box of the shell over the triangle widened by `reach`, padded by
// 8 ε of its coordinates.
fn shell_box(origin: vec3<f32>, ex: vec3<f32>, ey: vec3<f32>, ez: vec3<f32>, p1: vec3<f32>,
    p2: vec3<f32>, d0: vec3<f32>, d1: vec3<f32>, d2: vec3<f32>, sigma: vec2<f32>,
    reach: vec3<f32>) -> Box {
    let dz = min(min(d0.z, d1.z), d2.z);
    let s_lo = sigma.x / dz;
    let s_hi = sigma.y / dz;
    let m = reach;
    var lo = vec3<f32>(F32_MAX);
    var hi = vec3<f32>(-F32_MAX);
    for (var c = 0u; c < 3u; c++) {
        var x = vec3<f32>(1.0 + m.y + m.z, -m.y, -m.z);
        if (c == 1u) {
            x = vec3<f32>(-m.x, 1.0 + m.x + m.z, -m.z);
        } else if (c == 2u) {
            x = vec3<f32>(-m.x, -m.y, 1.0 + m.x + m.y);
        }
        for (var k = 0u; k < 2u; k++) {
            let s = select(s_lo, s_hi, k == 1u);
            var q = vec3<f32>(0.0);
            q = q + (vec3<f32>(0.0) + d0 * s) * x.x;
            q = q + (p1 + d1 * s) * x.y;
            q = q + (p2 + d2 * s) * x.z;
            let w = origin + ex * q.x + ey * q.y + ez * q.z;
            lo = min(lo, w);
            hi = max(hi, w);
        }
    }
    let e = max(abs(lo), abs(hi)) * (8.0 * EPS);
    return Box(lo - e, hi + e);
}

// band.rs `bary_xy`.
fn bary_xy(l: Local, x: f32, y: f32, lin: bool) -> vec3<f32> {
    let b2 = y / l.p2y;
    let b1 = (x - l.p2x * b2) / l.p1x;
    let b0 = select(1.0 - b1 - b2, -b1 - b2, lin);
    return vec3<f32>(b0, b1, b2);
}

fn band_basis(b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(b.y * b.z, b.z * b.x, b.x * b.y);
}

fn det3(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    // Rows a, b, c.
    return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x)
        + a.z * (b.x * c.y - b.y * c.x);
}

// The world box and band of one built patch.
struct Fitted {
    sigma: vec2<f32>,
    band0: vec4<f32>,
    band1: vec4<f32>,
    ok: bool,
}

// The shell sample heights of the patch record at `id` (written with sigma 0 first).
var<private> heights: array<f32, 19>;

// shell.rs `samples` (through the kernel's height: the CPU's lane evaluation within rounding)
// and `bounds_of`, then band.rs `fit`.
fn fit_shell(id: u32, l: Local) -> Fitted {
    var out: Fitted;
    let pt = load_patch(id);
    var lo = 0.0;
    var hi = 0.0;
    for (var i = 0u; i < SHELL_SAMPLES; i++) {
        var h = height_at(pt, sample_bary(i));
        if (!fin(h) && i < 15u) {
            // The CPU's scalar fallback: the edge curve's height there.
            let t = EDGE_T[i % 5u];
            var ep = pt.e0;
            if (i / 5u == 1u) {
                ep = pt.e1;
            } else if (i / 5u == 2u) {
                ep = pt.e2;
            }
            h = edge_point_normal(ep, t).c.z;
        }
        heights[i] = h;
        lo = min(lo, h);
        hi = max(hi, h);
    }
    let size = longest_edge(l);
    let m = MARGIN_REL * (hi - lo) + MARGIN_ABS * size;
    out.sigma = vec2<f32>(lo - m, hi + m);
    out.ok = shell_valid(l, out.sigma);
    // The band (band.rs `fit`); unbounded for steep patches or where it is not finite.
    out.band0 = vec4<f32>(0.0, 0.0, 0.0, -F32_MAX);
    out.band1 = vec4<f32>(F32_MAX, 0.0, 0.0, 0.0);
    if (!(l.n0.z >= BAND_MIN_NORMAL_COS && l.n1.z >= BAND_MIN_NORMAL_COS
        && l.n2.z >= BAND_MIN_NORMAL_COS)) {
        return out;
    }
    let p1 = lp(l, 1u);
    let p2 = lp(l, 2u);
    var m0 = vec3<f32>(0.0);
    var m1 = vec3<f32>(0.0);
    var m2 = vec3<f32>(0.0);
    var r = vec3<f32>(0.0);
    let par = parallel_sections(l);
    for (var i = 0u; i < SHELL_SAMPLES; i++) {
        let x = sample_bary(i);
        let q = sample_point(l, x, heights[i], par);
        let phi = band_basis(bary_xy(l, q.x, q.y, false));
        m0 = m0 + vec3<f32>(phi.x * phi.x, phi.x * phi.y, phi.x * phi.z);
        m1 = m1 + vec3<f32>(phi.y * phi.x, phi.y * phi.y, phi.y * phi.z);
        m2 = m2 + vec3<f32>(phi.z * phi.x, phi.z * phi.y, phi.z * phi.z);
        r = r + phi * q.z;
    }
    let det = det3(m0, m1, m2);
    let c = vec3<f32>(
        det3(vec3<f32>(r.x, m0.y, m0.z), vec3<f32>(r.y, m1.y, m1.z), vec3<f32>(r.z, m2.y, m2.z))
            / det,
        det3(vec3<f32>(m0.x, r.x, m0.z), vec3<f32>(m1.x, r.y, m1.z), vec3<f32>(m2.x, r.z, m2.z))
            / det,
        det3(vec3<f32>(m0.x, m0.y, r.x), vec3<f32>(m1.x, m1.y, r.y), vec3<f32>(m2.x, m2.y, r.z))
            / det);
    var rlo = 0.0;
    var rhi = 0.0;
    for (var i = 0u; i < SHELL_SAMPLES; i++) {
        let q = sample_point(l, sample_bary(i), heights[i], par);
        let b = bary_xy(l, q.x, q.y, false);
        let res = q.z - (c.x * (b.y * b.z) + c.y * (b.z * b.x) + c.z * (b.x * b.y));
        rlo = min(rlo, res);
        rhi = max(rhi, res);
    }
    let margin = MARGIN_REL * (rhi - rlo) + MARGIN_ABS * size;
    let csum = abs(c.x) + abs(c.y) + abs(c.z);
    let perimeter = length3(p1) + length3(p2 - p1) + length3(-p2);
    let two_area = l.p1x * l.p2y;
    let grad_q = 1.5 * csum * perimeter / two_area;
    let dxy = max(max(max(0.0, sqrt(l.d0.x * l.d0.x + l.d0.y * l.d0.y)),
        sqrt(l.d1.x * l.d1.x + l.d1.y * l.d1.y)), sqrt(l.d2.x * l.d2.x + l.d2.y * l.d2.y));
    let snap = ROUNDING_ULPS * EPS * (size * EXTENT_EDGES + length3(l.origin));
    let rounding = 4.0 * snap * (1.0 + grad_q * dxy);
    let smax = max(max(0.0, abs(out.sigma.x)), abs(out.sigma.y));
    let ell = size + 2.0 * smax * dxy;
    var mismatch = 0.0;
    let bx = bary_xy(l, 1.0, 0.0, true);
    let by = bary_xy(l, 0.0, 1.0, true);
    for (var i = 0u; i < 15u; i++) {
        let x = sample_bary(i);
        let q = sample_point(l, x, heights[i], par);
        var n = vec3<f32>(0.0);
        n = n + l.n0 * x.x;
        n = n + l.n1 * x.y;
        n = n + l.n2 * x.z;
        let b = bary_xy(l, q.x, q.y, false);
        let dq = vec3<f32>(c.y * b.z + c.z * b.y, c.x * b.z + c.z * b.x, c.x * b.y + c.y * b.x);
        let gx = dq.x * bx.x + dq.y * bx.y + dq.z * bx.z;
        let gy = dq.x * by.x + dq.y * by.y + dq.z * by.z;
        let sx = n.x / n.z + gx;
        let sy = n.y / n.z + gy;
        mismatch = max(mismatch, sqrt(sx * sx + sy * sy));
    }
    let inv_alt = perimeter / two_area;
    let hess = csum * inv_alt * inv_alt;
    let two_ell = 2.0 * ell;
    let per_reach = two_ell * (2.0 * mismatch + 0.5 * hess * two_ell * MAX_CRACK_REACH);
    let blo = rlo - margin - rounding;
    let bhi = rhi + margin + rounding;
    let z = c.x * 0.0 + c.y * 0.0 + c.z * 0.0 + per_reach * 0.0;
    if (z == 0.0 && fin(blo) && fin(bhi) && fin(det) && det != 0.0) {
        out.band0 = vec4<f32>(c, blo);
        out.band1 = vec4<f32>(bhi, per_reach, 0.0, 0.0);
    }
    return out;
}

fn length3(v: vec3<f32>) -> f32 {
    return sqrt(dot3(v, v));
}

// scalar.rs `point_from_height`: base + h·dir, dir the (unit-height) interpolated line.
fn sample_point(l: Local, x: vec3<f32>, h: f32, par: bool) -> vec3<f32> {
    let base = vec3<f32>(0.0) * x.x + lp(l, 1u) * x.y + lp(l, 2u) * x.z;
    var dir = l.d0 * x.x + l.d1 * x.y + l.d2 * x.z;
    if (!par) {
        dir = dir * (1.0 / dir.z);
    }
    return base + dir * h;
}

fn vertex_in(buf: u32, i: u32) -> vec3<f32> {
    // buf 0: positions, 1: normals; the caller checked i < vertices.
    if (buf == 0u) {
        return vec3<f32>(b_positions[3u * i], b_positions[3u * i + 1u], b_positions[3u * i + 2u]);
    }
    return vec3<f32>(b_normals[3u * i], b_normals[3u * i + 1u], b_normals[3u * i + 2u]);
}

// The whole of `Patch::with_field` for one set of normals: 0 and the record written, or the
// error code (the record then holds scratch).
fn build_one(id: u32, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, m0: vec3<f32>,
    m1: vec3<f32>, m2: vec3<f32>) -> u32 {
    let c = construct(p0, p1, p2, m0, m1, m2);
    if (c.code != 0u) {
        return c.code;
    }
    let l = c.l;
    let zero4 = vec4<f32>(0.0);
    write_record(id, l, vec2<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), zero4, zero4);
    let f = fit_shell(id, l);
    if (!f.ok) {
        return E_INVALID_SHELL;
    }
    let bx = shell_box(l.origin, l.ex, l.ey, l.ez, lp(l, 1u), lp(l, 2u), l.d0, l.d1, l.d2,
        f.sigma, vec3<f32>(0.0));
    // Patch::all_finite.
    let finite = fin3(l.origin) && fin3(l.ex) && fin3(l.ey) && fin3(l.ez) && fin(l.p1x)
        && fin(l.p2x) && fin(l.p2y) && fin3(l.n0) && fin3(l.n1) && fin3(l.n2) && fin3(l.d0)
        && fin3(l.d1) && fin3(l.d2) && fin(f.sigma.x) && fin(f.sigma.y) && fin3(bx.lo)
        && fin3(bx.hi) && curvatures_finite(l);
    if (!finite) {
        return E_OUT_OF_RANGE;
    }
    write_record(id, l, f.sigma, bx.lo, bx.hi, f.band0, f.band1);
    return 0u;
}

fn curvatures_finite(l: Local) -> bool {
    for (var j = 0u; j < 3u; j++) {
        let k = (j + 1u) % 3u;
        if (!fin(curvature(lp(l, j), ln(l, j), lp(l, k)) + curvature(lp(l, k), ln(l, k), lp(l, j)))) {
            return false;
        }
    }
    return true;
}

// The normal `u` rotated toward `nf` down to the clamp (cos_max, sin_max), as the CPU's
// `new_or_tilted_with`.
fn clamped(u: vec3<f32>, nf: vec3<f32>, cs: vec2<f32>) -> vec3<f32> {
    let cos = dot3(u, nf);
    if (cos >= cs.x) {
        return u;
    }
    let w = unit_or_zero(u - nf * cos);
    if (w.w == 0.0) {
        return nf;
    }
    return nf * cs.x + w.xyz * cs.y;
}

@compute @workgroup_size(64)
fn build_patches(@builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>) {
    let id = gid.x + gid.y * groups.x * 64u;
    if (id >= bparams.count || id >= arrayLength(&slot_remedy)
        || (id + 1u) * PATCH_VEC4 > arrayLength(&patches)
        || 3u * id + 2u >= arrayLength(&b_triangles)) {
        return;
    }
    if (bparams.seams != 0u && (id + 1u) * SEAM_VEC4 <= arrayLength(&seam_out)) {
        // Every seam starts at zero (no correction); the edge pass fits the shared edges.
        for (var k = 0u; k < SEAM_VEC4; k++) {
            seam_out[id * SEAM_VEC4 + k] = vec4<f32>(0.0);
        }
    }
    let ia = b_triangles[3u * id];
    let ib = b_triangles[3u * id + 1u];
    let ic = b_triangles[3u * id + 2u];
    let nv = min(bparams.vertices, min(arrayLength(&b_positions), arrayLength(&b_normals)) / 3u);
    if (ia >= nv || ib >= nv || ic >= nv) {
        write_placeholder(id);
        slot_remedy[id] = REJECTED | E_NON_FINITE;
        return;
    }
    let p0 = vertex_in(0u, ia);
    let p1 = vertex_in(0u, ib);
    let p2 = vertex_in(0u, ic);
    let m0 = vertex_in(1u, ia);
    let m1 = vertex_in(1u, ib);
    let m2 = vertex_in(1u, ic);
    let first = build_one(id, p0, p1, p2, m0, m1, m2);
    if (first == 0u) {
        slot_remedy[id] = 0u;
        return;
    }
    if (first == E_NON_FINITE || first == E_DEGENERATE || first == E_OUT_OF_RANGE) {
        write_placeholder(id);
        slot_remedy[id] = REJECTED | first;
        return;
    }
    // The per-patch remedy: each clamp in turn.
    let nf = unit_or_zero(cross3(p1 - p0, p2 - p0));
    if (nf.w == 0.0) {
        write_placeholder(id);
        slot_remedy[id] = REJECTED | first;
        return;
    }
    let u0 = unit_or_zero(m0);
    let u1 = unit_or_zero(m1);
    let u2 = unit_or_zero(m2);
    let v0 = select(nf.xyz, u0.xyz, u0.w != 0.0);
    let v1 = select(nf.xyz, u1.xyz, u1.w != 0.0);
    let v2 = select(nf.xyz, u2.xyz, u2.w != 0.0);
    for (var k = 0u; k < 6u; k++) {
        let cs = bparams.clamp[k].xy;
        let code = build_one(id, p0, p1, p2, clamped(v0, nf.xyz, cs), clamped(v1, nf.xyz, cs),
            clamped(v2, nf.xyz, cs));
        if (code == 0u) {
            slot_remedy[id] = k + 1u;
            return;
        }
    }
    write_placeholder(id);
    slot_remedy[id] = REJECTED | first;
}

