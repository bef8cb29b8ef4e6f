//! `smoothtri tessellate` end to end: the output stays on the smooth surface, reloads through
//! the demo's loaders with the welding rule's counts and stays closed, converges on the torus;
//! `--max-error` levels, the checked options and `--picture`.

mod common;

use std::path::Path;

use common::{fails, ok, tmp, words, write};
use smoothtri_testkit::Mesh;

/// Every undirected edge is used by exactly two triangles: the mesh is closed, without cracks
/// or T-junctions.
fn assert_closed(m: &Mesh, what: &str) {
    let mut uses = std::collections::HashMap::<(u32, u32), u32>::new();
    for t in &m.triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let open = uses.values().filter(|&&u| u != 2).count();
    assert_eq!(
        open, 0,
        "{what}: {open} edges not shared by exactly two triangles"
    );
}

/// The number after `key` in `text` (e.g. `"max distance to the smooth surface: "`).
fn figure(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {text}"))
        + key.len();
    let num: String = text[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '+'))
        .collect();
    num.parse()
        .unwrap_or_else(|_| panic!("bad number {num:?} after {key:?}"))
}

fn load(dir: &Path, name: &str) -> Mesh {
    let path = dir.join(name);
    smoothtri_io::load(path.to_str().expect("utf-8 path"))
        .expect("reload")
        .mesh
}

