// The height evaluation f(τ) = z − σS(X) (core/src/surface/lanes/height.rs, one point per call)

struct Root {
    s: f32,
    q: f32,
    sq: f32,
    ok: bool,
}

// Root nearest 0 of qa s² + 2 qb s + qc = 0, c = (qa, qb, qc) (sphere::nearest_root's stable
// form and double-root test; the axis may be scaled, m2 = |m|²).
fn root(c: vec3<f32>, k: f32, w2: f32, g2: f32, m2: f32) -> Root {
    let disc = c.y * c.y - c.x * c.z;
    let sq = sqrt(select(0.0, disc, disc > 0.0));
    let q = select(-c.y - sq, sq - c.y, c.y < 0.0);
    let tol = EPS * 16.0;
    let tol2 = tol * tol;
    let kk = k * k;
    let c_scale = 2.0 * (kk * w2 * w2 + 4.0 * w2 * m2);
    let b_scale = 2.0 * (kk * w2 * g2 + g2 * m2);
    let noise = (c.z * c.z <= tol2 * c_scale) && (c.y * c.y <= tol2 * b_scale);
    let s = c.z / select(1.0, q, q != 0.0);
    let ok = !noise && q != 0.0 && fin(s);
    return Root(select(0.0, s, ok), select(0.0, q, ok), sq, ok);
}

// Derivative s′ of a root from the coefficients' derivatives dc (forward mode; the square root
// has derivative 0 where the discriminant is clamped).
fn root_derivative(r: Root, c: vec3<f32>, dc: vec3<f32>) -> f32 {
    let ddisc = 2.0 * c.y * dc.y - dc.x * c.z - c.x * dc.z;
    let dsq = select(0.0, ddisc / select(1.0, 2.0 * r.sq, r.sq > 0.0), r.sq > 0.0);
    let dq = select(-dc.y - dsq, dsq - dc.y, c.y < 0.0);
    let ds = (dc.z - r.s * dq) / select(1.0, r.q, r.ok);
    return select(0.0, ds, r.ok && fin(ds));
}

struct PointNormal {
    c: vec3<f32>,
    n: vec3<f32>,
}

// One edge sphere of eq. (3) at the edge's parameter t: the root s of the line through the
// edge point with w = v·e from the sphere's anchor (v = t for S¹ from A, t − 1 for S² from B),
// of curvature k and axis terms m, and its derivative s′ (x, y). gg, dgg and eg are the line
// direction's |g|², its derivative and e·g at t.
fn edge_sphere(ep: Edge, k: f32, v: f32, t: f32, m: vec3<f32>, gg: f32, dgg: f32,
    eg: f32) -> vec2<f32> {
    let w2 = v * v * ep.ee;
    let c = vec3<f32>(k * gg, k * v * eg - (m.x + t * m.y), v * (k * v * ep.ee - 2.0 * m.z));
    let dc = vec3<f32>(k * dgg, k * (eg + v * ep.eg1) - m.y, 2.0 * (k * v * ep.ee - m.z));
    let r = root(c, k, w2, gg, 1.0);
    return vec2<f32>(r.s, root_derivative(r, c, dc));
}

// Conjugation point c(t) of an edge and its normal n*(t) scaled by |c′|² (eq. (3)).
fn edge_point_normal(ep: Edge, t: f32) -> PointNormal {
    let u = t - 1.0;
    let e = vec3<f32>(ep.e, 0.0);
    let gd = vec3<f32>(ep.gd, select(ep.gdz, 0.0, TILTED == 0u));
    let g = vec3<f32>(ep.da.x + t * gd.x, ep.da.y + t * gd.y,
        select(ep.daz + t * gd.z, 1.0, TILTED == 0u));
    let gg = ep.gg0 + t * (ep.gg1 + t * ep.gg2);
    let dgg = ep.gg1 + 2.0 * t * ep.gg2;
    let eg = ep.eg0 + t * ep.eg1;
    // S¹: anchor A, w = t·e; S²: anchor B, w = (t − 1)·e.
    let s1 = edge_sphere(ep, ep.k1, t, t, ep.ma, gg, dgg, eg);
    let s2 = edge_sphere(ep, ep.k2, u, t, ep.mb, gg, dgg, eg);
    let s = t * s2.x - u * s1.x;
    let ds = t * s2.y - u * s1.y + (s2.x - s1.x);
    let cpt = vec3<f32>(ep.a, 0.0) + e * t + g * s;
    // c′ = e + g′·s + g·s′.
    let tng = e + gd * s + g * ds;
    let tt = dot(tng, tng);
    let n = g * tt - tng * dot(tng, g);
    let good = tt > 0.0 && dot(n, n) > 0.0;
    return PointNormal(cpt, select(g, n, good));
}

