//! Hostile files (issue 64): counts that ask for more than the file holds, accessors without
//! data of huge counts, buffer URIs that leave the asset's folder or are not regular files.
//! Each gives its typed error naming the file and the field or URI; nothing aborts, hangs or
//! reads outside the folder without `allow_outside_folder`.

mod crafted;

use std::path::Path;

use smoothtri_io::{
    DEFAULT_MAX_BYTES, Error, LoadOptions, load, load_animated, load_with, parse, parse_animated,
    parse_with,
};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

/// Loads `bytes` as `name` (statically, or with its animations).
fn load_crafted(name: &str, bytes: &[u8], animated: bool) -> Error {
    if animated {
        parse_animated(bytes, name).map(|_| ()).unwrap_err()
    } else {
        parse(bytes, name).map(|_| ()).unwrap_err()
    }
}

#[test]
fn the_default_budget_is_two_gib() {
    assert_eq!(DEFAULT_MAX_BYTES, 2 << 30);
    let o = LoadOptions::default();
    assert_eq!(o.max_bytes, DEFAULT_MAX_BYTES);
    assert!(!o.allow_outside_folder);
}

/// The issue's 570-byte file aborted the process ("memory allocation of 96000000000 bytes
/// failed"); now it is a budget error naming the accessor.
#[test]
fn a_sparse_viewless_accessor_of_four_billion_is_a_budget_error() {
    let bytes = crafted::sparse_viewless_position();
    assert!(bytes.len() < 600, "{} bytes", bytes.len());
    match parse(&bytes, "f.gltf").map(|_| ()).unwrap_err() {
        Error::Budget {
            path,
            field,
            needed,
            budget,
        } => {
            assert_eq!(path, "f.gltf");
            assert!(field.contains("POSITION accessor 0"), "{field}");
            assert!(
                needed > budget && budget == DEFAULT_MAX_BYTES,
                "{needed} {budget}"
            );
        }
        e => panic!("{e}"),
    }
}

#[test]
fn every_crafted_file_is_a_one_line_typed_error() {
    for (name, bytes, animated) in crafted::all() {
        let e = load_crafted(name, &bytes, animated);
        let text = e.to_string();
        assert!(text.starts_with(&format!("{name}: ")), "{name}: {text}");
        assert_eq!(text.lines().count(), 1, "{name}: {text}");
        let want = match name {
            "sparse.gltf" => "POSITION accessor 0",
            "viewless.gltf" => "accessors[0].bufferView: Missing data",
            "sampler.gltf" => "input accessor 1",
            "morph.gltf" => "target 0 POSITION accessor 1",
            "skin.gltf" => "inverseBindMatrices accessor 1",
            "vertices.ply" | "ascii.ply" => "element 'vertex' declares 4000000000 elements",
            _ => "element 'face' declares 4000000000 elements",
        };
        assert!(text.contains(want), "{name}: {text}");
        if name.ends_with(".ply") || name == "viewless.gltf" {
            assert!(matches!(e, Error::Format { .. }), "{name}: {e:?}");
        } else {
            assert!(matches!(e, Error::Budget { .. }), "{name}: {e:?}");
        }
    }
}

/// The budget bounds what a well-formed file may take: the same triangle loads under the
/// default and is refused under a budget smaller than what it decodes to.
#[test]
fn a_small_budget_refuses_what_the_default_loads() {
    let json = crafted::triangle_gltf(&crafted::embedded_buffer(), "", "");
    parse(json.as_bytes(), "t.gltf").unwrap();
    let small = LoadOptions::default().with_max_bytes(json.len() as u64 + 100);
    let e = parse_with(json.as_bytes(), "t.gltf", &small)
        .map(|_| ())
        .unwrap_err();
    assert!(matches!(e, Error::Budget { .. }), "{e:?}");
    let e = parse_with(
        json.as_bytes(),
        "t.gltf",
        &LoadOptions::default().with_max_bytes(10),
    )
    .map(|_| ())
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "t.gltf: the file's size needs {} bytes, over the load budget of 10 bytes",
            json.len()
        )
    );
    // OBJ: the line past the budget is named.
    let obj: String = (0..100).map(|k| format!("v {k} 0 0\n")).collect();
    let e = parse_with(
        obj.as_bytes(),
        "m.obj",
        &LoadOptions::default().with_max_bytes(2000),
    )
    .map(|_| ())
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("m.obj: line ") && e.contains("'v' (vertex)"),
        "{e}"
    );
    // PLY: the element.
    let mut ply = b"ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
    for _ in 0..100 {
        ply.extend(b"0 0 0\n");
    }
    let e = parse_with(&ply, "m.ply", &LoadOptions::default().with_max_bytes(2000))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("element 'vertex' (100 vertices)"), "{e}");
}

/// A folder with the asset `asset/m.gltf` whose buffer is `uri`, a triangle's bytes in
/// `outside/tri.bin` and in `asset/tri.bin`.
fn asset_with_uri(root: &Path, uri: &str) -> String {
    std::fs::create_dir_all(root.join("asset")).unwrap();
    std::fs::create_dir_all(root.join("outside")).unwrap();
    std::fs::write(root.join("outside/tri.bin"), crafted::triangle_bin()).unwrap();
    std::fs::write(root.join("asset/tri.bin"), crafted::triangle_bin()).unwrap();
    let json = crafted::triangle_gltf(&crafted::external_buffer(uri), "", "");
    write(&root.join("asset"), "m.gltf", json.as_bytes())
}

