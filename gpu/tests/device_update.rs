//! `GpuUpdate`: a smooth scene updated on the device from device vertex buffers holds the CPU
//! update's records within rounding (patches with their reaches and boxes, the remedy byte,
//! the placeholders) and the CPU's refitted tree, on the built-in scenes, a deforming mesh at
//! several times, steep normals that need the remedy and a triangle that degenerates
//! mid-animation; bad input is a typed error.
//! `cargo test -p smoothtri-gpu --test device_update`.

mod common;
use common::*;
use std::sync::Arc;

use glam::DVec3;
use smoothtri::internal::{CRACK_REACH, MAX_CRACK_REACH, ROUNDING_ULPS, TWIST_TERMS};
use smoothtri::mesh::Seam;
use smoothtri::{BuildOptions, LineField, NORMAL_CLAMP_DEG, OwnedScene, Patch, Vertices};
use smoothtri_gpu::{
    Gpu, GpuError, GpuNode, GpuScene, GpuUpdate, PATCH_VEC4, SEAM_VEC4, seam_record, smooth_record,
};
use smoothtri_testkit::Mesh;
use smoothtri_testkit::scenes::{builtin, tilted_normal_sphere};
use smoothtri_testkit::twist::{twist_pose, twisting_torus};

/// The error bound of one side's arithmetic, in units of `f32::EPSILON` times the patch's
/// length scale `L` (the record's `scale`: 4 × longest edge + |origin|): every value a patch
/// record holds (frame, local vertices, normals and line field, sampled heights and their
/// range, box, band) is within this of its exact value, on the CPU and on the device.
///
/// Derivation (a budget, like `ROUNDING_ULPS` itself: validated by the tests rather than
/// proven for every conditioning). Each side's value is the exact one plus the roundings on
/// its path, and their sum is the kernel's rounding budget, `smoothtri::internal::ROUNDING_ULPS`
/// = 16 ulps of `L` (core/src/kernel/budget.rs: a few ulps per stage, the frame's map, the
/// local point, the sphere-root heights), which the device's kernel is held to as well
/// (gpu/src/kernel/params.wgsl ROUNDING_ULPS, gpu/tests/parity.rs). The device's passes are the CPU's
/// operations in the CPU's order (gpu/src/update/patch.wgsl) in WGSL's `f32`, whose accuracy
/// (the WGSL spec, "Floating Point Accuracy") is: `+`, `−`, `×` correctly rounded (½ ulp, as
/// on the CPU); `x / y` within 2.5 ulp; `inverseSqrt` within 2 ulp, and `sqrt` inherited from
/// `1 / inverseSqrt` (2 + 2.5 + ½ = 5 ulp). A normalisation `v · (1 / sqrt(v · v))` (the frame
/// axes, the unit normals) is so within 5 + 2.5 + 3 × ½ = 9 ulps of the unit vector (the CPU's:
/// 2), and a path's few normalisations and divisions (the line directions `n / n.z`, the
/// curvatures, the heights' sphere roots) stay within the 16 ulps of `L` on the patches the
/// build accepts: not degenerate (`DEGENERATE_RATIO`), normals within `NORMAL_CLAMP_DEG` of the
/// face, and `L` ≥ 4 × the longest edge ≥ every local length. Values of size 1 (axes, normals,
/// directions) are measured against `max(L, |value|, 1)`.
const SIDE_ULPS: f32 = ROUNDING_ULPS as f32;

/// The largest difference allowed between a device record's value and the CPU's, scaled by
/// the larger of the patch's length scale `L`, the value and 1: each side is within
/// [`SIDE_ULPS`] of the exact value, so the two are within twice that of each other.
const RECORD_TOL: f32 = 2.0 * SIDE_ULPS * f32::EPSILON;

/// The largest difference allowed between the gap a wall's reach stands for on the device and
/// on the CPU (the reach is `CRACK_REACH` gaps over the wall's altitude), in units of
/// `f32::EPSILON` times the patch's length scale: the gap is the distance between two surface
/// points, one on each side of the shared edge, each of which is within [`RECORD_TOL`] `· L`
/// on the device of the CPU's (a point of the patch, as its record's values), so the two
/// gaps are within twice that.
const GAP_TOL_EPS: f32 = 2.0 * RECORD_TOL / f32::EPSILON;

