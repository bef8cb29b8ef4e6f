//! `smoothtri render` end to end: the default render, silhouettes against the analytic sphere
//! (primary-hit masks of every mode, precision and file format), `--compare`, the up axis
//! (`--up`, and `precision`'s camera), and `--verbose`'s CPU kernel.

mod common;

use std::path::Path;

use common::meshes::{glb_bytes, obj_text, ply_text};
use common::{fails, ok, smoothtri, tmp, words, write};
use glam::DVec3;
use smoothtri_testkit::scenes::{cube, icosphere};
use smoothtri_testkit::{Camera, Mesh};

const W: u32 = 96;

const H: u32 = 72;

fn read_pbm(path: &Path) -> (u32, u32, Vec<bool>) {
    let text = std::fs::read_to_string(path).expect("mask");
    let mut it = text.split_whitespace();
    assert_eq!(it.next(), Some("P1"));
    let w: u32 = it.next().and_then(|s| s.parse().ok()).expect("w");
    let h: u32 = it.next().and_then(|s| s.parse().ok()).expect("h");
    let bits: Vec<bool> = it.map(|s| s == "1").collect();
    assert_eq!(bits.len(), (w * h) as usize);
    (w, h, bits)
}

/// Pixels where the render's mask differs from the analytic sphere's silhouette by more than
/// one pixel (no pixel within one pixel in the analytic mask has the render's value).
fn silhouette_violations(mask: &[bool], cam: &Camera, c: DVec3, r: f64) -> usize {
    let (w, h) = (cam.width as i64, cam.height as i64);
    let analytic: Vec<bool> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = cam.pixel_ray(x as u32, y as u32);
            let oc = o - c;
            let b = oc.dot(d);
            let disc = b * b - (oc.length_squared() - r * r);
            disc >= 0.0 && -b + disc.sqrt() > 0.0
        })
        .collect();
    let mut bad = 0;
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if mask[i] == analytic[i] {
                continue;
            }
            let mut near = false;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx >= 0 && yy >= 0 && xx < w && yy < h {
                        near |= analytic[(yy * w + xx) as usize] == mask[i];
                    }
                }
            }
            if !near {
                bad += 1;
            }
        }
    }
    bad
}

fn mask_of(dir: &Path, extra: &[&str]) -> Vec<bool> {
    let (ws, hs) = (W.to_string(), H.to_string());
    let mut args = vec![
        "render", "--width", &ws, "--height", &hs, "--out", "m.png", "--mask", "m.pbm",
    ];
    args.extend_from_slice(extra);
    ok(dir, &args);
    let (w, h, bits) = read_pbm(&dir.join("m.pbm"));
    assert_eq!((w, h), (W, H));
    bits
}

#[test]
fn render_default_writes_png_and_reports() {
    let d = tmp();
    let r = ok(d.path(), &["render", "--width", "48", "--height", "36"]);
    assert!(r.out.contains("smoothtri.png"), "{}", r.out);
    assert!(r.out.contains("rays/s"), "{}", r.out);
    assert!(r.out.contains("N = 4"), "{}", r.out);
    let bytes = std::fs::read(d.path().join("smoothtri.png")).expect("png");
    assert_eq!(&bytes[1..4], b"PNG");
}

#[test]
fn cube_and_icosphere_silhouettes_match_the_sphere_flat_does_not() {
    let d = tmp();
    let cam = Camera::for_mesh(&cube(), 30.0, 35.0, W, H);
    let r3 = 3f64.sqrt();
    let smooth = mask_of(d.path(), &["--scene", "cube"]);
    assert_eq!(silhouette_violations(&smooth, &cam, DVec3::ZERO, r3), 0);
    let f64m = mask_of(d.path(), &["--scene", "cube", "--precision", "f64"]);
    assert_eq!(silhouette_violations(&f64m, &cam, DVec3::ZERO, r3), 0);
    let flat = mask_of(d.path(), &["--scene", "cube", "--mode", "flat"]);
    assert!(silhouette_violations(&flat, &cam, DVec3::ZERO, r3) > 50);
    let ico = icosphere(1, 1.0);
    let cam = Camera::for_mesh(&ico, 30.0, 35.0, W, H);
    let m = mask_of(d.path(), &["--scene", "sphere"]);
    assert_eq!(silhouette_violations(&m, &cam, DVec3::ZERO, 1.0), 0);
    let flat = mask_of(d.path(), &["--scene", "sphere", "--mode", "flat"]);
    assert!(silhouette_violations(&flat, &cam, DVec3::ZERO, 1.0) > 0);
    // Same cube read from files of every format.
    let c = cube();
    write(d.path(), "c.obj", &obj_text(&c, true));
    write(d.path(), "c.ply", &ply_text(&c));
    let cam = Camera::for_mesh(&c, 30.0, 35.0, W, H);
    for f in ["c.obj", "c.ply"] {
        let m = mask_of(d.path(), &["--mesh", f]);
        assert_eq!(silhouette_violations(&m, &cam, DVec3::ZERO, r3), 0, "{f}");
    }
}