fn outside(e: Error, uri: &str) {
    match &e {
        Error::OutsideFolder { path, uri: u } => {
            assert!(path.ends_with("m.gltf"), "{e}");
            assert_eq!(u, uri);
            let text = e.to_string();
            assert!(
                text.contains(&format!("{uri:?}")) && text.lines().count() == 1,
                "{text}"
            );
        }
        _ => panic!("{uri}: expected OutsideFolder, got {e:?}"),
    }
}

#[test]
fn buffers_inside_the_folder_load() {
    let dir = tempfile::tempdir().unwrap();
    for uri in ["tri.bin", "./tri.bin", "tri%2Ebin"] {
        let m = load(&asset_with_uri(dir.path(), uri)).unwrap();
        assert_eq!(m.mesh.triangles.len(), 1, "{uri}");
    }
}

#[test]
fn buffers_outside_the_folder_are_refused_without_the_opt_in() {
    let dir = tempfile::tempdir().unwrap();
    let abs = dir.path().join("outside/tri.bin");
    let abs = abs.to_str().unwrap().to_string();
    for uri in [
        "/etc/passwd",
        "../../etc/passwd",
        "../outside/tri.bin",
        "%2e%2e/outside/tri.bin",
        "%2E%2E%2Foutside%2Ftri.bin",
        "sub/../../outside/tri.bin",
        "file:///etc/passwd",
        abs.as_str(),
        "/dev/zero",
    ] {
        let path = asset_with_uri(dir.path(), uri);
        outside(load(&path).map(|_| ()).unwrap_err(), uri);
        outside(load_animated(&path).map(|_| ()).unwrap_err(), uri);
    }
    // With the opt-in, a regular file elsewhere is read (still size-checked).
    let allow = LoadOptions::default().with_allow_outside_folder(true);
    for uri in ["../outside/tri.bin", "%2e%2e/outside/tri.bin", abs.as_str()] {
        let m = load_with(&asset_with_uri(dir.path(), uri), &allow).unwrap();
        assert_eq!(m.mesh.triangles.len(), 1, "{uri}");
    }
    // … but never a device, even with the opt-in.
    let e = load_with(&asset_with_uri(dir.path(), "/dev/zero"), &allow)
        .map(|_| ())
        .unwrap_err();
    assert!(
        matches!(&e, Error::Resource { uri, why, .. } if uri == "/dev/zero" && why == "not a regular file"),
        "{e:?}"
    );
}

#[cfg(unix)]
#[test]
fn a_symlink_leaving_the_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = asset_with_uri(dir.path(), "link.bin");
    std::os::unix::fs::symlink(
        dir.path().join("outside/tri.bin"),
        dir.path().join("asset/link.bin"),
    )
    .unwrap();
    outside(load(&path).map(|_| ()).unwrap_err(), "link.bin");
    let allow = LoadOptions::default().with_allow_outside_folder(true);
    assert_eq!(load_with(&path, &allow).unwrap().mesh.triangles.len(), 1);
    // A symlink that stays inside is fine.
    std::os::unix::fs::symlink(
        dir.path().join("asset/tri.bin"),
        dir.path().join("asset/inside.bin"),
    )
    .unwrap();
    let path = asset_with_uri(dir.path(), "inside.bin");
    assert_eq!(load(&path).unwrap().mesh.triangles.len(), 1);
}

#[cfg(unix)]
#[test]
fn what_is_not_a_regular_file_is_refused_without_waiting() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("asset/sub")).unwrap();
    let fifo = dir.path().join("asset/fifo.bin");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    let mut uris = vec!["sub", "."];
    if made.is_ok_and(|s| s.success()) {
        uris.push("fifo.bin");
    }
    for uri in uris {
        let e = load(&asset_with_uri(dir.path(), uri))
            .map(|_| ())
            .unwrap_err();
        assert!(
            matches!(&e, Error::Resource { uri: u, why, .. } if u == uri && why == "not a regular file"),
            "{uri}: {e:?}"
        );
    }
    // The mesh file itself: a FIFO is an I/O error, not a wait.
    if fifo.exists() {
        let as_mesh = dir.path().join("asset/pipe.obj");
        std::fs::rename(&fifo, &as_mesh).unwrap();
        let e = load(as_mesh.to_str().unwrap()).map(|_| ()).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }
}

#[test]
fn a_buffer_file_shorter_than_its_byte_length_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let path = asset_with_uri(dir.path(), "short.bin");
    std::fs::write(dir.path().join("asset/short.bin"), [0u8; 20]).unwrap();
    let e = load(&path).map(|_| ()).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{path}: buffer URI \"short.bin\": the file has 20 bytes, fewer than the buffer's \
             byteLength 104"
        )
    );
    // A longer file: only byteLength bytes are read, and the mesh loads.
    std::fs::write(dir.path().join("asset/short.bin"), {
        let mut b = crafted::triangle_bin();
        b.extend([0xff; 1000]);
        b
    })
    .unwrap();
    assert_eq!(load(&path).unwrap().mesh.triangles.len(), 1);
    // A buffer file larger than the budget is refused by its byteLength, before reading.
    let big = crafted::triangle_gltf(r#"{"uri":"tri.bin","byteLength":36000000}"#, "", "");
    let p = write(&dir.path().join("asset"), "big.gltf", big.as_bytes());
    std::fs::write(dir.path().join("asset/tri.bin"), vec![0u8; 36_000_000]).unwrap();
    let e = load_with(&p, &LoadOptions::default().with_max_bytes(1 << 20))
        .map(|_| ())
        .unwrap_err();
    assert!(
        matches!(&e, Error::Budget { field, .. } if field.contains("buffer URI \"tri.bin\"")),
        "{e:?}"
    );
}
