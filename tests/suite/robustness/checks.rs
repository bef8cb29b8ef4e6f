//! The checks of `tests/suite/robustness.rs`: what must hold for every input, whatever it is. Each
//! returns a proptest failure naming what broke; none of them skips or relaxes a case.

use super::strategies::{RayParam, to_f};
use glam::DVec3;
use proptest::prelude::*;
use smoothtri::MIN_NORMAL_COS;
use smoothtri::accuracy::UNIT_LENGTH_ULPS;
use smoothtri::{Bvh, BvhNode, Float, Hit, KernelStats, Patch, PatchError, Ray};

// ---------------------------------------------------------------------------------------------
// Conversions between f64 test data and the precision under test

/// A vector of precision `F`, exactly, in `f64`.
pub fn to_d<F: Float>(v: F::Vec3) -> DVec3 {
    let w = F::from_glam(v);
    DVec3::new(w.x.to_f64(), w.y.to_f64(), w.z.to_f64())
}

/// Unit length within [`UNIT_LENGTH_ULPS`] ulps of precision `F`.
pub fn is_unit<F: Float>(v: F::Vec3) -> bool {
    let d = to_d::<F>(v);
    d.is_finite() && (d.length() - 1.0).abs() <= UNIT_LENGTH_ULPS * F::EPSILON.to_f64()
}

// ---------------------------------------------------------------------------------------------
// Construction

/// Builds the patch in precision `F`; a rejection must be the variant the input explains
/// ([`check_rejection`]); an accepted patch must evaluate finitely ([`check_evaluations`]) and
/// answer every ray finitely ([`check_ray`]).
pub fn check_input<F: Float>(
    p: [DVec3; 3],
    n: [DVec3; 3],
    extra: &[(f64, f64)],
    rays: &[RayParam],
) -> Result<Option<Patch<F>>, TestCaseError> {
    let (pf, nf) = (p.map(to_f::<F>), n.map(to_f::<F>));
    let patch = match Patch::<F>::new(pf, nf) {
        Ok(patch) => patch,
        Err(e) => {
            check_rejection::<F>(pf, nf, e)?;
            return Ok(None);
        }
    };
    check_evaluations(&patch, extra)?;
    let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
    let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
    let face = to_d::<F>(patch.face_normal());
    for r in rays {
        let target = to_d::<F>(patch.point(F::from_f64(r.aim.0), F::from_f64(r.aim.1)));
        let (o, d, t0, t1) = r.build(lo, hi, face, target);
        let ray = Ray::<F>::new(to_f::<F>(o), to_f::<F>(d));
        check_ray(&patch, &ray, F::from_f64(t0), F::from_f64(t1))?;
    }
    Ok(Some(patch))
}

