//! Compiling and running C and C++ programs against the header and the static library.
#![allow(dead_code, clippy::unwrap_used, clippy::panic)]

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
pub fn static_lib() -> &'static str {
    static LIB: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    LIB.get_or_init(|| {
        let exe = std::env::current_exe().unwrap();
        let lib = exe.parent().unwrap().join("libsmoothtri_capi.a");
        assert!(lib.exists(), "{} was not built", lib.display());
        lib.to_str().unwrap().to_owned()
    })
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

/// What a test program links: the static library, `libs`, then the system libraries.
pub fn link_flags<'a>(libs: &[&'a str]) -> Vec<&'a str> {
    let mut flags = vec![static_lib()];
    flags.extend_from_slice(libs);
    flags.extend_from_slice(NATIVE_LIBS);
    flags
}

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

/// The flags of the sanitizer builds: AddressSanitizer (out-of-bounds, use after free, leaks)
/// and UndefinedBehaviorSanitizer in the C and C++ test programs, every report fatal.
pub const SANITIZE: &[&str] = &[
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=all",
    "-fno-omit-frame-pointer",
];

/// Whether `name` is set in the environment (CI sets the `SMOOTHTRI_REQUIRE_*` variables).
fn required(name: &str) -> bool {
    std::env::var_os(name).is_some_and(|v| !v.is_empty())
}

/// Whether the C programs run natively only: `SMOOTHTRI_C_NATIVE_ONLY` is set. CI sets it when
/// it runs the C tests again for each narrower instruction set (`SMOOTHTRI_ISA`): those runs
/// test the kernel's bits, the memory tools' findings do not depend on the instruction set and
/// were checked in the first run, and valgrind cannot run AVX-512 code anyway.
fn native_only() -> bool {
    required("SMOOTHTRI_C_NATIVE_ONLY")
}

/// Whether valgrind can run here: `true` when it is installed; `false` (the caller then runs
/// the program natively, saying so) when it is not, unless `SMOOTHTRI_REQUIRE_VALGRIND` is
/// set, which fails the test instead.
pub fn valgrind_available() -> bool {
    let found = Command::new("valgrind")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        found || !required("SMOOTHTRI_REQUIRE_VALGRIND"),
        "SMOOTHTRI_REQUIRE_VALGRIND is set but valgrind is not installed \
         (apt-get install valgrind)"
    );
    found
}

/// Whether the C compiler builds and runs a program with [`SANITIZE`] (gcc's libasan and
/// libubsan, or clang's runtimes), probed once per test binary; `false` when it cannot, unless
/// `SMOOTHTRI_REQUIRE_SANITIZERS` is set, which fails the test instead.
pub fn sanitizers_available() -> bool {
    static PROBE: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    let probe = PROBE.get_or_init(|| {
        let dir = scratch("sanitizer-probe");
        let src = dir.join("probe.c");
        let exe = dir.join("probe");
        std::fs::write(
            &src,
            "#include <stdlib.h>\nint main(void) { free(malloc(8)); return 0; }\n",
        )
        .map_err(|e| e.to_string())?;
        let out = Command::new("cc")
            .args(SANITIZE)
            .arg(&src)
            .arg("-o")
            .arg(&exe)
            .output()
            .map_err(|e| format!("cc could not run: {e}"))?;
        if !out.status.success() {
            return Err(String::from_utf8_lossy(&out.stderr).into_owned());
        }
        let run = sanitized_command(&exe)
            .output()
            .map_err(|e| e.to_string())?;
        if run.status.success() {
            Ok(())
        } else {
            Err(String::from_utf8_lossy(&run.stderr).into_owned())
        }
    });
    match probe {
        Ok(()) => true,
        Err(why) => {
            assert!(
                !required("SMOOTHTRI_REQUIRE_SANITIZERS"),
                "SMOOTHTRI_REQUIRE_SANITIZERS is set but cc cannot build and run a program \
                 with {SANITIZE:?} (Debian: gcc's libasan8 and libubsan1):\n{why}"
            );
            eprintln!("sanitizers unavailable, sanitizer runs skipped: {why}");
            false
        }
    }
}

/// `exe` with the sanitizers' run-time options: every error fatal with a non-zero exit,
/// leaks reported (LeakSanitizer), stack traces printed.
fn sanitized_command(exe: &Path) -> Command {
    let mut c = Command::new(exe);
    c.env(
        "ASAN_OPTIONS",
        "detect_leaks=1:abort_on_error=0:exitcode=98:strict_string_checks=1:\
         detect_stack_use_after_return=1:check_initialization_order=1",
    )
    .env(
        "UBSAN_OPTIONS",
        "print_stacktrace=1:halt_on_error=1:exitcode=97",
    );
    c
}

