//! Outputs that lose nothing (`smoothtri_demo::output`), end to end through the binary: an
//! output that is an input (the same path, `./`, `dir/..`, a symbolic or hard link) is refused
//! before any work and the input stays byte for byte; an output's extension must name its
//! format; two outputs cannot name one file; a write that fails (the target a folder, a file
//! size limit reached mid-write) leaves the old contents; no temporary file is ever left.

mod common;

use std::path::Path;
use std::process::Command;

use common::{Run, fails, ok, tmp, with};
use smoothtri_io::FloatWidth;
use smoothtri_testkit::scenes::cube;

/// Runs, expects failure with one error line (no panic) containing every needle.
fn refused(dir: &Path, args: &[&str], needles: &[&str]) -> Run {
    let r = fails(dir, args, needles);
    let errors: Vec<&str> = r.err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{args:?}: one error line: {}", r.err);
    r
}

/// The names in `dir`, sorted (temporary files included: they start with a dot).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("read_dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn sorted(v: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = v.iter().map(|s| s.to_string()).collect();
    v.sort();
    v
}

/// The cube written as `name` in `dir` (its format by extension); returns its bytes.
fn mesh_file(dir: &Path, name: &str) -> Vec<u8> {
    let bytes = smoothtri_io::encode(&cube(), name, FloatWidth::F32, "a cube").expect("encode");
    std::fs::write(dir.join(name), &bytes).expect("write");
    bytes
}

const SMALL: [&str; 4] = ["--width", "24", "--height", "18"];

#[cfg(unix)]
#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    use std::os::unix::fs::symlink;
    let d = tmp();
    let p = d.path();
    let glb = mesh_file(p, "m.glb");
    let obj = mesh_file(p, "m.obj");
    symlink("m.glb", p.join("link.glb")).expect("symlink");
    symlink("m.obj", p.join("pic.png")).expect("symlink");
    symlink("m.obj", p.join("plot.svg")).expect("symlink");
    std::fs::hard_link(p.join("m.glb"), p.join("hard.glb")).expect("hard link");
    std::fs::create_dir(p.join("sub")).expect("sub");
    let before = names(p);
    let tess = ["tessellate", "--mesh", "m.glb", "--level", "1"];
    for out in ["m.glb", "./m.glb", "sub/../m.glb", "link.glb", "hard.glb"] {
        refused(
            p,
            &with(&tess, &["--out", out]),
            &[
                &format!("--out {out} is the input --mesh m.glb"),
                "refusing to overwrite",
            ],
        );
    }
    let absolute = p.join("m.glb");
    refused(
        p,
        &with(&tess, &["--out", absolute.to_str().expect("UTF-8")]),
        &["is the input --mesh m.glb"],
    );
    // Outputs of other formats, through links named for their format.
    refused(
        p,
        &[
            "tessellate",
            "--mesh",
            "m.obj",
            "--out",
            "t.ply",
            "--picture",
            "pic.png",
        ],
        &["--picture pic.png is the input --mesh m.obj"],
    );
    refused(
        p,
        &with(&["render", "--mesh", "m.obj", "--out", "pic.png"], &SMALL),
        &["--out pic.png is the input --mesh m.obj"],
    );
    refused(
        p,
        &with(
            &["precision", "--mesh", "m.obj", "--plot", "plot.svg"],
            &SMALL,
        ),
        &["--plot plot.svg is the input --mesh m.obj"],
    );
    // `view` refuses before it looks for a display.
    refused(
        p,
        &[
            "view",
            "--mesh",
            "m.obj",
            "--frames",
            "1",
            "--screenshot",
            "pic.png",
        ],
        &["--screenshot pic.png is the input --mesh m.obj"],
    );
    assert_eq!(std::fs::read(p.join("m.glb")).expect("m.glb"), glb);
    assert_eq!(std::fs::read(p.join("m.obj")).expect("m.obj"), obj);
    assert_eq!(names(p), before, "nothing written, no temporary file");
    // An output that does not exist yet is no input; the refused one is written elsewhere.
    ok(p, &with(&tess, &["--out", "sub/m.glb"]));
    assert_eq!(std::fs::read(p.join("m.glb")).expect("m.glb"), glb);
    assert_eq!(names(&p.join("sub")), sorted(&["m.glb"]));
}

