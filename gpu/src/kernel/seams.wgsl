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
// seam record (SEAM_VEC4 vec4s, gpu/src/records.rs `seam_record`).
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
