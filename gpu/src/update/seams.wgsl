// ---------------------------------------------------------------------------------------------
// The seam fit (core/src/mesh/seams.rs `fit_sides`): both neighbours' geometric normals at the
// FIT_SAMPLES nodes, their average as the common normal, its tilts in the frame both sides
// build from the edge's vertices and normals alone, fitted by the least-squares map.

// core/src/mesh/sampling.rs FIT_NODES; core/src/mesh/seams.rs FIT_SAMPLES, FREE_END_TOL.
const FIT_SAMPLES: u32 = 8u;
const FIT_NODES = array<u32, 8>(1u, 3u, 5u, 7u, 8u, 10u, 12u, 14u);
const FREE_END_TOL: f32 = 1.0e-5;

fn to_world(pt: Patch, v: vec3<f32>) -> vec3<f32> {
    return pt.ex * v.x + pt.ey * v.y + pt.ez * v.z;
}

fn to_local(pt: Patch, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot3(v, pt.ex), dot3(v, pt.ey), dot3(v, pt.ez));
}

fn vertex_of(pt: Patch, i: u32) -> vec3<f32> {
    switch i % 3u {
        case 0u: { return vec3<f32>(0.0); }
        case 1u: { return vec3<f32>(pt.p1x, 0.0, 0.0); }
        default: { return vec3<f32>(pt.p2x, pt.p2y, 0.0); }
    }
}

fn normal_of(pt: Patch, i: u32) -> vec3<f32> {
    switch i % 3u {
        case 0u: { return pt.n0; }
        case 1u: { return pt.n1; }
        default: { return pt.n2; }
    }
}

// The frame of edge (a, b) with normals (na, nb) at t that both sides share (seams.rs
// `shared_frame`): g, the across-edge ĝ, the along-edge â; w = 0 where it degenerates.
struct SharedFrame {
    g: vec3<f32>,
    b: vec3<f32>,
    a: vec3<f32>,
    ok: bool,
}

fn shared_frame(a: vec3<f32>, b: vec3<f32>, na: vec3<f32>, nb: vec3<f32>, t: f32) -> SharedFrame {
    var out: SharedFrame;
    out.ok = false;
    let g = unit_or_zero(na * (1.0 - t) + nb * t);
    if (g.w == 0.0) {
        return out;
    }
    let c = unit_or_zero(cross3(b - a, g.xyz));
    if (c.w == 0.0) {
        return out;
    }
    out.g = g.xyz;
    out.b = c.xyz;
    out.a = cross3(g.xyz, c.xyz);
    out.ok = fin3(out.a);
    return out;
}

// seams.rs `twist_of`: (v·b)/(v·n), or NaN where v is nearly perpendicular to n.
fn twist_of(v: vec3<f32>, n: vec3<f32>, b: vec3<f32>) -> f32 {
    let den = dot3(v, n);
    let nan = bitcast<f32>(0x7fc00000u);
    if (!(den > 1.0e-3)) {
        return nan;
    }
    let r = dot3(v, b) / den;
    return select(nan, r, fin(r));
}

var<private> fit_y: array<array<f32, 8>, 4>;

// Writes edge j's slots of patch `id`'s seam record: the tilts across and along (or the
// neighbour's two normals, for a free edge) and the free flag.
fn write_seam_edge(id: u32, j: u32, across: array<f32, 6>, along: array<f32, 6>, free: bool) {
    let base = id * SEAM_VEC4 * 4u + 12u * j;
    for (var k = 0u; k < 6u; k++) {
        let w = base + k;
        seam_out[w / 4u][w % 4u] = across[k];
        let v = base + 6u + k;
        seam_out[v / 4u][v % 4u] = along[k];
    }
    let f = id * SEAM_VEC4 * 4u + 36u + j;
    seam_out[f / 4u][f % 4u] = select(0.0, 1.0, free);
}

