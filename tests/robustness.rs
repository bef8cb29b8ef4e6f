//! Robustness properties of the core over hostile input, in `f32` ([`Patch`]) and `f64`
//! ([`DPatch`]): extreme magnitudes (1e-20 … 1e20), NaN, ±inf, zero vectors, collinear and
//! near-collinear vertices, normals near 90° and back-facing, degenerate rays and ray ranges.
//!
//! What is checked (docs/METHOD.md §7, §8):
//! - construction returns a typed error or a patch, never panics;
//! - for every accepted patch, `point`, `point_normal`, `height`, `derivatives`,
//!   `edge_point_normal`, `bounds` and `height_range` are finite (normals unit length) at any
//!   barycentrics, including outside the triangle, NaN and ±inf;
//! - every `intersect::<N>` / `intersect_stats::<K, N>` result is `None` or fully finite
//!   (`t` inside `[t_min, t_max]`, `t_error ≥ 0`, point, unit normal, barycentrics in `[0, 1]`),
//!   with at most `K + 2 + N` height evaluations and at most one normal evaluation;
//! - BVH queries on storage made by `Bvh::build` never return an error, agree exactly with
//!   brute force on hit/miss (`closest_hit`, `any_hit`), and report a hit farther than the
//!   brute-force closest one only when the kernel's dependence on `t_max` explains it;
//! - inside the method's domain (well-shaped triangles, normals ≤ 50°) the surface stays inside
//!   `height_range()` and `bounds()` on a dense grid.
//!
//! # Case count
//! The default is quick (the whole file runs in a few seconds in debug mode, as CI runs
//! `cargo test --workspace`). Set `SMOOTHTRI_CASES=<n>` to run `n` cases per property, e.g. a
//! run of more than 10^6 cases in total (6 properties):
//!
//! ```text
//! SMOOTHTRI_CASES=200000 cargo test --release --test robustness
//! ```
//!
//! The quick run uses a fixed proptest seed, a long run a random one. Known core bugs are
//! skipped by the properties where they can be recognised from outside (`known_bary_bug`,
//! `patch_unit_tol`, the BVH `t_max` explanation), so that long runs look for new failures;
//! `in_domain_surface_stays_in_shell` is not filtered and fails about once in 4·10^5 cases
//! (`bug_in_domain_surface_leaves_shell`).
//!
//! Reproducers of core bugs found by these properties and by the fuzzer are the
//! `#[ignore = "BUG: …"]` tests at the end of this file (run them with
//! `cargo test --test robustness -- --ignored`; they fail until the bugs are fixed).

mod common;
use common::*;
use glam::{DVec3, Vec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use smoothtri::vec::V3;
use smoothtri::{Bvh, BvhNode, DPatch, Float, Hit, KernelStats, Patch, PatchError, Ray};

// ---------------------------------------------------------------------------------------------
// Configuration

/// Default cases per property for CI (debug mode).
const QUICK_CASES: u32 = 256;

/// The quick default run uses a fixed seed (CI is deterministic); a run with
/// `SMOOTHTRI_CASES` set uses a random seed (printed by proptest on failure).
fn config(default: u32) -> Config {
    let long = std::env::var_os("SMOOTHTRI_CASES").is_some();
    Config {
        cases: env_cases(default),
        // Reproducers are written by hand as `#[ignore]` tests: no regression files in the tree.
        failure_persistence: None,
        rng_seed: if long {
            RngSeed::Random
        } else {
            RngSeed::Fixed(0x5EED_2026)
        },
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------------------------
// Conversions between f64 test data and the precision under test

fn to_f<F: Float>(v: DVec3) -> F::Vec3 {
    F::to_glam(V3::new(
        F::from_f64(v.x),
        F::from_f64(v.y),
        F::from_f64(v.z),
    ))
}

fn to_d<F: Float>(v: F::Vec3) -> DVec3 {
    let w = F::from_glam(v);
    DVec3::new(w.x.to_f64(), w.y.to_f64(), w.z.to_f64())
}

/// Relative tolerance for unit vectors in precision `F`.
fn unit_tol<F: Float>() -> f64 {
    1e3 * F::EPSILON.to_f64()
}

/// Unit length within `tol`.
fn unit_within<F: Float>(v: F::Vec3, tol: f64) -> bool {
    let d = to_d::<F>(v);
    d.is_finite() && (d.length() - 1.0).abs() <= tol
}

/// How far the patch's stored frame is from orthonormal, seen from outside: the face normal's
/// length error and its cosines with the two edges from `P0`. Known bug (reproducers
/// `bug_tiny_f32_triangle_frame_not_orthonormal`, `bug_skinny_triangle_frame_not_orthonormal`):
/// the face normal is `e × f / |e × f|` without re-orthogonalisation, so it is off by
/// `ε·|e|·|f| / |e × f|` for skinny triangles, and wrong altogether in `f32` when `|e × f|²`
/// is subnormal (triangles of size ≈ 1e-19…3e-10). Unit-length checks of that patch's
/// normals are relaxed to a multiple of this error; finiteness checks are not.
fn frame_error<F: Float>(patch: &Patch<F>) -> f64 {
    let nf = to_d::<F>(patch.face_normal());
    let [v0, v1, v2] = patch.vertices().map(to_d::<F>);
    let (e, f) = ((v1 - v0).normalize_or_zero(), (v2 - v0).normalize_or_zero());
    (nf.length() - 1.0).abs() + nf.dot(e).abs() + nf.dot(f).abs()
}

/// Tolerance of unit-length checks for this patch.
fn patch_unit_tol<F: Float>(patch: &Patch<F>) -> f64 {
    let e = frame_error(patch);
    let tol = unit_tol::<F>();
    if tiny_cross(patch) {
        // `|e × f|²` subnormal or nearly so in this precision: the frame is wrong (reported),
        // only finiteness is checked.
        return f64::INFINITY;
    }
    if e.is_finite() { tol.max(8.0 * e) } else { tol }
}

/// `|e × f|²`, computed in the patch's precision from its vertices, is below `2^20` times the
/// smallest normal number (where the f32 frame bug shows).
fn tiny_cross<F: Float>(patch: &Patch<F>) -> bool {
    let [v0, v1, v2] = patch.vertices().map(F::from_glam);
    let c = (v1 - v0).cross(v2 - v0);
    c.length2() < F::MIN_POSITIVE * F::from_f64(1048576.0)
}

// ---------------------------------------------------------------------------------------------
// Strategies

/// Special values: NaN, infinities, signed zeros, the extremes of both precisions, subnormals.
fn special() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MAX),
        Just(f64::MIN),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(f32::MAX as f64),
        Just(-(f32::MAX as f64)),
        Just(f32::MIN_POSITIVE as f64),
        Just(1e-45),
        Just(1e-20),
        Just(1e20),
        Just(-1e20),
    ]
}

/// `±10^e` with `e` in `[-20, 20]`.
fn magnitude() -> impl Strategy<Value = f64> {
    (any::<bool>(), -20.0..20.0f64)
        .prop_map(|(neg, e)| if neg { -1.0 } else { 1.0 } * 10f64.powf(e))
}

