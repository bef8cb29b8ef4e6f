//! Regression tests: one per bug found by the robustness properties (`tests/suite/robustness.rs`)
//! and the fuzzer (`fuzz/`), each named after the property it protects, each with the input
//! that broke it and an assertion of the intended behaviour. A comment above each names the bug.
//!
//! Two tests are ignored, each with its reason: a known limit of the method (isolated spikes
//! that leave the shell) and an open bug (tiny triangles misreported as degenerate).

use crate::robustness::strategies;

use crate::common::*;
use glam::{DVec3, Vec3};
use smoothtri::accuracy::{F64_INTERPOLATION, UNIT_LENGTH_ULPS};
use smoothtri::{Bvh, BvhNode, DPatch, Patch, PatchError, Ray};
use strategies::{RayParam, Structured};

/// Bug: `Patch::point` & co. projected barycentrics onto the triangle by dividing by the sum
/// of their cleaned values (`surface::project_bary`); when only one component survived the
/// cleaning and it was subnormal, `1 / sum` overflowed to infinity and `0 · inf` gave NaN.
#[test]
fn evaluations_are_finite_at_subnormal_barycentric_sums() {
    let octant = [DVec3::X, DVec3::Y, DVec3::Z];
    let p = DPatch::new(octant, octant).unwrap();
    // Only one component survives the cleaning: the point is that vertex.
    for (w1, w2, vertex) in [
        (f64::NAN, 1e-310, DVec3::Z),
        (f64::NEG_INFINITY, 1e-310, DVec3::Z),
        (1e-310, f64::NAN, DVec3::Y),
    ] {
        let x = p.point(w1, w2);
        let (y, n) = p.point_normal(w1, w2);
        let (d1, d2) = p.derivatives(w1, w2);
        assert!(
            x.is_finite() && y.is_finite() && n.is_finite() && d1.is_finite() && d2.is_finite(),
            "f64 ({w1}, {w2}): point {x}, point_normal {y} {n}, derivatives {d1} {d2}"
        );
        assert!(p.height(w1, w2).is_finite(), "f64 ({w1}, {w2}): height");
        assert_vec_close!(x, vertex, F64_INTERPOLATION, "f64 ({w1}, {w2})");
    }
    let q: Patch = Patch::new(octant.map(|v| v.as_vec3()), octant.map(|v| v.as_vec3())).unwrap();
    let x = q.point(f32::NAN, 1e-40);
    assert!(x.is_finite(), "f32 (NaN, 1e-40): point {x}");
}

/// Bug: the frame of an `f32` patch was built from `e × f / |e × f|` with `|e × f|²` computed
/// in `f32`: for triangles of size ≈ 1e-19…3e-10 it is subnormal, and the "unit" face normal
/// and the frame were off by up to several percent. Fixed: such triangles are rejected as
/// `OutOfRange` (too small for `f32`); the smallest accepted scale is 1e-7.
#[test]
fn tiny_f32_triangles_are_out_of_range() {
    // The triangle the properties found (3e-11 × 9e-12).
    let p = [
        Vec3::ZERO,
        Vec3::new(3e-11, 0.0, 0.0),
        Vec3::new(0.0, 9e-12, 0.0),
    ];
    assert_eq!(
        Patch::<f32>::new(p, [Vec3::Z; 3]),
        Err(PatchError::OutOfRange)
    );
    // Right triangles and sphere octants from 1e-11 to 1e-8 (accepted from 1e-7 on).
    for e in -11..=-7 {
        let s = 10f32.powi(e);
        let right = [Vec3::ZERO, Vec3::X * s, Vec3::Y * s];
        let octant = [Vec3::X * s, Vec3::Y * s, Vec3::Z * s];
        let (r, o) = (
            Patch::<f32>::new(right, [Vec3::Z; 3]).err(),
            Patch::<f32>::new(octant, [Vec3::X, Vec3::Y, Vec3::Z]).err(),
        );
        let want = if e < -7 {
            Some(PatchError::OutOfRange)
        } else {
            None
        };
        assert_eq!((r, o), (want, want), "scale {s:e}");
    }
}

