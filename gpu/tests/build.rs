//! `GpuPatchBuild`: the patches built on the device equal the CPU's `Patch::new_or_tilted`
//! records within rounding, with the same remedy byte and the same placeholders, on the built-in
//! scenes, a posed twisting torus, steep normals that need the remedy and malformed triangles.
//! `cargo test -p smoothtri-gpu --test build`.

mod common;
use common::*;
use glam::{DVec3, Vec3};
use smoothtri::{LineField, NORMAL_CLAMP_DEG, Patch, PatchError};
use smoothtri_gpu::{GpuError, GpuPatchBuild, PATCH_VEC4, smooth_record};
use smoothtri_testkit::Mesh;
use smoothtri_testkit::scenes::{builtin, tilted_normal_sphere};
use smoothtri_testkit::twist::{twist_pose, twisting_torus};

/// The largest difference allowed between a device record's value and the CPU's, relative to
/// the record's length scale for lengths and positions, absolute for unit vectors and ratios:
/// the two differ by the rounding of the shell's sampled heights (the kernel's height against
/// the CPU's lane evaluation, `tests/parity.rs`) and of single operations.
const RECORD_TOL: f32 = 4e-6;

/// The CPU's `remedy` byte of the patch of `p`, `n` (as the device reports it).
fn cpu_remedy(r: &Result<Patch, PatchError>) -> u32 {
    match r {
        Ok(p) => p.normal_clamp().map_or(0, |deg| {
            1 + NORMAL_CLAMP_DEG.iter().position(|&d| d == deg).expect("a listed clamp") as u32
        }),
        Err(e) => {
            0x80 | match *e {
                PatchError::NonFinite => 1,
                PatchError::DegenerateTriangle => 2,
                PatchError::ZeroNormal { vertex } => 3 + u32::from(vertex),
                PatchError::BackFacingNormal { vertex } => 6 + u32::from(vertex),
                PatchError::InvalidShell => 9,
                PatchError::OutOfRange => 10,
            }
        }
    }
}

fn f32s(v: &[DVec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.as_vec3().to_array()).collect()
}

/// Builds `m` on the device and on the CPU and compares every record; returns the worst
/// scaled difference and the device's remedy bytes (empty without a device).
fn compare(name: &str, m: &Mesh) -> (f32, Vec<u32>) {
    let Some(gpu) = gpu() else {
        return (0.0, Vec::new());
    };
    let b = GpuPatchBuild::new(&gpu, m.positions.len(), &m.triangles, LineField::Face)
        .expect("the device build");
    b.write_vertices(&f32s(&m.positions), &f32s(&m.normals))
        .expect("vertices");
    let (records, remedy) = b.run_and_read().expect("the pass runs");
    assert_eq!(records.len(), m.triangles.len() * PATCH_VEC4 * 4, "{name}");
    assert_eq!(remedy.len(), m.triangles.len(), "{name}");
    let mut worst = 0.0f32;
    for (t, tri) in m.triangles.iter().enumerate() {
        let corner = |i: u32, v: &[DVec3]| {
            v.get(i as usize)
                .map_or(Vec3::splat(f32::NAN), |p| p.as_vec3())
        };
        let p = tri.map(|i| corner(i, &m.positions));
        let n = tri.map(|i| corner(i, &m.normals));
        let cpu = Patch::<f32>::new_or_tilted(p, n);
        assert_eq!(
            remedy[t],
            cpu_remedy(&cpu),
            "{name}: triangle {t}: device remedy {:#x}, CPU {cpu:?}",
            remedy[t]
        );
        let want = smooth_record(&cpu.unwrap_or_default().data());
        let got = &records[t * PATCH_VEC4 * 4..(t + 1) * PATCH_VEC4 * 4];
        // Lengths are compared on the record's scale (4 × longest edge + |origin|, slot 3).
        let scale = want[3].max(f32::MIN_POSITIVE);
        for (k, (&g, &w)) in got.iter().zip(&want).enumerate() {
            if g.to_bits() == w.to_bits() {
                continue;
            }
            let d = (g - w).abs() / scale.max(1.0).max(w.abs());
            worst = worst.max(d);
            assert!(
                d <= RECORD_TOL,
                "{name}: triangle {t}, record value {k}: device {g:e}, CPU {w:e} (scaled \
                 difference {d:e})"
            );
        }
    }
    (worst, remedy)
}

