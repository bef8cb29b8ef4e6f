//! Eight rays against one patch at once (ray packets): one ray per lane of the height
//! evaluation, for coherent rays such as a 2×4 tile of camera pixels.
//!
//! Each ray is clipped on its own (box, slab, shell), then the packet runs the same bracketing
//! as the single-ray kernel (`K + 2` samples, now one lane call per sample index, each lane at its
//! own ray's sample: the same values bit for bit, so the same first sign change), then at most
//! `N` refinement steps in which every lane evaluates one point of its own bracket, chosen by
//! ITP ([`super::refine`]'s per-lane state: at most `W/2^(N−1)` after `N` steps, superlinear on
//! smooth functions). A lane stops once its bracket is within the early stop of the single-ray
//! kernel ([`EARLY_STOP`](super::refine::EARLY_STOP) of its rounding allowance), the packet
//! once every lane has.
//!
//! Work per packet and patch: at most `K + 2 + N` lane calls, whatever the input. A lane whose
//! ray misses the shell (or is inactive) rides along and its result is ignored.

use crate::geometry::Patch;
use crate::num::lanes::{LANES, Lane};
use crate::num::real::Float;
use crate::ray::Ray;

use super::refine::{Bracket, ItpLane, bracket_step};
use super::{
    Clipped, Crossing, clip_ray, complete, end_snap, rounding_allowance, rounding_scale, secant,
};
use crate::surface::height::{Prepared, f_lanes};

/// The crossings of up to eight rays with `patch` (`active[i]` false: lane `i` is skipped),
/// each in `[t_min, t_max[i]]`. At most `K + 2 + N` lane calls.
#[inline(always)]
pub(crate) fn crossings_packet<F: Float, const K: usize, const N: usize>(
    patch: &Patch<F>,
    rays: &[Ray<F>; LANES],
    t_min: F,
    t_max: &[F; LANES],
    active: [bool; LANES],
) -> [Option<Crossing<F>>; LANES] {
    let mut clipped: [Option<Clipped<F>>; LANES] = [None; LANES];
    for (((c, ray), &tm), on) in clipped.iter_mut().zip(rays).zip(t_max).zip(active) {
        if on {
            *c = clip_ray(patch, ray, t_min, tm);
        }
    }
    let mut out = [None; LANES];
    if clipped.iter().all(Option::is_none) {
        return out;
    }
    let prep = Prepared::new(&patch.shape);
    // Lanes of inactive rays evaluate a harmless copy of an active one.
    let fallback = clipped.iter().flatten().next().copied();
    let lane_ray: [Option<Clipped<F>>; LANES] = clipped.map(|c| c.or(fallback));
    let comp =
        |k: fn(&Clipped<F>) -> F| F::L8::from_array(lane_ray.map(|c| c.map_or(F::ZERO, |c| k(&c))));
    let o = [
        comp(|c| c.lray.o.x),
        comp(|c| c.lray.o.y),
        comp(|c| c.lray.o.z),
    ];
    let r = [
        comp(|c| c.lray.r.x),
        comp(|c| c.lray.r.y),
        comp(|c| c.lray.r.z),
    ];
    let f = |tau: [F; LANES]| f_lanes(&prep, o, r, F::L8::from_array(tau)).to_array();

    // Bracketing: sample j of every lane in call j (the single-ray kernel's points).
    let step = lane_ray.map(|c| c.map_or(F::ZERO, |c| (c.b - c.a) / F::from_f64((K + 1) as f64)));
    let point = |i: usize, j: usize| {
        let c = lane_ray.get(i).copied().flatten();
        let s = step.get(i).copied().unwrap_or(F::ZERO);
        match c {
            Some(c) if j > K => c.b,
            Some(c) => c.a + s * F::from_f64(j as f64),
            None => F::ZERO,
        }
    };
    // The patch's extent, the same for every lane.
    let scale = rounding_scale(patch);
    let snap = end_snap(scale);
    let mut prev: [(F, F); LANES] = [(F::ZERO, F::ZERO); LANES];
    let mut found: [Option<Bracket<F>>; LANES] = [None; LANES];
    let mut open = clipped.map(|c| c.is_some_and(|c| c.b >= c.a));
    for j in 0..K + 2 {
        if !open.iter().any(|&x| x) {
            break;
        }
        let xs: [F; LANES] = core::array::from_fn(|i| point(i, j));
        let fs = f(xs);
        for ((((x1, f1), p), fd), op) in xs
            .into_iter()
            .zip(fs)
            .zip(prev.iter_mut())
            .zip(found.iter_mut())
            .zip(open.iter_mut())
        {
            if !*op {
                continue;
            }
            let (f1, br) = bracket_step(j, K + 1, *p, (x1, f1), snap);
            if br.is_some() {
                *fd = br;
                *op = false;
            }
            *p = (x1, f1);
        }
    }

    // Refinement: one ITP point per lane per step.
    let early = F::from_f64(super::refine::EARLY_STOP);
    let mut itp: [Option<ItpLane<F>>; LANES] =
        found.map(|b| b.map(|b| ItpLane::new(b, early * rounding_allowance(scale, secant(&b)))));
    for _ in 0..N {
        if itp.iter().flatten().all(ItpLane::done) {
            break;
        }
        let xs: [F; LANES] = core::array::from_fn(|i| match itp.get(i).copied().flatten() {
            Some(s) if !s.done() => s.point(),
            _ => point(0, 0),
        });
        let fs = f(xs);
        for ((s, x), y) in itp.iter_mut().zip(xs).zip(fs) {
            if let Some(s) = s
                && !s.done()
            {
                s.update(x, y);
            }
        }
    }
    let lanes = out.iter_mut().zip(clipped).zip(found).zip(itp).zip(t_max);
    for ((((o, c), b), s), &tm) in lanes {
        if let (Some(c), Some(b), Some(s)) = (c, b, s) {
            *o = complete(patch, &c, &b, &s.br, t_min, tm);
        }
    }
    out
}
