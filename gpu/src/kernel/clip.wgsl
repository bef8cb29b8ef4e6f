// The shell clip (core/src/kernel/clip.rs)

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

fn cross2_poly(u0: vec2<f32>, u1: vec2<f32>, v0: vec2<f32>, v1: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(cross2(u0, v0), cross2(u0, v1) + cross2(u1, v0), cross2(u1, v1));
}

struct Roots {
    r: vec2<f32>,
    ok: vec2<bool>,
}

// Real roots of c0 + c1·x + c2·x² (numerically careful, up to two).
fn quadratic_roots(c: vec3<f32>) -> Roots {
    let none = Roots(vec2<f32>(0.0, 0.0), vec2<bool>(false, false));
    let scale = max(abs(c.y), abs(c.x));
    if (abs(c.z) <= EPS * 1e-3 * scale || c.z == 0.0) {
        if (c.y != 0.0) {
            let x = -c.x / c.y;
            return Roots(vec2<f32>(x, 0.0), vec2<bool>(fin(x), false));
        }
        return none;
    }
    let disc = c.y * c.y - 4.0 * c.z * c.x;
    if (!(disc >= 0.0) || !fin(disc)) {
        return none;
    }
    let sq = sqrt(disc);
    let q = select(-0.5 * (c.y + sq), -0.5 * (c.y - sq), c.y < 0.0);
    let r1 = q / c.z;
    let r2 = select(r1, c.x / select(1.0, q, q != 0.0), q != 0.0);
    return Roots(vec2<f32>(r1, r2), vec2<bool>(fin(r1), fin(r2)));
}

// Whether the ray point at τ is inside the walls Xk = −m_k: the wall polynomials for parallel
// sections, the point's barycentrics in its section for tilted ones.
fn inside(pt: Patch, polys: array<vec3<f32>, 3>, m: vec3<f32>, o: vec3<f32>, r: vec3<f32>,
    tau: f32) -> bool {
    if (TILTED != 0u && pt.tilted) {
        let nm = bary_numerators(pt, o + r * tau);
        return nm.n.x + m.x * nm.area >= 0.0 && nm.n.y + m.y * nm.area >= 0.0
            && nm.n.z + m.z * nm.area >= 0.0;
    }
    var ok_all = true;
    for (var k = 0u; k < 3u; k++) {
        let c = polys[k];
        ok_all = ok_all && (c.x + tau * (c.y + tau * c.z) >= 0.0);
    }
    return ok_all;
}

// Base point and direction of the line over the barycentrics x (local frame).
struct Line {
    p: vec3<f32>,
    g: vec3<f32>,
}

fn line_at(pt: Patch, x: vec3<f32>) -> Line {
    let p = vec3<f32>(x.y * pt.p1x + x.z * pt.p2x, x.z * pt.p2y, 0.0);
    let g = vec3<f32>(x.x * pt.d0 + x.y * pt.d1 + x.z * pt.d2, dot(x, pt.dz));
    return Line(p, g);
}

// Where the ray o + τ·r meets wall k (walls moved out by m3) of a shell with
// tilted sections (core clip.rs `ruled_wall_crossings`): the Plücker side product of the ray
// with the wall's line at t, a quadratic in t; each root's ray parameter, or not ok.
fn ruled_crossings(pt: Patch, m3: vec3<f32>, k: u32, o: vec3<f32>, r: vec3<f32>) -> Roots {
    // The moved corners' lines (core shell.rs `moved_corners`): corner i has Xj = −m_j for
    // the two other vertices j; wall k runs from corner k+1 to corner k+2.
    let corner = array<vec3<f32>, 3>(vec3<f32>(1.0 + m3.y + m3.z, -m3.y, -m3.z),
        vec3<f32>(-m3.x, 1.0 + m3.x + m3.z, -m3.z), vec3<f32>(-m3.x, -m3.y, 1.0 + m3.x + m3.y));
    let la = line_at(pt, corner[(k + 1u) % 3u]);
    let lb = line_at(pt, corner[(k + 2u) % 3u]);
    let pe = lb.p - la.p;
    let ge = lb.g - la.g;
    let m = cross(o, r);
    let q = vec3<f32>(dot(r, cross(la.p, la.g)) + dot(la.g, m),
        dot(r, cross(la.p, ge) + cross(pe, la.g)) + dot(ge, m), dot(r, cross(pe, ge)));
    let ts = quadratic_roots(q);
    var out = Roots(vec2<f32>(0.0, 0.0), vec2<bool>(false, false));
    for (var j = 0u; j < 2u; j++) {
        if (ts.ok[j]) {
            let t = ts.r[j];
            let p = la.p + pe * t;
            let g = la.g + ge * t;
            let rg = cross(r, g);
            let tau = dot(cross(p - o, g), rg) / dot(rg, rg);
            out.r[j] = tau;
            out.ok[j] = fin(tau);
        }
    }
    return out;
}

// [τa, τb]: the hull of the sub-intervals of [τ_lo, τ_hi] inside all three walls (at most 8
// breakpoints, a fixed sorting network, 7 midpoint tests).
// The walls Xk = −margin (core/src/kernel/clip.rs `wall_margin`): the margin's world width
// WALL_MARGIN_ULPS·ε·L over the triangle's smallest altitude 2·area / longest edge; each wall
// also moves out by its crack reach (`wall_margins`).
fn wall_margins(pt: Patch) -> vec3<f32> {
    let longest = sqrt(max(max(pt.p1x * pt.p1x, pt.p2x * pt.p2x + pt.p2y * pt.p2y),
        (pt.p2x - pt.p1x) * (pt.p2x - pt.p1x) + pt.p2y * pt.p2y));
    var margin = WALL_MARGIN_ULPS * EPS * pt.scale * longest / (pt.p1x * pt.p2y);
    if (!fin(margin)) {
        margin = 0.0;
    }
    return pt.reach + vec3<f32>(margin, margin, margin);
}

