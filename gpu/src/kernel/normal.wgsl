// The exact surface normal (docs/METHOD.md §5; core/src/surface/scalar.rs point_derivs_local and
// normal_local), by forward-mode derivatives written out: a "G" value is vec3(value, ∂/∂w1,
// ∂/∂w2) with w0 = 1 − w1 − w2; a GV is a vector with its two partials. The edge curve enters
// through its parameter t(X): c and n* need c(t), c′(t) (for n*) and c″(t) (for n*′), carried
// as "J" values vec3(value, d/dt, d²/dt²).

fn g_mul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.x * b.x, a.yz * b.x + a.x * b.yz);
}

fn g_div(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = a.x / b.x;
    return vec3<f32>(q, (a.yz - q * b.yz) / b.x);
}

fn g_sqrt0(a: vec3<f32>) -> vec3<f32> {
    if (a.x > 0.0) {
        let r = sqrt(a.x);
        if (r > 0.0) {
            return vec3<f32>(r, a.yz / (r + r));
        }
    }
    return vec3<f32>(0.0, 0.0, 0.0);
}

struct GV {
    v: vec3<f32>,
    d1: vec3<f32>,
    d2: vec3<f32>,
}

fn gv_const(v: vec3<f32>) -> GV {
    return GV(v, vec3<f32>(0.0), vec3<f32>(0.0));
}

fn gv_sub(a: GV, b: GV) -> GV {
    return GV(a.v - b.v, a.d1 - b.d1, a.d2 - b.d2);
}

fn gv_dot(a: GV, b: GV) -> vec3<f32> {
    return vec3<f32>(dot(a.v, b.v), dot(a.d1, b.v) + dot(a.v, b.d1), dot(a.d2, b.v) + dot(a.v, b.d2));
}

// Root nearest 0 of the line base + s·g (w = base − anchor) and the sphere with axis m
// (|m|² = m2, value only: the double-root test's scale) and curvature kappa.
fn root_g(w: GV, g: GV, m: GV, m2: f32, kappa: vec3<f32>) -> vec3<f32> {
    let g2 = gv_dot(g, g);
    let w2 = gv_dot(w, w);
    let qa = g_mul(kappa, g2);
    let qb = g_mul(kappa, gv_dot(w, g)) - gv_dot(g, m);
    let qc = g_mul(kappa, w2) - 2.0 * gv_dot(w, m);
    let kk = kappa.x * kappa.x;
    let c_scale = 2.0 * (kk * w2.x * w2.x + 4.0 * w2.x * m2);
    let b_scale = 2.0 * (kk * w2.x * g2.x + g2.x * m2);
    return quadratic_root(qa, qb, qc, vec2<f32>(c_scale, b_scale), false);
}

fn j_mul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.x * b.x, a.y * b.x + a.x * b.y, a.z * b.x + 2.0 * a.y * b.y + a.x * b.z);
}

fn j_div(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = a.x / b.x;
    let q1 = (a.y - q * b.y) / b.x;
    let q2 = (a.z - 2.0 * q1 * b.y - q * b.z) / b.x;
    return vec3<f32>(q, q1, q2);
}

fn j_sqrt0(a: vec3<f32>) -> vec3<f32> {
    if (a.x > 0.0) {
        let r = sqrt(a.x);
        if (r > 0.0) {
            let r1 = a.y / (r + r);
            let r2 = (a.z - 2.0 * r1 * r1) / (r + r);
            return vec3<f32>(r, r1, r2);
        }
    }
    return vec3<f32>(0.0, 0.0, 0.0);
}

struct JV {
    v: vec3<f32>,
    d: vec3<f32>,
    dd: vec3<f32>,
}

fn jv_dot(a: JV, b: JV) -> vec3<f32> {
    return vec3<f32>(dot(a.v, b.v), dot(a.d, b.v) + dot(a.v, b.d),
        dot(a.dd, b.v) + 2.0 * dot(a.d, b.d) + dot(a.v, b.dd));
}

fn jv_dot_c(a: JV, m: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(a.v, m), dot(a.d, m), dot(a.dd, m));
}