/// The relative rounding of the tree's cost on the two sides, beyond what the boxes' bounds
/// move it (`cost_bound`): a slot's half area `xy + yz + zx` from correctly rounded
/// differences, products and sums of positive terms is within 2.5 ulps, times its count ½
/// more; the device sums a node's four slots in `f32` (1.5 more: 4.5) and divides by the
/// root's half area (2.5); the CPU computes the half areas in `f32` (2.5 each for the slots
/// and the root) and sums in `f64`. 4.5 + 2.5 + 2.5 + 2.5 = 12 ulps.
const COST_ROUNDING: f64 = 12.0 * f32::EPSILON as f64;

/// The largest angle allowed between the seamless shading normal of a device-fitted seam and
/// of the CPU's, in degrees, at points across each patch: the fits agree to the rounding of
/// the sampled normals (`f32` on the device, the CPU's derivatives widened to `f64`).
const SEAM_NORMAL_TOL_DEG: f64 = 0.005;

/// The largest angle allowed between a vertex normal generated on the device (`f32`) and the
/// CPU's (`f64`), in degrees.
const NORMAL_TOL_DEG: f64 = 1e-4;

/// Where a record's reaches ride: value 3 of each edge's fourth `vec4` (`smooth_record`).
const REACH_SLOTS: [usize; 3] = [4 * 13 + 3, 4 * 18 + 3, 4 * 23 + 3];

fn packed(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn f32s(v: &[DVec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.as_vec3().to_array()).collect()
}

fn options(seams: bool) -> BuildOptions<(), ()> {
    BuildOptions {
        field: LineField::Face,
        seams,
        observer: (),
        executor: (),
    }
}

fn cpu_build(m: &Mesh, seams: bool) -> OwnedScene<f32> {
    let (p, n) = (packed(&m.positions), packed(&m.normals));
    OwnedScene::<f32>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &m.triangles,
        &mut options(seams),
    )
    .expect("the CPU build")
}

/// Uploads the CPU scene, with its seams where it has them.
fn upload(gpu: &Arc<Gpu>, cpu: &OwnedScene<f32>, seams: bool) -> GpuScene {
    let s = cpu.scene();
    if seams {
        GpuScene::smooth_seamless(gpu, s.bvh(), s.seams())
    } else {
        GpuScene::smooth(gpu, s.bvh())
    }
    .expect("upload")
}

/// A seam from its record (`seam_record`'s layout).
fn seam_of(r: &[f32]) -> Seam<f32> {
    let mut seam = Seam::<f32>::default();
    for j in 0..3 {
        for k in 0..TWIST_TERMS {
            seam.common[j][k] = r[12 * j + k];
            seam.common_along[j][k] = r[12 * j + 6 + k];
        }
        seam.free[j] = r[36 + j] != 0.0;
    }
    seam
}

/// The CPU's `remedy` byte of `p` (as the device reports it; `rejected` placeholders by
/// their code).
fn cpu_remedy(p: &Patch) -> u32 {
    if let Some(e) = p.rejected() {
        use smoothtri::PatchError as E;
        return 0x80
            | match e {
                E::NonFinite => 1,
                E::DegenerateTriangle => 2,
                E::ZeroNormal { vertex } => 3 + u32::from(vertex),
                E::BackFacingNormal { vertex } => 6 + u32::from(vertex),
                E::InvalidShell => 9,
                E::OutOfRange => 10,
            };
    }
    p.normal_clamp().map_or(0, |deg| {
        1 + NORMAL_CLAMP_DEG
            .iter()
            .position(|&d| d == deg)
            .expect("a listed clamp") as u32
    })
}

/// Builds `m` on the CPU (with seams where `seams`), uploads it and makes its device update.
fn on_device(gpu: &Arc<Gpu>, m: &Mesh, seams: bool) -> (OwnedScene<f32>, GpuScene, GpuUpdate) {
    let cpu = cpu_build(m, seams);
    let gs = upload(gpu, &cpu, seams);
    let up = GpuUpdate::new(
        &gs,
        &cpu.scene(),
        &m.triangles,
        m.positions.len(),
        LineField::Face,
    )
    .expect("the device update");
    (cpu, gs, up)
}

