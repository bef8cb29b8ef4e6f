//! Compiling and running C and C++ programs against the header and the static library.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// `capi/include`.
pub fn include_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("include")
}

/// A fresh folder for one test's files under the target directory.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("capi")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The static library cargo built with this test: `cargo test` compiles the library target
/// with all its crate types into `target/<profile>/deps/` (it copies them up to
/// `target/<profile>/` only for `cargo build`).
pub fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let lib = deps.join("libsmoothtri_capi.a");
    assert!(lib.exists(), "{} was not built", lib.display());
    lib
}

/// The system libraries a Rust static library needs on this platform
/// (`cargo rustc -p smoothtri-capi --crate-type staticlib -- --print native-static-libs`).
pub const NATIVE_LIBS: &[&str] = &[
    "-lgcc_s",
    "-lutil",
    "-lrt",
    "-lpthread",
    "-lm",
    "-ldl",
    "-lc",
];

/// The language of a compile.
#[derive(Clone, Copy)]
pub enum Lang {
    C99,
    Cpp17,
}

/// Compiles `sources` into `exe` with every warning an error, against `capi/include`, adding
/// `extra` (libraries, defines) at the end of the command line.
pub fn compile_c(sources: &[PathBuf], exe: &Path, lang: Lang, extra: &[&str]) {
    let (cc, std) = match lang {
        Lang::C99 => ("cc", "-std=c99"),
        Lang::Cpp17 => ("c++", "-std=c++17"),
    };
    let mut cmd = Command::new(cc);
    cmd.args([std, "-Wall", "-Wextra", "-Werror", "-pedantic", "-g", "-O1"])
        .arg("-I")
        .arg(include_dir())
        .args(sources)
        .arg("-o")
        .arg(exe)
        .args(extra);
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{cc} could not run: {e}"));
    assert!(
        out.status.success(),
        "{cc} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `exe` with `args` (under valgrind's memcheck when `memcheck` is set and valgrind is
/// installed: its errors fail the run) and returns its standard output; fails the test on a
/// non-zero exit.
pub fn run(exe: &Path, args: &[&str], memcheck: bool) -> String {
    let valgrind = memcheck && Command::new("valgrind").arg("--version").output().is_ok();
    let mut cmd = if valgrind {
        let mut c = Command::new("valgrind");
        c.args(["--quiet", "--error-exitcode=99", "--track-origins=yes"])
            .arg(exe);
        c
    } else {
        Command::new(exe)
    };
    let out = cmd.args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{} failed ({}):\n{stdout}{}",
        exe.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}
