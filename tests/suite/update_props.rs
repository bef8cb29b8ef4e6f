//! Property (proptest): an update of a random mesh equals a fresh build of the same vertices.
//!
//! Each case draws a mesh (a torus of 3–8 × 3–6 quads, or an icosphere of level 0–1, its
//! vertices displaced at random and its normals tilted), the precision, the line field and the
//! seams setting, then a sequence of 1–4 poses (small jitters, which refit the tree, or large
//! scrambles, which rebuild it; sometimes a pose that collapses some triangles). The scene is
//! built from the first mesh and updated in place to each pose; after every update it is
//! compared with a fresh build of that pose:
//! - patches, slots, seams, and the report's counts: bit for bit;
//! - on a fixed set of rays, each patch's own hit (`Patch::closest_hit`, the kernel's answer
//!   independent of the tree): bit for bit, `t`, barycentrics, normal and `t_error`;
//! - the scene's closest hit (with the seamless shading normal) and its shadow ray: bit for bit
//!   where the update built the tree anew; where it refitted the tree the traversal may test
//!   the patches in another order with another best `t` (see `DynamicScene::update`), so the
//!   same hit or miss with `t` within the larger `t_error` (the kernel's certified bound).
//!
//! The same default as `robustness.rs`: a quick run with a fixed seed; `SMOOTHTRI_CASES=<n>`
//! runs `n` cases with a random seed.

use crate::common::*;
use glam::DVec3;
use proptest::prelude::*;
use smoothtri::{BuildOptions, LineField, OwnedScene, Ray, Scene, Vertices};
use smoothtri_testkit::random::Rng;
use smoothtri_testkit::{Mesh, scenes};

/// Default cases for CI (debug mode).
const QUICK_CASES: u32 = 48;

/// The quick default run's seed ([`proptest_config`]).
const SEED: u64 = 0x0DA7_E064;

/// What one case draws.
#[derive(Clone, Debug)]
struct Case {
    /// 0: torus; 1: icosphere.
    shape: u8,
    size: (usize, usize),
    /// Seed of the displacements of the build's mesh and of every pose.
    seed: u64,
    /// Displacement of the build's vertices (fraction of the mesh's size) and normal tilt (°).
    noise: f64,
    tilt: f64,
    f64: bool,
    field: LineField,
    seams: bool,
    /// Each pose: its displacement (a jitter below 0.05, a scramble above 0.3), and whether a
    /// few triangles collapse (their vertices moved onto one point).
    poses: Vec<(f64, bool)>,
}

fn case() -> impl Strategy<Value = Case> {
    (
        0u8..2,
        (3usize..9, 3usize..7),
        any::<u64>(),
        0.0..0.05f64,
        0.0..30.0f64,
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop::collection::vec(
            (
                prop_oneof![0.0..0.05f64, 0.3..1.5f64],
                prop::bool::weighted(0.2),
            ),
            1..5,
        ),
    )
        .prop_map(
            |(shape, size, seed, noise, tilt, f64, shared, seams, poses)| Case {
                shape,
                size,
                seed,
                noise,
                tilt,
                f64,
                field: if shared {
                    LineField::Vertex
                } else {
                    LineField::Face
                },
                seams,
                poses,
            },
        )
}

/// The case's base mesh.
fn base(c: &Case) -> Mesh {
    if c.shape == 0 {
        scenes::torus(c.size.0, c.size.1, 1.0, 0.4)
    } else {
        scenes::icosphere((c.size.0 % 2) as u32, 1.0)
    }
}

/// `m` with every vertex displaced by up to `amount` and every normal tilted by up to `tilt`
/// degrees (random, from `rng`); with `collapse`, the vertices of every seventh triangle moved
/// onto its first vertex (degenerate: placeholders after an update).
fn displaced(m: &Mesh, rng: &mut Rng, amount: f64, tilt: f64, collapse: bool) -> Mesh {
    let mut out = m.clone();
    for (p, n) in out.positions.iter_mut().zip(out.normals.iter_mut()) {
        *p += rng.unit() * amount;
        *n = tilted(rng, n.normalize_or(DVec3::Z), tilt);
    }
    if collapse {
        for t in m.triangles.iter().step_by(7) {
            let a = out.positions[t[0] as usize];
            for &i in &t[1..] {
                out.positions[i as usize] = a;
            }
        }
    }
    out
}