#[test]
fn device_patches_equal_the_cpu_patches_on_the_built_in_scenes() {
    for name in ["torus", "sphere", "cube", "teapot"] {
        let m = builtin(name).expect("a built-in scene");
        let (worst, _) = compare(name, &m);
        eprintln!("{name}: worst scaled difference {worst:e}");
    }
}

#[test]
fn device_patches_follow_a_deforming_mesh() {
    let mut m = twisting_torus(16, 0.0);
    for t in [0.0, 0.7, 2.3] {
        twist_pose(16, t, &mut m.positions, &mut m.normals);
        let (worst, _) = compare(&format!("twist at {t}"), &m);
        eprintln!("twist at {t}: worst scaled difference {worst:e}");
    }
}

#[test]
fn steep_normals_take_the_cpu_remedy() {
    let mut m = tilted_normal_sphere();
    compare("tilted-normal sphere", &m);
    // Tip every other normal further, past what the construction accepts unclamped.
    for (k, n) in m.normals.iter_mut().enumerate() {
        let tip = DVec3::new(0.9, -0.4, 0.2) * (k % 3) as f64;
        *n = (*n + tip).normalize();
    }
    let (_, remedy) = compare("tipped normals", &m);
    let clamped = remedy.iter().filter(|&&r| (1..0x80).contains(&r)).count();
    eprintln!("tipped normals: {clamped} of {} patches clamped", remedy.len());
    assert!(remedy.is_empty() || clamped > 0, "the test tips no normal far enough");
}

#[test]
fn malformed_triangles_get_the_cpu_placeholders() {
    let mut m = builtin("torus").expect("torus");
    let v = m.positions.len() as u32;
    m.triangles.push([0, 0, 1]); // degenerate
    m.triangles.push([0, 1, v + 5]); // an index out of range
    let far = m.positions.len();
    m.positions.push(DVec3::new(f64::NAN, 0.0, 0.0));
    m.normals.push(DVec3::Z);
    m.triangles.push([0, 1, far as u32]); // a non-finite vertex
    m.positions.push(DVec3::new(3.0, 0.0, 0.0));
    m.normals.push(DVec3::ZERO);
    m.triangles.push([0, 1, far as u32 + 1]); // a zero normal
    let (_, remedy) = compare("malformed", &m);
    if let [.., a, b, c, d] = remedy[..] {
        // Degenerate; out of range and non-finite (both NonFinite); a zero normal, which the
        // remedy replaces by the face normal (then clamps as its neighbours need).
        assert_eq!([a, b, c], [0x82, 0x81, 0x81], "{remedy:?}");
        assert!((1..0x80).contains(&d), "{d:#x}");
    }
}

#[test]
fn bad_vertex_buffers_are_typed_errors() {
    let Some(gpu) = gpu() else { return };
    let m = builtin("cube").expect("cube");
    assert!(matches!(
        GpuPatchBuild::new(&gpu, m.positions.len(), &m.triangles, LineField::Vertex),
        Err(GpuError::Unsupported(_))
    ));
    let b = GpuPatchBuild::new(&gpu, m.positions.len(), &m.triangles, LineField::Face)
        .expect("the device build");
    let p = f32s(&m.positions);
    assert_eq!(
        b.write_vertices(&p[1..], &p),
        Err(GpuError::VertexCount {
            expected: p.len(),
            given: p.len() - 1
        })
    );
}