/// Bug (found while removing the filters of `tests/suite/robustness.rs`, fixed): a well-shaped
/// triangle so small that `|e × f|²` underflows the precision (`f32`: edges below about
/// 1e-12) was rejected as `DegenerateTriangle` ("collinear or coincident vertices"), not as
/// `OutOfRange` ("too small for this precision"), because `Patch::new` tested the relative
/// area before the magnitude. It now tests the scale (`longest_edge⁴ < MIN_POSITIVE / ε`)
/// first.
#[test]
fn tiny_triangles_are_out_of_range_not_degenerate() {
    let mut wrong = Vec::new();
    for e in -22..=-12 {
        let s = 10f32.powi(e);
        for p in [
            [Vec3::ZERO, Vec3::X * s, Vec3::Y * s],
            [Vec3::X * s, Vec3::Y * s, Vec3::Z * s],
        ] {
            let r = Patch::<f32>::new(p, [Vec3::ONE; 3]).err();
            if r != Some(PatchError::OutOfRange) {
                wrong.push(format!("f32 scale {s:e}: {r:?}"));
            }
        }
    }
    let s = 1e-200;
    let p = [DVec3::ZERO, DVec3::X * s, DVec3::Y * s];
    let r = DPatch::new(p, [DVec3::Z; 3]).err();
    if r != Some(PatchError::OutOfRange) {
        wrong.push(format!("f64 scale {s:e}: {r:?}"));
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// Bug: the frame's face normal was not re-orthogonalised against the first edge, so for
/// skinny or badly scaled triangles it was off by `ε·|e|·|f| / |e × f|` and world normals were
/// not unit (here by 4e-13 in `f64`). Found by the fuzzer (raw f64 input).
#[test]
fn skinny_triangle_frames_are_orthonormal() {
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
        (nrm.length() - 1.0).abs() <= UNIT_LENGTH_ULPS * f64::EPSILON,
        "normal {nrm}, length − 1 = {:e}",
        nrm.length() - 1.0
    );
}

/// Bug: a hit could be returned with `t < t_min` (here `t = 0` for `t_min = 4.5e-33`): the
/// kernel re-bases the ray at the middle `t0` of its box interval and `t = t0 + τ` lost
/// `t_min` below an ulp of `t0`. Fixed: `t` is clamped to `[t_min, t_max]`. Found by the
/// fuzzer (raw f32 input: the ray starts on the surface).
#[test]
fn hits_are_inside_the_ray_range() {
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
    let hits = [
        patch.closest_hit(&ray, t_min, f32::INFINITY, 4),
        patch
            .closest_hit_stats::<0>(&ray, t_min, f32::INFINITY, 0)
            .0,
        patch
            .closest_hit_stats::<4>(&ray, t_min, f32::INFINITY, 8)
            .0,
    ];
    for h in &hits {
        let h = h.expect("the ray starts on the surface and crosses it");
        assert!(h.t >= t_min, "t = {} < t_min = {t_min}", h.t);
    }
}

/// Bug: at a vertex, the edge conjugation line's normal (eq. (3)) and the surface normal must
/// be the vertex normal; they were not when the generator direction at the vertex is tangent
/// to the opposite edge sphere `S¹` there (a double root of `nearest_root`, whose derivative
/// `sqrt0` took as zero). Here (a right-angled triangle with normals at 45°) the f64 normals at
/// `P0` were off by 40–55°; in f32, a fuzzed input gave an edge normal of length 1.0107.
#[test]
fn vertex_normals_are_exact_at_double_roots() {
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
        (edge_n - DVec3::X).length() <= F64_INTERPOLATION
            && (surf_n - DVec3::X).length() <= F64_INTERPOLATION,
        "f64: edge normal {edge_n}, surface normal {surf_n}, vertex normal {}",
        DVec3::X
    );
    assert!(
        (m32.length() as f64 - 1.0).abs() <= UNIT_LENGTH_ULPS * f32::EPSILON as f64,
        "f32 edge normal {m32} (length {})",
        m32.length()
    );
}