#[cfg(unix)]
#[test]
fn two_outputs_naming_one_file_are_refused() {
    let d = tmp();
    let p = d.path();
    // A dangling link: the mask would be written over the image written just before.
    std::os::unix::fs::symlink("out.png", p.join("mask.pbm")).expect("symlink");
    refused(
        p,
        &with(
            &["render", "--out", "out.png", "--mask", "mask.pbm"],
            &SMALL,
        ),
        &["--out out.png and --mask mask.pbm name the same file"],
    );
    assert_eq!(names(p), sorted(&["mask.pbm"]));
}

#[test]
fn an_output_must_have_its_formats_extension() {
    let d = tmp();
    let p = d.path();
    let obj = mesh_file(p, "a.obj");
    let cases: [(Vec<&str>, &str); 8] = [
        (
            with(&["render", "--out", "a.obj"], &SMALL),
            "--out a.obj: the output is a PNG image, so its name must end in .png",
        ),
        (
            with(&["render", "--out", "r.png", "--mask", "r.png.txt"], &SMALL),
            "--mask r.png.txt: the output is a PBM mask, so its name must end in .pbm",
        ),
        (
            vec!["tessellate", "--scene", "cube", "--out", "x.stl"],
            "--out x.stl: the output is a mesh, so its name must end in .obj, .ply or .glb",
        ),
        (
            vec![
                "tessellate",
                "--scene",
                "cube",
                "--out",
                "x.obj",
                "--picture",
                "x.jpg",
            ],
            "--picture x.jpg: the output is a PNG image, so its name must end in .png",
        ),
        (
            with(&["precision", "--csv", "p.txt"], &SMALL),
            "--csv p.txt: the output is a CSV table, so its name must end in .csv",
        ),
        (
            with(&["precision", "--plot", "p.png"], &SMALL),
            "--plot p.png: the output is an SVG plot, so its name must end in .svg",
        ),
        (
            with(&["precision", "--strip", "s"], &SMALL),
            "--strip s: the output is a PNG image, so its name must end in .png",
        ),
        (
            vec!["view", "--frames", "1", "--screenshot", "v.ppm"],
            "--screenshot v.ppm: the output is a PNG image, so its name must end in .png",
        ),
    ];
    for (args, needle) in &cases {
        refused(p, args, &[needle]);
    }
    assert_eq!(
        std::fs::read(p.join("a.obj")).expect("a.obj"),
        obj,
        "the mesh kept"
    );
    assert_eq!(names(p), sorted(&["a.obj"]), "nothing written");
    // Extensions compare without case; `-` is stdout.
    ok(p, &with(&["render", "--out", "UPPER.PNG"], &SMALL));
    let r = ok(p, &with(&["render", "--out", "-"], &SMALL));
    // The signature's first byte, 0x89, is not UTF-8: the lossy text shows U+FFFD before "PNG".
    assert!(r.out.starts_with("\u{FFFD}PNG\r\n"), "a PNG on stdout");
    assert_eq!(names(p), sorted(&["UPPER.PNG", "a.obj"]));
}

#[test]
fn a_missing_folder_is_refused_before_the_work() {
    let d = tmp();
    let p = d.path();
    refused(
        p,
        &["tessellate", "--scene", "cube", "--out", "none/x.obj"],
        &["cannot write none/x.obj: its folder none does not exist"],
    );
    assert!(names(p).is_empty());
}

