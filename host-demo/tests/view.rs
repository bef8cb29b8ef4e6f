//! `smoothtri view`: the headless screenshot equals `render`'s image and hit mask with the same
//! camera, mode and size (CPU, and `--gpu` on the GPU kernel), under `xvfb-run` (Debian's
//! `xvfb` and `xauth`; skipped without them unless `SMOOTHTRI_REQUIRE_DISPLAY` is set, as CI
//! does); without a display the viewer ends with one readable line.

mod common;

use std::path::Path;
use std::process::Command;

use common::{BIN, gpu_renders, output, smoothtri, xvfb_available};

/// `view --frames 2 --screenshot` under xvfb-run against `render` with `args` (mode, size,
/// precision…), both written into `dir`: the PNG and the PBM mask must be equal byte for byte.
/// Returns the viewer's summary line.
fn screenshot_equals_render(dir: &Path, args: &[&str], tag: &str) -> String {
    let (shot, shot_mask) = (
        dir.join(format!("{tag}-view.png")),
        dir.join(format!("{tag}-view.pbm")),
    );
    let (png, mask) = (
        dir.join(format!("{tag}-render.png")),
        dir.join(format!("{tag}-render.pbm")),
    );
    let (code, out, err) = output(
        Command::new("xvfb-run")
            .args([
                "-a",
                "-s",
                "-screen 0 1024x768x24",
                BIN,
                "view",
                "--frames",
                "2",
            ])
            .args(args)
            .arg("--screenshot")
            .arg(&shot)
            .arg("--mask")
            .arg(&shot_mask),
    );
    assert_eq!(code, 0, "view {args:?} failed: {err}");
    let (code, _, err) = output(
        smoothtri()
            .arg("render")
            .args(args)
            .arg("--out")
            .arg(&png)
            .arg("--mask")
            .arg(&mask),
    );
    assert_eq!(code, 0, "render {args:?} failed: {err}");
    assert!(
        std::fs::read(&shot).unwrap() == std::fs::read(&png).unwrap(),
        "view {args:?}: the screenshot differs from render's image"
    );
    assert!(
        std::fs::read(&shot_mask).unwrap() == std::fs::read(&mask).unwrap(),
        "view {args:?}: the hit mask differs from render's"
    );
    assert!(out.starts_with("view: 2 frames of "), "{out}");
    out
}

#[test]
fn headless_screenshots_equal_render_cpu_and_gpu() {
    if !xvfb_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "96", "--height", "72"];
    let cases: [&[&str]; 3] = [
        &[],
        &["--mode", "phong", "--view", "-40,20"],
        &[
            "--scene",
            "teapot",
            "--precision",
            "f64",
            "--normals",
            "geometric",
            "--iterations",
            "8",
        ],
    ];
    for (k, case) in cases.iter().enumerate() {
        let args: Vec<&str> = size.iter().chain(case.iter()).copied().collect();
        let out = screenshot_equals_render(dir.path(), &args, &format!("cpu{k}"));
        assert!(out.contains("(CPU)"), "{out}");
    }
    // The heat map: the same hits (mask), other colours.
    heat_map_keeps_the_hits(dir.path(), &size, "cpu0");
    // The GPU kernel (Mesa's lavapipe in CI): skipped without a Vulkan adapter unless
    // SMOOTHTRI_REQUIRE_GPU is set.
    if !gpu_renders(dir.path(), "the GPU viewer") {
        return;
    }
    // The GPU frames go to the window's wgpu swap chain; the screenshot reads the last back.
    // Smooth with seamless normals (the default), then Phong from another view.
    let args: Vec<&str> = size.iter().copied().chain(["--gpu"]).collect();
    let out = screenshot_equals_render(dir.path(), &args, "gpu");
    assert!(out.contains("(GPU)") && out.contains("seamless"), "{out}");
    let args: Vec<&str> = size
        .iter()
        .copied()
        .chain(["--gpu", "--mode", "phong", "--view", "-40,20"])
        .collect();
    screenshot_equals_render(dir.path(), &args, "gpu-phong");
    // The GPU's heat map: the same hits, other colours (its scale: tests/gpu.rs).
    let args: Vec<&str> = size.iter().copied().chain(["--gpu"]).collect();
    heat_map_keeps_the_hits(dir.path(), &args, "gpu");
}

/// `view --heat` with `args` keeps the hit mask of `render` run by [`screenshot_equals_render`]
/// under `tag` and changes its colours.
fn heat_map_keeps_the_hits(dir: &Path, args: &[&str], tag: &str) {
    let (heat, heat_mask) = (
        dir.join(format!("{tag}-heat.png")),
        dir.join(format!("{tag}-heat.pbm")),
    );
    let (code, _, err) = output(
        Command::new("xvfb-run")
            .args(["-a", BIN, "view", "--frames", "1", "--heat"])
            .args(args)
            .arg("--screenshot")
            .arg(&heat)
            .arg("--mask")
            .arg(&heat_mask),
    );
    assert_eq!(code, 0, "view --heat {args:?} failed: {err}");
    let read = |p: std::path::PathBuf| std::fs::read(p).unwrap();
    assert!(read(heat_mask) == read(dir.join(format!("{tag}-render.pbm"))));
    assert!(read(heat) != read(dir.join(format!("{tag}-render.png"))));
}

#[test]
fn without_a_display_view_is_one_readable_error() {
    let (code, out, err) = output(
        smoothtri()
            .args(["view", "--width", "64", "--height", "48"])
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY"),
    );
    assert_eq!(code, 1, "{out}{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: view: no display"), "{err}");
    assert!(!err.contains("panicked"));
}

#[test]
fn view_options_are_checked() {
    for (args, needle) in [
        (&["--frames", "0"][..], "--frames must be at least 1"),
        (&["--screenshot", "x.png"][..], "need --frames"),
        (
            &["--iterations", "17"][..],
            "--iterations must be in 0..=16",
        ),
        (&["--width", "0"][..], "--width and --height"),
        (&["--gpu", "--precision", "f64"][..], "--gpu traces in f32"),
    ] {
        let (code, _, err) = output(smoothtri().arg("view").args(args));
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