/// The most a corner of the box of the patch whose CPU record is `want` may move between the
/// device and the CPU through its reaches, when each reach's gap is within [`GAP_TOL_EPS`] of
/// the CPU's (as `compare` asserts): 0 for a placeholder.
///
/// The reach over wall `j` (the edge from vertex `j + 1` to `j + 2`, of length `len`) is
/// `min(CRACK_REACH · gap · len / (2 · area), MAX_CRACK_REACH)`, so a gap off by `dg` moves it by
/// `dm ≤ min(CRACK_REACH · dg · len / (2 · area), MAX_CRACK_REACH)`. The box's corners are the
/// shell's at the widened triangle's corners (`shell_box`): corner `c`'s barycentrics move by
/// `dm` towards `c` and away from `j`, which moves the point by `dm` times the vector between
/// the two shell corners at the same height, at most `lever` (the longest such vector over the
/// shell's lowest and highest section); the frame is orthonormal, so each world coordinate
/// moves by at most that length. Summed over the three walls.
fn reach_box_bound(want: &[f32]) -> f32 {
    let (l, p1x, p2x, p2y) = (want[3], want[15], want[19], want[23]);
    let two_area = p1x * p2y;
    if two_area.is_nan() || two_area <= 0.0 {
        return 0.0;
    }
    let p = [[0.0, 0.0, 0.0], [p1x, 0.0, 0.0], [p2x, p2y, 0.0]];
    // The line directions: x and y in the vertex rows, z beside each edge's dot products.
    let d = [
        [want[27], want[31], want[59]],
        [want[35], want[36], want[79]],
        [want[37], want[38], want[99]],
    ];
    let dz = d[0][2].min(d[1][2]).min(d[2][2]);
    let sigma = [want[7] / dz, want[11] / dz];
    let dist = |a: usize, b: usize, s: f32| {
        (0..3)
            .map(|k| (p[a][k] + d[a][k] * s) - (p[b][k] + d[b][k] * s))
            .map(|x| x * x)
            .sum::<f32>()
            .sqrt()
    };
    let lever = [(0, 1), (1, 2), (2, 0)]
        .iter()
        .flat_map(|&(a, b)| sigma.map(|s| dist(a, b, s)))
        .fold(0.0f32, f32::max);
    let dg = GAP_TOL_EPS * f32::EPSILON * l;
    (0..3)
        .map(|j| {
            let len = dist((j + 1) % 3, (j + 2) % 3, 0.0);
            let dm = (CRACK_REACH as f32 * dg * len / two_area).min(MAX_CRACK_REACH as f32);
            dm * lever
        })
        .sum()
}

/// How far the refitted tree's cost may be from the CPU's, relative to it: the cost (slot
/// half areas times counts, over the root's half area; core/src/bvh/build.rs `tree_cost`) of
/// the CPU's boxes with every coordinate moved by up to `delta` outwards (inwards for the
/// root), and the other way round, plus [`COST_ROUNDING`].
fn cost_bound(nodes: &[GpuNode], delta: f64) -> f64 {
    let used = |n: &GpuNode, s: usize| n.child[s] != smoothtri::BVH_EMPTY_SLOT;
    let half_area = |e: [f64; 3], grow: f64| {
        let e = e.map(|x| (x + 2.0 * grow).max(0.0));
        e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
    };
    let extent =
        |n: &GpuNode, s: usize| [0, 1, 2].map(|a| f64::from(n.hi[a][s]) - f64::from(n.lo[a][s]));
    let sum = |grow: f64| -> f64 {
        nodes
            .iter()
            .flat_map(|n| (0..4).filter(|&s| used(n, s)).map(move |s| (n, s)))
            .map(|(n, s)| half_area(extent(n, s), grow) * f64::from(n.count[s].max(1)))
            .sum()
    };
    let root = &nodes[0];
    let root_extent = [0, 1, 2].map(|a| {
        let slots = || (0..4).filter(|&s| used(root, s));
        let hi = slots()
            .map(|s| f64::from(root.hi[a][s]))
            .fold(f64::MIN, f64::max);
        let lo = slots()
            .map(|s| f64::from(root.lo[a][s]))
            .fold(f64::MAX, f64::min);
        hi - lo
    });
    let cost = sum(0.0) / half_area(root_extent, 0.0);
    let up = sum(delta) / half_area(root_extent, -delta);
    let down = sum(-delta) / half_area(root_extent, delta);
    (up - cost).abs().max((cost - down).abs()) / cost + COST_ROUNDING
}

