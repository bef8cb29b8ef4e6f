// Entry point of the batch queries (gpu/src/query.rs `GpuScene::closest_hit`, `any_hit`): one ray
// per invocation, from `rays` to `hits`.

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
