// Bracketing and refinement (core/src/kernel/refine.rs)

struct Bracket {
    a: f32,
    b: f32,
    fa: f32,
    fb: f32,
}

// Regula falsi point of the bracket, clamped inside it (the midpoint if degenerate).
fn estimate(br: Bracket) -> f32 {
    if (br.fa == 0.0) {
        return br.a;
    }
    if (br.fb == 0.0) {
        return br.b;
    }
    let den = br.fb - br.fa;
    let x = (br.fb * br.a - br.fa * br.b) / select(1.0, den, den != 0.0);
    if (den != 0.0 && fin(x) && x >= br.a && x <= br.b) {
        return x;
    }
    return 0.5 * (br.a + br.b);
}

// Bracketing sample j of the shell interval: shell.a + j·stp, the last (j = SAMPLES + 1)
// exactly shell.b.
fn sample_at(shell: Span, stp: f32, j: u32) -> f32 {
    return select(shell.a + stp * f32(j), shell.b, j >= SAMPLES + 1u);
}

// A sample (x, f(x)) beside a bracket, for the start estimate; `ok` false where there is none.
struct Side {
    ok: bool,
    x: f32,
    f: f32,
}

// The CPU's `refine::start_estimate`: the zero of the inverse interpolation x(f) through the
// bracket's ends and the samples before and after it where f is strictly monotone over them
// (cubic, quadratic), else regula falsi.
fn start_estimate(br: Bracket, before: Side, after: Side) -> f32 {
    let rf = estimate(br);
    if (br.fa == 0.0 || br.fb == 0.0) {
        return rf;
    }
    let rising = br.fb > br.fa;
    let use_p = before.ok && select((before.f > br.fa), (before.f < br.fa), rising);
    // (The comparisons in parentheses: `a < b, c > d` would parse as a template list.)
    let use_q = after.ok && select((after.f < br.fb), (after.f > br.fb), rising);
    var xs: array<f32, 4>;
    var fs: array<f32, 4>;
    var m = 0u;
    if (use_p) {
        xs[m] = before.x;
        fs[m] = before.f;
        m++;
    }
    xs[m] = br.a;
    fs[m] = br.fa;
    m++;
    xs[m] = br.b;
    fs[m] = br.fb;
    m++;
    if (use_q) {
        xs[m] = after.x;
        fs[m] = after.f;
        m++;
    }
    if (m == 2u) {
        return rf;
    }
    // Lagrange: Σ_i x_i Π_{j≠i} f_j / (f_j − f_i).
    var x = 0.0;
    for (var i = 0u; i < m; i++) {
        var w = 1.0;
        for (var j = 0u; j < m; j++) {
            if (j != i) {
                w = w * (fs[j] / (fs[j] - fs[i]));
            }
        }
        x = x + xs[i] * w;
    }
    if (fin(x) && x > br.a && x < br.b) {
        return x;
    }
    return rf;
}

struct Crossing {
    ok: bool,
    t: f32,
    t_error: f32,
    bary: vec3<f32>,
}

fn no_crossing() -> Crossing {
    return Crossing(false, 0.0, 0.0, vec3<f32>(0.0, 0.0, 0.0));
}

