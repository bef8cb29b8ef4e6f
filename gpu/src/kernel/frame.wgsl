// Entry point of whole frames (gpu/src/frame.rs `GpuScene::render_frame`): one invocation per pixel
// generates the camera ray, traces it, shades the closest hit with the shading normal, Lambert
// and ambient light and one shadow ray, and writes the pixel's colour and hit. The demo's
// renderer (host-demo/src/renderer.rs `render`, `shade`, `background`, and the heat map of
// `view`) in f32.

fn to_u8(x: f32) -> u32 {
    let c = clamp(x, 0.0, 1.0);
    return u32(select(0.0, pow(c, 1.0 / 2.2), c > 0.0) * 255.0 + 0.5);
}

fn pack(c: vec3<u32>) -> u32 {
    return min(c.x, 255u) | (min(c.y, 255u) << 8u) | (min(c.z, 255u) << 16u) | (255u << 24u);
}

// host-demo/src/image.rs `heat`.
fn heat(l: f32) -> vec3<u32> {
    let t = clamp(l, 0.0, 1.0);
    var a = 0.0;
    var b = 0.33;
    var ca = vec3<f32>(20.0, 20.0, 90.0);
    var cb = vec3<f32>(30.0, 170.0, 200.0);
    if (t > 0.66) {
        a = 0.66;
        b = 1.0;
        ca = vec3<f32>(240.0, 220.0, 60.0);
        cb = vec3<f32>(220.0, 30.0, 30.0);
    } else if (t > 0.33) {
        a = 0.33;
        b = 0.66;
        ca = cb;
        cb = vec3<f32>(240.0, 220.0, 60.0);
    }
    return vec3<u32>(ca + (cb - ca) * ((t - a) / (b - a)));
}

@compute @workgroup_size(8, 8)
fn frame(@builtin(global_invocation_id) gid: vec3<u32>) {
    let x = gid.x;
    let y = gid.y;
    let w = view.width;
    let h = view.height;
    if (x >= w || y >= h) {
        return;
    }
    let i = y * w + x;
    if (i >= arrayLength(&image) || i >= arrayLength(&pixels)) {
        return;
    }
    // host/src/camera.rs `Camera::pixel_ray` through the pixel's centre.
    let sx = (2.0 * (f32(x) + 0.5) / f32(w) - 1.0) * view.tan_half * view.aspect;
    let sy = (1.0 - 2.0 * (f32(y) + 0.5) / f32(h)) * view.tan_half;
    let d = normalize(view.forward + view.right * sx + view.up * sy);
    let o = view.eye;
    let tr = trace(o, d, 0.0, 3.4028235e38, false);
    if (tr.err != 0u) {
        atomicOr(&status[0], tr.err);
    }
    var n = vec4<f32>(0.0);
    if (tr.found) {
        n = hit_normal(tr.id, tr.best);
    }
    if (n.w == 0.0) {
        let s = f32(y) / f32(max(h, 1u));
        var bg = vec3<u32>(vec3<f32>(48.0 - 24.0 * s, 54.0 - 26.0 * s, 66.0 - 30.0 * s));
        if (view.heat_scale > 0.0) {
            bg = vec3<u32>(0u);
        }
        image[i] = pack(bg);
        pixels[i] = PixelOut(vec3<f32>(0.0), MISS, 0.0, 0u, 0u, 0u);
        return;
    }
    let best = tr.best;
    let p = o + d * best.t;
    var nn = shading_normal(tr.id, best, n.xyz);
    if (dot(nn, d) > 0.0) {
        nn = -nn;
    }
    let lambert = max(dot(nn, view.light), 0.0);
    var vis = 0.0;
    if (lambert > 0.0) {
        atomicAdd(&frame_stats[0], 1u);
        let shadow = trace(p - d * view.eps, view.light, view.eps, 3.4028235e38, true);
        if (shadow.err != 0u) {
            atomicOr(&status[0], shadow.err);
        }
        vis = select(1.0, 0.0, shadow.found);
    }
    var c: vec3<u32>;
    if (view.heat_scale > 0.0) {
        let rel = max(best.t_error * view.heat_scale, 1e-12);
        c = heat((log2(rel) * 0.30103 + 9.0) / 6.0);
    } else {
        let front = dot(n.xyz, d) < 0.0;
        let albedo = select(vec3<f32>(0.25, 0.45, 0.80), vec3<f32>(0.85, 0.50, 0.22), front);
        let s = 0.12 + (1.0 - 0.12) * lambert * vis;
        c = vec3<u32>(to_u8(albedo.x * s), to_u8(albedo.y * s), to_u8(albedo.z * s));
    }
    image[i] = pack(c);
    pixels[i] = PixelOut(p, tr.id, best.t_error, 0u, 0u, 0u);
    atomicMax(&frame_stats[1], bitcast<u32>(best.t_error));
}
