//! Shared by the `capi` and `scene_update` targets: the mapping of a fuzzed vertex onto a small
//! sphere-like cloud, so that most triangles of arbitrary input are accepted.

/// Maps a fuzzed vertex (position then normal) onto a small sphere-like cloud: finite
/// positions in `[-1, 1]³`, normals pointing outwards (the position plus a small fuzzed tilt).
pub fn structured(v: [f64; 6]) -> [f64; 6] {
    let f = |x: f64| {
        if x.is_finite() {
            (x.abs().fract() - 0.5) * 2.0
        } else {
            0.25
        }
    };
    let p = [f(v[0]), f(v[1]), f(v[2])];
    [
        p[0],
        p[1],
        p[2],
        p[0] + 0.1 * f(v[3]),
        p[1] + 0.1 * f(v[4]),
        p[2] + 0.1 * f(v[5]) + 1e-3,
    ]
}