// The search part of the kernel for one patch (clip, bracket, refine): where the ray crosses
// it in [t_min, t_max].
fn smooth_crossing(id: u32, o: vec3<f32>, d: vec3<f32>, inv: vec3<f32>, t_min: f32,
    t_max: f32) -> Crossing {
    let b = id * PATCH_VEC4;
    let bx = box_span(patches[b + 4u].xyz, patches[b + 5u].xyz, o, d, inv, t_min, t_max);
    if (!bx.ok) {
        return no_crossing();
    }
    let pt = load_patch(id);
    // Local ray re-based at the middle of the box interval.
    let t0 = 0.5 * (bx.a + bx.b);
    let w = o + d * t0 - pt.origin;
    let lo = vec3<f32>(dot(w, pt.ex), dot(w, pt.ey), dot(w, pt.ez));
    let lr = vec3<f32>(dot(d, pt.ex), dot(d, pt.ey), dot(d, pt.ez));
    // Slab σmin ≤ σ ≤ σmax.
    var a = bx.a - t0;
    var bb = bx.b - t0;
    if (lr.z != 0.0) {
        let iz = 1.0 / lr.z;
        let u = (pt.sig_lo - lo.z) * iz;
        let v = (pt.sig_hi - lo.z) * iz;
        a = max(a, min(u, v));
        bb = min(bb, max(u, v));
    } else if (lo.z < pt.sig_lo || lo.z > pt.sig_hi) {
        return no_crossing();
    }
    if (!(a <= bb) || !fin(a) || !fin(bb)) {
        return no_crossing();
    }
    // The band, first over the slab's interval (before the wall quadratics), as on the CPU.
    if (band_misses(pt, b, lo, lr, a, bb)) {
        return no_crossing();
    }
    let shell = shell_interval(pt, lo, lr, a, bb);
    if (!shell.ok || !(shell.b >= shell.a)) {
        return no_crossing();
    }
    // The band: no surface point on the interval, nothing to sample.
    if (band_misses(pt, b, lo, lr, shell.a, shell.b)) {
        return no_crossing();
    }
    // Bracketing: the ends and SAMPLES interior points, the first sign change.
    let stp = (shell.b - shell.a) / f32(SAMPLES + 1u);
    var found = false;
    var br = Bracket(0.0, 0.0, 0.0, 0.0);
    var x0 = shell.a;
    var f0 = 0.0;
    // f at the interval's ends within the rounding of f counts as zero (the CPU's
    // `refine::bracket_step`): neighbours decide a crossing at their shared wall alike.
    let snap = ROUNDING_ULPS * EPS * pt.scale;
    var before = Side(false, 0.0, 0.0);
    var at = 0u;
    for (var j = 0u; j < SAMPLES + 2u; j++) {
        let x1 = sample_at(shell, stp, j);
        var f1 = f_at(pt, lo, lr, x1);
        if ((j == 0u || j == SAMPLES + 1u) && abs(f1) <= snap) {
            f1 = 0.0;
        }
        if (j > 0u && (f0 == 0.0 || f1 == 0.0 || (f1 > 0.0) != (f0 > 0.0))) {
            br = Bracket(x0, x1, f0, f1);
            found = true;
            at = j;
            break;
        }
        if (j > 0u) {
            before = Side(true, x0, f0);
        }
        x0 = x1;
        f0 = f1;
    }
    if (!found) {
        return no_crossing();
    }
    // The sample after the bracket (the CPU's lane call computes it with the others), for the
    // start estimate; none after the last.
    var after = Side(false, 0.0, 0.0);
    if (at < SAMPLES + 1u && br.fa != 0.0 && br.fb != 0.0) {
        let x2 = sample_at(shell, stp, at + 1u);
        after = Side(true, x2, f_at(pt, lo, lr, x2));
    }
    let first = br;
    // Early stop, as on the CPU: once the bracket is within EARLY_STOP of the rounding
    // allowance computed from the sampling bracket's secant (a lower bound of the final one).
    var stop = 0.0;
    if (first.b > first.a) {
        let s0 = abs(first.fb - first.fa) / (first.b - first.a);
        let floor = ROUNDING_ULPS * EPS * pt.scale / select(1.0, s0, s0 > 0.0);
        if (s0 > 0.0 && fin(floor)) {
            stop = EARLY_STOP * floor;
        }
    }
    // Refinement: at most ITERATIONS steps of 8 points (fewer once the bracket has collapsed
    // onto an exact zero or is within `stop`) and at most ESTIMATE_STEPS estimate steps of the
    // 4 points around a trusted estimate (the CPU's `refine::refine`, "Estimate steps").
    var x = start_estimate(br, before, after);
    var estimate_steps = ESTIMATE_STEPS;
    var steps = 0u;
    for (var it = 0u; it < ITERATIONS + ESTIMATE_STEPS; it++) {
        if (br.fa == 0.0 || br.fb == 0.0 || !(br.b - br.a > stop)) {
            break;
        }
        let wd = br.b - br.a;
        // Radii around the estimate from its distance e to regula falsi's (the CPU's
        // `refine::refine`).
        let e = abs(x - estimate(br));
        var r_in = max(e * INNER_OF_SPREAD, stop * INNER_OF_STOP);
        if (!(e > 0.0)) {
            r_in = max(r_in, wd * (OUTER_OF_WIDTH / OUTER_OF_INNER));
        }
        let r_out = max(max(e * OUTER_OF_SPREAD, r_in * OUTER_OF_INNER), wd * OUTER_OF_WIDTH);
        // Trusted: a root caught within r_in ends the refinement; then only the 4 points
        // around the estimate (at most ESTIMATE_STEPS times), else a uniform step (at most
        // ITERATIONS of them).
        var first_k = 0u;
        if (ITERATIONS > 0u && estimate_steps > 0u && e > 0.0 && r_in + r_in <= stop) {
            estimate_steps -= 1u;
            first_k = 4u;
        } else {
            if (steps == ITERATIONS) {
                break;
            }
            steps++;
        }
        let neg_a = br.fa < 0.0;
        var nb = br.b;
        var fnb = br.fb;
        var xs: array<f32, 8>;
        var fs: array<f32, 8>;
        for (var k = 0u; k < 8u; k++) {
            if (k < first_k) {
                // Not evaluated: a copy of the bracket's start, which no search below takes.
                xs[k] = br.a;
                fs[k] = br.fa;
                continue;
            }
            var xk: f32;
            switch k {
                case 0u, 1u, 2u, 3u: {
                    xk = br.a + wd * (0.2 * f32(k + 1u));
                }
                case 4u: {
                    xk = x - r_out;
                }
                case 5u: {
                    xk = x - r_in;
                }
                case 6u: {
                    xk = x + r_in;
                }
                default: {
                    xk = x + r_out;
                }
            }
            xk = min(max(xk, br.a), br.b);
            let fk = f_at(pt, lo, lr, xk);
            xs[k] = xk;
            fs[k] = fk;
            // b′: the smallest point whose sign differs from f(a)'s (or is zero).
            if ((fk == 0.0 || (fk < 0.0) != neg_a) && xk < nb) {
                nb = xk;
                fnb = fk;
            }
        }
        // a′: the largest point below b′ (all of them have f(a)'s sign).
        var na = br.a;
        var fna = br.fa;
        for (var k = 0u; k < 8u; k++) {
            if (xs[k] < nb && xs[k] > na) {
                na = xs[k];
                fna = fs[k];
            }
        }
        // The nearest samples outside the new bracket, for the next estimate.
        var bef = Side(false, 0.0, 0.0);
        var aft = Side(false, 0.0, 0.0);
        for (var k = 0u; k < 10u; k++) {
            var xk: f32;
            var fk: f32;
            if (k < 8u) {
                xk = xs[k];
                fk = fs[k];
            } else if (k == 8u) {
                xk = br.a;
                fk = br.fa;
            } else {
                xk = br.b;
                fk = br.fb;
            }
            if (xk < na && (!bef.ok || xk > bef.x)) {
                bef = Side(true, xk, fk);
            }
            if (xk > nb && (!aft.ok || xk < aft.x)) {
                aft = Side(true, xk, fk);
            }
        }
        if (fnb == 0.0) {
            br = Bracket(nb, nb, fnb, fnb);
        } else {
            br = Bracket(na, nb, fna, fnb);
        }
        // A bracket within `stop` ends the refinement and takes the regula falsi point below.
        if (br.b - br.a > stop) {
            x = start_estimate(br, bef, aft);
        }
    }
    // The estimate inside the final bracket (the CPU's `refine` returns it with the bracket):
    // regula falsi once the bracket is within `stop`, where the samples are rounding noise.
    if (!(br.b - br.a > stop)) {
        x = estimate(br);
    }
    let tau = x;
    let bc = bary(pt, lo + lr * tau);
    // Re-basing can round the hit an ulp outside the caller's range: clamp it.
    let t = min(max(t0 + tau, t_min), t_max);
    // Rounding allowance ROUNDING_ULPS ε L / |f′|, f′ the smaller of the sampling bracket's and
    // the final bracket's secants (near convergence the final bracket's end values are rounding
    // noise and its secant alone can be far too steep), as on the CPU.
    var slope: f32 = 0.0;
    var s_first: f32 = 0.0;
    if (first.b > first.a) {
        s_first = abs(first.fb - first.fa) / (first.b - first.a);
    }
    if (br.b > br.a) {
        let s_fin = abs(br.fb - br.fa) / (br.b - br.a);
        slope = select(s_fin, min(s_fin, s_first), first.b > first.a);
    } else {
        slope = s_first;
    }
    var rounding = ROUNDING_ULPS * EPS * pt.scale / select(1.0, slope, slope > 0.0);
    if (!(slope > 0.0) || !fin(rounding)) {
        rounding = 0.0;
    }
    // A zero at an end of the bracket is the root up to the rounding of f (as on the CPU).
    let width = select(br.b - br.a, 0.0, br.fa == 0.0 || br.fb == 0.0);
    let t_error = width + rounding;
    if (fin(t) && fin(t_error)) {
        return Crossing(true, t, t_error, bc);
    }
    return no_crossing();
}
