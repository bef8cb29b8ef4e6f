// Presents a frame of the frame pass (gpu/src/kernel/frame.wgsl `frame`: one packed RGBA8 colour
// per pixel, row-major) in a window: a full-screen triangle whose fragments read the frame's pixel
// under them, scaled to the window (nearest pixel). The colours are already gamma-encoded; for an
// sRGB swap chain they are decoded so the window shows the frame's bytes.

struct Blit {
    image_w: u32,
    image_h: u32,
    target_w: u32,
    target_h: u32,
    srgb: u32,
}

@group(0) @binding(0) var<uniform> blit: Blit;
@group(0) @binding(1) var<storage, read> image: array<u32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    return vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
}

fn decode(c: f32) -> f32 {
    if (c <= 0.04045) {
        return c / 12.92;
    }
    return pow((c + 0.055) / 1.055, 2.4);
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let tw = max(blit.target_w, 1u);
    let th = max(blit.target_h, 1u);
    let sx = min(u32(p.x) * blit.image_w / tw, max(blit.image_w, 1u) - 1u);
    let sy = min(u32(p.y) * blit.image_h / th, max(blit.image_h, 1u) - 1u);
    let i = sy * blit.image_w + sx;
    if (i >= arrayLength(&image)) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let c = image[i];
    var rgb = vec3<f32>(f32(c & 255u), f32((c >> 8u) & 255u), f32((c >> 16u) & 255u)) / 255.0;
    if (blit.srgb != 0u) {
        rgb = vec3<f32>(decode(rgb.x), decode(rgb.y), decode(rgb.z));
    }
    return vec4<f32>(rgb, 1.0);
}