// The term of vertex i in eq. (5): ½ (Xi·s¹ + ((1 − Xi)/2)·s²), for the line base + s·dir.
fn vertex_term(ep: Edge, pi: vec3<f32>, ni: vec3<f32>, xi: f32, xa: f32, xb: f32,
    base: vec3<f32>, dir: vec3<f32>, dd: f32) -> f32 {
    let den = xa + xb;
    let t = select(0.5, xb / select(1.0, den, den > EPS), den > EPS);
    let en = edge_point_normal(ep, t);
    // Ŝ¹: anchor Pi, unit axis ni, through c; Ŝ²: anchor c, axis n* (scaled), through Pi.
    let wc = en.c - pi;
    let l2 = dot(wc, wc);
    let has = l2 > 0.0;
    let inv = 2.0 / select(1.0, l2, has);
    let k1 = select(0.0, dot(wc, ni) * inv, has);
    let k2 = select(0.0, -(dot(wc, en.n) * inv), has);
    let wa = base - pi;
    let wa2 = dot(wa, wa);
    let r1 = root(vec3<f32>(k1 * dd, k1 * dot(wa, dir) - dot(dir, ni), k1 * wa2 - 2.0 * dot(wa, ni)),
        k1, wa2, dd, 1.0);
    let wb = base - en.c;
    let wb2 = dot(wb, wb);
    let r2 = root(vec3<f32>(k2 * dd, k2 * dot(wb, dir) - dot(dir, en.n),
        k2 * wb2 - 2.0 * dot(wb, en.n)), k2, wb2, dd, dot(en.n, en.n));
    return 0.5 * xi * r1.s + 0.25 * (1.0 - xi) * r2.s;
}

// The line parameter λ of the section through the local point x (core/src/surface/field.rs
// `Section::param`): x.z for parallel sections, else SECTION_NEWTON_STEPS Newton steps on the
// cubic g(λ) = det[A1 − A0, A2 − A0, x − A0] from x.z / mean(di.z).
fn section_param(pt: Patch, x: vec3<f32>) -> f32 {
    if (TILTED == 0u || !pt.tilted) {
        return x.z;
    }
    // (A1 − A0) × (A2 − A0) = k0 + λ·k1 + λ²·k2 (formed here, only for tilted sections, so
    // the parallel path carries none of it).
    let q1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let q2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    let d0 = vec3<f32>(pt.d0, pt.dz.x);
    let c1 = vec3<f32>(pt.d1 - pt.d0, pt.dz.y - pt.dz.x);
    let c2 = vec3<f32>(pt.d2 - pt.d0, pt.dz.z - pt.dz.x);
    let k0 = cross(q1, q2);
    let k1 = cross(q1, c2) + cross(c1, q2);
    let k2 = cross(c1, c2);
    let c0 = dot(k0, x);
    let cc1 = dot(k1, x) - dot(k0, d0);
    let cc2 = dot(k2, x) - dot(k1, d0);
    let c3 = -dot(k2, d0);
    var l = x.z * 3.0 / (pt.dz.x + pt.dz.y + pt.dz.z);
    for (var i = 0u; i < SECTION_NEWTON_STEPS; i++) {
        let g = c0 + l * (cc1 + l * (cc2 + l * c3));
        let dg = cc1 + l * (2.0 * cc2 + 3.0 * l * c3);
        let next = l - g / dg;
        l = select(l, next, fin(next));
    }
    return l;
}

// The barycentric numerators (n0, n1, n2) of the local point x in its section (parameter λ of
// section_param) and their sum, twice the section's projected area (core clip.rs
// `bary_numerators`), with λ in .w of the second.
struct Numerators {
    n: vec3<f32>,
    area: f32,
    s: f32,
}

fn bary_numerators(pt: Patch, x: vec3<f32>) -> Numerators {
    let s = section_param(pt, x);
    let a0x = pt.d0.x * s - x.x;
    let a0y = pt.d0.y * s - x.y;
    let a1x = pt.p1x + pt.d1.x * s - x.x;
    let a1y = pt.d1.y * s - x.y;
    let a2x = pt.p2x + pt.d2.x * s - x.x;
    let a2y = pt.p2y + pt.d2.y * s - x.y;
    let n1 = a2x * a0y - a2y * a0x;
    let n2 = a0x * a1y - a0y * a1x;
    let n0 = a1x * a2y - a1y * a2x;
    return Numerators(vec3<f32>(n0, n1, n2), n0 + n1 + n2, s);
}

// Raw barycentrics (w0, w1, w2) of the local point x in its section (0, 0, 1 where the
// section has no area), with the section's λ in .w.
fn bary_raw(pt: Patch, x: vec3<f32>) -> vec4<f32> {
    let nm = bary_numerators(pt, x);
    let area = nm.area;
    let ar = select(1.0, area, area != 0.0);
    let w1 = select(0.0, nm.n.y / ar, area != 0.0);
    let w2 = select(0.0, nm.n.z / ar, area != 0.0);
    return vec4<f32>(1.0 - w1 - w2, w1, w2, nm.s);
}