/// What one comparison saw.
#[derive(Debug, Default)]
struct Seen {
    worst: f32,
    /// In units of ε times the patch's scale ([`GAP_TOL_EPS`]).
    worst_reach: f32,
    /// Barycentric; reported, never a tolerance.
    widest_reach_difference: f32,
    largest_scale: f32,
    /// The largest [`reach_box_bound`] of a patch.
    reach_bound: f32,
    /// The tree's cost's allowed relative difference ([`cost_bound`]), where the nodes were
    /// compared.
    cost_tol: f64,
    worst_seam_deg: f64,
    fitted_edges: usize,
    free_edges: usize,
    clamped: usize,
    placeholders: usize,
    /// The CPU refitted its tree (so the nodes were compared).
    refitted: bool,
    reaches: usize,
}

/// Compares the device scene `gs` (updated by `up`) with the CPU scene `cpu`: records,
/// remedy bytes and, where `nodes`, the tree.
fn compare(name: &str, gs: &GpuScene, up: &GpuUpdate, cpu: &OwnedScene<f32>, nodes: bool) -> Seen {
    let s = cpu.scene();
    let (records, gpu_nodes) = gs.read_back().expect("read back");
    let remedy = up.read_remedies().expect("remedies");
    let patches = s.patches();
    assert_eq!(records.len(), patches.len() * PATCH_VEC4 * 4, "{name}");
    let mut seen = Seen::default();
    for (t, p) in patches.iter().enumerate() {
        let want = smooth_record(&p.data());
        let got = &records[t * PATCH_VEC4 * 4..(t + 1) * PATCH_VEC4 * 4];
        // The box's corners move with the reaches by at most `reach_box_bound` (from the CPU's
        // record and the gaps' bound); the reaches' measured difference is only reported.
        let reach_bound = reach_box_bound(&want);
        seen.reach_bound = seen.reach_bound.max(reach_bound);
        let dr = REACH_SLOTS
            .iter()
            .map(|&k| (got[k] - want[k]).abs())
            .fold(0.0f32, f32::max);
        seen.widest_reach_difference = seen.widest_reach_difference.max(dr);
        seen.largest_scale = seen.largest_scale.max(want[3]);
        let want_remedy = cpu_remedy(p);
        assert_eq!(
            remedy[t], want_remedy,
            "{name}: patch {t}: remedy {:#x}",
            remedy[t]
        );
        seen.clamped += usize::from((1..0x80).contains(&want_remedy));
        seen.placeholders += usize::from(want_remedy >= 0x80);
        let scale = want[3].max(1.0);
        for (k, (&g, &w)) in got.iter().zip(&want).enumerate() {
            if g.to_bits() == w.to_bits() {
                continue;
            }
            if let Some(wall) = REACH_SLOTS.iter().position(|&r| r == k) {
                // Wall `wall` lies over the edge from vertex wall + 1 to wall + 2; its
                // altitude is twice the area over that edge's length.
                let v = |i: usize| match i % 3 {
                    0 => (0.0f32, 0.0f32),
                    1 => (want[15], 0.0),
                    _ => (want[19], want[23]),
                };
                let ((ax, ay), (bx, by)) = (v(wall + 1), v(wall + 2));
                let altitude = want[15] * want[23] / (bx - ax).hypot(by - ay);
                let d = (g - w).abs() * altitude / 4.0 / (f32::EPSILON * want[3]);
                seen.worst_reach = seen.worst_reach.max(d);
                assert!(
                    d <= GAP_TOL_EPS,
                    "{name}: patch {t}, reach at {k}: device {g:e}, CPU {w:e} (gaps {d} ε·scale \
                     apart)"
                );
                continue;
            }
            let tol = if (16..24).contains(&k) {
                RECORD_TOL + reach_bound / scale.max(w.abs())
            } else {
                RECORD_TOL
            };
            let d = (g - w).abs() / scale.max(w.abs());
            seen.worst = seen.worst.max(d);
            assert!(
                d <= tol,
                "{name}: patch {t}, record value {k}: device {g:e}, CPU {w:e} (scaled \
                 difference {d:e})"
            );
        }
        seen.reaches += REACH_SLOTS.iter().filter(|&&k| want[k] > 0.0).count();
    }
    if gs.shading() == smoothtri_gpu::Shading::Seamless {
        let shading = gs.read_shading().expect("seams");
        for (t, (p, want)) in patches.iter().zip(s.seams()).enumerate() {
            let r = &shading[t * SEAM_VEC4 * 4..(t + 1) * SEAM_VEC4 * 4];
            let cpu_r = seam_record(want);
            // Which edges are fitted, free or zero, and the record's flag, exactly.
            for k in 36..40 {
                assert_eq!(r[k], cpu_r[k], "{name}: patch {t}: seam flag {k}");
            }
            for j in 0..3 {
                let zero = |q: &[f32]| q[12 * j..12 * j + 12].iter().all(|&x| x == 0.0);
                assert_eq!(zero(r), zero(&cpu_r), "{name}: patch {t}: edge {j} fitted");
            }
            if p.rejected().is_some() {
                continue;
            }
            let got = seam_of(r);
            for (w1, w2) in [(0.2f32, 0.3f32), (0.45, 0.45), (0.05, 0.9), (0.6, 0.01)] {
                let (a, b) = (
                    got.shading_normal(p, w1, w2),
                    want.shading_normal(p, w1, w2),
                );
                // The angle from both the sine and the cosine, in f64 (an f32 cosine cannot
                // tell angles below 0.02° apart).
                let (a, b) = (a.as_dvec3(), b.as_dvec3());
                let deg = a.cross(b).length().atan2(a.dot(b)).to_degrees();
                seen.worst_seam_deg = seen.worst_seam_deg.max(deg);
                assert!(
                    deg <= SEAM_NORMAL_TOL_DEG,
                    "{name}: patch {t} at ({w1}, {w2}): seamless normals {deg}° apart"
                );
            }
            seen.free_edges += want.free.iter().filter(|&&f| f).count();
            seen.fitted_edges += (0..3)
                .filter(|&j| !want.common[j].iter().all(|&c| c == 0.0))
                .count();
        }
    }
    if nodes {
        let cpu_nodes: Vec<GpuNode> = s.bvh().nodes().iter().map(GpuNode::from_node).collect();
        assert_eq!(gpu_nodes.len(), cpu_nodes.len(), "{name}");
        // A node's box is the union of its patches' boxes, so each coordinate is one patch's
        // and within that patch's bound: RECORD_TOL of the larger of its length scale and the
        // coordinate (the root's box bounds every coordinate), plus its reaches' bound.
        let root = cpu_nodes[0];
        let scale = (0..3)
            .flat_map(|a| (0..4).map(move |s| (a, s)))
            .filter(|&(_, s)| root.child[s] != smoothtri::BVH_EMPTY_SLOT)
            .map(|(a, s)| root.lo[a][s].abs().max(root.hi[a][s].abs()))
            .fold(seen.largest_scale.max(1.0), f32::max);
        let delta = RECORD_TOL * scale + seen.reach_bound;
        seen.cost_tol = cost_bound(&cpu_nodes, f64::from(delta));
        for (i, (g, w)) in gpu_nodes.iter().zip(&cpu_nodes).enumerate() {
            assert_eq!((g.child, g.count), (w.child, w.count), "{name}: node {i}");
            for a in 0..3 {
                for s in 0..4 {
                    for (x, y) in [(g.lo[a][s], w.lo[a][s]), (g.hi[a][s], w.hi[a][s])] {
                        assert!(
                            (x - y).abs() <= delta,
                            "{name}: node {i}, slot {s}, axis {a}: device {x:e}, CPU {y:e}"
                        );
                    }
                }
            }
        }
    }
    eprintln!("{name}: {seen:?}");
    seen
}

