//! Fuzz target `scene_update`: the core's `OwnedScene::build` and `OwnedScene::update` on
//! arbitrary small meshes (up to 12 vertices and 16 triangles, raw coordinates or mapped onto
//! a sphere-like cloud so most triangles are accepted), in `f32` or `f64`, either line field,
//! with or without seams, then up to four updates (other positions and normals, sometimes
//! another vertex count, NaN and infinities included).
//!
//! Asserts: the build and every update return a scene or a typed error, never panic; after a
//! successful update the scene equals a fresh build of the same vertices (patches, slots,
//! seams and the report's counts bit for bit; every closest hit of a few rays bit for bit
//! where the tree was built anew, and the same hit or miss with `t` within the larger
//! `t_error` where it was refitted, as `DynamicScene::update` documents), and every hit is
//! finite; after a failed update the scene answers every ray bit for bit as before.
#![no_main]

use arbitrary::Arbitrary;
use glam::DVec3;
use libfuzzer_sys::fuzz_target;
use smoothtri::{BuildOptions, Float, LineField, OwnedScene, Ray, SceneHit, Vertices};

#[path = "structured.rs"]
mod structured;

#[derive(Arbitrary, Debug)]
struct Input {
    /// Bit 0: f64 (else f32); bit 1: shared line field; bit 2: seams; bit 3: raw vertices.
    mode: u8,
    vertices: Vec<[f64; 6]>,
    indices: Vec<[u8; 3]>,
    updates: Vec<Update>,
    rays: Vec<[f32; 6]>,
}

#[derive(Arbitrary, Debug)]
struct Update {
    /// Vertices of the update (cycled to the build's count unless bit 0 of `mode` is set).
    vertices: Vec<[f64; 6]>,
    /// Bit 0: keep this update's own vertex count; bit 1: raw vertices.
    mode: u8,
}

/// A fuzzed vertex mapped onto a small sphere-like cloud with outward normals, or raw.
fn vertex(v: [f64; 6], raw: bool) -> [f64; 6] {
    if raw {
        return v;
    }
    structured::structured(v)
}

fn split(vs: &[[f64; 6]]) -> (Vec<f64>, Vec<f64>) {
    let p = vs.iter().flat_map(|v| [v[0], v[1], v[2]]).collect();
    let n = vs.iter().flat_map(|v| [v[3], v[4], v[5]]).collect();
    (p, n)
}

/// The two precisions, with the conversion of the fuzzer's `f64` vectors.
trait Prec: Float {
    fn v(d: DVec3) -> Self::Vec3;
}
impl Prec for f32 {
    fn v(d: DVec3) -> glam::Vec3 {
        d.as_vec3()
    }
}
impl Prec for f64 {
    fn v(d: DVec3) -> DVec3 {
        d
    }
}

/// The scene's closest hit of each ray, with finiteness asserted.
fn hits<F: Prec>(s: &OwnedScene<F>, rays: &[Ray<F>]) -> Vec<Option<SceneHit<F>>> {
    rays.iter()
        .map(|r| {
            let h = s
                .scene()
                .closest_hit(r, F::ZERO, F::from_f64(f64::INFINITY), 8);
            if let Some(h) = &h {
                let t = h.hit.t.to_f64();
                assert!(t.is_finite() && t >= 0.0, "t = {t}");
                assert!(h.hit.t_error.to_f64() >= 0.0, "negative t_error");
            }
            h
        })
        .collect()
}