/// Rays from around the unit ball toward its middle, the same for every case.
fn rays() -> Vec<(DVec3, DVec3)> {
    let mut rng = Rng(0x5EED_0064);
    (0..48)
        .map(|_| {
            let o = rng.unit().normalize_or(DVec3::X) * 4.0;
            (o, rng.unit() * 0.8 - o)
        })
        .collect()
}

fn build<F: Float>(m: &Mesh, options: &mut BuildOptions) -> Option<OwnedScene<F>> {
    build_owned(m, options).ok()
}

/// The updated scene against the fresh build, as the module says.
fn same<F: Float>(a: &Scene<'_, F>, b: &Scene<'_, F>) -> Result<(), TestCaseError> {
    same_parts("", a, b)?;
    let refitted = a.report().bvh_refitted;
    let inf = F::from_f64(f64::INFINITY);
    for (k, (o, d)) in rays().into_iter().enumerate() {
        let ray = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
        for (i, (pa, pb)) in a.patches().iter().zip(b.patches()).enumerate() {
            prop_assert_eq!(
                pa.closest_hit(&ray, F::ZERO, inf, 8),
                pb.closest_hit(&ray, F::ZERO, inf, 8),
                "ray {}, patch {}",
                k,
                i
            );
        }
        let (ha, hb) = (
            a.closest_hit(&ray, F::ZERO, inf, 8),
            b.closest_hit(&ray, F::ZERO, inf, 8),
        );
        if refitted {
            prop_assert_eq!(ha.is_some(), hb.is_some(), "ray {}: hit vs miss", k);
            if let (Some(x), Some(y)) = (ha, hb) {
                let tol = x.hit.t_error.to_f64().max(y.hit.t_error.to_f64());
                let gap = (x.hit.t.to_f64() - y.hit.t.to_f64()).abs();
                prop_assert!(gap <= tol, "ray {}: t differs by {} > {}", k, gap, tol);
            }
        } else {
            prop_assert_eq!(ha, hb, "ray {}", k);
            prop_assert_eq!(
                a.any_hit(&ray, F::ZERO, inf, 8),
                b.any_hit(&ray, F::ZERO, inf, 8),
                "ray {}: shadow",
                k
            );
        }
    }
    Ok(())
}

fn check<F: Float>(c: &Case) -> Result<(), TestCaseError> {
    let mut options = BuildOptions {
        field: c.field,
        seams: c.seams,
        ..BuildOptions::default()
    };
    let m = base(c);
    let mut rng = Rng(c.seed);
    let first = displaced(&m, &mut rng, c.noise, c.tilt, false);
    let Some(mut scene) = build::<F>(&first, &mut options) else {
        return Err(TestCaseError::reject(
            "the first mesh has no usable triangle",
        ));
    };
    for &(amount, collapse) in &c.poses {
        let pose = displaced(&first, &mut rng, amount, c.tilt * 0.5, collapse);
        let (p, n) = buffers(&pose);
        let updated = scene.update(Vertices::packed(&p), Vertices::packed(&n), &mut options);
        prop_assert!(updated.is_ok(), "update: {:?}", updated.err());
        match build::<F>(&pose, &mut options) {
            Some(fresh) => same(&scene.scene(), &fresh.scene())?,
            // A build refuses a mesh with no usable triangle; the update keeps an empty scene.
            None => prop_assert_eq!(scene.scene().report().patches, 0),
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(proptest_config(QUICK_CASES, SEED))]

    /// An update of a random mesh to random poses equals a fresh build of each pose (the
    /// module's comparison), in either precision, line field and seams setting.
    #[test]
    fn an_update_of_a_random_mesh_equals_a_fresh_build(c in case()) {
        if c.f64 {
            check::<f64>(&c)?;
        } else {
            check::<f32>(&c)?;
        }
    }
}
