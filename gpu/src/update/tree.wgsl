// ---------------------------------------------------------------------------------------------
// The BVH refit (core/src/bvh/build.rs `refit`): one dispatch per depth of the tree, deepest
// first; each invocation refits one node's four slots from its leaves' patch boxes or its
// children's slots (refitted by the dispatch before).

struct LevelParams {
    start: u32, // first entry of level_nodes of this depth
    count: u32, // nodes at this depth
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(15) var<uniform> level: LevelParams;
@group(0) @binding(16) var<storage, read> level_nodes: array<u32>;
// Per node, its part of the tree's cost by the surface area heuristic (core/src/bvh/build.rs
// `tree_cost`): each used slot's half area times what a ray entering it tests (one node, or
// the leaf's patches). The host sums them and divides by the root's half area.
@group(0) @binding(20) var<storage, read_write> node_cost: array<f32>;

// aabb.rs `half_area`: xy + yz + zx of the extents, 0 for an empty box.
fn half_area(lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    let e = hi - lo;
    if (!(e.x >= 0.0 && e.y >= 0.0 && e.z >= 0.0)) {
        return 0.0;
    }
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

@compute @workgroup_size(64)
fn refit_nodes(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= level.count || level.start + gid.x >= arrayLength(&level_nodes)) {
        return;
    }
    let i = level_nodes[level.start + gid.x];
    let nn = arrayLength(&nodes);
    let np = arrayLength(&patches) / PATCH_VEC4;
    if (i >= nn) {
        return;
    }
    var node = nodes[i];
    for (var k = 0u; k < 4u; k++) {
        let child = node.child[k];
        let count = node.count[k];
        if (child == EMPTY_SLOT) {
            continue;
        }
        var lo = vec3<f32>(F32_MAX);
        var hi = vec3<f32>(-F32_MAX);
        if (count > 0u) {
            let end = min(child + count, arrayLength(&order));
            for (var o = child; o < end; o++) {
                let id = order[o];
                if (id < np) {
                    lo = min(lo, patches[id * PATCH_VEC4 + 4u].xyz);
                    hi = max(hi, patches[id * PATCH_VEC4 + 5u].xyz);
                }
            }
        } else if (child < nn && child > i) {
            let sub = nodes[child];
            for (var s = 0u; s < 4u; s++) {
                if (sub.child[s] != EMPTY_SLOT) {
                    lo = min(lo, vec3<f32>(sub.lo[0][s], sub.lo[1][s], sub.lo[2][s]));
                    hi = max(hi, vec3<f32>(sub.hi[0][s], sub.hi[1][s], sub.hi[2][s]));
                }
            }
        } else {
            continue;
        }
        node.lo[0][k] = lo.x;
        node.lo[1][k] = lo.y;
        node.lo[2][k] = lo.z;
        node.hi[0][k] = hi.x;
        node.hi[1][k] = hi.y;
        node.hi[2][k] = hi.z;
    }
    nodes[i] = node;
    var cost = 0.0;
    for (var k = 0u; k < 4u; k++) {
        if (node.child[k] != EMPTY_SLOT) {
            let lo = vec3<f32>(node.lo[0][k], node.lo[1][k], node.lo[2][k]);
            let hi = vec3<f32>(node.hi[0][k], node.hi[1][k], node.hi[2][k]);
            cost = cost + half_area(lo, hi) * f32(max(node.count[k], 1u));
        }
    }
    if (i < arrayLength(&node_cost)) {
        node_cost[i] = cost;
    }
}

