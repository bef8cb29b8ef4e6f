//! The checked-in header is what cbindgen makes of the sources (regenerated here; run with
//! `SMOOTHTRI_BLESS=1` to rewrite it after changing the API), and it compiles alone as C99 and
//! C++17 with every warning an error.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::Path;

#[test]
fn header_is_generated_from_the_sources() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut fresh = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen reads the sources")
        .write(&mut fresh);
    let fresh = String::from_utf8(fresh).expect("UTF-8");
    let path = dir.join("include/smoothtri.h");
    if std::env::var_os("SMOOTHTRI_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("write the header");
    }
    let checked_in = std::fs::read_to_string(&path).expect("include/smoothtri.h");
    assert!(
        checked_in == fresh,
        "capi/include/smoothtri.h differs from what cbindgen makes of capi/src; rerun with \
         SMOOTHTRI_BLESS=1 and commit the header"
    );
}

#[test]
fn header_version_macros_match_the_crate() {
    let header = std::fs::read_to_string(common::include_dir().join("smoothtri.h")).unwrap();
    for (name, value) in [
        ("MAJOR", env!("CARGO_PKG_VERSION_MAJOR")),
        ("MINOR", env!("CARGO_PKG_VERSION_MINOR")),
        ("PATCH", env!("CARGO_PKG_VERSION_PATCH")),
    ] {
        let line = format!("#define SMOOTHTRI_VERSION_{name} {value}\n");
        assert!(header.contains(&line), "the header lacks `{}`", line.trim());
    }
}

#[test]
fn header_includes_only_the_standard_headers() {
    let header = std::fs::read_to_string(common::include_dir().join("smoothtri.h")).unwrap();
    let includes: Vec<&str> = header
        .lines()
        .filter(|l| l.trim_start().starts_with("#include"))
        .collect();
    assert_eq!(
        includes,
        [
            "#include <stdint.h>",
            "#include <stddef.h>",
            "#include <stdbool.h>"
        ]
    );
}

#[test]
fn header_compiles_as_c99_and_cpp17_with_warnings_as_errors() {
    let out = common::scratch("header");
    let probe = out.join("probe.c");
    std::fs::write(
        &probe,
        "#include \"smoothtri.h\"\n#include \"smoothtri.h\"\nint main(void) { return \
         (int)sizeof(st_rayhit) == 96 ? 0 : 1; }\n",
    )
    .unwrap();
    common::compile_c(
        std::slice::from_ref(&probe),
        &out.join("probe_c"),
        common::Lang::C99,
        &[],
    );
    let probe_cpp = out.join("probe.cpp");
    std::fs::copy(&probe, &probe_cpp).unwrap();
    common::compile_c(
        &[probe_cpp],
        &out.join("probe_cpp"),
        common::Lang::Cpp17,
        &[],
    );
}