// Edge-sphere root with its first two t-derivatives (unit axis m, constant curvature kappa).
fn root_j(w: JV, g: JV, m: vec3<f32>, kappa: f32) -> vec3<f32> {
    let g2 = jv_dot(g, g);
    let w2 = jv_dot(w, w);
    let qa = kappa * g2;
    let qb = kappa * jv_dot(w, g) - jv_dot_c(g, m);
    let qc = kappa * w2 - 2.0 * jv_dot_c(w, m);
    let kk = kappa * kappa;
    let c_scale = 2.0 * (kk * w2.x * w2.x + 4.0 * w2.x);
    let b_scale = 2.0 * (kk * w2.x * g2.x + g2.x);
    return quadratic_root(qa, qb, qc, vec2<f32>(c_scale, b_scale), true);
}

// The root nearest 0 of qa s² + 2 qb s + qc = 0 for `root_g` (G values, `jets` false) and
// `root_j` (J values, `jets` true), as core/src/surface/sphere.rs nearest_root: s = qc / q with
// the cancellation-free q = −qb ∓ √max(qb² − qa qc, 0); 0 at a double root (qc and qb within
// 16 ε of their scales, `scales` = (c's, b's)), where q is 0, or where s is not finite.
fn quadratic_root(qa: vec3<f32>, qb: vec3<f32>, qc: vec3<f32>, scales: vec2<f32>, jets: bool)
    -> vec3<f32> {
    let zero = vec3<f32>(0.0);
    var disc: vec3<f32>;
    if (jets) {
        disc = j_mul(qb, qb) - j_mul(qa, qc);
    } else {
        disc = g_mul(qb, qb) - g_mul(qa, qc);
    }
    if (!(disc.x > 0.0)) {
        disc = zero;
    }
    var sq: vec3<f32>;
    if (jets) {
        sq = j_sqrt0(disc);
    } else {
        sq = g_sqrt0(disc);
    }
    let q = select(-qb - sq, sq - qb, qb.x < 0.0);
    let tol = EPS * 16.0;
    let double_root = qc.x * qc.x <= tol * tol * scales.x && qb.x * qb.x <= tol * tol * scales.y;
    if (double_root || q.x == 0.0) {
        return zero;
    }
    var s: vec3<f32>;
    if (jets) {
        s = j_div(qc, q);
    } else {
        s = g_div(qc, q);
    }
    if (fin3(s)) {
        return s;
    }
    return zero;
}

struct EdgeJet {
    c: vec3<f32>,   // c(t)
    dc: vec3<f32>,  // c′(t)
    n: vec3<f32>,   // n*(t) scaled by |c′|²
    dn: vec3<f32>,  // its t-derivative
}

fn edge_jet(ep: Edge, t: f32) -> EdgeJet {
    let zero = vec3<f32>(0.0);
    let e = vec3<f32>(ep.e, 0.0);
    let gd = vec3<f32>(ep.gd, select(ep.gdz, 0.0, TILTED == 0u));
    let g = JV(vec3<f32>(ep.da + ep.gd * t, select(ep.daz + t * gd.z, 1.0, TILTED == 0u)), gd,
        zero);
    let w1 = JV(e * t, e, zero);
    let w2 = JV(e * (t - 1.0), e, zero);
    let s1 = root_j(w1, g, ep.na, ep.k1);
    let s2 = root_j(w2, g, ep.nb, ep.k2);
    let s = j_mul(vec3<f32>(1.0 - t, -1.0, 0.0), s1) + j_mul(vec3<f32>(t, 1.0, 0.0), s2);
    let c = vec3<f32>(ep.a, 0.0) + e * t + g.v * s.x;
    let tng = e + gd * s.x + g.v * s.y;
    let dtan = 2.0 * gd * s.y + g.v * s.z;
    let tt = dot(tng, tng);
    let dtt = 2.0 * dot(tng, dtan);
    let tg = dot(tng, g.v);
    let n = g.v * tt - tng * tg;
    let dn = gd * tt + g.v * dtt - dtan * tg - tng * (dot(dtan, g.v) + dot(tng, gd));
    if (tt > 0.0 && dot(n, n) > 0.0) {
        return EdgeJet(c, tng, n, dn);
    }
    return EdgeJet(c, tng, g.v, gd);
}

