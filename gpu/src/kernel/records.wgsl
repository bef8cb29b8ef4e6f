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
