//! Animation in the demo: `render --time` on the two animated files of `assimp-testmodels`
//! (skipped without them unless `SMOOTHTRI_REQUIRE_ASSETS` is set) and on `--scene twist`; bad
//! `--time`, `--clip` and sources end with one readable line; `view --animate` headless (under
//! `xvfb-run`, skipped without it unless `SMOOTHTRI_REQUIRE_DISPLAY` is set) shows, as frame
//! `k`, `render --time` at `--time + k · FRAME_STEP`, pixel for pixel, on the CPU and (where a
//! Vulkan adapter is, or `SMOOTHTRI_REQUIRE_GPU` is set) on the GPU.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{BIN, gpu_renders, output, smoothtri, xvfb_available};
use smoothtri_demo::animate::FRAME_STEP;

const SKIN: &str = "glTF2/simple_skin/simple_skin.gltf";
const MORPH: &str = "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
const SIZE: [&str; 4] = ["--width", "80", "--height", "60"];

/// The animated file `rel` of `assimp-testmodels`, or `None` (skipped).
fn asset(rel: &str) -> Option<String> {
    let root = smoothtri_testkit::assimp_models().unwrap()?;
    Some(root.join(rel).to_str().unwrap().to_string())
}

/// `render <args> --out dir/tag.png --mask dir/tag.pbm`; returns the two files' bytes.
fn render(dir: &Path, args: &[&str], tag: &str) -> (Vec<u8>, Vec<u8>) {
    let (png, pbm) = (
        dir.join(format!("{tag}.png")),
        dir.join(format!("{tag}.pbm")),
    );
    let (code, _, err) = output(
        smoothtri()
            .arg("render")
            .args(SIZE)
            .args(args)
            .arg("--out")
            .arg(&png)
            .arg("--mask")
            .arg(&pbm),
    );
    assert_eq!(code, 0, "render {args:?}: {err}");
    (std::fs::read(png).unwrap(), std::fs::read(pbm).unwrap())
}

#[test]
fn render_time_poses_the_animated_files() {
    let (Some(skin), Some(morph)) = (asset(SKIN), asset(MORPH)) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // simple_skin: its joint turns by 90° between t = 0 and t = 1, so the silhouette changes;
    // the same time renders the same image; after the last key (5.5 s) the pose holds.
    let a = render(d, &["--mesh", &skin, "--time", "0"], "skin0");
    let b = render(d, &["--mesh", &skin, "--time", "1"], "skin1");
    assert_ne!(a.1, b.1, "the hit mask does not move");
    assert_eq!(a, render(d, &["--mesh", &skin, "--time", "0"], "skin0b"));
    let end = render(d, &["--mesh", &skin, "--time", "5.5"], "skin-end");
    assert_eq!(
        end,
        render(d, &["--mesh", &skin, "--time", "60"], "skin-late")
    );
    // The morph cube: its weights move between the keys (a thin slab by 1.5 s).
    let a = render(d, &["--mesh", &morph, "--time", "0"], "cube0");
    let b = render(
        d,
        &["--mesh", &morph, "--time", "1.5", "--clip", "0"],
        "cube1",
    );
    assert_ne!(a.1, b.1, "the hit mask does not move");
    // Several times: one labelled panel each, side by side (4 pixels apart).
    let (code, out, err) = output(
        smoothtri()
            .args(["render", "--mesh", &skin, "--time", "0, 1,2.5"])
            .args(SIZE)
            .arg("--out")
            .arg(d.join("strip.png")),
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("at 3 times"), "{out}");
    let png = std::fs::read(d.join("strip.png")).unwrap();
    let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
    assert_eq!(width, 3 * 80 + 2 * 4);
    // The compare layout takes the posed mesh as well.
    let (code, out, err) = output(
        smoothtri()
            .args(["render", "--compare", "--mesh", &morph, "--time", "2"])
            .args(SIZE)
            .arg("--out")
            .arg(d.join("cmp.png")),
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("smooth/flat/phong"), "{out}");
}

#[test]
fn render_time_plays_the_twisting_torus() {
    let dir = tempfile::tempdir().unwrap();
    let a = render(dir.path(), &["--scene", "twist", "--time", "0"], "t0");
    let b = render(dir.path(), &["--scene", "twist", "--time", "1"], "t1");
    assert_ne!(a.1, b.1, "the twisting torus does not move");
}