/// A sphere mesh tessellated stays on the sphere: every vertex to 1e-12 (f64) or 1e-6 (f32)
/// relative, normals radial, through every writer and the demo's own loaders.
#[test]
fn tessellated_sphere_stays_on_the_sphere() {
    let d = tmp();
    let p = d.path();
    for (out, prec, tol) in [
        ("s.obj", "f64", 1e-12),
        ("s.ply", "f64", 1e-12),
        ("s32.obj", "f32", 1e-6),
        ("s32.ply", "f32", 1e-6),
        ("s.glb", "f64", 1e-6),
    ] {
        let args = format!("tessellate --scene sphere --level 5 --out {out} --precision {prec}");
        ok(p, &words(&args));
        let m = load(p, out);
        assert_eq!(m.triangles.len(), 80 * 25, "{out}");
        let worst = m
            .positions
            .iter()
            .map(|x| (x.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst <= tol, "{out}: {worst:e} off the sphere");
        for (x, n) in m.positions.iter().zip(&m.normals) {
            assert!(n.normalize().dot(x.normalize()) > 1.0 - 10.0 * tol, "{out}");
        }
        assert_closed(&m, out);
    }
}

/// The output reloads through the demo's loaders (OBJ, binary PLY, GLB) with the printed
/// counts and size; the vertex count is the welding rule's: mesh vertices + shared edges ·
/// (L − 1) + triangles · (L − 1)(L − 2)/2 (torus 8×8: 64 + 192 · 2 + 128 · 1 = 576 at L = 3).
#[test]
fn tessellation_reloads_with_the_welding_rules_counts() {
    let d = tmp();
    let p = d.path();
    for out in ["t.obj", "t.ply", "t.glb"] {
        let r = ok(
            p,
            &words(&format!("tessellate --scene torus --level 3 --out {out}")),
        );
        let size = std::fs::metadata(p.join(out)).expect("output").len();
        assert!(
            r.out.contains(&format!(
                "wrote {out}: 1152 triangles, 576 vertices, {size} bytes"
            )),
            "{}",
            r.out
        );
        assert!(
            r.out
                .contains("welded 384 edge samples on 192 shared edges"),
            "{}",
            r.out
        );
        let m = load(p, out);
        assert_eq!((m.triangles.len(), m.positions.len()), (1152, 576), "{out}");
        assert_closed(&m, out);
        let r = ok(p, &["inspect", "--mesh", out]);
        assert!(
            r.out.contains("triangles: 1152   vertices: 576"),
            "{}",
            r.out
        );
    }
}

/// On the torus the tessellation converges to the smooth surface (distance ÷ ~4 per doubling of
/// L), and its distance to the true torus tends to the smooth surface's own: within 10 % at
/// L = 8. The distances to the torus are measured here, on the reloaded file, independently of
/// the command's figures.
#[test]
fn tessellated_torus_tends_to_the_smooth_surfaces_distance() {
    use smoothtri::DPatch;
    use smoothtri_testkit::scenes::{torus, torus_distance};
    let d = tmp();
    let p = d.path();
    let mesh = torus(8, 8, 1.0, 0.4);
    let mut smooth = 0.0f64;
    for t in 0..mesh.triangles.len() {
        let (pp, nn) = mesh.triangle(t);
        let patch = DPatch::new_or_tilted(pp, nn).expect("torus patch");
        for i in 0..=12 {
            for j in 0..=12 - i {
                let x = patch.point(i as f64 / 12.0, j as f64 / 12.0);
                smooth = smooth.max(torus_distance(x, 1.0, 0.4));
            }
        }
    }
    let probes = [
        [1.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    ];
    let mut last = (f64::INFINITY, f64::INFINITY);
    for l in ["2", "4", "8"] {
        let out = format!("t{l}.obj");
        let r = ok(
            p,
            &words(&format!("tessellate --scene torus --level {l} --out {out}")),
        );
        let to_surface = figure(&r.out, "max distance to the smooth surface: ");
        let m = load(p, &out);
        let mut to_torus = 0.0f64;
        for t in &m.triangles {
            let v = t.map(|i| m.positions[i as usize]);
            for rot in 0..3 {
                for w in probes {
                    let x = v[rot] * w[0] + v[(rot + 1) % 3] * w[1] + v[(rot + 2) % 3] * w[2];
                    to_torus = to_torus.max(torus_distance(x, 1.0, 0.4));
                }
            }
        }
        eprintln!(
            "L = {l}: to the smooth surface {to_surface:.3e}, to the torus {to_torus:.3e} \
             (smooth surface {smooth:.3e})"
        );
        assert!(
            to_surface < last.0 / 3.0 && to_torus < last.1,
            "L = {l}: no convergence"
        );
        let printed = figure(&r.out, "max distance to the exact torus: ");
        assert!((printed - to_torus).abs() <= 0.02 * to_torus, "{}", r.out);
        last = (to_surface, to_torus);
    }
    assert!(
        (last.1 - smooth).abs() <= 0.1 * smooth,
        "L = 8: {:.3e} vs the smooth surface's {smooth:.3e}",
        last.1
    );
}

/// `--max-error`: levels chosen per patch (powers of two), the shared edges at the larger
/// level with stitched fans, and the output still closed; the measured distance meets the
/// target.
#[test]
fn max_error_levels_differ_and_stay_watertight() {
    let d = tmp();
    let p = d.path();
    let r = ok(
        p,
        &words("tessellate --scene torus --max-error 1e-2 --out e.ply"),
    );
    // The torus's patches on the outer equator are flatter than those on the inner one.
    let kinds = r.out.lines().next().unwrap_or("").matches("× L = ").count();
    assert!(kinds >= 2, "one level only: {}", r.out);
    let dist = figure(&r.out, "max distance to the smooth surface: ");
    assert!(dist <= 1e-2, "{}", r.out);
    assert_closed(&load(p, "e.ply"), "e.ply");
}

#[test]
fn tessellate_options_are_checked() {
    let d = tmp();
    let p = d.path();
    let t = ["tessellate", "--scene", "cube"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { [&t[..], extra].concat() };
    fails(
        p,
        &with(&["--level", "0", "--out", "x.obj"]),
        &["--level", "1..=256"],
    );
    fails(
        p,
        &with(&["--level", "300", "--out", "x.obj"]),
        &["--level"],
    );
    fails(
        p,
        &with(&["--max-error", "0", "--out", "x.obj"]),
        &["--max-error"],
    );
    fails(
        p,
        &with(&["--max-error", "NaN", "--out", "x.obj"]),
        &["--max-error"],
    );
    fails(
        p,
        &with(&["--max-error", "1e-3", "--max-level", "3", "--out", "x.obj"]),
        &["power of two"],
    );
    fails(
        p,
        &with(&["--level", "2", "--max-error", "1e-3", "--out", "x.obj"]),
        &["cannot be used"],
    );
    fails(
        p,
        &with(&["--out", "x.stl"]),
        &["x.stl", ".obj, .ply or .glb"],
    );
    fails(p, &with(&[]), &["--out"]);
    fails(p, &["tessellate", "--out", "x.obj"], &["--mesh"]);
    fails(
        p,
        &with(&["--out", "/nonexistent-dir/x.obj"]),
        &["/nonexistent-dir/x.obj"],
    );
    fails(
        p,
        &with(&["--out", "x.obj", "--picture", "x.obj"]),
        &["--picture x.obj", "must end in .png"],
    );
    write(p, "tri.gltf", "{ not json");
    fails(
        p,
        &["tessellate", "--mesh", "tri.gltf", "--out", "x.obj"],
        &["tri.gltf", "malformed glTF"],
    );
}

/// `--picture`: the traced smooth surface and the flat-shaded tessellation side by side.
#[test]
fn tessellate_picture_has_two_panels() {
    let d = tmp();
    let p = d.path();
    let picture = "--picture t.png --width 40 --height 30";
    let r = ok(
        p,
        &words(&format!(
            "tessellate --scene torus --level 2 --out t.obj {picture}"
        )),
    );
    assert!(r.out.contains("wrote t.png"), "{}", r.out);
    let png = std::fs::read(p.join("t.png")).expect("png");
    let be = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().expect("4 bytes"));
    assert_eq!((be(16), be(20)), (84, 30));
}
