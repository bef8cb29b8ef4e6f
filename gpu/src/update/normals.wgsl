// ---------------------------------------------------------------------------------------------
// Vertex normals of a mesh without any (mesh-io's `angle_weighted_normals`): one invocation
// per vertex sums the unit face normals of its triangles, each weighted by the triangle's
// angle at the vertex (there `acos` of the dot product in f64; here `angle_between`, since
// WGSL's trigonometry carries no useful error bound), in triangle order, and normalises the
// sum (zero where it vanishes).

// Per vertex, the corners 3·triangle + corner at it, in triangle order; vertex v's are
// incident[incident_start[v] .. incident_start[v + 1]].
@group(0) @binding(18) var<storage, read> incident: array<u32>;
@group(0) @binding(19) var<storage, read> incident_start: array<u32>;

// atan(x) for x ≥ 0 to a few ulps in f32 arithmetic (WGSL's own atan and acos may be 4096 ulps
// off): the argument reduced to |y| ≤ tan(π/8) by atan(x) = π/2 − atan(1/x) and
// atan(x) = π/4 + atan((x − 1)/(x + 1)), then Cephes' odd minimax polynomial of atanf.
fn atan_pos(x: f32) -> f32 {
    var base = 0.0;
    var y = x;
    if (x > 2.4142137) {
        base = 1.5707964;
        y = -1.0 / x;
    } else if (x > 0.41421357) {
        base = 0.7853982;
        y = (x - 1.0) / (x + 1.0);
    }
    let z = y * y;
    let p = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
        - 3.33329491539e-1) * z * y + y;
    return base + p;
}

// The angle between unit vectors u and w, well conditioned at every angle:
// 2·atan(|u − w| / |u + w|) (π where u = −w).
fn angle_between(u: vec3<f32>, w: vec3<f32>) -> f32 {
    let d = length3(u - w);
    let s = length3(u + w);
    if (!(s > 0.0)) {
        return 3.1415927;
    }
    return 2.0 * atan_pos(d / s);
}

fn corner_of(tri: u32, k: u32) -> vec3<f32> {
    return vertex_in(0u, b_triangles[3u * tri + k % 3u]);
}

@compute @workgroup_size(64)
fn vertex_normals(@builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>) {
    let v = gid.x + gid.y * groups.x * 64u;
    let nv = min(bparams.vertices, min(arrayLength(&b_positions), arrayLength(&b_normals)) / 3u);
    if (v >= nv || v + 1u >= arrayLength(&incident_start)) {
        return;
    }
    let ntri = arrayLength(&b_triangles) / 3u;
    let end = min(incident_start[v + 1u], arrayLength(&incident));
    var acc = vec3<f32>(0.0);
    for (var e = incident_start[v]; e < end; e++) {
        let tri = incident[e] / 3u;
        let k = incident[e] % 3u;
        if (tri >= ntri || b_triangles[3u * tri] >= nv || b_triangles[3u * tri + 1u] >= nv
            || b_triangles[3u * tri + 2u] >= nv) {
            continue;
        }
        let pa = corner_of(tri, 0u);
        let nf = unit_or_zero(cross3(corner_of(tri, 1u) - pa, corner_of(tri, 2u) - pa));
        if (nf.w == 0.0) {
            continue;
        }
        let p = corner_of(tri, k);
        let u = unit_or_zero(corner_of(tri, k + 1u) - p);
        let w = unit_or_zero(corner_of(tri, k + 2u) - p);
        if (u.w == 0.0 || w.w == 0.0) {
            continue;
        }
        acc = acc + nf.xyz * angle_between(u.xyz, w.xyz);
    }
    let n = unit_or_zero(acc).xyz;
    b_normals[3u * v] = n.x;
    b_normals[3u * v + 1u] = n.y;
    b_normals[3u * v + 2u] = n.z;
}