fn check<F: Prec>(input: &Input) {
    let field = if input.mode & 2 != 0 {
        LineField::Vertex
    } else {
        LineField::Face
    };
    let mut options = BuildOptions {
        field,
        seams: input.mode & 4 != 0,
        ..BuildOptions::default()
    };
    let raw = input.mode & 8 != 0;
    let verts: Vec<[f64; 6]> = input
        .vertices
        .iter()
        .take(12)
        .map(|&v| vertex(v, raw))
        .collect();
    if verts.is_empty() {
        return;
    }
    let indices: Vec<[u32; 3]> = input
        .indices
        .iter()
        .take(16)
        .map(|t| t.map(|i| u32::from(i) % (verts.len() as u32 + 1)))
        .collect();
    let rays: Vec<Ray<F>> = input
        .rays
        .iter()
        .take(8)
        .map(|r| {
            let v =
                |a: f32, b: f32, c: f32| F::v(DVec3::new(f64::from(a), f64::from(b), f64::from(c)));
            Ray::new(v(r[0], r[1], r[2]), v(r[3], r[4], r[5]))
        })
        .chain([Ray::new(
            F::v(DVec3::new(3.0, 2.0, 1.0)),
            F::v(DVec3::new(-3.0, -2.0, -1.0)),
        )])
        .collect();
    let (p, n) = split(&verts);
    let Ok(mut scene) = OwnedScene::<F>::build(
        Vertices::packed(&p),
        Vertices::packed(&n),
        &indices,
        &mut options,
    ) else {
        return;
    };
    for u in input.updates.iter().take(4) {
        if u.vertices.is_empty() {
            continue;
        }
        let count = if u.mode & 1 != 0 {
            u.vertices.len().min(16)
        } else {
            verts.len()
        };
        let moved: Vec<[f64; 6]> = (0..count)
            .map(|k| vertex(u.vertices[k % u.vertices.len()], u.mode & 2 != 0))
            .collect();
        let (p, n) = split(&moved);
        let before = hits(&scene, &rays);
        let patches_before = scene.scene().patches().to_vec();
        match scene.update(Vertices::packed(&p), Vertices::packed(&n), &mut options) {
            Err(_) => {
                assert_eq!(
                    scene.scene().patches(),
                    &patches_before[..],
                    "patches changed"
                );
                assert_eq!(
                    hits(&scene, &rays),
                    before,
                    "a failed update changed the hits"
                );
            }
            Ok(report) => {
                let refitted = report.bvh_refitted;
                let fresh = OwnedScene::<F>::build(
                    Vertices::packed(&p),
                    Vertices::packed(&n),
                    &indices,
                    &mut options,
                );
                let (a, got) = (scene.scene(), hits(&scene, &rays));
                let Ok(fresh) = fresh else {
                    // A fresh build refuses a mesh with no usable triangle, where an update
                    // keeps an empty scene: every ray misses.
                    assert_eq!(
                        a.report().patches,
                        0,
                        "an update accepted what a build refuses"
                    );
                    assert!(got.iter().all(Option::is_none), "an empty scene hit");
                    continue;
                };
                let b = fresh.scene();
                assert_eq!(
                    a.patches(),
                    b.patches(),
                    "patches differ from a fresh build"
                );
                assert_eq!(a.seams(), b.seams(), "seams differ from a fresh build");
                assert_eq!(a.triangle_ids(), b.triangle_ids(), "slots differ");
                let (ra, rb) = (a.report(), b.report());
                assert_eq!(
                    (ra.triangles, ra.patches, ra.rejected, ra.remedied),
                    (rb.triangles, rb.patches, rb.rejected, rb.remedied)
                );
                for (x, y) in got.iter().zip(hits(&fresh, &rays)) {
                    match (x, y) {
                        (Some(x), Some(y)) if refitted => {
                            let tol = x.hit.t_error.to_f64().max(y.hit.t_error.to_f64());
                            let d = (x.hit.t.to_f64() - y.hit.t.to_f64()).abs();
                            assert!(d <= tol, "t differs by {d} > t_error {tol}");
                        }
                        (x, y) if !refitted => assert_eq!(*x, y, "hits differ after a rebuild"),
                        (x, y) => assert_eq!(x.is_some(), y.is_some(), "hit vs miss"),
                    }
                }
            }
        }
    }
}

fuzz_target!(|input: Input| {
    if input.mode & 1 != 0 {
        check::<f64>(&input);
    } else {
        check::<f32>(&input);
    }
});
