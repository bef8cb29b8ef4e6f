// ---------------------------------------------------------------------------------------------
// Crack closure (core/src/mesh/cracks.rs, core/src/mesh/sampling.rs): one invocation per shared
// edge measures the widest gap between the two neighbours' surfaces at the CRACK_SAMPLES
// Chebyshev nodes and widens both walls over it to CRACK_REACH times the gap. Each wall belongs
// to one shared edge, so no two invocations write the same reach.

// core/src/mesh/cracks.rs CRACK_REACH and CRACK_SAMPLES.
const CRACK_REACH: f32 = 4.0;
const CRACK_SAMPLES: u32 = 16u;

struct EdgeParams {
    count: u32, // shared edges
    seams: u32, // 1: fit the seams too
    pad1: u32,
    pad2: u32,
    // Per node s: (t, 1 − t, 1 − (1 − t)) rounded from f64, as the CPU's barycentrics.
    nodes: array<vec4<f32>, 16>,
    // The seam fit's least-squares map (smoothtri::internal::seam_fit_matrix), row k's eight
    // entries in fit[2k], fit[2k + 1].
    fit: array<vec4<f32>, 12>,
}

@group(0) @binding(13) var<uniform> eparams: EdgeParams;
// Per shared edge: 3·triangle + local edge of its two sides (smoothtri::mesh::shared_edges).
@group(0) @binding(14) var<storage, read> pairs: array<vec2<u32>>;

// The barycentrics of edge j at own parameter t (1 − t given rounded as the CPU's):
// core/src/mesh/topology.rs `edge_bary`.
fn edge_bary(j: u32, t: f32, u: f32) -> vec3<f32> {
    switch j {
        case 0u: { return vec3<f32>(u, t, 0.0); }
        case 1u: { return vec3<f32>(0.0, u, t); }
        default: { return vec3<f32>(t, 0.0, u); }
    }
}

// The surface point of patch `pt` at barycentrics x, in world axes relative to the patch's
// origin (the gap is the difference of two such points plus the difference of the origins,
// so the rounding stays at the triangles' scale).
fn edge_sample(pt: Patch, x: vec3<f32>) -> vec3<f32> {
    let h = height_at(pt, x);
    let d0 = vec3<f32>(pt.d0, pt.dz.x);
    let d1 = vec3<f32>(pt.d1, pt.dz.y);
    let d2 = vec3<f32>(pt.d2, pt.dz.z);
    let base = vec3<f32>(pt.p1x, 0.0, 0.0) * x.y + vec3<f32>(pt.p2x, pt.p2y, 0.0) * x.z;
    var dir = d0 * x.x + d1 * x.y + d2 * x.z;
    if (pt.tilted) {
        dir = dir * (1.0 / dir.z);
    }
    let q = base + dir * h;
    return pt.ex * q.x + pt.ey * q.y + pt.ez * q.z;
}

// The reach of a wall over edge j of `pt` for `gap` (cracks.rs `widen_wall`), or −1 where it
// stays 0.
fn wall_reach(pt: Patch, j: u32, gap: f32) -> f32 {
    let p1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let p2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    var e = p1;
    if (j == 1u) {
        e = p2 - p1;
    } else if (j == 2u) {
        e = -p2;
    }
    let len = length3(e);
    let area2 = pt.p1x * pt.p2y;
    let r = min(CRACK_REACH * gap * len / area2, MAX_CRACK_REACH);
    return select(-1.0, r, fin(r) && r >= 0.0);
}


@compute @workgroup_size(64)
fn close_edges(@builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>) {
    let k = gid.x + gid.y * groups.x * 64u;
    if (k >= eparams.count || k >= arrayLength(&pairs)) {
        return;
    }
    let sides = pairs[k];
    let ta = sides.x / 3u;
    let ja = sides.x % 3u;
    let tb = sides.y / 3u;
    let jb = sides.y % 3u;
    let n = min(arrayLength(&slot_remedy), arrayLength(&patches) / PATCH_VEC4);
    if (ta >= n || tb >= n) {
        return;
    }
    // An edge with a placeholder on either side is not a shared edge.
    if ((slot_remedy[ta] & REJECTED) != 0u || (slot_remedy[tb] & REJECTED) != 0u) {
        return;
    }
    let pa = load_patch(ta);
    let pb = load_patch(tb);
    let offset = pa.origin - pb.origin;
    var gap = 0.0;
    for (var s = 0u; s < CRACK_SAMPLES; s++) {
        let node = eparams.nodes[s];
        // The second side runs the edge backwards: its own parameter is 1 − t.
        let a = edge_sample(pa, edge_bary(ja, node.x, node.y));
        let b = edge_sample(pb, edge_bary(jb, node.y, node.z));
        let d = offset + a - b;
        let l = sqrt(dot3(d, d));
        if (!fin(l)) {
            gap = bitcast<f32>(0x7f800000u); // +∞, as the CPU's widest_gap
            break;
        }
        gap = max(gap, l);
    }
    if (eparams.seams != 0u) {
        fit_seam(pa, ta, ja, pb, tb, jb);
    }
    if (!(gap > 0.0)) {
        return;
    }
    let ra = wall_reach(pa, ja, gap);
    if (ra >= 0.0) {
        patches[ta * PATCH_VEC4 + 10u + 5u * ((ja + 2u) % 3u) + 3u].w = ra;
    }
    let rb = wall_reach(pb, jb, gap);
    if (rb >= 0.0) {
        patches[tb * PATCH_VEC4 + 10u + 5u * ((jb + 2u) % 3u) + 3u].w = rb;
    }
}

// The box of every patch from its final reaches (core/src/patch.rs `fit_box`); placeholders keep
// their empty box.
@compute @workgroup_size(64)
fn fit_boxes(@builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>) {
    let id = gid.x + gid.y * groups.x * 64u;
    if (id >= bparams.count || id >= arrayLength(&slot_remedy)
        || (id + 1u) * PATCH_VEC4 > arrayLength(&patches)) {
        return;
    }
    if ((slot_remedy[id] & REJECTED) != 0u) {
        return;
    }
    let pt = load_patch(id);
    let bx = shell_box(pt.origin, pt.ex, pt.ey, pt.ez, vec3<f32>(pt.p1x, 0.0, 0.0),
        vec3<f32>(pt.p2x, pt.p2y, 0.0), vec3<f32>(pt.d0, pt.dz.x), vec3<f32>(pt.d1, pt.dz.y),
        vec3<f32>(pt.d2, pt.dz.z), vec2<f32>(pt.sig_lo, pt.sig_hi), pt.reach);
    let b = id * PATCH_VEC4;
    patches[b + 4u] = vec4<f32>(bx.lo, patches[b + 4u].w);
    patches[b + 5u] = vec4<f32>(bx.hi, patches[b + 5u].w);
    if (bparams.seams != 0u && (id + 1u) * SEAM_VEC4 <= arrayLength(&seam_out)) {
        // Seam::is_zero over the coefficients (the first nine vec4s): the record's flag.
        var nonzero = false;
        for (var k = 0u; k < 9u; k++) {
            nonzero = nonzero || any(seam_out[id * SEAM_VEC4 + k] != vec4<f32>(0.0));
        }
        seam_out[id * SEAM_VEC4 + 9u].w = select(0.0, 1.0, nonzero);
    }
}