/// Moves the CPU scene and the device's to the pose `m` (the device from the positions alone
/// where it generates its normals) and compares them ([`compare`]; the tree where the CPU
/// refitted its own).
fn step(
    name: &str,
    cpu: &mut OwnedScene<f32>,
    gs: &GpuScene,
    up: &GpuUpdate,
    m: &Mesh,
    seams: bool,
) -> Seen {
    let (p, n) = (packed(&m.positions), packed(&m.normals));
    let report = *cpu
        .update(
            Vertices::packed(&p),
            Vertices::packed(&n),
            &mut options(seams),
        )
        .expect("the CPU update");
    if up.generates_normals() {
        up.write_positions(&f32s(&m.positions))
    } else {
        up.write_vertices(&f32s(&m.positions), &f32s(&m.normals))
    }
    .expect("vertices");
    up.run(gs).expect("the device update runs");
    let mut seen = compare(name, gs, up, cpu, report.bvh_refitted);
    seen.refitted = report.bvh_refitted;
    if report.bvh_refitted {
        // The same tree refitted to boxes equal within rounding: the same cost.
        let cost = up.tree_cost().expect("the tree's cost");
        let d = (cost - report.bvh_cost).abs() / report.bvh_cost;
        // The boxes' bound moved through the cost's formula (`cost_bound`).
        let tol = seen.cost_tol;
        assert!(
            d <= tol,
            "{name}: tree cost {cost} on the device, {} on the CPU (relative difference {d:e}, \
             allowed {tol:e})",
            report.bvh_cost
        );
    }
    seen
}