fn fit_seam(pa: Patch, ta: u32, ja: u32, pb: Patch, tb: u32, jb: u32) {
    if ((max(ta, tb) + 1u) * SEAM_VEC4 > arrayLength(&seam_out)) {
        return;
    }
    // World points relative to A's origin.
    let ob = pb.origin - pa.origin;
    let ea_a = vertex_of(pa, ja);
    let ea_b = vertex_of(pa, ja + 1u);
    let eb_a = vertex_of(pb, jb);
    let eb_b = vertex_of(pb, jb + 1u);
    let a0 = to_world(pa, ea_a);
    let a1 = to_world(pa, ea_b);
    let b0 = ob + to_world(pb, eb_a);
    let b1 = ob + to_world(pb, eb_b);
    let len = length3(a1 - a0);
    let tol = sqrt(EPS) * len;
    if (!(length3(a0 - b1) <= tol && length3(a1 - b0) <= tol)) {
        return;
    }
    let ea_na = normal_of(pa, ja);
    let ea_nb = normal_of(pa, ja + 1u);
    let eb_na = normal_of(pb, jb);
    let eb_nb = normal_of(pb, jb + 1u);
    // Each side's view of the other's two vertex normals at this edge's ends.
    let sa0 = to_local(pa, to_world(pb, eb_nb));
    let sa1 = to_local(pa, to_world(pb, eb_na));
    let sb0 = to_local(pb, to_world(pa, ea_nb));
    let sb1 = to_local(pb, to_world(pa, ea_na));
    let zero6 = array<f32, 6>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    if (length3(sa0 - ea_na) > FREE_END_TOL || length3(sa1 - ea_nb) > FREE_END_TOL) {
        let ca = array<f32, 6>(sa0.x, sa0.y, sa0.z, sa1.x, sa1.y, sa1.z);
        let cb = array<f32, 6>(sb0.x, sb0.y, sb0.z, sb1.x, sb1.y, sb1.z);
        if (fin3(sa0) && fin3(sa1) && fin3(sb0) && fin3(sb1)) {
            write_seam_edge(ta, ja, ca, zero6, true);
            write_seam_edge(tb, jb, cb, zero6, true);
        }
        return;
    }
    for (var s = 0u; s < FIT_SAMPLES; s++) {
        let node = eparams.nodes[FIT_NODES[s]];
        let fa = shared_frame(ea_a, ea_b, ea_na, ea_nb, node.x);
        let fb = shared_frame(eb_a, eb_b, eb_na, eb_nb, node.y);
        if (!fa.ok || !fb.ok) {
            return;
        }
        let na = normal_local(pa, edge_bary(ja, node.x, node.y));
        let nb = normal_local(pb, edge_bary(jb, node.y, node.z));
        let m = unit_or_zero(to_world(pa, na) + to_world(pb, nb));
        if (m.w == 0.0) {
            return;
        }
        let ma = to_local(pa, m.xyz);
        let mb = to_local(pb, m.xyz);
        // B's samples lie at its own parameters 1 − t_s: stored reversed.
        let r = FIT_SAMPLES - 1u - s;
        fit_y[0][s] = twist_of(ma, fa.g, fa.b);
        fit_y[1][s] = twist_of(ma, fa.g, fa.a);
        fit_y[2][r] = twist_of(mb, fb.g, fb.b);
        fit_y[3][r] = twist_of(mb, fb.g, fb.a);
        if (!(fin(fit_y[0][s]) && fin(fit_y[1][s]) && fin(fit_y[2][r]) && fin(fit_y[3][r]))) {
            return;
        }
    }
    var c: array<array<f32, 6>, 4>;
    for (var q = 0u; q < 4u; q++) {
        for (var k = 0u; k < 6u; k++) {
            let lo = eparams.fit[2u * k];
            let hi = eparams.fit[2u * k + 1u];
            let y = fit_y[q];
            let v = lo.x * y[0] + lo.y * y[1] + lo.z * y[2] + lo.w * y[3] + hi.x * y[4]
                + hi.y * y[5] + hi.z * y[6] + hi.w * y[7];
            if (!fin(v)) {
                return;
            }
            c[q][k] = v;
        }
    }
    write_seam_edge(ta, ja, c[0], c[1], false);
    write_seam_edge(tb, jb, c[2], c[3], false);
}

