//! The `smoothtri` binary on hostile files (issue 64): each crafted file ends the process with
//! a non-zero exit and one readable line on stderr naming the file and the field or URI,
//! within a bounded time and without reading outside the asset's folder unless
//! `--allow-outside-folder` is given.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long one run may take: these files fail before any real work (loading, building), in
/// milliseconds; the limit leaves room for a loaded CI machine and a cold start.
const LIMIT: Duration = Duration::from_secs(60);

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = c.iter().fold(0u32, |a, &x| a << 8 | x as u32) << (8 * (3 - c.len()));
        for k in 0..4 {
            out.push(if k <= c.len() {
                B64[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    out
}

/// The issue's file: a POSITION accessor that is sparse, has no `bufferView`, and says
/// `count: 4000000000` (it aborted with "memory allocation of 96000000000 bytes failed").
fn sparse_viewless() -> String {
    let mut bin = 0u32.to_le_bytes().to_vec();
    bin.extend([1f32, 2.0, 3.0].iter().flat_map(|c| c.to_le_bytes()));
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"buffers":[{{"uri":"data:application/octet-stream;base64,{}","byteLength":16}}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":4}},{{"buffer":0,"byteOffset":4,"byteLength":12}}],"accessors":[{{"componentType":5126,"count":4000000000,"type":"VEC3","min":[0,0,0],"max":[1,2,3],"sparse":{{"count":1,"indices":{{"bufferView":0,"componentType":5125}},"values":{{"bufferView":1}}}}}}]}}"#,
        base64(&bin)
    )
}

/// A triangle whose positions are the external buffer `uri` (36 bytes).
fn triangle_with_buffer(uri: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"buffers":[{{"uri":"{uri}","byteLength":36}}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
    )
}

fn triangle_bin() -> Vec<u8> {
    [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect()
}

/// `smoothtri ARGS` in `dir`, within [`LIMIT`]: (exit success, stdout, stderr).
fn run(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_smoothtri"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            panic!("smoothtri {args:?} ran past {LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The run failed with exactly one line on stderr, containing each of `want`.
fn fails_with_one_line(dir: &Path, args: &[&str], want: &[&str]) {
    let (ok, _, err) = run(dir, args);
    assert!(!ok, "{args:?} succeeded: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error: "), "{args:?}: {err}");
    for w in want {
        assert!(err.contains(w), "{args:?}: {err} lacks {w}");
    }
}

#[test]
fn the_sparse_four_billion_file_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("f.gltf"), sparse_viewless()).unwrap();
    for cmd in ["inspect", "render"] {
        let mut args = vec![cmd, "--mesh", "f.gltf"];
        if cmd == "render" {
            args.extend(["--out", "f.png", "--width", "8", "--height", "8"]);
        }
        fails_with_one_line(
            dir.path(),
            &args,
            &["f.gltf: ", "POSITION accessor 0", "over the load budget"],
        );
    }
    assert!(!dir.path().join("f.png").exists());
}

#[test]
fn huge_ply_and_obj_budgets_are_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("v.ply"),
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
         property float y\nproperty float z\nend_header\n0123456789ab",
    )
    .unwrap();
    fails_with_one_line(
        dir.path(),
        &["inspect", "--mesh", "v.ply"],
        &["v.ply: element 'vertex' declares 4000000000 elements"],
    );
}

#[test]
fn buffers_outside_the_folder_need_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let asset = dir.path().join("asset");
    std::fs::create_dir_all(&asset).unwrap();
    std::fs::write(dir.path().join("tri.bin"), triangle_bin()).unwrap();
    for (name, uri) in [
        ("abs.gltf", "/etc/passwd"),
        ("up.gltf", "../../etc/passwd"),
        ("enc.gltf", "%2e%2e/tri.bin"),
        ("zero.gltf", "/dev/zero"),
        ("sib.gltf", "../tri.bin"),
    ] {
        std::fs::write(asset.join(name), triangle_with_buffer(uri)).unwrap();
        fails_with_one_line(
            &asset,
            &["inspect", "--mesh", name],
            &[
                &format!("{name}: buffer URI \"{uri}\""),
                "outside the file's folder",
            ],
        );
    }
    // The flag lets a trusted file read its sibling folder's buffer …
    let (ok, out, err) = run(
        &asset,
        &["inspect", "--mesh", "sib.gltf", "--allow-outside-folder"],
    );
    assert!(ok, "{err}");
    assert!(!out.is_empty());
    // … but never a device.
    fails_with_one_line(
        &asset,
        &["inspect", "--allow-outside-folder", "--mesh", "zero.gltf"],
        &["zero.gltf: buffer URI \"/dev/zero\": not a regular file"],
    );
}