/// How a test program runs: [`Mode::Native`], [`Mode::Valgrind`] (memcheck: invalid reads and
/// writes, uninitialised values, definite leaks; any error fails the run) or
/// [`Mode::Sanitizers`] (the program compiled with [`SANITIZE`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mode {
    Native,
    Valgrind,
    Sanitizers,
}

/// The modes a C or C++ test program runs in: under valgrind (or natively when `memcheck` is
/// false: valgrind is too slow for it) and with the sanitizers, each when available (see
/// [`valgrind_available`], [`sanitizers_available`]); natively only under
/// `SMOOTHTRI_C_NATIVE_ONLY` ([`native_only`]).
pub fn modes(memcheck: bool) -> Vec<Mode> {
    if native_only() {
        return vec![Mode::Native];
    }
    let mut modes = vec![if memcheck && valgrind_available() {
        Mode::Valgrind
    } else {
        if memcheck {
            eprintln!("valgrind is not installed: running natively");
        }
        Mode::Native
    }];
    if sanitizers_available() {
        modes.push(Mode::Sanitizers);
    }
    modes
}

/// Compiles `sources` into `exe` for `mode` (with [`SANITIZE`] for [`Mode::Sanitizers`]), as
/// [`compile_c`] does.
pub fn compile_for(mode: Mode, sources: &[PathBuf], exe: &Path, lang: Lang, extra: &[&str]) {
    if mode == Mode::Sanitizers {
        let mut all: Vec<&str> = SANITIZE.to_vec();
        all.extend_from_slice(extra);
        compile_c(sources, exe, lang, &all);
    } else {
        compile_c(sources, exe, lang, extra);
    }
}

/// Compiles the test program `tests/{source}` (C99 for a `.c` file, C++17 for a `.cpp` one)
/// for `mode` ([`compile_for`]) into a fresh scratch folder named after it (with `-san` for the
/// sanitizer build), linked as [`link_flags`] says; returns the executable.
pub fn build_program(source: &str, mode: Mode, libs: &[&str]) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(source);
    let name = src.file_stem().unwrap().to_str().unwrap();
    let sanitized = mode == Mode::Sanitizers;
    let dir = scratch(&format!("{name}{}", if sanitized { "-san" } else { "" }));
    let exe = dir.join(name);
    let lang = if source.ends_with(".cpp") {
        Lang::Cpp17
    } else {
        Lang::C99
    };
    compile_for(mode, &[src], &exe, lang, &link_flags(libs));
    exe
}

/// Runs `exe` with `args` in `mode` and returns its standard output; fails the test on a
/// non-zero exit, which includes every valgrind error (`--error-exitcode`, definite leaks
/// among them) and every sanitizer report.
pub fn run_in(mode: Mode, exe: &Path, args: &[&str]) -> String {
    try_run_in(mode, exe, args).unwrap_or_else(|e| panic!("{e}"))
}

/// [`run_in`] returning the failure (the exit status, standard output and error) instead of
/// failing the test.
pub fn try_run_in(mode: Mode, exe: &Path, args: &[&str]) -> Result<String, String> {
    let mut cmd = match mode {
        Mode::Native => Command::new(exe),
        Mode::Sanitizers => sanitized_command(exe),
        Mode::Valgrind => {
            let mut c = Command::new("valgrind");
            c.args([
                "--quiet",
                "--error-exitcode=99",
                "--track-origins=yes",
                "--leak-check=full",
                "--errors-for-leak-kinds=definite",
                "--show-leak-kinds=definite",
            ])
            .arg(exe);
            c
        }
    };
    let out = cmd
        .args(args)
        .output()
        .map_err(|e| format!("{} could not run: {e}", exe.display()))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "{} failed ({mode:?}, {}):\n{stdout}{}",
            exe.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Runs `exe` with `args` (under valgrind's memcheck when `memcheck` is set and valgrind is
/// installed; see [`run_in`]) and returns its standard output; fails the test on a non-zero
/// exit.
pub fn run(exe: &Path, args: &[&str], memcheck: bool) -> String {
    let mode = if memcheck && !native_only() && valgrind_available() {
        Mode::Valgrind
    } else {
        Mode::Native
    };
    run_in(mode, exe, args)
}
