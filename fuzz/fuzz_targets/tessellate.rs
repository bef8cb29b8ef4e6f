//! Fuzz target `tessellate`: a small arbitrary mesh (up to 8 vertices with normals, up to 8
//! triangles, raw or bounded coordinates) built as the demo builds it and through
//! `smoothtri_host::tessellate` at a uniform level or a `max_error` target, in `f32` or `f64`, then through each writer (OBJ, binary
//! PLY, GLB) and back through the parser of `smoothtri-io` for that format, in memory.
//!
//! Asserts: tessellation returns a result or a typed error; an accepted result has finite
//! positions and normals, indices in range, one origin per triangle, the triangle count of
//! its levels (`Σ L²`, plus stitching fans when levels differ), and vertices at least the mesh
//! vertices it uses; every written file parses back with the same number of triangles and
//! the same positions (exactly, or to the same `f32` values where the file is `f32`). Any
//! panic is a bug.
#![no_main]

use arbitrary::Arbitrary;
use glam::DVec3;
use libfuzzer_sys::fuzz_target;
use smoothtri::{Float, LineField};
use smoothtri_host::tessellate::{Level, tessellate};
use smoothtri_io::{FloatWidth, Mesh};

#[path = "mesh_checks.rs"]
mod mesh_checks;

#[derive(Arbitrary, Debug)]
struct Input {
    /// Bit 0: f32 (else f64); bit 1: raw coordinates (else bounded); bit 2: max-error levels.
    mode: u8,
    level: u8,
    max_error: f64,
    positions: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    triangles: Vec<[u8; 3]>,
}

/// Maps any float into `[-2, 2]` (non-finite to 0).
fn bounded(x: f64) -> f64 {
    if x.is_finite() {
        4.0 * x.fract() / 2.0
    } else {
        0.0
    }
}

fn mesh_of(inp: &Input) -> Option<Mesh> {
    let raw = inp.mode & 2 != 0;
    let n = inp.positions.len().min(inp.normals.len()).min(8);
    if n < 3 {
        return None;
    }
    let conv = |a: [f64; 3]| {
        let v = DVec3::from_array(a);
        if raw {
            v
        } else {
            v.to_array().map(bounded).into()
        }
    };
    let triangles: Vec<[u32; 3]> = inp
        .triangles
        .iter()
        .take(8)
        .map(|t| t.map(|i| (i as usize % n) as u32))
        .collect();
    if triangles.is_empty() {
        return None;
    }
    Some(Mesh {
        positions: inp.positions[..n].iter().map(|&p| conv(p)).collect(),
        normals: inp.normals[..n].iter().map(|&p| conv(p)).collect(),
        triangles,
    })
}

fn check<F: Float>(m: &Mesh, level: Level, width: FloatWidth) {
    let Ok(owned) = smoothtri_host::build_scene::<F>(m, LineField::Face, false) else {
        return;
    };
    let scene = owned.scene();
    let Ok(t) = tessellate(m, &scene, level) else {
        return;
    };
    let out = &t.mesh;
    assert_eq!(out.positions.len(), out.normals.len());
    assert_eq!(out.triangles.len(), t.origins.len());
    assert_eq!(t.levels.len(), scene.patches().len());
    mesh_checks::assert_well_formed(out);
    let grid: usize = t.levels.iter().map(|&l| (l * l) as usize).sum();
    match level {
        Level::Uniform(_) => assert_eq!(out.triangles.len(), grid),
        Level::MaxError { .. } => assert!(out.triangles.len() >= grid),
    }
    for ext in ["obj", "ply", "glb"] {
        let path = format!("/nonexistent-smoothtri-fuzz/out.{ext}");
        let bytes = smoothtri_io::encode(out, &path, width, "fuzz").expect("encode");
        let back = smoothtri_io::parse(&bytes, &path).expect("written file parses back");
        assert_eq!(back.mesh.triangles.len(), out.triangles.len(), "{ext}");
        // f64 files read back exactly; f32 ones (GLB always) to the same f32 values.
        let exact = width == FloatWidth::F64 && ext != "glb";
        for (k, tri) in out.triangles.iter().enumerate() {
            let (p, _) = back.mesh.triangle(k);
            for c in 0..3 {
                let want = out.positions[tri[c] as usize];
                if exact {
                    assert_eq!(p[c], want, "{ext}: position changed");
                } else {
                    assert_eq!(p[c].as_vec3(), want.as_vec3(), "{ext}: position changed");
                }
            }
        }
    }
}

fuzz_target!(|inp: Input| {
    let Some(m) = mesh_of(&inp) else { return };
    let level = if inp.mode & 4 != 0 {
        Level::MaxError {
            max_error: inp.max_error.abs().max(1e-3),
            max_level: 8,
        }
    } else {
        Level::Uniform(1 + inp.level as u32 % 6)
    };
    if inp.mode & 1 != 0 {
        check::<f32>(&m, level, FloatWidth::F32);
    } else {
        check::<f64>(&m, level, FloatWidth::F64);
    }
});