/// Every command's outputs written afresh and over old files: each in place, complete (the
/// format's signature), the permissions of the file replaced kept, a link written through,
/// and nothing else in the folder.
#[cfg(unix)]
#[test]
fn outputs_replace_old_files_whole_and_leave_nothing_else() {
    use std::os::unix::fs::PermissionsExt;
    let d = tmp();
    let p = d.path();
    std::fs::create_dir(p.join("real")).expect("real");
    std::os::unix::fs::symlink("real/t.obj", p.join("t.obj")).expect("symlink");
    for f in [
        "r.png",
        "r.pbm",
        "p.csv",
        "p.svg",
        "s.png",
        "real/t.obj",
        "pic.png",
    ] {
        std::fs::write(p.join(f), "old contents").expect("old");
        std::fs::set_permissions(p.join(f), std::fs::Permissions::from_mode(0o640)).expect("chmod");
    }
    ok(
        p,
        &with(&["render", "--out", "r.png", "--mask", "r.pbm"], &SMALL),
    );
    ok(
        p,
        &with(
            &[
                "precision",
                "--csv",
                "p.csv",
                "--plot",
                "p.svg",
                "--strip",
                "s.png",
            ],
            &SMALL,
        ),
    );
    ok(
        p,
        &with(
            &[
                "tessellate",
                "--scene",
                "cube",
                "--level",
                "1",
                "--out",
                "t.obj",
                "--picture",
                "pic.png",
            ],
            &SMALL,
        ),
    );
    let starts = [
        ("r.png", &b"\x89PNG"[..]),
        ("s.png", b"\x89PNG"),
        ("pic.png", b"\x89PNG"),
        ("r.pbm", b"P1"),
        ("p.csv", b"precision,"),
        ("p.svg", b"<svg"),
        ("real/t.obj", b"#"),
    ];
    for (f, magic) in starts {
        let bytes = std::fs::read(p.join(f)).expect("output");
        assert!(
            bytes.starts_with(magic),
            "{f}: {:?}",
            &bytes[..bytes.len().min(16)]
        );
        let mode = std::fs::metadata(p.join(f))
            .expect("meta")
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o640, "{f}: the old file's permissions");
    }
    assert!(
        std::fs::symlink_metadata(p.join("t.obj"))
            .expect("link")
            .file_type()
            .is_symlink(),
        "the link stays a link"
    );
    let obj = std::fs::read_to_string(p.join("real/t.obj")).expect("t.obj");
    assert!(obj.contains("\nf "), "the tessellation through the link");
    assert_eq!(
        names(p),
        sorted(&[
            "r.png", "r.pbm", "p.csv", "p.svg", "s.png", "real", "t.obj", "pic.png"
        ])
    );
    assert_eq!(names(&p.join("real")), sorted(&["t.obj"]));
}

/// A target that cannot be replaced (a folder): the write fails with the path named, the
/// folder and its contents stay, and no temporary file is left. Works as root too.
#[test]
fn a_failed_rename_leaves_the_target_and_no_temporary_file() {
    let d = tmp();
    let p = d.path();
    std::fs::create_dir(p.join("out.png")).expect("a folder named like the output");
    std::fs::write(p.join("out.png/keep.txt"), "kept").expect("keep");
    refused(
        p,
        &with(&["render", "--out", "out.png"], &SMALL),
        &["out.png"],
    );
    assert_eq!(
        std::fs::read_to_string(p.join("out.png/keep.txt")).expect("keep"),
        "kept"
    );
    assert_eq!(names(p), sorted(&["out.png"]));
    assert_eq!(names(&p.join("out.png")), sorted(&["keep.txt"]));
}

/// A write that fails midway (the file size limit, `ulimit -f`, which binds root too, with
/// SIGXFSZ ignored so that the write returns EFBIG): the old file keeps its contents and no
/// temporary file is left. A plain `fs::write` would have truncated the old file.
#[cfg(target_os = "linux")]
#[test]
fn a_write_that_fails_midway_leaves_the_old_file() {
    let d = tmp();
    let p = d.path();
    let args = ["render", "--width", "320", "--height", "240", "--out"];
    // The limit below is 1 KiB at most (POSIX sh counts 512-byte blocks, bash 1024); the image
    // is larger, so the write must fail past its start.
    ok(p, &with(&args, &["probe.png"]));
    let size = std::fs::metadata(p.join("probe.png")).expect("probe").len();
    assert!(size > 4096, "the image must exceed the limit: {size} bytes");
    std::fs::remove_file(p.join("probe.png")).expect("rm");
    let old = b"old contents of big.png".to_vec();
    std::fs::write(p.join("big.png"), &old).expect("old");
    let o = Command::new("sh")
        .current_dir(p)
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 1 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_smoothtri"))
        .args(with(&args, &["big.png"]))
        .output()
        .expect("sh");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "the write should fail: {err}");
    assert!(err.contains("big.png"), "the error names the file: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(std::fs::read(p.join("big.png")).expect("big.png"), old);
    assert_eq!(names(p), sorted(&["big.png"]));
}