fn vertex_term_g(ep: Edge, pi: vec3<f32>, ni: vec3<f32>, xi: vec3<f32>, xa: vec3<f32>,
    xb: vec3<f32>, base: GV, dir: GV) -> vec3<f32> {
    let den = xa + xb;
    var t = vec3<f32>(0.5, 0.0, 0.0);
    if (den.x > EPS) {
        t = g_div(xb, den);
    }
    let ej = edge_jet(ep, t.x);
    let c = GV(ej.c, ej.dc * t.y, ej.dc * t.z);
    let nc = GV(ej.n, ej.dn * t.y, ej.dn * t.z);
    let wc = gv_sub(c, gv_const(pi));
    let l2 = gv_dot(wc, wc);
    var k1 = vec3<f32>(0.0);
    var k2 = vec3<f32>(0.0);
    if (l2.x > 0.0) {
        k1 = g_div(2.0 * gv_dot(wc, gv_const(ni)), l2);
        k2 = g_div(-2.0 * gv_dot(wc, nc), l2);
    }
    let s1 = root_g(gv_sub(base, gv_const(pi)), dir, gv_const(ni), 1.0, k1);
    let s2 = root_g(gv_sub(base, c), dir, nc, dot(nc.v, nc.v), k2);
    return 0.5 * g_mul(xi, s1) + 0.25 * g_mul(vec3<f32>(1.0, 0.0, 0.0) - xi, s2);
}

fn try_normalize(v: vec3<f32>) -> vec4<f32> {
    let l = length(v);
    if (l > 0.0 && fin(l)) {
        let u = v * (1.0 / l);
        if (fin3(u)) {
            return vec4<f32>(u, 1.0);
        }
    }
    return vec4<f32>(0.0);
}

// Unit surface normal (local frame) at the projected barycentrics x, oriented like the vertex
// normals; the normalised interpolated vertex normal where the derivatives degenerate.
fn normal_local(pt: Patch, x: vec3<f32>) -> vec3<f32> {
    let x0 = vec3<f32>(x.x, -1.0, -1.0);
    let x1 = vec3<f32>(x.y, 1.0, 0.0);
    let x2 = vec3<f32>(x.z, 0.0, 1.0);
    let p0 = vec3<f32>(0.0, 0.0, 0.0);
    let p1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let p2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    let d0 = vec3<f32>(pt.d0, pt.dz.x);
    let d1 = vec3<f32>(pt.d1, pt.dz.y);
    let d2 = vec3<f32>(pt.d2, pt.dz.z);
    let base = GV(p0 * x.x + p1 * x.y + p2 * x.z, p1 - p0, p2 - p0);
    var dir = GV(d0 * x.x + d1 * x.y + d2 * x.z, d1 - d0, d2 - d0);
    if (TILTED != 0u && pt.tilted) {
        // D = V / Vz: ∂D/∂Xk = ((dk − d0) − D·(dk.z − d0.z)) / Vz.
        let inv = 1.0 / dir.v.z;
        let dv = dir.v * inv;
        dir = GV(dv, (dir.d1 - dv * dir.d1.z) * inv, (dir.d2 - dv * dir.d2.z) * inv);
    }
    let h = vertex_term_g(pt.e1, p0, pt.n0, x0, x1, x2, base, dir)
        + vertex_term_g(pt.e2, p1, pt.n1, x1, x2, x0, base, dir)
        + vertex_term_g(pt.e0, p2, pt.n2, x2, x0, x1, base, dir);
    let du1 = base.d1 + dir.d1 * h.x + dir.v * h.y;
    let du2 = base.d2 + dir.d2 * h.x + dir.v * h.z;
    let phong = pt.n0 * x.x + pt.n1 * x.y + pt.n2 * x.z;
    var fallback = vec3<f32>(0.0, 0.0, 1.0);
    let fb = try_normalize(phong);
    if (fb.w > 0.0) {
        fallback = fb.xyz;
    }
    let n = try_normalize(cross(du1, du2));
    if (n.w > 0.0) {
        return select(n.xyz, -n.xyz, dot(n.xyz, phong) < 0.0);
    }
    return fallback;
}