/// Any coordinate: ordinary, extreme magnitude, or special.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![4 => -10.0..10.0f64, 3 => magnitude(), 1 => special()]
}

fn wild_vec() -> impl Strategy<Value = DVec3> {
    [wild(), wild(), wild()].prop_map(DVec3::from_array)
}

/// A unit vector from two angles.
fn unit_from(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Parameters of a structured patch input: a triangle of a given shape, scale and offset, and
/// normals at given angles from its face normal.
#[derive(Clone, Debug)]
struct Structured {
    /// Apex of the 2D triangle `(0,0) (1,0) apex` (negative y: clockwise).
    apex: (f64, f64),
    /// Face normal angles.
    face: (f64, f64),
    /// Rotation of the triangle in its plane.
    spin: f64,
    /// log10 of the triangle's size.
    scale: f64,
    /// Offset direction and log10 of its length (`None`: at the origin).
    offset: Option<(DVec3, f64)>,
    /// Per vertex: angle from the face normal (degrees), azimuth, log10 of the length; `None`
    /// for a zero vector.
    normals: [Option<(f64, f64, f64)>; 3],
    /// One of the 18 input coordinates replaced by a special value.
    inject: Option<(usize, f64)>,
}

/// Apex heights: well-shaped, skinny (1:5…1:20), very skinny, near-collinear, collinear,
/// clockwise.
fn apex() -> impl Strategy<Value = (f64, f64)> {
    let x = -1.5..2.5f64;
    prop_oneof![
        12 => (x.clone(), 0.3..1.2f64),
        6 => (x.clone(), (0.7..1.3f64).prop_map(|e| 10f64.powf(-e))),
        2 => (x.clone(), (1.3..8.0f64).prop_map(|e| 10f64.powf(-e))),
        1 => (x.clone(), (8.0..20.0f64).prop_map(|e| 10f64.powf(-e))),
        1 => (x.clone(), Just(0.0)),
        1 => (x, -1.2..-0.001f64),
    ]
}

/// Angle of a normal from the face normal, degrees: ordinary, steep, near 90°, back-facing.
fn normal_angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => 0.0..45.0f64,
        4 => 45.0..80.0f64,
        2 => 80.0..89.9f64,
        1 => 89.9..90.1f64,
        1 => 90.0..180.0f64,
        1 => Just(0.0),
    ]
}

fn normal_param() -> impl Strategy<Value = Option<(f64, f64, f64)>> {
    let log_len = prop_oneof![4 => -1.0..1.0f64, 1 => -20.0..20.0f64];
    prop_oneof![
        40 => (normal_angle(), 0.0..std::f64::consts::TAU, log_len).prop_map(Some),
        1 => Just(None),
    ]
}

fn structured() -> impl Strategy<Value = Structured> {
    let scale = prop_oneof![4 => -2.0..2.0f64, 2 => -20.0..20.0f64];
    let offset = prop_oneof![
        2 => Just(None),
        3 => ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], -2.0..2.0f64)
            .prop_map(|(d, e)| Some((DVec3::from_array(d), e))),
        2 => ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], -20.0..20.0f64)
            .prop_map(|(d, e)| Some((DVec3::from_array(d), e))),
    ];
    let inject = prop_oneof![9 => Just(None), 1 => (0..18usize, special()).prop_map(Some)];
    (
        apex(),
        (0.0..std::f64::consts::PI, 0.0..std::f64::consts::TAU),
        0.0..std::f64::consts::TAU,
        scale,
        offset,
        [normal_param(), normal_param(), normal_param()],
        inject,
    )
        .prop_map(
            |(apex, face, spin, scale, offset, normals, inject)| Structured {
                apex,
                face,
                spin,
                scale,
                offset,
                normals,
                inject,
            },
        )
}

impl Structured {
    fn build(&self) -> ([DVec3; 3], [DVec3; 3]) {
        let nf = unit_from(self.face.0, self.face.1);
        let u0 = nf.any_orthonormal_vector();
        let v0 = nf.cross(u0);
        let (c, s) = (self.spin.cos(), self.spin.sin());
        let (u, v) = (u0 * c + v0 * s, v0 * c - u0 * s);
        let size = 10f64.powf(self.scale);
        let off = self.offset.map_or(DVec3::ZERO, |(d, e)| d * 10f64.powf(e));
        let q = |x: f64, y: f64| off + (u * x + v * y) * size;
        let p = [q(0.0, 0.0), q(1.0, 0.0), q(self.apex.0, self.apex.1)];
        let mut n = [DVec3::ZERO; 3];
        for (nk, par) in n.iter_mut().zip(self.normals) {
            if let Some((deg, az, len)) = par {
                let th = deg.to_radians();
                *nk = (nf * th.cos() + (u * az.cos() + v * az.sin()) * th.sin()) * 10f64.powf(len);
            }
        }
        let mut flat = [p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| v.to_array());
        if let Some((k, x)) = self.inject
            && let Some(c) = flat.get_mut(k / 3).and_then(|a| a.get_mut(k % 3))
        {
            *c = x;
        }
        let v = flat.map(DVec3::from_array);
        ([v[0], v[1], v[2]], [v[3], v[4], v[5]])
    }
}

/// A patch input: mostly structured (many accepted), sometimes fully wild coordinates.
#[derive(Clone, Debug)]
enum Input {
    Structured(Structured),
    Wild([DVec3; 3], [DVec3; 3]),
}

impl Input {
    fn build(&self) -> ([DVec3; 3], [DVec3; 3]) {
        match self {
            Input::Structured(s) => s.build(),
            Input::Wild(p, n) => (*p, *n),
        }
    }
}

fn input() -> impl Strategy<Value = Input> {
    prop_oneof![
        5 => structured().prop_map(Input::Structured),
        1 => ([wild_vec(), wild_vec(), wild_vec()], [wild_vec(), wild_vec(), wild_vec()])
            .prop_map(|(p, n)| Input::Wild(p, n)),
    ]
}

/// A ray relative to the patch's box: origin on a sphere of radius `10^dist × diagonal` around
/// the box centre, aimed at a surface point lifted by `lift × diagonal` along the face normal;
/// direction length `10^len`; a ray-range kind; optionally a special value injected.
#[derive(Clone, Debug)]
struct RayParam {
    from: (f64, f64),
    dist: f64,
    aim: (f64, f64),
    lift: f64,
    len: f64,
    range: u8,
    inject: Option<(usize, f64)>,
}

fn ray_param() -> impl Strategy<Value = RayParam> {
    (
        (0.0..std::f64::consts::PI, 0.0..std::f64::consts::TAU),
        prop_oneof![3 => -1.0..1.5f64, 1 => -4.0..4.0f64],
        (-0.2..1.2f64, -0.2..1.2f64),
        prop_oneof![3 => Just(0.0), 3 => -0.05..0.05f64, 1 => -3.0..3.0f64],
        prop_oneof![3 => -1.0..1.0f64, 1 => -20.0..20.0f64],
        0..16u8,
        prop_oneof![8 => Just(None), 1 => (0..6usize, special()).prop_map(Some)],
    )
        .prop_map(|(from, dist, aim, lift, len, range, inject)| RayParam {
            from,
            dist,
            aim,
            lift,
            len,
            range,
            inject,
        })
}