/// Builds `m` on the CPU, uploads it, and updates the upload on the device from `m`'s own
/// vertices: the device must reproduce the CPU build.
fn same_pose(name: &str, m: &Mesh, seams: bool) -> Option<Seen> {
    let gpu = gpu()?;
    let (cpu, gs, up) = on_device(&gpu, m, seams);
    // First every vertex at the origin: every patch a placeholder, every box empty, so that
    // nothing of the upload survives into the comparison below.
    let zeros = vec![0.0f32; 3 * m.positions.len()];
    up.write_vertices(&zeros, &zeros).expect("vertices");
    up.run(&gs).expect("the update runs");
    let remedies = up.read_remedies().expect("remedies");
    assert!(remedies.iter().all(|&r| r == 0x82), "{name}: {remedies:?}");
    up.write_vertices(&f32s(&m.positions), &f32s(&m.normals))
        .expect("vertices");
    up.run(&gs).expect("the update runs");
    Some(compare(
        &format!("{name} seams={seams}"),
        &gs,
        &up,
        &cpu,
        true,
    ))
}

#[test]
fn the_device_update_reproduces_the_cpu_build_of_the_built_in_scenes() {
    for name in ["torus", "sphere", "cube", "teapot"] {
        for seams in [false, true] {
            same_pose(name, &builtin(name).expect("a built-in scene"), seams);
        }
    }
}

#[test]
fn steep_normals_take_the_cpu_remedy_on_the_device() {
    let mut m = tilted_normal_sphere();
    for (k, n) in m.normals.iter_mut().enumerate() {
        let tip = DVec3::new(0.9, -0.4, 0.2) * (k % 3) as f64;
        *n = (*n + tip).normalize();
    }
    for seams in [false, true] {
        if let Some(seen) = same_pose("tipped normals", &m, seams) {
            assert!(seen.clamped > 0, "no normal tipped far enough: {seen:?}");
            // A clamped patch's neighbours no longer share its vertex normals: free edges.
            assert_eq!(seen.free_edges > 0, seams, "{seen:?}");
        }
    }
}

#[test]
fn the_device_update_follows_a_deforming_mesh() {
    let Some(gpu) = gpu() else { return };
    const SIDE: usize = 16;
    for seams in [false, true] {
        let mut m = twisting_torus(SIDE, 0.0);
        let (mut cpu, gs, up) = on_device(&gpu, &m, seams);
        let (mut reaches, mut refits, mut fitted) = (0, 0, 0);
        for (k, t) in [0.7, 2.3, 4.1].into_iter().enumerate() {
            twist_pose(SIDE, t, &mut m.positions, &mut m.normals);
            if k == 2 {
                // Triangle 5 degenerates mid-animation: its three vertices on one line.
                let [a, b, c] = m.triangles[5].map(|i| i as usize);
                m.positions[c] = m.positions[a] + (m.positions[b] - m.positions[a]) * 0.5;
            }
            let name = format!("twist at {t} seams={seams}");
            let seen = step(&name, &mut cpu, &gs, &up, &m, seams);
            reaches += seen.reaches;
            fitted += seen.fitted_edges;
            refits += usize::from(seen.refitted);
            if k == 2 {
                assert_eq!(seen.placeholders, 1, "{seen:?}");
            }
        }
        assert!(reaches > 0, "the twist's cracks were never measured open");
        assert!(
            refits > 0,
            "the CPU never refitted: the device's refit was not compared"
        );
        assert_eq!(fitted > 0, seams, "seams fitted: {fitted}");
    }
}

