// Flat triangles on their own: a four-wide BVH over the triangles' boxes (smoothtri's
// `BoxBvh`, the same node layout as the smooth kernel's), nearest child first with a fixed
// stack, Möller–Trumbore in the leaves, one invocation per ray. No smooth code: the baseline
// the smooth kernel is compared with (`FlatScene`, flat_tris.rs).

// (rays, nodes, order entries, triangles).
@group(0) @binding(0) var<uniform> params: vec4<u32>;
// Per triangle: (p0, 0), (p1 − p0, 0), (p2 − p0, 0).
@group(0) @binding(1) var<storage, read> tris: array<vec4<f32>>;
// Per node (smoothtri's `BvhNode`, 128 bytes): lo.x, lo.y, lo.z, hi.x, hi.y, hi.z of the four
// slots, then their children and counts as bits.
@group(0) @binding(2) var<storage, read> nodes: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> order: array<u32>;
// Per ray: (origin, t_min), (dir, t_max).
@group(0) @binding(4) var<storage, read> rays: array<vec4<f32>>;
// Per ray: (t, w1, w2, triangle as bits); triangle 0xffffffff for a miss.
@group(0) @binding(5) var<storage, read_write> hits: array<vec4<f32>>;
// Bit 0: the stack would overflow; bit 1: the tree is corrupt (visits or tests exhausted).
@group(0) @binding(6) var<storage, read_write> status: array<atomic<u32>, 4>;

const EMPTY: u32 = 0xffffffffu;
const STACK: u32 = 192u;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= params.x) {
        return;
    }
    let a = rays[2u * i];
    let b = rays[2u * i + 1u];
    let o = a.xyz;
    let d = b.xyz;
    let t_min = a.w;
    var best = b.w;
    var out = vec4<f32>(0.0, 0.0, 0.0, bitcast<f32>(EMPTY));
    var found = false;
    if (!(t_min <= best)) {
        hits[i] = out;
        return;
    }
    // 1/d with zero components replaced by a tiny value of their sign (huge, finite slabs).
    let safe = select(d, select(vec3<f32>(1e-30), vec3<f32>(-1e-30), d < vec3<f32>(0.0)), abs(d) < vec3<f32>(1e-30));
    let inv = 1.0 / safe;
    var stack: array<u32, STACK>;
    var stack_t: array<f32, STACK>;
    var sp = 0u;
    var node = 0u;
    var visits = params.y;
    var tests = params.z;
    var flags = 0u;
    loop {
        if (node >= params.y || visits == 0u) {
            flags |= 2u;
            break;
        }
        visits -= 1u;
        let at = 8u * node;
        let child = bitcast<vec4<u32>>(nodes[at + 6u]);
        let count = bitcast<vec4<u32>>(nodes[at + 7u]);
        let t0 = (nodes[at] - vec4<f32>(o.x)) * inv.x;
        let t1 = (nodes[at + 3u] - vec4<f32>(o.x)) * inv.x;
        let u0 = (nodes[at + 1u] - vec4<f32>(o.y)) * inv.y;
        let u1 = (nodes[at + 4u] - vec4<f32>(o.y)) * inv.y;
        let v0 = (nodes[at + 2u] - vec4<f32>(o.z)) * inv.z;
        let v1 = (nodes[at + 5u] - vec4<f32>(o.z)) * inv.z;
        let near = max(max(min(t0, t1), min(u0, u1)), max(min(v0, v1), vec4<f32>(t_min)));
        let far = min(min(max(t0, t1), max(u0, u1)), min(max(v0, v1), vec4<f32>(best)));
        var kids: array<u32, 4>;
        var kt: array<f32, 4>;
        var nk = 0u;
        for (var k = 0u; k < 4u; k++) {
            if (child[k] == EMPTY || near[k] > far[k]) {
                continue;
            }
            let c = count[k];
            if (c == 0u) {
                // Insertion by entry distance, nearest last.
                var j = nk;
                while (j > 0u && kt[j - 1u] < near[k]) {
                    kids[j] = kids[j - 1u];
                    kt[j] = kt[j - 1u];
                    j -= 1u;
                }
                kids[j] = child[k];
                kt[j] = near[k];
                nk += 1u;
                continue;
            }
            // A leaf: Möller–Trumbore on its triangles.
            let first = child[k];
            if (c > tests || first >= params.z || c > params.z - first) {
                flags |= 2u;
                continue;
            }
            tests -= c;
            for (var m = 0u; m < c; m++) {
                let id = order[first + m];
                if (id >= params.w) {
                    flags |= 2u;
                    continue;
                }
                let p0 = tris[3u * id].xyz;
                let e1 = tris[3u * id + 1u].xyz;
                let e2 = tris[3u * id + 2u].xyz;
                let pv = cross(d, e2);
                let det = dot(e1, pv);
                if (det == 0.0) {
                    continue;
                }
                let inv_det = 1.0 / det;
                let tv = o - p0;
                let u = dot(tv, pv) * inv_det;
                if (!(u >= 0.0 && u <= 1.0)) {
                    continue;
                }
                let qv = cross(tv, e1);
                let v = dot(d, qv) * inv_det;
                if (!(v >= 0.0 && u + v <= 1.0)) {
                    continue;
                }
                let t = dot(e2, qv) * inv_det;
                if (t >= t_min && t <= best && (!found || t < best)) {
                    best = t;
                    found = true;
                    out = vec4<f32>(t, u, v, bitcast<f32>(id));
                }
            }
        }
        // Children: the nearest next, the others onto the stack (farthest deepest).
        if (nk > 0u) {
            if (sp + nk - 1u > STACK) {
                flags |= 1u;
                break;
            }
            for (var j = 0u; j + 1u < nk; j++) {
                stack[sp] = kids[j];
                stack_t[sp] = kt[j];
                sp += 1u;
            }
            node = kids[nk - 1u];
            continue;
        }
        // Pop the nearest pending child the best hit has not moved in front of.
        var popped = false;
        while (sp > 0u) {
            sp -= 1u;
            if (stack_t[sp] <= best) {
                node = stack[sp];
                popped = true;
                break;
            }
        }
        if (!popped) {
            break;
        }
    }
    hits[i] = out;
    if (flags != 0u) {
        atomicOr(&status[0], flags);
    }
}