/// Runs `smoothtri <args>` expecting exit code 1 and one line on stderr containing `needle`.
fn one_line_error(args: &[&str], needle: &str) {
    let (code, out, err) = output(smoothtri().args(args));
    assert_eq!(code, 1, "{args:?}: {out}{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(needle),
        "{args:?}: {err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_times_clips_and_sources_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    for t in ["-1", "nan", "NaN", "inf", "-inf", "abc", ""] {
        one_line_error(
            &["render", "--scene", "twist", "--time", t, "--out", out],
            &format!("--time {}", t.trim()),
        );
    }
    // Sources without animation: a built-in scene, an OBJ, a glTF without animations.
    one_line_error(
        &["render", "--scene", "cube", "--time", "1", "--out", out],
        "the cube scene has no animation",
    );
    let cube = smoothtri_testkit::scenes::cube();
    let obj = dir.path().join("cube.obj");
    let glb = dir.path().join("cube.glb");
    for p in [&obj, &glb] {
        smoothtri_io::save(
            &cube,
            p.to_str().unwrap(),
            smoothtri_io::FloatWidth::F32,
            "t",
        )
        .unwrap();
    }
    let path = |p: &PathBuf| p.to_str().unwrap().to_string();
    one_line_error(
        &["render", "--mesh", &path(&obj), "--time", "0", "--out", out],
        "cube.obj has no animation",
    );
    one_line_error(
        &["render", "--mesh", &path(&glb), "--time", "0", "--out", out],
        "cube.glb has no animation",
    );
    one_line_error(
        &[
            "render", "--scene", "twist", "--clip", "1", "--time", "0", "--out", out,
        ],
        "--clip 1: the twist scene has one animation",
    );
    one_line_error(
        &["render", "--scene", "twist", "--clip", "0", "--out", out],
        "--clip needs --time",
    );
    one_line_error(
        &["render", "--scene", "twist", "--time", "0,x", "--out", out],
        "--time x:",
    );
    one_line_error(
        &[
            "render", "--scene", "twist", "--time", "0,1", "--gpu", "--out", out,
        ],
        "several --time values render one panel each on the CPU",
    );
    one_line_error(&["view", "--time", "1"], "--time and --clip need --animate");
    one_line_error(
        &["view", "--animate", "--time", "1,2"],
        "view: --time takes one time",
    );
    one_line_error(&["view", "--animate", "--time", "-2"], "--time -2");
    if let Some(skin) = asset(SKIN) {
        one_line_error(
            &[
                "render", "--mesh", &skin, "--time", "0", "--clip", "1", "--out", out,
            ],
            "has 1 animation (0..1)",
        );
    }
    // A malformed animation: the loader's line, naming the file and the field.
    let bad = dir.path().join("bad.gltf");
    std::fs::write(
        &bad,
        r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
"animations":[{"channels":[{"sampler":0,"target":{"node":5,"path":"rotation"}}],"samplers":[{"input":1,"output":0}]}],
"buffers":[{"byteLength":40,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAA=="}],
"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":4}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5126,"count":1,"type":"SCALAR","min":[0],"max":[0]}]}"#,
    )
    .unwrap();
    one_line_error(
        &["render", "--mesh", &path(&bad), "--time", "0", "--out", out],
        "bad.gltf: animation 0, channel 0 (node 5 rotation): node 5 does not exist",
    );
}

/// `view --animate --time START --frames 3 <args>` (headless, under xvfb-run) writes the frame
/// at START + 2·FRAME_STEP: equal, image and hit mask, to `render --time` at that time.
fn animated_view_equals_render(dir: &Path, args: &[&str], start: f64, tag: &str) {
    let (shot, mask) = (
        dir.join(format!("{tag}-view.png")),
        dir.join(format!("{tag}-view.pbm")),
    );
    let start_s = start.to_string();
    let (code, out, err) = output(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1024x768x24"])
            .arg(BIN)
            .args(["view", "--animate", "--time", &start_s, "--frames", "3"])
            .args(SIZE)
            .args(args)
            .arg("--screenshot")
            .arg(&shot)
            .arg("--mask")
            .arg(&mask),
    );
    assert_eq!(code, 0, "view --animate {args:?}: {err}");
    assert!(out.starts_with("view: 3 frames of "), "{out}");
    let last = (start + 2.0 * FRAME_STEP).to_string();
    let mut rargs: Vec<&str> = args.to_vec();
    rargs.extend(["--time", &last]);
    let (png, pbm) = render(dir, &rargs, &format!("{tag}-render"));
    assert!(
        std::fs::read(&shot).unwrap() == png,
        "{tag}: the frame differs from render's"
    );
    assert!(
        std::fs::read(&mask).unwrap() == pbm,
        "{tag}: the mask differs from render's"
    );
    // And it moved: the first frame (START) differs from the last.
    let first = start.to_string();
    let mut fargs: Vec<&str> = args.to_vec();
    fargs.extend(["--time", &first]);
    let (_, first_mask) = render(dir, &fargs, &format!("{tag}-first"));
    assert!(first_mask != pbm, "{tag}: no motion over two frames");
}

#[test]
fn headless_animation_frames_equal_render_time() {
    if !xvfb_available() {
        return;
    }
    let Some(skin) = asset(SKIN) else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    animated_view_equals_render(d, &["--mesh", &skin, "--view", "-90,10"], 0.3, "skin");
    if let Some(morph) = asset(MORPH) {
        animated_view_equals_render(d, &["--mesh", &morph], 1.2, "cube");
    }
    // The GPU kernel: skipped without a Vulkan adapter unless SMOOTHTRI_REQUIRE_GPU is set.
    if !gpu_renders(d, "the GPU animation") {
        return;
    }
    animated_view_equals_render(
        d,
        &["--mesh", &skin, "--view", "-90,10", "--gpu"],
        0.3,
        "skin-gpu",
    );
}