#[test]
fn bad_input_to_the_device_update_is_a_typed_error() {
    let Some(gpu) = gpu() else { return };
    let m = builtin("cube").expect("cube");
    let cpu = cpu_build(&m, false);
    let s = cpu.scene();
    let gs = GpuScene::smooth(&gpu, s.bvh()).expect("upload");
    let tris = &m.triangles;
    let nv = m.positions.len();
    let up = GpuUpdate::new(&gs, &s, tris, nv, LineField::Face).expect("the device update");
    let p = f32s(&m.positions);
    assert_eq!(
        up.write_vertices(&p[1..], &p),
        Err(GpuError::VertexCount {
            expected: p.len(),
            given: p.len() - 1
        })
    );
    // Another scene's buffers.
    let other = GpuScene::smooth(&gpu, s.bvh()).expect("upload");
    assert!(matches!(
        up.run(&other),
        Err(GpuError::SceneMismatch { .. })
    ));
    // The same scene, rewritten from the CPU since (its tree could have another topology).
    let mut gs = gs;
    up.run(&gs).expect("the update runs");
    gs.update(s.bvh(), None).expect("rewritten");
    assert!(matches!(up.run(&gs), Err(GpuError::SceneMismatch { .. })));
    GpuUpdate::new(&gs, &s, tris, nv, LineField::Face)
        .expect("a new update")
        .run(&gs)
        .expect("the new update runs");
    // A vertex index out of range, the wrong triangle count, a seamless scene.
    let mut bad = tris.clone();
    bad[0][1] = nv as u32;
    assert!(matches!(
        GpuUpdate::new(&gs, &s, &bad, nv, LineField::Face),
        Err(GpuError::Mesh(_))
    ));
    assert!(matches!(
        GpuUpdate::new(&gs, &s, &tris[1..], nv, LineField::Face),
        Err(GpuError::SceneMismatch { .. })
    ));
    assert!(matches!(
        GpuUpdate::new(&gs, &s, tris, nv, LineField::Vertex),
        Err(GpuError::Unsupported(_))
    ));
    let flat = GpuScene::flat(&gpu, s.bvh()).expect("upload");
    assert!(matches!(
        GpuUpdate::new(&flat, &s, tris, nv, LineField::Face),
        Err(GpuError::Unsupported(_))
    ));
}

/// The animated files of `assimp-testmodels` (skinned, morphed), posed at five times of their
/// first clip: each device update holds the CPU update's records.
#[test]
fn the_device_update_follows_the_animated_files() {
    let Some(gpu) = gpu() else { return };
    let Some(root) = smoothtri_testkit::assimp_models().expect("assimp-testmodels") else {
        return;
    };
    for file in [
        "glTF2/simple_skin/simple_skin.gltf",
        "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    ] {
        let path = root.join(file);
        let mut anim = smoothtri_io::load_animated(path.to_str().expect("a UTF-8 path"))
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let duration = anim.clips().first().map_or(0.0, |c| c.duration);
        let rest = anim.posed_mesh(None, 0.0).expect("the rest pose");
        let seams = true;
        let (mut cpu, gs, up) = on_device(&gpu, &rest, seams);
        for k in 1u32..=5 {
            let t = duration * f64::from(k) / 5.0;
            let frame = anim.posed_mesh(Some(0), t).expect("a pose");
            step(
                &format!("{file} at {t:.2}"),
                &mut cpu,
                &gs,
                &up,
                &frame,
                seams,
            );
        }
    }
}

