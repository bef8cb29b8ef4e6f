//! Real meshes for the tests and benchmarks: Debian's `assimp-testmodels` ([`assimp_models`]).

use std::path::{Path, PathBuf};

/// Where Debian's `assimp-testmodels` keeps its files (`/usr/share/assimp/models`), for the tests
/// and benchmarks that run on real exports: `Ok(Some(dir))` when it is installed, `Ok(None)`
/// when it is not (the caller skips; one line on stderr says so), `Err` when it is not but
/// `SMOOTHTRI_REQUIRE_ASSETS` is set (CI installs the package, so a missing one there is a
/// failure, not a skip).
pub fn assimp_models() -> Result<Option<PathBuf>, String> {
    let root = Path::new("/usr/share/assimp/models");
    if root.is_dir() {
        Ok(Some(root.to_path_buf()))
    } else if std::env::var_os("SMOOTHTRI_REQUIRE_ASSETS").is_some() {
        Err(format!(
            "{} is missing: install Debian's assimp-testmodels",
            root.display()
        ))
    } else {
        eprintln!("skipped: no {}", root.display());
        Ok(None)
    }
}
