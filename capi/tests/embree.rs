//! The Embree plug-in (`include/smoothtri_embree.h`) from C++: `tests/cpp/embree_test.cpp`,
//! compiled with `c++ -std=c++17 -Wall -Wextra -Werror -pedantic` against the headers, the
//! static library and Embree 3 (Debian's `libembree-dev`). Skipped when Embree's headers are
//! absent, unless `SMOOTHTRI_REQUIRE_EMBREE` is set (CI sets it).
#![allow(clippy::unwrap_used)]

mod common;

use std::path::Path;

#[test]
fn embree_scene_with_smooth_patches_beside_triangles_and_instances() {
    if !Path::new("/usr/include/embree3/rtcore.h").exists() {
        assert!(
            std::env::var_os("SMOOTHTRI_REQUIRE_EMBREE").is_none(),
            "SMOOTHTRI_REQUIRE_EMBREE is set but Embree 3 is not installed \
             (apt-get install libembree-dev)"
        );
        eprintln!("skipped: Embree 3 is not installed (apt-get install libembree-dev)");
        return;
    }
    // Under valgrind and with the sanitizers (each when available, see `common::modes`).
    let mut out = String::new();
    for mode in common::modes(true) {
        let exe = common::build_program("cpp/embree_test.cpp", mode, &["-lembree3"]);
        out = common::run_in(mode, &exe, &[]);
        assert!(out.contains("all checks passed"), "{mode:?}: {out}");
    }
    let dir = common::scratch("embree");
    // The plug-in header is C99 too (a renderer in C includes it the same way).
    let probe = dir.join("probe.c");
    std::fs::write(
        &probe,
        "#include \"smoothtri_embree.h\"\nint main(void) { return st_embree_new_geometry(NULL, \
         NULL) == NULL ? 0 : 1; }\n",
    )
    .unwrap();
    let probe_exe = dir.join("probe");
    let link = common::link_flags(&["-lembree3"]);
    common::compile_c(&[probe], &probe_exe, common::Lang::C99, &link);
    common::run(&probe_exe, &[], false);
    assert!(out.contains("all checks passed"), "{out}");
    println!("{out}");
}