/// A mesh's pose at a time.
type Poser = Box<dyn FnMut(f64) -> Mesh>;

/// A mesh without normals: the device generates the angle-weighted vertex normals from the
/// posed positions (as `smoothtri_io::angle_weighted_normals`, in `f32`), and the update from
/// them holds the CPU update's records from the CPU's normals; `simple_skin.gltf` has none.
#[test]
fn the_device_generates_the_normals_of_a_mesh_without_any() {
    let Some(gpu) = gpu() else { return };
    let mut sources: Vec<(String, Poser)> = Vec::new();
    const SIDE: usize = 16;
    let twist = twisting_torus(SIDE, 0.0);
    sources.push((
        "twist".into(),
        Box::new(move |t| {
            let mut m = twist.clone();
            twist_pose(SIDE, t, &mut m.positions, &mut m.normals);
            let tris = m.triangles.iter().map(|t| t.map(|i| i as usize));
            m.normals = smoothtri_io::angle_weighted_normals(&m.positions, tris);
            m
        }),
    ));
    if let Some(root) = smoothtri_testkit::assimp_models().expect("assimp-testmodels") {
        let path = root.join("glTF2/simple_skin/simple_skin.gltf");
        let mut anim =
            smoothtri_io::load_animated(path.to_str().expect("a UTF-8 path")).expect("simple_skin");
        assert!(anim.all_normals_computed(), "simple_skin has normals now");
        sources.push((
            "simple_skin".into(),
            Box::new(move |t| anim.posed_mesh(Some(0), t).expect("a pose")),
        ));
    }
    for (name, mut pose) in sources {
        for seams in [false, true] {
            let rest = pose(0.0);
            let (mut cpu, gs, mut up) = on_device(&gpu, &rest, seams);
            up.generate_normals(true);
            for t in [0.4, 1.3] {
                let m = pose(t);
                let name = format!("{name} at {t} seams={seams}, generated normals");
                step(&name, &mut cpu, &gs, &up, &m, seams);
                let normals = up.read_normals().expect("normals");
                let mut worst = 0.0f64;
                for (v, want) in m.normals.iter().enumerate() {
                    let got = DVec3::new(
                        f64::from(normals[3 * v]),
                        f64::from(normals[3 * v + 1]),
                        f64::from(normals[3 * v + 2]),
                    );
                    let deg = got.cross(*want).length().atan2(got.dot(*want)).to_degrees();
                    worst = worst.max(deg);
                }
                eprintln!("{name}: generated normals within {worst:e}°");
                assert!(worst <= NORMAL_TOL_DEG, "{name}: normals {worst}° apart");
            }
        }
    }
}

/// A vertex that is not finite cannot be refused on the device (nothing is read back): its
/// triangles become placeholders (the CPU's `NonFinite`), the rest of the scene updates as the
/// CPU's, and the next good pose restores them.
#[test]
fn a_non_finite_vertex_on_the_device_makes_placeholders() {
    let Some(gpu) = gpu() else { return };
    let m = builtin("torus").expect("torus");
    let (cpu, gs, up) = on_device(&gpu, &m, true);
    let (mut p, n) = (f32s(&m.positions), f32s(&m.normals));
    p[3 * 7 + 1] = f32::NAN;
    up.write_vertices(&p, &n).expect("vertices");
    up.run(&gs).expect("the device update runs");
    let remedies = up.read_remedies().expect("remedies");
    for (t, &id) in cpu.scene().triangle_ids().iter().enumerate() {
        let tri = m.triangles[id as usize];
        let want = if tri.contains(&7) { 0x81 } else { 0 };
        assert_eq!(remedies[t], want, "triangle {t} {tri:?}");
    }
    let (records, nodes) = gs.read_back().expect("read back");
    assert!(
        nodes
            .iter()
            .all(|n| n.lo.iter().chain(&n.hi).flatten().all(|x| !x.is_nan()))
    );
    assert!(
        records.iter().all(|x| !x.is_nan()),
        "a NaN reached a record"
    );
    // The good pose again: the CPU build's records.
    up.write_vertices(&f32s(&m.positions), &n)
        .expect("vertices");
    up.run(&gs).expect("the device update runs");
    compare("torus after a NaN", &gs, &up, &cpu, true);
}
