// The flat baseline: Möller–Trumbore on the record's three world vertices
// (core/src/kernel/flat.rs).

fn flat_crossing(id: u32, o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32) -> Crossing {
    let b = id * FLAT_VEC4;
    let p0 = patches[b].xyz;
    let p1 = patches[b + 1u].xyz;
    let p2 = patches[b + 2u].xyz;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if (det == 0.0 || !fin(det)) {
        return no_crossing();
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = dot(tv, pv) * inv;
    if (!(u >= 0.0 && u <= 1.0)) {
        return no_crossing();
    }
    let qv = cross(tv, e1);
    let v = dot(d, qv) * inv;
    if (!(v >= 0.0 && u + v <= 1.0)) {
        return no_crossing();
    }
    let t = dot(e2, qv) * inv;
    if (t >= t_min && t <= t_max && fin(t)) {
        return Crossing(true, t, 0.0, vec3<f32>(1.0 - u - v, u, v));
    }
    return no_crossing();
}