// The barycentrics of the local (x, y) in the triangle; `lin` for a direction (core
// band.rs `bary_xy`).
fn band_bary(pt: Patch, xy: vec2<f32>, lin: bool) -> vec3<f32> {
    let b2 = xy.y / pt.p2y;
    let b1 = (xy.x - pt.p2x * b2) / pt.p1x;
    let b0 = select(1.0 - b1 - b2, -b1 - b2, lin);
    return vec3<f32>(b0, b1, b2);
}

// q(β) = c0·β1β2 + c1·β2β0 + c2·β0β1 (core band.rs `q`).
fn band_q(c: vec3<f32>, x: vec3<f32>) -> f32 {
    return c.x * (x.y * x.z) + c.y * (x.z * x.x) + c.z * (x.x * x.y);
}

// Whether the local ray o + τ·r, τ in [a, b], misses the patch's band (core/src/kernel/clip.rs
// `misses`): h(τ) = z − q(β) stays above hi or below lo, widened by per_reach times the largest
// wall offset. The band rides in the record's last two vec4s: (c0, c1, c2, lo), (hi, per_reach).
fn band_misses(pt: Patch, base: u32, o: vec3<f32>, r: vec3<f32>, a: f32, b: f32) -> bool {
    let v0 = patches[base + 25u];
    let v1 = patches[base + 26u];
    let m = wall_margins(pt);
    let widen = v1.y * max(max(m.x, m.y), m.z);
    let lo = v0.w - widen;
    let hi = v1.x + widen;
    let bo = band_bary(pt, o.xy, false);
    let br = band_bary(pt, r.xy, true);
    let ha = o.z + r.z * a - band_q(v0.xyz, bo + br * a);
    let hb = o.z + r.z * b - band_q(v0.xyz, bo + br * b);
    let h2 = -band_q(v0.xyz, br);
    let w = b - a;
    let bow = h2 * w * w * 0.25;
    let hmin = min(ha, hb) - max(bow, 0.0);
    let hmax = max(ha, hb) - min(bow, 0.0);
    return fin(hmin) && fin(hmax) && ((hmin > hi) || (hmax < lo));
}

fn shell_interval(pt: Patch, o: vec3<f32>, r: vec3<f32>, tau_lo: f32, tau_hi: f32) -> Span {
    // a_i(τ) − q(τ) = (p_i + o.z·d_i − o) + τ (r.z·d_i − r), in the xy-plane.
    let u0 = vec2<f32>(0.0, 0.0) + pt.d0 * o.z - o.xy;
    let u1 = vec2<f32>(pt.p1x, 0.0) + pt.d1 * o.z - o.xy;
    let u2 = vec2<f32>(pt.p2x, pt.p2y) + pt.d2 * o.z - o.xy;
    let v0 = pt.d0 * r.z - r.xy;
    let v1 = pt.d1 * r.z - r.xy;
    let v2 = pt.d2 * r.z - r.xy;
    let w0 = cross2_poly(u1, v1, u2, v2);
    let w1 = cross2_poly(u2, v2, u0, v0);
    let w2 = cross2_poly(u0, v0, u1, v1);
    let sum = w0 + w1 + w2;
    let m = wall_margins(pt);
    let polys = array<vec3<f32>, 3>(w0 + m.x * sum, w1 + m.y * sum, w2 + m.z * sum);
    var brk = array<f32, 8>(tau_lo, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi, tau_hi);
    var count = 1u;
    for (var k = 0u; k < 3u; k++) {
        var rs: Roots;
        if (TILTED != 0u && pt.tilted) {
            rs = ruled_crossings(pt, m, k, o, r);
        } else {
            rs = quadratic_roots(polys[k]);
        }
        for (var m = 0u; m < 2u; m++) {
            let x = rs.r[m];
            if (rs.ok[m] && x > tau_lo && x < tau_hi && count < 8u) {
                brk[count] = x;
                count += 1u;
            }
        }
    }
    // Fixed insertion network over all slots (unused slots hold τ_hi, which sorts last).
    for (var i = 1u; i < 8u; i++) {
        for (var j = i; j >= 1u; j--) {
            let x = brk[j - 1u];
            let y = brk[j];
            if (y < x) {
                brk[j - 1u] = y;
                brk[j] = x;
            }
        }
    }
    var first = 0.0;
    var last = 0.0;
    var has = false;
    for (var k = 0u; k < 7u; k++) {
        let a = brk[k];
        let b = brk[k + 1u];
        if (b > a && inside(pt, polys, m, o, r, 0.5 * (a + b))) {
            if (!has) {
                first = a;
            }
            has = true;
            last = b;
        }
    }
    if (has) {
        return Span(first, last, true);
    }
    // A ray that only touches the shell at a point can still cross the surface there.
    if (tau_hi <= tau_lo && inside(pt, polys, m, o, r, tau_lo)) {
        return Span(tau_lo, tau_lo, true);
    }
    return Span(0.0, 0.0, false);
}