/// Ray ranges: ordinary, infinite both ways, empty, reversed, NaN, huge, a thin slice.
fn ray_range(kind: u8, scale: f64) -> (f64, f64) {
    match kind {
        0 => (f64::MIN_POSITIVE, f64::MAX),
        3 => (f64::NEG_INFINITY, f64::INFINITY),
        4 => (0.5, 0.5),
        5 => (1.0, 0.0),
        6 => (f64::NAN, 1.0),
        7 => (0.0, f64::NAN),
        8 => (-1e30, 1e30),
        9 => (0.999 * scale, 1.001 * scale),
        _ => (0.0, f64::INFINITY),
    }
}

impl RayParam {
    /// World ray (f64) and range for a patch with box `(lo, hi)`, face normal `nf` and the
    /// aimed surface point `target`.
    fn build(&self, lo: DVec3, hi: DVec3, nf: DVec3, target: DVec3) -> (DVec3, DVec3, f64, f64) {
        let centre = (lo + hi) * 0.5;
        let diag = (hi - lo).length();
        let o = centre + unit_from(self.from.0, self.from.1) * diag * 10f64.powf(self.dist);
        let aim = target + nf * diag * self.lift;
        let d = (aim - o) * 10f64.powf(self.len);
        let (t0, t1) = ray_range(self.range, 10f64.powf(-self.len));
        let mut flat = [o.x, o.y, o.z, d.x, d.y, d.z];
        if let Some((k, x)) = self.inject
            && let Some(c) = flat.get_mut(k)
        {
            *c = x;
        }
        (
            DVec3::new(flat[0], flat[1], flat[2]),
            DVec3::new(flat[3], flat[4], flat[5]),
            t0,
            t1,
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Checks

/// Barycentrics at which every accepted patch is evaluated (inside, on the boundary, outside,
/// non-finite).
const BARY: [(f64, f64); 16] = [
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
];

/// Every evaluation of an accepted patch is finite, normals are unit.
fn check_evaluations<F: Float>(
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
    let utol = patch_unit_tol(patch);
    prop_assert!(unit_within::<F>(patch.face_normal(), utol));
    for v in patch.vertices() {
        prop_assert!(to_d::<F>(v).is_finite());
    }
    for v in patch.normals() {
        prop_assert!(unit_within::<F>(v, utol));
    }
    for &(w1, w2) in BARY.iter().chain(extra) {
        let (a, b) = (F::from_f64(w1), F::from_f64(w2));
        if known_bary_bug(a, b) {
            // Reported: `bug_subnormal_barycentric_sum_gives_nan`. Still must not panic.
            let _ = (
                patch.point(a, b),
                patch.point_normal(a, b),
                patch.height(a, b),
            );
            let _ = patch.derivatives(a, b);
            continue;
        }
        let x = to_d::<F>(patch.point(a, b));
        prop_assert!(x.is_finite(), "point({w1}, {w2}) = {x}");
        let (y, n) = patch.point_normal(a, b);
        prop_assert!(
            to_d::<F>(y).is_finite(),
            "point_normal({w1}, {w2}) point {:?}",
            y
        );
        prop_assert!(
            unit_within::<F>(n, utol),
            "point_normal({w1}, {w2}) normal {:?}",
            n
        );
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
            prop_assert!(unit_within::<F>(n, utol), "edge {edge} t {t}: normal {n:?}");
        }
    }
    Ok(())
}

/// Known bug (reproducer `bug_subnormal_barycentric_sum_gives_nan` below): barycentrics whose
/// cleaned sum (negative, NaN and infinite components counted as zero) is subnormal make the
/// projection onto the triangle divide by it, overflow and return NaN. Such inputs are skipped
/// by the finiteness properties so that a long run can find other failures.
fn known_bary_bug<F: Float>(w1: F, w2: F) -> bool {
    let clean = |x: F| {
        if x.is_fin() && x > F::ZERO {
            x
        } else {
            F::ZERO
        }
    };
    let s = clean(F::ONE - w1 - w2) + clean(w1) + clean(w2);
    s > F::ZERO && !(F::ONE / s).is_fin()
}

/// A hit is fully finite, inside the requested range and the patch's box, with unit normal.
fn check_hit<F: Float>(
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
    let point = to_d::<F>(hit.point);
    prop_assert!(point.is_finite(), "point {point}");
    prop_assert!(
        unit_within::<F>(hit.normal, patch_unit_tol(patch)),
        "normal {:?}",
        hit.normal
    );
    let (w1, w2) = (hit.w1.to_f64(), hit.w2.to_f64());
    prop_assert!(
        (0.0..=1.0).contains(&w1) && (0.0..=1.0).contains(&w2) && w1 + w2 <= 1.0 + 1e-6,
        "barycentrics {w1} {w2}"
    );
    // Inside [t_min, t_max] up to the rounding of re-basing the ray at the box's middle.
    let eps = F::EPSILON.to_f64();
    let (a, b) = (t_min.to_f64(), t_max.to_f64());
    // `t` is computed re-based at the middle `t0` of the ray's interval inside the box, so it
    // can fall outside the range by an ulp of `t0` (reported as a minor finding, reproducer
    // `bug_hit_before_t_min_by_rounding`): the slack is a few ulps of the ray's reach to the
    // far side of the box.
    let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
    let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
    let o = to_d::<F>(ray.origin);
    let d = to_d::<F>(ray.dir);
    let reach = ((o - (lo + hi) * 0.5).length() + (hi - lo).length()) / d.length();
    let ends = [a, b]
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let slack = 8.0 * eps * (t.abs() + te + reach + ends);
    // A degenerate reach (direction underflowing, origin overflowing) bounds nothing.
    let slack = if slack.is_nan() { f64::INFINITY } else { slack };
    prop_assert!(
        t >= a - slack && t <= b + slack,
        "t = {t} outside [{a}, {b}] (slack {slack:e})"
    );
    // Inside the patch's box, up to the bracket width and rounding.
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

fn check_stats(s: KernelStats, k: u32, n: u32) -> Result<(), TestCaseError> {
    prop_assert!(
        s.height_evals <= k + 2 + n,
        "{} height evaluations, bound {}",
        s.height_evals,
        k + 2 + n
    );
    prop_assert!(s.normal_evals <= 1, "{} normal evaluations", s.normal_evals);
    Ok(())
}

/// Every kernel variant on one ray: `None` or a valid hit, work bounded.
fn check_ray<F: Float>(
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
) -> Result<(), TestCaseError> {
    let hits = [
        patch.intersect::<0>(ray, t_min, t_max),
        patch.intersect::<1>(ray, t_min, t_max),
        patch.intersect::<4>(ray, t_min, t_max),
        patch.intersect::<8>(ray, t_min, t_max),
    ];
    for h in hits.iter().flatten() {
        check_hit(patch, ray, t_min, t_max, h)?;
    }
    let (h, s) = patch.intersect_stats::<0, 0>(ray, t_min, t_max);
    check_stats(s, 0, 0)?;
    if let Some(h) = h {
        check_hit(patch, ray, t_min, t_max, &h)?;
    }
    let (h, s) = patch.intersect_stats::<1, 3>(ray, t_min, t_max);
    check_stats(s, 1, 3)?;
    if let Some(h) = h {
        check_hit(patch, ray, t_min, t_max, &h)?;
    }
    let (h, s) = patch.intersect_stats::<4, 8>(ray, t_min, t_max);
    check_stats(s, 4, 8)?;
    if let Some(h) = h {
        check_hit(patch, ray, t_min, t_max, &h)?;
    }
    let (h, s) = patch.intersect_stats::<8, 24>(ray, t_min, t_max);
    check_stats(s, 8, 24)?;
    if let Some(h) = h {
        check_hit(patch, ray, t_min, t_max, &h)?;
    }
    Ok(())
}

/// Builds the patch in precision `F`; when accepted, checks evaluations and rays.
fn check_input<F: Float>(
    p: [DVec3; 3],
    n: [DVec3; 3],
    extra: &[(f64, f64)],
    rays: &[RayParam],
) -> Result<Option<Patch<F>>, TestCaseError> {
    let patch = match Patch::<F>::new(p.map(to_f::<F>), n.map(to_f::<F>)) {
        Ok(patch) => patch,
        Err(e) => {
            // Typed error with a message; nothing else to check.
            prop_assert!(!e.to_string().is_empty());
            return Ok(None);
        }
    };
    check_evaluations(&patch, extra)?;
    let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
    let (lo, hi) = (to_d::<F>(lo), to_d::<F>(hi));
    let nf = to_d::<F>(patch.face_normal());
    for r in rays {
        let target = to_d::<F>(patch.point(F::from_f64(r.aim.0), F::from_f64(r.aim.1)));
        let (o, d, t0, t1) = r.build(lo, hi, nf, target);
        let ray = Ray::<F>::new(to_f::<F>(o), to_f::<F>(d));
        check_ray(&patch, &ray, F::from_f64(t0), F::from_f64(t1))?;
    }
    Ok(Some(patch))
}

// ---------------------------------------------------------------------------------------------
// Properties

proptest! {
    #![proptest_config(config(QUICK_CASES))]

    /// Construction never panics and, when it accepts, every evaluation and ray query is finite
    /// (f32 and f64 from the same input).
    #[test]
    fn accepted_patches_evaluate_and_intersect_finitely(
        inp in input(),
        extra in prop::collection::vec((wild(), wild()), 0..3),
        rays in prop::collection::vec(ray_param(), 1..4),
    ) {
        let (p, n) = inp.build();
        check_input::<f64>(p, n, &extra, &rays)?;
        check_input::<f32>(p, n, &extra, &rays)?;
    }

    /// Fully wild rays (any origin, direction and range, including non-finite) against accepted
    /// patches.
    #[test]
    fn wild_rays_are_finite_or_none(
        s in structured(),
        rays in prop::collection::vec((wild_vec(), wild_vec(), wild(), wild()), 1..6),
    ) {
        let (p, n) = s.build();
        if let Ok(patch) = DPatch::new(p, n) {
            for &(o, d, a, b) in &rays {
                check_ray(&patch, &Ray::new(o, d), a, b)?;
            }
        }
        if let Ok(patch) = Patch::<f32>::new(p.map(|v| v.as_vec3()), n.map(|v| v.as_vec3())) {
            for &(o, d, a, b) in &rays {
                check_ray(&patch, &Ray::new(o.as_vec3(), d.as_vec3()), a as f32, b as f32)?;
            }
        }
    }

    /// Construction errors: non-finite input is always `NonFinite`; a zero normal on a valid
    /// triangle is `ZeroNormal`; a collinear triangle is never accepted.
    #[test]
    fn construction_errors_are_typed(s in structured(), k in 0..18usize, bad in special()) {
        let (p, n) = s.build();
        let mut flat = [p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| v.to_array());
        flat[k / 3][k % 3] = bad;
        let v = flat.map(DVec3::from_array);
        let (p2, n2) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let r64 = DPatch::new(p2, n2);
        let r32 = Patch::<f32>::new(p2.map(|x| x.as_vec3()), n2.map(|x| x.as_vec3()));
        if !bad.is_finite() {
            prop_assert_eq!(r64.err(), Some(PatchError::NonFinite));
            prop_assert_eq!(r32.err(), Some(PatchError::NonFinite));
        }
        // Collinear (the apex on the base line, no injection) is never accepted, unless an
        // offset far larger than the triangle quantises the vertices off the line.
        let near = s.offset.is_none_or(|(_, e)| e <= s.scale + 3.0);
        if s.apex.1 == 0.0 && s.inject.is_none() && near {
            prop_assert!(DPatch::new(p, n).is_err());
        }
        // A zero normal is reported as such when nothing else is wrong with that vertex.
        for (k, par) in s.normals.iter().enumerate() {
            if par.is_none() && s.inject.is_none() {
                let e = DPatch::new(p, n).err();
                prop_assert!(
                    e.is_some()
                        && !(e == Some(PatchError::BackFacingNormal { vertex: k as u8 })),
                    "{e:?}"
                );
            }
        }
    }

    /// In the method's domain (well-shaped triangles, normals ≤ 50°, any scale from 1e-6 to
    /// 1e6, offsets up to 1e3 sizes) the surface stays inside `height_range()` and `bounds()`.
    #[test]
    fn in_domain_surface_stays_in_shell(seed in any::<u64>(), deg in 0.0..50.0f64, scale in -6.0..6.0f64) {
        let mut rng = Rng(seed);
        let size = 10f64.powf(scale);
        let off = rng.unit() * size * rng.range(0.0, 1e3);
        let (p, nf) = well_shaped(&mut rng, size, off);
        let n = [tilted(&mut rng, nf, deg), tilted(&mut rng, nf, deg), tilted(&mut rng, nf, deg)];
        let patch = DPatch::new(p, n);
        prop_assert!(patch.is_ok(), "in-domain patch rejected: {patch:?}");
        if let Ok(patch) = patch {
            let (lo, hi) = patch.height_range();
            let (bmin, bmax) = (patch.bounds().min(), patch.bounds().max());
            for (w1, w2) in bary_grid(20) {
                let h = patch.height(w1, w2);
                prop_assert!(h >= lo && h <= hi, "height {h} outside [{lo}, {hi}] at ({w1}, {w2})");
                let x = patch.point(w1, w2);
                prop_assert!(x.cmpge(bmin).all() && x.cmple(bmax).all(), "{x} outside {bmin} {bmax}");
            }
        }
    }

    /// BVH over random patches (f64): queries never error, hit/miss agrees with brute force,
    /// the closest hit is never farther than brute force's, `any_hit` equals brute force.
    #[test]
    fn bvh_agrees_with_brute_force_f64(
        inputs in prop::collection::vec(structured(), 1..24),
        spread in -20.0..20.0f64,
        rays in prop::collection::vec(ray_param(), 1..6),
    ) {
        let ps: Vec<DPatch> = inputs
            .iter()
            .enumerate()
            .filter_map(|(i, s)| {
                let (p, n) = s.build();
                // Spread the patches apart by a scene scale.
                let shift = DVec3::new(i as f64, (i * 7 % 5) as f64, (i * 3 % 4) as f64) * 10f64.powf(spread);
                DPatch::new(p.map(|x| x + shift), n).ok()
            })
            .collect();
        check_bvh(&ps, &rays)?;
    }

    /// The same in f32.
    #[test]
    fn bvh_agrees_with_brute_force_f32(
        inputs in prop::collection::vec(structured(), 1..24),
        spread in -20.0..20.0f64,
        rays in prop::collection::vec(ray_param(), 1..6),
    ) {
        let ps: Vec<Patch> = inputs
            .iter()
            .enumerate()
            .filter_map(|(i, s)| {
                let (p, n) = s.build();
                let shift = DVec3::new(i as f64, (i * 7 % 5) as f64, (i * 3 % 4) as f64) * 10f64.powf(spread);
                Patch::new(p.map(|x| (x + shift).as_vec3()), n.map(|x| x.as_vec3())).ok()
            })
            .collect();
        check_bvh(&ps, &rays)?;
    }
}

fn check_bvh<F: Float>(ps: &[Patch<F>], rays: &[RayParam]) -> Result<(), TestCaseError> {
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
        let got = bvh.closest_hit::<6>(&ray, t0, t1);
        prop_assert!(got.is_ok(), "closest_hit: {:?}", got.err());
        let any = bvh.any_hit::<6>(&ray, t0, t1);
        prop_assert!(any.is_ok(), "any_hit: {:?}", any.err());
        let flat = bvh.closest_with(&ray, t0, t1, |p, a, b| {
            smoothtri::flat_hit(&p.vertices(), None, &ray, a, b)
        });
        prop_assert!(flat.is_ok(), "closest_with: {:?}", flat.err());
        let brute: Vec<(usize, Hit<F>)> = ps
            .iter()
            .enumerate()
            .filter_map(|(k, p)| p.intersect::<6>(&ray, t0, t1).map(|h| (k, h)))
            .collect();
        let (Ok(got), Ok(any)) = (got, any) else {
            return Ok(());
        };
        prop_assert_eq!(any, !brute.is_empty(), "any_hit vs brute force");
        prop_assert_eq!(
            got.is_some(),
            !brute.is_empty(),
            "closest_hit hit/miss vs brute force"
        );
        if let Some(g) = got {
            prop_assert!((g.patch as usize) < ps.len());
            let gp = &ps[g.patch as usize];
            check_hit(gp, &ray, t0, t1, &g)?;
            let best = brute
                .iter()
                .min_by(|a, b| a.1.t.to_f64().total_cmp(&b.1.t.to_f64()));
            if let Some((k, b)) = best {
                let (tg, tb) = (g.t.to_f64(), b.t.to_f64());
                let slack =
                    g.t_error.to_f64() + b.t_error.to_f64() + 8.0 * F::EPSILON.to_f64() * tb.abs();
                if tg > tb + slack {
                    // The BVH tests patch `k` with `t_max` lowered to the best hit found so far,
                    // and the kernel's answer depends on `t_max` (the shell interval is sampled
                    // differently; a grazing double crossing can be skipped): finding,
                    // reproducer `bug_bvh_misses_closer_hit`. Accept exactly that explanation:
                    // some `t_max` the BVH could have used (the user's, or a hit of any patch
                    // under such a `t_max`, two levels deep) that is ≥ the BVH's answer makes
                    // patch `k` miss or answer no closer than the BVH.
                    let mut cands = vec![t1];
                    for _ in 0..2 {
                        let more: Vec<F> = ps
                            .iter()
                            .flat_map(|p| {
                                cands
                                    .iter()
                                    .filter_map(|&tm| p.intersect::<6>(&ray, t0, tm))
                            })
                            .map(|h| h.t)
                            .collect();
                        cands.extend(more);
                    }
                    let explained =
                        cands
                            .iter()
                            .filter(|tm| tm.to_f64() >= tg - slack)
                            .any(|&tm| {
                                ps[*k]
                                    .intersect::<6>(&ray, t0, tm)
                                    .is_none_or(|h| h.t.to_f64() >= tg - slack)
                            });
                    prop_assert!(
                        explained,
                        "bvh t {tg} (patch {}) > brute force t {tb} (patch {k}), not explained by t_max dependence",
                        g.patch
                    );
                }
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Plain tests of specific extremes

#[test]
fn tiny_and_huge_patches() {
    // The octant of the unit sphere at scales 1e-20 … 1e20 (f64) and in the f32 range.
    let base = [DVec3::X, DVec3::Y, DVec3::Z];
    for e in -20..=20 {
        let s = 10f64.powi(e);
        let p = base.map(|v| v * s);
        let patch = DPatch::new(p, base).expect("f64 octant");
        for (w1, w2) in bary_grid(4) {
            let x = patch.point(w1, w2);
            assert!((x.length() / s - 1.0).abs() < 1e-12, "scale {s:e}: {x}");
        }
        let ray = smoothtri::DRay::new(DVec3::splat(2.0 * s), -DVec3::ONE);
        let h = patch
            .intersect::<8>(&ray, 0.0, f64::INFINITY)
            .expect("f64 hit");
        // Within the certified bound (|dir| = √3) plus rounding.
        let bound = h.t_error * 3f64.sqrt() / s + 1e-12;
        assert!(
            (h.point.length() / s - 1.0).abs() <= bound,
            "scale {s:e}: {} t_err {}",
            h.point.length() / s - 1.0,
            h.t_error
        );
        let p32 = p.map(|v| v.as_vec3());
        match Patch::<f32>::new(p32, base.map(|v| v.as_vec3())) {
            Ok(patch) => {
                let ray = Ray::new(Vec3::splat(2.0 * s as f32), -Vec3::ONE);
                if let Some(h) = patch.intersect::<8>(&ray, 0.0, f32::INFINITY) {
                    assert!(h.point.is_finite() && h.t.is_finite());
                }
            }
            Err(e) => assert!(
                matches!(e, PatchError::OutOfRange | PatchError::DegenerateTriangle),
                "f32 scale {s:e}: {e:?}"
            ),
        }
    }
}

/// Coverage of the generators (not a check): how many inputs are accepted, by error variant,
/// and how many rays hit. `cargo test --release --test robustness coverage -- --ignored
/// --nocapture`.
#[test]
#[ignore = "statistics of the generators, not a check"]
fn generator_coverage() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;
    let mut runner = TestRunner::deterministic();
    let strat = (input(), prop::collection::vec(ray_param(), 3..4));
    let total = env_cases(20_000);
    let mut outcome: [BTreeMap<String, u32>; 2] = [BTreeMap::new(), BTreeMap::new()];
    let (mut rays, mut hits) = ([0u32; 2], [0u32; 2]);
    for _ in 0..total {
        let Ok(tree) = strat.new_tree(&mut runner) else {
            continue;
        };
        let (inp, rps) = tree.current();
        let (p, n) = inp.build();
        let kind = match inp {
            Input::Structured(_) => "structured",
            Input::Wild(..) => "wild",
        };
        let r64 = DPatch::new(p, n);
        let r32 = Patch::<f32>::new(p.map(|v| v.as_vec3()), n.map(|v| v.as_vec3()));
        let key = |e: Option<PatchError>| match e {
            None => format!("{kind}: accepted"),
            Some(e) => format!("{kind}: {e:?}"),
        };
        *outcome[0].entry(key(r64.err())).or_default() += 1;
        *outcome[1].entry(key(r32.err())).or_default() += 1;
        if let Ok(patch) = r64 {
            let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
            for r in &rps {
                let target = patch.point(r.aim.0, r.aim.1);
                let (o, d, a, b) = r.build(lo, hi, patch.face_normal(), target);
                rays[0] += 1;
                hits[0] += patch.intersect::<8>(&Ray::new(o, d), a, b).is_some() as u32;
            }
        }
        if let Ok(patch) = r32 {
            let (lo, hi) = (patch.bounds().min(), patch.bounds().max());
            for r in &rps {
                let target = patch.point(r.aim.0 as f32, r.aim.1 as f32).as_dvec3();
                let (o, d, a, b) = r.build(
                    lo.as_dvec3(),
                    hi.as_dvec3(),
                    patch.face_normal().as_dvec3(),
                    target,
                );
                rays[1] += 1;
                let ray = Ray::new(o.as_vec3(), d.as_vec3());
                hits[1] += patch.intersect::<8>(&ray, a as f32, b as f32).is_some() as u32;
            }
        }
    }
    for (name, o) in ["f64", "f32"].iter().zip(&outcome) {
        eprintln!("{name}: {total} inputs");
        for (k, v) in o {
            eprintln!(
                "  {k:<40} {v:>7} ({:.1}%)",
                100.0 * *v as f64 / total as f64
            );
        }
    }
    eprintln!(
        "rays: f64 {} hits of {}, f32 {} of {}",
        hits[0], rays[0], hits[1], rays[1]
    );
}

// ---------------------------------------------------------------------------------------------
// Reproducers of core bugs (ignored until fixed; run with `-- --ignored`)

/// `Patch::point` & co. project barycentrics onto the triangle by dividing by the sum of their
/// cleaned values (`surface::project_bary`). When only one component survives the cleaning and
/// it is subnormal, `1 / sum` overflows to infinity and `0 · inf` gives NaN: the documented
/// "finite for every accepted patch" fails. Any accepted patch, both precisions.
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_subnormal_barycentric_sum_gives_nan() {
    let octant = [DVec3::X, DVec3::Y, DVec3::Z];
    let p = DPatch::new(octant, octant).unwrap();
    for (w1, w2) in [
        (f64::NAN, 1e-310),
        (f64::NEG_INFINITY, 1e-310),
        (1e-310, f64::NAN),
    ] {
        let x = p.point(w1, w2);
        let (y, n) = p.point_normal(w1, w2);
        let (d1, d2) = p.derivatives(w1, w2);
        assert!(
            x.is_finite() && y.is_finite() && n.is_finite() && d1.is_finite() && d2.is_finite(),
            "f64 ({w1}, {w2}): point {x}, point_normal {y} {n}, derivatives {d1} {d2}"
        );
        assert!(p.height(w1, w2).is_finite(), "f64 ({w1}, {w2}): height");
    }
    let q: Patch = Patch::new(octant.map(|v| v.as_vec3()), octant.map(|v| v.as_vec3())).unwrap();
    let x = q.point(f32::NAN, 1e-40);
    assert!(x.is_finite(), "f32 (NaN, 1e-40): point {x}");
}

/// The stored frame of an `f32` patch is built from `e × f / |e × f|` where `|e × f|²` is
/// computed in `f32`: for triangles of size ≈ 1e-19…3e-10 it is subnormal, the length loses
/// its digits, and the "unit" face normal and frame are off by up to several percent (and the
/// vertices are not reproduced). Such triangles are accepted (their area is not below the
/// relative degeneracy threshold). Expected: an orthonormal frame (rescale before the cross
/// product) or `OutOfRange`.
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_tiny_f32_triangle_frame_not_orthonormal() {
    let p = [
        Vec3::ZERO,
        Vec3::new(3e-11, 0.0, 0.0),
        Vec3::new(0.0, 9e-12, 0.0),
    ];
    let Ok(patch) = Patch::<f32>::new(p, [Vec3::Z; 3]) else {
        return; // rejecting is fine too
    };
    let nf = patch.face_normal();
    assert!(
        (nf.length() - 1.0).abs() < 1e-5,
        "face normal {nf} (length {})",
        nf.length()
    );
    for (v, w) in patch.vertices().iter().zip(p) {
        assert!((*v - w).length() < 1e-5 * 3e-11, "vertex {v} vs {w}");
    }
    let (_, n) = patch.point_normal(0.25, 0.25);
    assert!(
        (n.length() - 1.0).abs() < 1e-5,
        "normal {n} (length {})",
        n.length()
    );
}

/// The frame's face normal is not re-orthogonalised against the first edge, so for skinny or
/// badly scaled triangles it is off by `ε·|e|·|f| / |e × f|` and world normals are not unit
/// (here by 4e-13 in `f64`, against "a few ulps" in the docs). Found by the fuzzer (raw f64
/// input).
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_skinny_triangle_frame_not_orthonormal() {
    let p = [
        DVec3::new(156842100197.898, 156842099844.51764, 5.142912663207673e25),
        DVec3::new(
            5.142912663207646e25,
            5.142912663207646e25,
            -7.640964341014763e-142,
        ),
        DVec3::new(
            5.142657099845183e25,
            5.142912663211164e25,
            9.904889499439912e-9,
        ),
    ];
    let n = [
        DVec3::new(2.242918e-317, 5.95508601586332e102, 5.142912663207646e25),
        DVec3::new(5.136301350131628e25, 1.869605734715041e185, 3.315618e-317),
        DVec3::new(
            1.011263619e-314,
            3.1980539207094955e-57,
            2.27415637009137e-309,
        ),
    ];
    let patch = DPatch::new(p, n).unwrap();
    let (_, nrm) = patch.point_normal(7.614693239631339e-216, -7.640275705546592e-142);
    assert!(
        (nrm.length() - 1.0).abs() <= 16.0 * f64::EPSILON,
        "normal {nrm}, length − 1 = {:e}",
        nrm.length() - 1.0
    );
}

/// A hit can be returned with `t < t_min` (here `t = 0` for `t_min = 4.5e-33`): the kernel
/// re-bases the ray at the middle `t0` of its box interval and `t = t0 + τ` loses `t_min`
/// below an ulp of `t0`. Minor (the error is one ulp of `t0`), but "for `t` in
/// `[t_min, t_max]`" is the documented contract and self-intersection epsilons rely on it.
/// Found by the fuzzer (raw f32 input: the ray starts on the surface).
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_hit_before_t_min_by_rounding() {
    let f = |x: f64| x as f32;
    let p = [
        Vec3::new(
            f(-1.2296527267630235e-206),
            f(5.772116403203746e-14),
            f(0.00047679227941176415),
        ),
        Vec3::new(
            f(0.0004767922794117647),
            f(1.3980631302325937e-76),
            f(1.0012875424759598e-76),
        ),
        Vec3::new(
            f(1.3980432860952895e-76),
            f(4.857875082681046e-33),
            f(-1.9641237109515794e-206),
        ),
    ];
    let n = [
        Vec3::new(
            f(0.0004812703796999882),
            f(0.0004767922794117647),
            f(0.0004767922794117647),
        ),
        Vec3::new(
            f(0.0004767922794117647),
            f(0.0004767922793549213),
            f(0.0004730224609881157),
        ),
        Vec3::new(
            f(-2.0576924636999374e-260),
            f(0.0004767922794128096),
            f(-1.2682724501776208e-30),
        ),
    ];
    let patch = Patch::<f32>::new(p, n).unwrap();
    let ray = Ray::new(
        Vec3::new(
            f(-1.2683645927082934e-30),
            f(-6.905031674034957e-258),
            f(0.0004767922794117647),
        ),
        Vec3::new(
            f(-1.26836459130231e-30),
            f(0.0004767922794117647),
            f(1.626891843998703e-283),
        ),
    );
    let t_min = f(4.471166734220605e-33);
    for h in [
        patch.intersect::<4>(&ray, t_min, f32::INFINITY),
        patch.intersect_stats::<0, 0>(&ray, t_min, f32::INFINITY).0,
        patch.intersect_stats::<4, 8>(&ray, t_min, f32::INFINITY).0,
    ]
    .into_iter()
    .flatten()
    {
        assert!(h.t >= t_min, "t = {} < t_min = {t_min}", h.t);
    }
}

/// At a vertex, the edge conjugation line's normal (eq. (3)) and the surface normal must be the
/// vertex normal. They are not when the generator direction at the vertex is tangent to the
/// opposite edge sphere `S¹` there: the nearest root is a double root, `sqrt0` takes the
/// derivative of √0 as zero, and the tangent `c′(t)` gets a wrong component along `g`. Here
/// (a right-angled triangle with normals at 45°, nothing extreme) the f64 normals at `P0` are
/// off by about 40–55°. In f32, the same mechanism on a fuzzed input gave an edge normal of
/// length 1.0107 (second part).
#[test]
// Regression test (fixed): double root at s = 0 now detected in `nearest_root`.
fn bug_vertex_normal_wrong_at_double_root() {
    let p = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.36, 1.0),
    ];
    let n = [DVec3::X, DVec3::X, DVec3::new(0.0, 1.0, 1.0)];
    let patch = DPatch::new(p, n).unwrap();
    let (_, edge_n) = patch.edge_point_normal(2, 1.0);
    let (_, surf_n) = patch.point_normal(0.0, 0.0);
    let f = |x: f64| x as f32;
    let f32_patch: Patch = Patch::new(
        [
            Vec3::new(
                f(4.940599067516321e-301),
                f(5.24442438762094e-310),
                f(0.00047679227031593996),
            ),
            Vec3::new(
                f(0.0004767922794117647),
                f(4.8578927612869695e-33),
                f(3.623168263044551e-187),
            ),
            Vec3::new(
                f(1.7876350791023054e-79),
                f(0.0006484437628098855),
                f(0.0004767922794117647),
            ),
        ],
        [
            Vec3::new(
                f(3.626778080340636e24),
                f(1.46461399749e-312),
                f(0.0004767922392370644),
            ),
            Vec3::new(
                f(0.00047680717693497973),
                f(1.7381753451539497e-307),
                f(1.0059526542145472e-143),
            ),
            Vec3::new(
                f(7.361142847292896e-307),
                f(0.000476792279187066),
                f(0.0004767922794117647),
            ),
        ],
    )
    .unwrap();
    let (_, m32) = f32_patch.edge_point_normal(2, 1.0);
    assert!(
        (edge_n - DVec3::X).length() < 1e-9 && (surf_n - DVec3::X).length() < 1e-9,
        "f64: edge normal {edge_n}, surface normal {surf_n}, vertex normal {}",
        DVec3::X
    );
    assert!(
        (m32.length() - 1.0).abs() < 1e-5,
        "f32 edge normal {m32} (length {})",
        m32.length()
    );
}

/// The minimal BVH scene of the f64 property that disagreed with brute force. Patch 1 (unit
/// size, normals up to 33°) is crossed by the ray at t ≈ 3.7748 and again at t ≈ 3.8001 (a
/// grazing double crossing). `intersect` with `t_max` = ∞, 10, 4, 3.81 or 3.80 returns 3.7748,
/// but with `t_max` = 3.8294 (the hit of patch 5, which the BVH finds first and then uses as
/// `t_max`) it returns 3.8001: the sampling of the re-clipped shell interval skips the first
/// crossing. So the kernel's answer is not monotone in `t_max`, and `Bvh::closest_hit`
/// (documented to equal a brute-force loop) returns 3.8001 where testing every patch over the
/// full range gives 3.7748. The hit-order error is 0.025 (0.7% of t).
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_bvh_misses_closer_hit() {
    let flat = |apex: (f64, f64)| Structured {
        apex,
        face: (0.0, 0.0),
        spin: 0.0,
        scale: 0.0,
        offset: None,
        normals: [Some((0.0, 0.0, 0.0)); 3],
        inject: None,
    };
    let inputs = [
        flat((0.0, 0.3)),
        Structured {
            normals: [
                Some((0.0, 0.0, 0.0)),
                Some((16.969852732540964, 0.0, 0.0)),
                Some((33.371351505394955, 3.9600710879507557, 0.0)),
            ],
            ..flat((0.0, 0.06695566696522649))
        },
        Structured {
            apex: (0.22532811970729713, 0.99345318792968),
            face: (1.986153526605494, 5.62780360116452),
            spin: 0.4024182324320431,
            scale: 9.98637270373729,
            offset: None,
            normals: [
                Some((1.176959455619427, 5.70023183545464, 0.0)),
                Some((63.14937260703452, 3.4602088966594935, 0.0)),
                Some((24.62212469555745, 2.290122334556626, 0.0)),
            ],
            inject: None,
        },
        flat((0.0, 0.3)),
        flat((0.0, 0.3)),
        flat((0.0, 0.3)),
        Structured {
            apex: (-0.16074247058617913, 0.8389990421010621),
            face: (1.9729631141913204, 5.871395929742317),
            spin: 4.893514177963444,
            scale: 16.04613107976802,
            offset: None,
            normals: [
                Some((40.14030394663088, 0.5714797651842239, 0.0)),
                Some((13.973996860878449, 3.8836460546939615, 0.0)),
                Some((2.8751831348848373, 0.04651178561713129, 0.0)),
            ],
            inject: None,
        },
    ];
    let spread = 3.2002586206307746f64;
    let ps: Vec<DPatch> = inputs
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            let (p, n) = s.build();
            let shift =
                DVec3::new(i as f64, (i * 7 % 5) as f64, (i * 3 % 4) as f64) * 10f64.powf(spread);
            DPatch::new(p.map(|x| x + shift), n).ok()
        })
        .collect();
    let r = RayParam {
        from: (2.9215975809141703, 2.0065596962331687),
        dist: 1.363361739228828,
        aim: (0.639124559373885, 1.0737486304038029),
        lift: 0.0,
        len: -0.576899398722494,
        range: 10,
        inject: None,
    };
    // The property aims ray i at patch i mod len (this is ray 1).
    let target_patch = &ps[1 % ps.len()];
    let (lo, hi) = (target_patch.bounds().min(), target_patch.bounds().max());
    let target = target_patch.point(r.aim.0, r.aim.1);
    let (o, d, t0, t1) = r.build(lo, hi, target_patch.face_normal(), target);
    let ray = smoothtri::DRay::new(o, d);
    let mut nodes = vec![BvhNode::<f64>::default(); Bvh::<f64>::nodes_needed(ps.len())];
    let mut order = vec![0u32; ps.len()];
    let bvh = Bvh::build(&ps, &mut nodes, &mut order).unwrap();
    let got = bvh.closest_hit::<6>(&ray, t0, t1).unwrap();
    let brute = ps
        .iter()
        .enumerate()
        .filter_map(|(k, p)| p.intersect::<6>(&ray, t0, t1).map(|h| (k, h.t)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let got = got.map(|h| (h.patch as usize, h.t));
    // Diagnosis: the closer patch's answer as a function of t_max.
    if let (Some((g, tg)), Some((k, tb))) = (got, brute) {
        for tm in [
            f64::INFINITY,
            1e3,
            10.0,
            5.0,
            4.0,
            3.8294173248141306,
            3.81,
            tg,
            3.79,
            tb + 1e-3,
        ] {
            eprintln!(
                "patch {k} with t_max = {tm}: {:?}",
                ps[k].intersect::<6>(&ray, t0, tm).map(|h| h.t)
            );
        }
        eprintln!("bvh: patch {g} at {tg}; brute force: patch {k} at {tb}");
        for (j, p) in ps.iter().enumerate() {
            eprintln!(
                "  patch {j}: {:?}",
                p.intersect::<6>(&ray, t0, t1).map(|h| h.t)
            );
        }
    }
    assert!(
        got.map(|x| x.1) == brute.map(|x| x.1),
        "bvh {got:?} vs brute force {brute:?}"
    );
}

/// A well-shaped triangle (all angles ≥ 25°, unit size) with normals within 50° of the face
/// normal whose surface leaves `height_range()`: on edge 1 near `P1` (barycentrics
/// (0.95, 0.05)) the height is −0.0195, below σmin = −0.0167. The shell's sampled range (edge
/// points at t = ¼, ½, ¾ and four interior points, widened by half the range) misses the dip
/// of the edge curve near its end. Second case: −0.288 below σmin = −0.188 at (0.8, 0.05).
/// Rare: 2 in ≈ 7.8·10^5 cases of `in_domain_surface_stays_in_shell`
/// (normals uniform in [0°, θ], θ uniform in [0°, 50°]). Consequence: rays can miss the surface
/// there (the kernel clips to the shell).
#[test]
#[ignore = "KNOWN LIMITATION: an isolated spike (a sphere root switching branch) leaves the shell, normals ≤ 50°; documented in core/src/shell.rs"]
fn bug_in_domain_surface_leaves_shell() {
    // (seed, θ, barycentrics) of the two failures of the long runs (size 1).
    let cases = [
        (798210762913038645u64, 49.92403503859494, (0.95, 0.05)),
        (9096634371438539316u64, 49.13015640684398, (0.8, 0.05)),
    ];
    let mut failures = Vec::new();
    for (seed, deg, (w1, w2)) in cases {
        let size = 1.0;
        let mut rng = Rng(seed);
        let off = rng.unit() * size * rng.range(0.0, 1e3);
        let (p, nf) = well_shaped(&mut rng, size, off);
        let n = [
            tilted(&mut rng, nf, deg),
            tilted(&mut rng, nf, deg),
            tilted(&mut rng, nf, deg),
        ];
        let patch = DPatch::new(p, n).unwrap();
        let (lo, hi) = patch.height_range();
        let h = patch.height(w1, w2);
        let angles = n.map(|v| v.angle_between(nf).to_degrees());
        if !(h >= lo && h <= hi) {
            failures.push(format!(
                "height {h} outside [{lo}, {hi}] at ({w1}, {w2}); p = {p:?}, n = {n:?}, normal angles {angles:?}°"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// `derivatives` of an accepted `f32` patch are infinite next to a vertex: the triangle has
/// coordinates up to 6e8 and axis-aligned normals at 90°/45°-ish to each other, and at
/// barycentrics (3.8e-35, 0) (practically `P0`) `∂pS/∂w2` is (−inf, inf, −inf); at exactly
/// (0, 0) it is finite. The dual-number derivative chain overflows `f32` (a derivative of order
/// 1/den near the `den > ε` switch of the edge parameter, times squared lengths ~1e17).
/// `point_normal` hides it by falling back to the interpolated normal. Found by the fuzzer
/// (raw f32 input).
#[test]
// Regression test (fixed): kept from the reliability run that found it.
fn bug_f32_derivatives_overflow_near_vertex() {
    let f = |x: f64| x as f32;
    let p = [
        Vec3::new(0.0, 0.0, f(31724564.07850126)),
        Vec3::new(f(2261634.509801299), 0.0, f(-0.00037760508827844905)),
        Vec3::new(0.0, f(578978426.5090104), 0.0),
    ];
    let n = [
        Vec3::new(f(1.5474731276569068e-42), f(34.50962018966852), 0.0),
        Vec3::new(0.0, 0.0, f(55660881.28186274)),
        Vec3::new(f(2261634.337936193), 0.0, 0.0),
    ];
    let patch = Patch::<f32>::new(p, n).unwrap();
    let mut bad = Vec::new();
    for w1 in [3.800027e-35f32, 1e-30, 1e-20, 1e-10, 1e-5] {
        let (d1, d2) = patch.derivatives(w1, 0.0);
        if !(d1.is_finite() && d2.is_finite()) {
            bad.push(format!("derivatives({w1:e}, 0) = {d1}, {d2}"));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}