#[test]
fn compare_modes_and_views() {
    let d = tmp();
    let r = ok(
        d.path(),
        &words(
            "render --compare --scene torus --width 40 --height 30 --out c.png --view -20,60 \
             --iterations 4",
        ),
    );
    assert!(r.out.contains("c.png"));
    for mode in ["flat", "phong", "smooth"] {
        ok(
            d.path(),
            &[
                "render", "--mode", mode, "--scene", "teapot", "--width", "32", "--height", "24",
                "--out", "t.png",
            ],
        );
    }
}

/// A tall y-up shape: the ellipsoid with semi-axes 1, 3, 1 (the icosphere stretched along y,
/// normals by the inverse transpose).
fn tall_y_up() -> Mesh {
    let mut m = icosphere(2, 1.0);
    for p in &mut m.positions {
        p.y *= 3.0;
    }
    for n in &mut m.normals {
        n.y /= 3.0;
    }
    m
}

/// Width and height in pixels of the hit pixels' bounding box.
fn extent(mask: &[bool]) -> (usize, usize) {
    let (w, h) = (W as usize, H as usize);
    let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
    for y in 0..h {
        for x in 0..w {
            if mask[y * w + x] {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    (x1.saturating_sub(x0) + 1, y1.saturating_sub(y0) + 1)
}

/// `--up`: mesh files default to y up, built-ins to their own axis (z); the same shape written
/// z-up and read with `--up z` gives the same mask as written y-up and read by default; the view
/// is relative to the up axis; glTF is always y-up.
#[test]
fn up_axis_stands_meshes_upright() {
    let d = tmp();
    let p = d.path();
    let tall = tall_y_up();
    write(p, "tall.obj", &obj_text(&tall, true));
    let mut z_up = tall.clone();
    for v in z_up.positions.iter_mut().chain(z_up.normals.iter_mut()) {
        *v = DVec3::new(v.x, -v.z, v.y);
    }
    write(p, "tall_z.obj", &obj_text(&z_up, true));
    std::fs::write(p.join("tall.glb"), glb_bytes(&tall)).expect("glb");

    let upright = mask_of(p, &["--mesh", "tall.obj"]);
    let (w, h) = extent(&upright);
    assert!(h as f64 > 1.5 * w as f64, "y-up shape not upright: {w}x{h}");
    assert_eq!(upright, mask_of(p, &["--mesh", "tall.obj", "--up", "y"]));
    assert_eq!(upright, mask_of(p, &["--mesh", "tall_z.obj", "--up", "z"]));
    // Read with the wrong axis it lies on its side (the bunny).
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.obj", "--up", "z"]));
    assert!(w > h, "z-up reading should lie down: {w}x{h}");
    // The view is relative to the up axis: from straight above, the ellipsoid is a disc.
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.obj", "--view", "0,90"]));
    assert!(w.abs_diff(h) <= 2, "top view {w}x{h}");
    // glTF: y-up by specification (f32 positions, so compare shapes, not masks).
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.glb"]));
    assert!(h as f64 > 1.5 * w as f64, "glTF not upright: {w}x{h}");
    fails(
        p,
        &["render", "--mesh", "tall.glb", "--up", "z"],
        &["--up z", "tall.glb", "y-up by specification"],
    );
    // Built-ins keep their own axis (z): the README's pictures are unchanged.
    let torus = mask_of(p, &["--scene", "torus"]);
    assert_eq!(torus, mask_of(p, &["--scene", "torus", "--up", "z"]));
    assert_ne!(torus, mask_of(p, &["--scene", "torus", "--up", "y"]));
    // `precision` frames a camera too.
    let r = ok(
        p,
        &[
            "precision",
            "--mesh",
            "tall.obj",
            "--up",
            "y",
            "--width",
            "8",
            "--height",
            "6",
        ],
    );
    assert!(r.out.contains("precision study: tall.obj"), "{}", r.out);
}

#[test]
fn verbose_names_the_cpu_kernel_and_smoothtri_isa_is_checked() {
    let d = tmp();
    let args = ["render", "--width", "16", "--height", "12", "--verbose"];
    let r = ok(d.path(), &args);
    let best = smoothtri_isa::Isa::best();
    assert!(r.err.contains(&format!("CPU kernel: {best}")), "{}", r.err);
    // Each instruction set this CPU has, by name; one it lacks or an unknown name is a usage
    // error of one line.
    for isa in smoothtri_isa::Isa::ALL {
        let out = smoothtri()
            .current_dir(d.path())
            .args(args)
            .env(smoothtri_isa::ENV, isa.name())
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        if isa.supported() {
            assert!(out.status.success(), "{isa}: {err}");
            assert!(err.contains(&format!("CPU kernel: {isa}")), "{err}");
        } else {
            assert_eq!(out.status.code(), Some(1), "{isa}: {err}");
            assert!(err.contains("this CPU lacks it"), "{err}");
        }
    }
    let out = smoothtri()
        .current_dir(d.path())
        .args(args)
        .env(smoothtri_isa::ENV, "avx3")
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("names no instruction set"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