// Raw barycentrics projected onto the triangle (negative or non-finite components 0,
// renormalised; the centroid if all vanish).
fn project(w: vec3<f32>) -> vec3<f32> {
    let a = select(0.0, w.x, fin(w.x) && w.x > 0.0);
    let b = select(0.0, w.y, fin(w.y) && w.y > 0.0);
    let c = select(0.0, w.z, fin(w.z) && w.z > 0.0);
    let m = max(max(a, b), c);
    if (!(m > 0.0) || !fin(m)) {
        return vec3<f32>(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
    }
    let an = a / m;
    let bn = b / m;
    let cn = c / m;
    let inv = 1.0 / (an + bn + cn);
    return vec3<f32>(an * inv, bn * inv, cn * inv);
}

// Barycentrics of the local point x in the cross-section at its height, projected onto the
// triangle.
fn bary(pt: Patch, x: vec3<f32>) -> vec3<f32> {
    return project(bary_raw(pt, x).xyz);
}

// The height change of the surface's continuation beyond the triangle's edges, from the projected
// point q to the raw barycentrics w in the cross-section at height s, along the plane normal to the
// interpolated vertex normal (core/src/surface/lanes/height.rs `beyond_edge`); 0 inside.
fn beyond_edge(pt: Patch, w: vec3<f32>, q: vec3<f32>, s: f32) -> f32 {
    let e = w - q;
    let ox = e.y * pt.p1x + e.z * pt.p2x + s * (e.x * pt.d0.x + e.y * pt.d1.x + e.z * pt.d2.x);
    let oy = e.z * pt.p2y + s * (e.x * pt.d0.y + e.y * pt.d1.y + e.z * pt.d2.y);
    let nx = q.x * pt.n0.x + q.y * pt.n1.x + q.z * pt.n2.x;
    let ny = q.x * pt.n0.y + q.y * pt.n1.y + q.z * pt.n2.y;
    let nz = q.x * pt.n0.z + q.y * pt.n1.z + q.z * pt.n2.z;
    let dx = q.x * pt.d0.x + q.y * pt.d1.x + q.z * pt.d2.x;
    let dy = q.x * pt.d0.y + q.y * pt.d1.y + q.z * pt.d2.y;
    var dh = 0.0;
    if (TILTED != 0u && pt.tilted) {
        // The point is o.z above the section point of q (core height.rs `beyond_edge`).
        let oz = s * dot(e, pt.dz);
        let vz = dot(q, pt.dz);
        let nd = (nx * dx + ny * dy) / vz + nz;
        dh = oz - (nx * ox + ny * oy + nz * oz) / nd;
    } else {
        let nd = nx * dx + ny * dy + nz;
        dh = 0.0 - (nx * ox + ny * oy) / nd;
    }
    let outside = w.x < 0.0 || w.y < 0.0 || w.z < 0.0;
    return select(0.0, dh, outside && fin(dh));
}

// Height σS(X) at barycentrics x (summing to one, inside the triangle).
fn height_at(pt: Patch, x: vec3<f32>) -> f32 {
    let base = vec3<f32>(x.y * pt.p1x + x.z * pt.p2x, x.z * pt.p2y, 0.0);
    var dir = vec3<f32>(x.x * pt.d0.x + x.y * pt.d1.x + x.z * pt.d2.x,
        x.x * pt.d0.y + x.y * pt.d1.y + x.z * pt.d2.y, x.x + x.y + x.z);
    if (TILTED != 0u && pt.tilted) {
        // Unit height (core/src/surface/field.rs `unit_height_dir`).
        let inv = 1.0 / dot(x, pt.dz);
        dir = vec3<f32>(dir.x * inv, dir.y * inv, 1.0);
    }
    let dd = dot(dir, dir);
    let p0 = vec3<f32>(0.0, 0.0, 0.0);
    let p1 = vec3<f32>(pt.p1x, 0.0, 0.0);
    let p2 = vec3<f32>(pt.p2x, pt.p2y, 0.0);
    return vertex_term(pt.e1, p0, pt.n0, x.x, x.y, x.z, base, dir, dd)
        + vertex_term(pt.e2, p1, pt.n1, x.y, x.z, x.x, base, dir, dd)
        + vertex_term(pt.e0, p2, pt.n2, x.z, x.x, x.y, base, dir, dd);
}

// f(τ) at the local point lo + τ·lr.
fn f_at(pt: Patch, lo: vec3<f32>, lr: vec3<f32>, tau: f32) -> f32 {
    let x = lo + lr * tau;
    let w = bary_raw(pt, x);
    let q = project(w.xyz);
    return x.z - (height_at(pt, q) + beyond_edge(pt, w.xyz, q, w.w));
}