/// A rejection names what is wrong with the input, as measured here in `f64` from the values
/// precision `F` was given (docs of [`PatchError`]):
/// - `NonFinite` exactly when a coordinate is NaN or infinite;
/// - `DegenerateTriangle`: twice the area below `√ε · longest edge²` (with rounding slack);
/// - `OutOfRange`: a magnitude near the precision's limits (edges so long that `|e × f|²`
///   overflows, so small that it is below `MIN_POSITIVE / ε`, or coordinates near `MAX`);
/// - `ZeroNormal { vertex }`: that normal's length is below `√MIN_POSITIVE`;
/// - `BackFacingNormal { vertex }`: that normal's cosine to the face normal is below
///   [`MIN_NORMAL_COS`] (up to the face normal's rounding, `√ε` at the degeneracy limit);
/// - for the vertex errors, the vertices before it have neither problem, and for these and
///   `InvalidShell` the triangle itself is not degenerate.
pub fn check_rejection<F: Float>(
    p: [F::Vec3; 3],
    n: [F::Vec3; 3],
    e: PatchError,
) -> Result<(), TestCaseError> {
    let (p, n) = (p.map(to_d::<F>), n.map(to_d::<F>));
    let finite = p.iter().chain(&n).all(|v| v.is_finite());
    prop_assert_eq!(
        e == PatchError::NonFinite,
        !finite,
        "{:?} for input p = {:?}, n = {:?}",
        e,
        p,
        n
    );
    if !finite {
        return Ok(());
    }
    let eps = F::EPSILON.to_f64();
    let (min_pos, max) = (F::MIN_POSITIVE.to_f64(), F::MAX.to_f64());
    // Lengths by scaled norms, so that the measurement itself neither overflows nor underflows.
    let len = |v: DVec3| {
        let m = v.abs().max_element();
        if m > 0.0 { m * (v / m).length() } else { 0.0 }
    };
    let (a, b, c) = (p[1] - p[0], p[2] - p[0], p[2] - p[1]);
    let lmax = len(a).max(len(b)).max(len(c));
    let (sa, sb) = (a / lmax, b / lmax);
    // |e × f| / lmax², computed on the scaled edges.
    let rel_area = len(sa.cross(sb));
    let area = rel_area * lmax * lmax;
    let face = sa.cross(sb).normalize_or_zero();
    let coord = p.iter().fold(0.0f64, |m, v| m.max(v.abs().max_element()));
    let degenerate = rel_area.is_nan() || rel_area <= 0.5 * eps.sqrt();
    let zero = |k: usize| len(n[k]) < min_pos.sqrt() * (1.0 + 8.0 * eps);
    // The normal's direction, scaled first (a length can overflow near `MAX`).
    let cos = |k: usize| {
        (n[k] / n[k].abs().max_element())
            .normalize_or_zero()
            .dot(face)
    };
    let cos_tol = 4.0 * eps.sqrt();
    let back = |k: usize| cos(k) < MIN_NORMAL_COS + cos_tol;
    let good_before = |k: usize| (0..k).all(|j| !zero(j) && cos(j) >= MIN_NORMAL_COS - cos_tol);
    let why = format!(
        "{e:?}: relative area {rel_area:e}, longest edge {lmax:e}, |e × f| {area:e}, largest \
         coordinate {coord:e}, normal lengths {:?}, cosines {:?}",
        n.map(len),
        [0, 1, 2].map(cos)
    );
    match e {
        PatchError::NonFinite => {}
        PatchError::DegenerateTriangle => prop_assert!(
            // NaN: coincident vertices (no longest edge to scale by).
            rel_area.is_nan() || rel_area <= 2.0 * eps.sqrt(),
            "{}",
            why
        ),
        PatchError::OutOfRange => prop_assert!(
            lmax >= 0.5 * max.sqrt().sqrt()
                || area * area <= 2.0 * min_pos / eps
                || coord >= max / 1e3,
            "{}",
            why
        ),
        PatchError::ZeroNormal { vertex } => {
            let k = usize::from(vertex);
            prop_assert!(k < 3 && zero(k) && good_before(k) && !degenerate, "{}", why)
        }
        PatchError::BackFacingNormal { vertex } => {
            let k = usize::from(vertex);
            prop_assert!(k < 3 && back(k) && good_before(k) && !degenerate, "{}", why)
        }
        PatchError::InvalidShell => prop_assert!(!degenerate, "{}", why),
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Evaluation

/// Barycentrics at which every accepted patch is evaluated (inside, on the boundary, outside,
/// non-finite, and subnormal sums after cleaning).
pub const BARY: [(f64, f64); 19] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (1.0 / 3.0, 1.0 / 3.0),
    (0.5, 0.0),
    (0.0, 0.5),
    (0.5, 0.5),
    (0.25, 0.6),
    (1e-9, 1e-9),
    (1.0 - 1e-9, 0.0),
    (-0.5, 0.2),
    (2.0, -1.0),
    (f64::NAN, 0.3),
    (f64::INFINITY, 0.0),
    (f64::NEG_INFINITY, f64::INFINITY),
    (1e30, 1e30),
    (f64::NAN, 1e-310),
    (f64::NEG_INFINITY, 1e-40),
    (1e-45, f64::NAN),
];

/// Every evaluation of an accepted patch is finite, normals are unit.
pub fn check_evaluations<F: Float>(
    patch: &Patch<F>,
    extra: &[(f64, f64)],
) -> Result<(), TestCaseError> {
    let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
    let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
    prop_assert!(
        lo.is_finite() && hi.is_finite() && lo.cmple(hi).all(),
        "bounds {lo} {hi}"
    );
    let (s0, s1) = patch.height_range();
    prop_assert!(
        s0.is_fin() && s1.is_fin() && s0 <= s1,
        "height range {s0:?} {s1:?}"
    );
    let nf = patch.face_normal();
    prop_assert!(is_unit::<F>(nf), "face normal {nf:?}");
    for v in patch.vertices() {
        prop_assert!(to_d::<F>(v).is_finite(), "vertex {v:?}");
    }
    for v in patch.normals() {
        prop_assert!(is_unit::<F>(v), "vertex normal {v:?}");
    }
    for &(w1, w2) in BARY.iter().chain(extra) {
        let (a, b) = (F::from_f64(w1), F::from_f64(w2));
        let x = to_d::<F>(patch.point(a, b));
        prop_assert!(x.is_finite(), "point({w1}, {w2}) = {x}");
        let (y, n) = patch.point_normal(a, b);
        prop_assert!(
            to_d::<F>(y).is_finite(),
            "point_normal({w1}, {w2}) point {y:?}"
        );
        prop_assert!(is_unit::<F>(n), "point_normal({w1}, {w2}) normal {n:?}");
        let h = patch.height(a, b);
        prop_assert!(h.is_fin(), "height({w1}, {w2}) = {h:?}");
        let (d1, d2) = patch.derivatives(a, b);
        prop_assert!(
            to_d::<F>(d1).is_finite() && to_d::<F>(d2).is_finite(),
            "derivatives({w1}, {w2}) = {d1:?} {d2:?}"
        );
    }
    for edge in [0usize, 1, 2, 3, 7, usize::MAX] {
        for t in [0.0, 1.0, 0.5, 0.1, 0.9, -1.0, 2.0, f64::NAN, f64::INFINITY] {
            let (c, n) = patch.edge_point_normal(edge, F::from_f64(t));
            prop_assert!(to_d::<F>(c).is_finite(), "edge {edge} t {t}: point {c:?}");
            prop_assert!(is_unit::<F>(n), "edge {edge} t {t}: normal {n:?}");
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Rays

/// A hit is fully finite, inside the requested range (exactly: the kernel clamps it) and the
/// patch's box (up to its bracket and rounding), with unit normal and barycentrics in the
/// triangle.
pub fn check_hit<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
    hit: &Hit<F>,
) -> Result<(), TestCaseError> {
    let t = hit.t.to_f64();
    let te = hit.t_error.to_f64();
    prop_assert!(t.is_finite(), "t = {t}");
    prop_assert!(te.is_finite() && te >= 0.0, "t_error = {te}");
    prop_assert!(
        hit.t >= t_min && hit.t <= t_max,
        "t = {t} outside [{}, {}]",
        t_min.to_f64(),
        t_max.to_f64()
    );
    let point = to_d::<F>(hit.point);
    prop_assert!(point.is_finite(), "point {point}");
    prop_assert!(is_unit::<F>(hit.normal), "normal {:?}", hit.normal);
    let eps = F::EPSILON.to_f64();
    let (w1, w2) = (hit.w1.to_f64(), hit.w2.to_f64());
    prop_assert!(
        (0.0..=1.0).contains(&w1) && (0.0..=1.0).contains(&w2) && w1 + w2 <= 1.0 + 4.0 * eps,
        "barycentrics {w1} {w2}"
    );
    // Inside the patch's box, up to the bracket width and rounding.
    let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
    let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
    let o = to_d::<F>(ray.origin);
    let d = to_d::<F>(ray.dir);
    let pad = d.length() * te
        + 16.0
            * eps
            * (o.abs().max_element()
                + (d * t).abs().max_element()
                + lo.abs().max(hi.abs()).max_element());
    prop_assert!(
        point.cmpge(lo - pad).all() && point.cmple(hi + pad).all(),
        "hit point {point} outside box {lo} {hi} (pad {pad:e})"
    );
    Ok(())
}

/// The work bound: at most `max_height_evals(K, N)` height evaluations (`max_lane_calls(K, N)`
/// lane calls of eight and two estimate steps of four) and one normal evaluation.
pub fn check_stats(s: KernelStats, k: u32, n: u32) -> Result<(), TestCaseError> {
    let bound = smoothtri::max_height_evals(k as usize, n as usize) as u32;
    prop_assert!(
        s.height_evals <= bound,
        "{} height evaluations, bound {bound}",
        s.height_evals,
    );
    prop_assert!(s.normal_evals <= 1, "{} normal evaluations", s.normal_evals);
    Ok(())
}

/// Every kernel variant on one ray: `None` or a valid hit, work bounded.
pub fn check_ray<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
) -> Result<(), TestCaseError> {
    let hits = [
        patch.closest_hit(ray, t_min, t_max, 0),
        patch.closest_hit(ray, t_min, t_max, 1),
        patch.closest_hit(ray, t_min, t_max, 4),
        patch.closest_hit(ray, t_min, t_max, 8),
    ];
    for h in hits.iter().flatten() {
        check_hit(patch, ray, t_min, t_max, h)?;
    }
    for (k, n, (h, s)) in [
        (0, 0, patch.closest_hit_stats::<0>(ray, t_min, t_max, 0)),
        (1, 3, patch.closest_hit_stats::<1>(ray, t_min, t_max, 3)),
        (4, 8, patch.closest_hit_stats::<4>(ray, t_min, t_max, 8)),
        (8, 24, patch.closest_hit_stats::<8>(ray, t_min, t_max, 24)),
    ] {
        check_stats(s, k, n)?;
        if let Some(h) = h {
            check_hit(patch, ray, t_min, t_max, &h)?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// BVH

/// A BVH built over `ps` equals brute force exactly: `closest_hit` returns, bit for bit, the
/// hit of a patch whose brute-force `t` is the smallest; `any_hit` is brute force's hit/miss;
/// no query errs (`closest_with` with the flat triangles included).
pub fn check_bvh<F: Float>(ps: &[Patch<F>], rays: &[RayParam]) -> Result<(), TestCaseError> {
    if ps.is_empty() {
        return Ok(());
    }
    let mut nodes = vec![BvhNode::<F>::default(); Bvh::<F>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(ps, &mut nodes, &mut order);
    prop_assert!(bvh.is_ok(), "build: {:?}", bvh.err());
    let Ok(bvh) = bvh else { return Ok(()) };
    for (i, r) in rays.iter().enumerate() {
        // Aim at one of the patches (round robin).
        let patch = &ps[i % ps.len()];
        let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
        let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
        let target = to_d::<F>(patch.point(F::from_f64(r.aim.0), F::from_f64(r.aim.1)));
        let (o, d, t0, t1) = r.build(lo, hi, to_d::<F>(patch.face_normal()), target);
        let ray = Ray::<F>::new(to_f::<F>(o), to_f::<F>(d));
        let (t0, t1) = (F::from_f64(t0), F::from_f64(t1));
        let got = bvh.closest_hit(&ray, t0, t1, 6);
        let any = bvh.any_hit(&ray, t0, t1, 6);
        if let Some(f) = bvh.closest_with(&ray, t0, t1, |_, p, a, b| {
            smoothtri::flat_hit(&p.vertices(), None, &ray, a, b)
        }) {
            prop_assert!(f.t.is_fin() && f.t >= t0 && f.t <= t1, "flat hit {f:?}");
        }
        // Brute force, each hit tagged with its patch's index as the BVH does.
        let all: Vec<Hit<F>> = ps
            .iter()
            .enumerate()
            .filter_map(|(k, p)| {
                let h = p.closest_hit(&ray, t0, t1, 6)?;
                Some(Hit {
                    patch: k as u32,
                    ..h
                })
            })
            .collect();
        prop_assert_eq!(any, !all.is_empty(), "any_hit vs brute force");
        let best = all
            .iter()
            .map(|h| h.t)
            .reduce(|a, b| if b < a { b } else { a });
        match (got, best) {
            (None, None) => {}
            (Some(g), Some(tb)) => {
                prop_assert!(
                    g.t == tb && all.contains(&g),
                    "closest_hit {:?} vs brute force {:?}",
                    g,
                    all
                );
                check_hit(&ps[g.patch as usize], &ray, t0, t1, &g)?;
            }
            (g, _) => prop_assert!(false, "closest_hit {:?} vs brute force {:?}", g, all),
        }
    }
    Ok(())
}
