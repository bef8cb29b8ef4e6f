//! What the demo's end-to-end tests share: running the `smoothtri` binary ([`smoothtri`],
//! [`run`], [`ok`], [`fails`], [`output`]) and reading what it gave ([`Run`]), scratch folders
//! and files ([`tmp`], [`write`]), and test meshes as files of each format ([`meshes`]).
#![allow(dead_code)]

pub mod meshes;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The path of the `smoothtri` binary cargo built for the tests.
pub const BIN: &str = env!("CARGO_BIN_EXE_smoothtri");

/// A command of the `smoothtri` binary, without arguments yet.
pub fn smoothtri() -> Command {
    Command::new(BIN)
}

/// What a run gave: its exit code (-1 when a signal ended it), stdout and stderr.
pub struct Run {
    pub code: i32,
    pub out: String,
    pub err: String,
}

impl From<Output> for Run {
    fn from(o: Output) -> Self {
        Run {
            code: o.status.code().unwrap_or(-1),
            out: String::from_utf8_lossy(&o.stdout).into_owned(),
            err: String::from_utf8_lossy(&o.stderr).into_owned(),
        }
    }
}

/// Runs `cmd` to its end; returns (exit code, stdout, stderr).
pub fn output(cmd: &mut Command) -> (i32, String, String) {
    let r = Run::from(cmd.output().expect("run"));
    (r.code, r.out, r.err)
}

/// Runs `smoothtri args` in `dir`, with `stdin` as its standard input (none when `None`).
pub fn run_in(dir: &Path, args: &[&str], stdin: Option<&str>) -> Run {
    let mut c = smoothtri();
    c.current_dir(dir).args(args);
    c.stdin(if stdin.is_some() {
        Stdio::piped()
    } else {
        Stdio::null()
    });
    c.stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = c.spawn().expect("spawn smoothtri");
    if let Some(s) = stdin {
        child
            .stdin
            .take()
            .expect("stdin")
            .write_all(s.as_bytes())
            .expect("write stdin");
    }
    Run::from(child.wait_with_output().expect("wait"))
}

/// Runs `smoothtri args` in `dir` without standard input.
pub fn run(dir: &Path, args: &[&str]) -> Run {
    run_in(dir, args, None)
}

/// Runs and expects success.
pub fn ok(dir: &Path, args: &[&str]) -> Run {
    let r = run(dir, args);
    assert_eq!(r.code, 0, "{args:?} failed: {}", r.err);
    r
}

/// Runs and expects failure with a message containing every `needle`.
pub fn fails(dir: &Path, args: &[&str], needles: &[&str]) -> Run {
    let r = run(dir, args);
    assert_ne!(r.code, 0, "{args:?} should fail; stdout {}", r.out);
    for n in needles {
        assert!(r.err.contains(n), "{args:?}: stderr lacks {n:?}: {}", r.err);
    }
    assert!(!r.err.contains("panicked"), "{args:?} panicked: {}", r.err);
    r
}

/// A fresh scratch folder, removed when dropped.
pub fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("tempdir")
}

/// Writes `text` to `dir/name`; returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

/// `a` followed by `b` (a command's arguments and some more).
pub fn with<'a>(a: &[&'a str], b: &[&'a str]) -> Vec<&'a str> {
    [a, b].concat()
}

/// The words of `line`, a command line without quotes: `words("render --scene cube")`.
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// Whether `xvfb-run` is here to give the viewer a display (Debian's `xvfb` and `xauth`); if
/// not, says so on stderr, and fails where `SMOOTHTRI_REQUIRE_DISPLAY` is set (as CI does).
pub fn xvfb_available() -> bool {
    let found = Command::new("xvfb-run").arg("--help").output().is_ok();
    if !found {
        assert!(
            std::env::var_os("SMOOTHTRI_REQUIRE_DISPLAY").is_none(),
            "SMOOTHTRI_REQUIRE_DISPLAY is set but xvfb-run is missing (apt-get install xvfb xauth)"
        );
        eprintln!("skipped: xvfb-run is missing (apt-get install xvfb xauth)");
    }
    found
}

/// Whether `render --gpu` runs here (a Vulkan adapter: Mesa's lavapipe in CI), tried with its
/// output in `dir`; if not, says on stderr that `what` is skipped, and fails where
/// `SMOOTHTRI_REQUIRE_GPU` is set.
pub fn gpu_renders(dir: &Path, what: &str) -> bool {
    let (code, _, err) = output(
        smoothtri()
            .args(["render", "--gpu", "--width", "8", "--height", "8", "--out"])
            .arg(dir.join("probe.png")),
    );
    if code != 0 {
        assert!(
            std::env::var_os("SMOOTHTRI_REQUIRE_GPU").is_none(),
            "SMOOTHTRI_REQUIRE_GPU is set but render --gpu failed: {err}"
        );
        eprintln!("skipped {what}: {}", err.trim());
    }
    code == 0
}
