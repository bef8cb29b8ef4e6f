// Traversal (core/src/bvh/tree.rs `traverse`: four-wide nodes, entered children pushed farthest
// first so the nearest is visited next, leaves tested when popped)

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