/// Bug: `Bvh::closest_hit` could return another crossing than brute force: it tested each
/// patch with `t_max` lowered to the best hit so far, and the kernel's answer depends on its
/// range (the shell interval is sampled differently). In this scene (found by
/// `bvh_agrees_with_brute_force` (f64); patch indices count the accepted inputs) the ray meets
/// patch 1 (size 1e10) at t ≈ 3.7748, on the patch's boundary edge (barycentric `w0` ≈
/// 1e-15), and crosses its interior at t ≈ 3.8001; which of the two the kernel reports depends
/// on `t_max` (3.8001 for `t_max` = ∞; 3.7748 for 3.83 and 3.81; none for 3.80), so a BVH that
/// lowers `t_max` to patch 5's hit (3.8294, size 1e16) answers differently from brute force.
/// Fixed: the BVH tests every patch over the caller's whole range, so it equals brute force,
/// bit for bit.
#[test]
fn bvh_closest_hit_equals_brute_force() {
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
    let ps: Vec<DPatch> = strategies::scene(&inputs, 3.2002586206307746);
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
    let got = bvh.closest_hit(&ray, t0, t1, 6);
    // Brute force over the whole range, each hit tagged with its patch's index.
    let brute = ps
        .iter()
        .enumerate()
        .filter_map(|(k, p)| {
            let h = p.closest_hit(&ray, t0, t1, 6)?;
            Some(smoothtri::DHit {
                patch: k as u32,
                ..h
            })
        })
        .min_by(|a, b| a.t.total_cmp(&b.t));
    assert_eq!(got, brute, "bvh vs brute force");
    assert!(got.is_some(), "the ray hits");
    // The mechanism of the fix: every patch test gets the caller's range, never one shortened
    // to the best hit so far.
    let mut ranges = Vec::new();
    bvh.closest_with(&ray, t0, t1, |_, p, a, b| {
        ranges.push((a, b));
        p.closest_hit(&ray, a, b, 6)
    })
    .unwrap();
    assert!(ranges.len() >= 2, "{} patch tests", ranges.len());
    assert!(
        ranges.iter().all(|&r| r == (t0, t1)),
        "ranges {ranges:?}, caller's ({t0}, {t1})"
    );
}

/// Known limit of the method (not a bug of the code): a well-shaped triangle (all angles ≥
/// 25°, unit size) with normals within 50° of the face normal whose surface leaves
/// `height_range()`: on edge 1 near `P1` (barycentrics (0.95, 0.05)) the height is −0.0195,
/// below σmin = −0.0167, an isolated spike where a sphere root switches branch, which no
/// sampling bound of the shell contains. Second case: −0.288 below σmin = −0.188 at (0.8,
/// 0.05). Rare: 2 in ≈ 7.8·10^5 cases of `in_domain_surface_stays_in_shell`. Consequence: rays
/// can miss the surface there (the kernel clips to the shell).
#[test]
#[ignore = "KNOWN LIMITATION: an isolated spike (a sphere root switching branch) leaves the shell, normals ≤ 50°; documented in core/src/surface/shell.rs"]
fn surface_stays_in_shell_at_isolated_spikes() {
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

/// Bug: `derivatives` of an accepted `f32` patch were infinite next to a vertex: the triangle
/// has coordinates up to 6e8 and axis-aligned normals, and at barycentrics (3.8e-35, 0) the
/// dual-number derivative chain overflowed `f32` (`∂pS/∂w2` = (−inf, inf, −inf)). Fixed: where
/// the derivatives overflow, the flat triangle's edge vectors are returned. Found by the fuzzer
/// (raw f32 input).
#[test]
fn f32_derivatives_are_finite_near_vertices() {
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
