//! Meshes through the command line, end to end: files of every format load (`inspect`), real
//! exports and glTF scenes, the shared line field through `inspect`, `render` and `trace`, and
//! bad input of every kind is one readable error.

mod common;

use common::meshes::{glb_bytes, gltf_parts, obj_text, ply_text};
use common::{fails, ok, tmp, write};
use smoothtri_testkit::scenes::cube;

#[test]
fn meshes_of_every_format_load() {
    let d = tmp();
    let c = cube();
    write(d.path(), "n.obj", &obj_text(&c, true));
    write(d.path(), "nn.obj", &obj_text(&c, false));
    write(d.path(), "c.ply", &ply_text(&c));
    let (json, bin) = gltf_parts(&c, Some("c.bin"));
    write(d.path(), "c.gltf", &json);
    std::fs::write(d.path().join("c.bin"), bin).expect("bin");
    std::fs::write(d.path().join("c.glb"), glb_bytes(&c)).expect("glb");
    for f in ["n.obj", "nn.obj", "c.ply", "c.gltf", "c.glb"] {
        let r = ok(d.path(), &["inspect", "--mesh", f]);
        assert!(r.out.contains("triangles: 12"), "{f}: {}", r.out);
        assert!(r.out.contains("memory"), "{f}: {}", r.out);
        if f == "nn.obj" {
            assert!(r.err.contains("angle-weighted"), "{}", r.err);
        } else {
            assert!(!r.err.contains("angle-weighted"), "{f}: {}", r.err);
        }
    }
    // A quad and a pentagon are fan-triangulated; negative indices and v/vt/vn work.
    write(
        d.path(),
        "poly.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0.1\nv 0 1 0\nv -0.5 0.5 0\nvt 0 0\nvn 0 0 1\n\
         f 1/1/1 2/1/1 3/1/1 4/1/1\nf -5//-1 -2//-1 -1//-1\ng x\ns off\nusemtl m\n",
    );
    let r = ok(d.path(), &["inspect", "--mesh", "poly.obj"]);
    assert!(r.out.contains("triangles: 3"), "{}", r.out);
}

/// Blender 2.4x writes a bare text line into the PLY header ("Created by Blender3D 247 …",
/// without `comment`); other readers take it as a comment, and so does ours (blank header lines
/// too). The body is read as usual.
#[test]
fn ply_headers_with_bare_text_lines_load() {
    let d = tmp();
    let c = cube();
    let text = ply_text(&c).replacen(
        "format ascii 1.0\n",
        "format ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: 'x.blend'\n\n",
        1,
    );
    write(d.path(), "blender.ply", &text);
    write(d.path(), "plain.ply", &ply_text(&c));
    // Everything but the build's timing line.
    let report = |name: &str| -> Vec<String> {
        ok(d.path(), &["inspect", "--mesh", name])
            .out
            .replace(name, "m.ply")
            .lines()
            .filter(|l| !l.starts_with("build ("))
            .map(str::to_owned)
            .collect()
    };
    assert_eq!(
        report("blender.ply"),
        report("plain.ply"),
        "the same mesh either way"
    );
}

/// Real exports from Debian's `assimp-testmodels` (installed by `.ci/run`; skipped where the
/// package is absent unless `SMOOTHTRI_REQUIRE_ASSETS` is set): Blender 2.47's PLY with its bare
/// header line loads, a glTF 1.0 file is refused by name, a truncated binary PLY is one line.
#[test]
fn real_exports_load_or_fail_in_one_line() {
    let Some(root) = smoothtri_testkit::assimp_models().unwrap() else {
        return;
    };
    let d = tmp();
    let wuson = root.join("PLY/Wuson.ply");
    let r = ok(
        d.path(),
        &["inspect", "--mesh", wuson.to_str().expect("path")],
    );
    assert!(r.out.contains("triangles: 3732"), "{}", r.out);
    let old = root.join("glTF/TwoBoxes/TwoBoxes.gltf");
    fails(
        d.path(),
        &["inspect", "--mesh", old.to_str().expect("path")],
        &["TwoBoxes.gltf", "glTF 1.0 is not supported"],
    );
    let pond = root.join("PLY/pond.0.ply");
    let r = fails(
        d.path(),
        &["inspect", "--mesh", pond.to_str().expect("path")],
        // A truncated export: its header's vertex count needs more bytes than the file holds.
        &[
            "pond.0.ply",
            "element 'vertex' declares 70051 elements",
            "after the header",
        ],
    );
    assert_eq!(r.err.trim_end().lines().count(), 1, "{}", r.err);
}

/// `--field vertex` builds the patches on the shared line field: `inspect` reports the
/// teapot's accepted neighbours' edge curves meeting (to rounding; 5.6e-4 of the diagonal on
/// the paper's field), and `render` and `trace` run on it.
#[test]
fn shared_line_field_from_the_command_line() {
    let d = tmp();
    let crack = |out: &str| -> f64 {
        let line = out
            .lines()
            .find(|l| l.starts_with("crack width"))
            .expect("crack line");
        let rel = line.split('(').nth(1).expect("relative width");
        rel.split_whitespace()
            .next()
            .expect("a number")
            .parse()
            .expect("a float")
    };
    let face = ok(d.path(), &["inspect", "--scene", "teapot"]);
    let shared = ok(
        d.path(),
        &["inspect", "--scene", "teapot", "--field", "vertex"],
    );
    assert!(shared.out.contains("line field: vertex"), "{}", shared.out);
    assert!(crack(&face.out) > 1e-4, "{}", face.out);
    assert!(crack(&shared.out) < 1e-14, "{}", shared.out);
    ok(
        d.path(),
        &[
            "render", "--scene", "teapot", "--field", "vertex", "--width", "32", "--height", "24",
            "--out", "t.png",
        ],
    );
    write(d.path(), "r.csv", "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n");
    let r = ok(
        d.path(),
        &[
            "trace", "--scene", "teapot", "--field", "vertex", "--rays", "r.csv",
        ],
    );
    assert!(r.out.lines().count() == 2, "{}", r.out);
}

#[test]
fn inspect_reports() {
    let d = tmp();
    let r = ok(d.path(), &["inspect", "--scene", "torus"]);
    for needle in [
        "triangles: 128",
        "bounding box",
        "128 accepted, 0 rejected",
        "vertex-normal angle",
        "crack width",
        "normal jump",
        "192 interior",
        "memory",
    ] {
        assert!(r.out.contains(needle), "{needle}: {}", r.out);
    }
    // A degenerate triangle is rejected, a back-facing normal is repaired by the core's remedy
    // (clamped toward the face normal); both are counted and reported; the render completes.
    write(
        d.path(),
        "deg.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 5 0 0\nvn 0 0 1\nvn 0 0 -1\n\
         f 1//1 2//1 3//1\nf 4//1 5//1 6//1\nf 2//2 4//1 3//1\n",
    );
    let r = ok(d.path(), &["inspect", "--mesh", "deg.obj"]);
    assert!(r.out.contains("2 accepted, 1 rejected"), "{}", r.out);
    assert!(r.out.contains("degenerate"), "{}", r.out);
    assert!(r.out.contains("new_or_tilted): 1 = 1 ×"), "{}", r.out);
    let r = ok(
        d.path(),
        &[
            "render", "--mesh", "deg.obj", "--width", "16", "--height", "12",
        ],
    );
    for needle in ["skipped 1 of 3", "1 of 3 triangles have normals outside"] {
        assert!(r.err.contains(needle), "{needle}: {}", r.err);
    }
}

#[test]
fn bad_input_is_one_readable_error() {
    let d = tmp();
    let p = d.path();
    fails(p, &["inspect", "--mesh", "missing.obj"], &["missing.obj"]);
    let (nobin, _) = gltf_parts(&cube(), Some("nowhere.bin"));
    // Mesh files, each with what `render --mesh` of it says.
    let meshes: [(&str, &str, &[&str]); 16] = [
        (
            "num.obj",
            "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n",
            &["num.obj:2", "malformed number 'x'"],
        ),
        (
            "face.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
            &["face.obj:4", "face"],
        ),
        (
            "face2.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n",
            &["face2.obj:4", "'q'"],
        ),
        (
            "idx.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
            &["idx.obj:4", "out of range"],
        ),
        (
            "nidx.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n",
            &["nidx.obj:5", "out of range"],
        ),
        (
            "nan.obj",
            "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n",
            &["nan.obj:3", "non-finite"],
        ),
        (
            "inf.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 inf 1\nf 1//1 2//1 3//1\n",
            &["inf.obj:4", "non-finite"],
        ),
        ("empty.obj", "# nothing\nv 0 0 0\n", &["no triangles"]),
        (
            "alldeg.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
            &["no usable triangles"],
        ),
        ("x.stl", "solid x\n", &["unknown mesh format"]),
        (
            "bad.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nzz\n",
            &["bad.ply", "line 6"],
        ),
        // A glTF 1.0 document (named dictionaries, asset version 1.0) is refused by name.
        (
            "old.gltf",
            r#"{"asset":{"version":"1.0"},"meshes":{"m":{"primitives":[]}},"nodes":{}}"#,
            &["old.gltf", "glTF 1.0 is not supported"],
        ),
        (
            "older.gltf",
            r#"{"meshes":{"m":{}},"accessors":{}}"#,
            &["glTF 1.0 is not supported"],
        ),
        (
            "range.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n",
            &["range.ply", "out of range"],
        ),
        ("bad.gltf", "{ not json", &["bad.gltf", "glTF"]),
        ("nobin.gltf", nobin.as_str(), &["nowhere.bin"]),
    ];
    for (name, text, needles) in meshes {
        write(p, name, text);
        let r = fails(p, &["render", "--mesh", name], needles);
        if name == "bad.ply" {
            // One readable line, without the parser's debug structures.
            assert_eq!(r.err.trim_end().lines().count(), 1, "{}", r.err);
            assert!(!r.err.contains("ParseError"), "{}", r.err);
        }
    }
    fails(p, &["render", "--iterations", "65"], &["--iterations 65"]);
    fails(p, &["render", "--view", "10"], &["AZ,EL"]);
    fails(p, &["trace", "--rays", "r.csv"], &["--mesh"]);
    fails(
        p,
        &["render", "--scene", "torus", "--mesh", "x.obj"],
        &["cannot be used"],
    );
    fails(p, &["render", "--scene", "blob"], &["blob"]);
    // Ray files, each with what `trace --rays` of it says (none.csv is missing).
    let rays: [(&str, Option<&str>, &[&str]); 4] = [
        ("hdr.csv", Some("a,b,c\n"), &["hdr.csv:1", "header"]),
        (
            "r.csv",
            Some("ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n0,0,5,0,0\n"),
            &["r.csv:3", "fields"],
        ),
        (
            "r2.csv",
            Some("ox,oy,oz,dx,dy,dz\n0,0,5,0,0,nan\n"),
            &["r2.csv:2", "non-finite"],
        ),
        ("none.csv", None, &["none.csv"]),
    ];
    for (name, text, needles) in rays {
        if let Some(text) = text {
            write(p, name, text);
        }
        fails(p, &["trace", "--scene", "cube", "--rays", name], needles);
    }
    fails(
        p,
        &[
            "render",
            "--out",
            "/nonexistent-dir/x.png",
            "--width",
            "8",
            "--height",
            "6",
        ],
        &["/nonexistent-dir/x.png"],
    );
}

/// Regression (found by the `gltf` fuzz target): a GLB header announcing more data than the
/// file holds made the `gltf` crate panic; it is now one readable error.
#[test]
fn truncated_glb_is_an_error_not_a_panic() {
    let d = tmp();
    let bytes: &[u8] = &[
        0x67, 0x6c, 0x54, 0x46, 0x01, 0x00, 0x00, 0x45, 0x00, 0x00, 0x00, 0x00, 0x0a,
    ];
    std::fs::write(d.path().join("bad.glb"), bytes).unwrap();
    fails(
        d.path(),
        &["inspect", "--mesh", "bad.glb"],
        &["bad.glb", "malformed glTF"],
    );
}

/// A GLB container that breaks the glTF 2.0 rules is one readable error naming the file and
/// what is wrong, found before the `gltf` crate sees the bytes.
#[test]
fn malformed_glb_containers_are_readable_errors() {
    let d = tmp();
    let good = glb_bytes(&cube());
    let json_len = u32::from_le_bytes(good[12..16].try_into().expect("4 bytes")) as usize;
    let bin_at = 12 + 8 + json_len;
    let bin_len = good.len() - bin_at - 8;
    let set = |b: &mut Vec<u8>, at: usize, v: u32| b[at..at + 4].copy_from_slice(&v.to_le_bytes());

    let mut wrong_magic = good.clone();
    wrong_magic[..4].copy_from_slice(b"glTX");
    let mut wrong_version = good.clone();
    set(&mut wrong_version, 4, 1);
    let mut past_end = good.clone();
    set(&mut past_end, bin_at, 4000);
    let mut unaligned = good.clone();
    set(&mut unaligned, 12, json_len as u32 + 1);
    let mut trailing = good.clone();
    trailing.extend([0; 4]);

    let cases: Vec<(&str, Vec<u8>, String)> = vec![
        (
            "header.glb",
            good[..7].to_vec(),
            "the file has 7 bytes, fewer than the 12-byte GLB header".into(),
        ),
        (
            "magic.glb",
            wrong_magic,
            r#"the file starts with "glTX", not the GLB magic "glTF""#.into(),
        ),
        (
            "version.glb",
            wrong_version,
            "GLB version 1 (glTF 1.0) is not supported (only glTF 2.0; convert the file to 2.0 first)".into(),
        ),
        (
            "past.glb",
            past_end,
            format!("GLB chunk 1 (BIN) declares 4000 bytes but only {bin_len} remain"),
        ),
        (
            "align.glb",
            unaligned,
            format!(
                "GLB chunk 0 (JSON) declares {} bytes, not a multiple of 4",
                json_len + 1
            ),
        ),
        (
            "length.glb",
            trailing,
            format!(
                "the GLB header declares a length of {} bytes but the file has {}",
                good.len(),
                good.len() + 4
            ),
        ),
    ];
    for (name, bytes, msg) in cases {
        std::fs::write(d.path().join(name), bytes).expect("write glb");
        let r = fails(
            d.path(),
            &["inspect", "--mesh", name],
            &[&format!("error: {name}: malformed glTF binary: {msg}")],
        );
        assert_eq!(r.err.lines().count(), 1, "{name}: one line: {}", r.err);
    }
}

/// glTF scenes through the command line: every node of the scene, instanced meshes instanced,
/// a skipped primitive named with its node and mesh, and errors naming node, mesh and accessor.
#[test]
fn gltf_scenes_through_the_cli() {
    let d = tmp();
    let p = d.path();
    let (json, bin) = gltf_parts(&cube(), None);
    let scene = json
        .replace(
            r#""scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}]"#,
            r#""scenes":[{"nodes":[0,1]}],"nodes":[{"name":"Left","mesh":0,"translation":[-3,0,0],"children":[2]},{"name":"Right","mesh":0,"translation":[3,0,0]},{"name":"Wire","mesh":1}]"#,
        )
        .replace(
            r#""indices":2}]}]"#,
            r#""indices":2}]},{"name":"wire","primitives":[{"attributes":{"POSITION":0},"mode":1}]}]"#,
        );
    assert_ne!(scene, json, "template changed");
    let glb = smoothtri_io::glb::build(scene.as_bytes(), Some(&bin));
    std::fs::write(p.join("s.glb"), &glb).expect("glb");
    let r = ok(p, &["inspect", "--mesh", "s.glb"]);
    assert!(r.out.contains("triangles: 24"), "{}", r.out);
    assert!(
        r.out
            .contains("bounding box: min (-4, -1, -1)  max (4, 1, 1)"),
        "{}",
        r.out
    );
    assert!(
        r.err.contains(
            r#"warning: s.glb: mesh 1 "wire", primitive 0 (drawn by node 2 "Wire"): mode Lines is not triangles, skipped"#
        ),
        "{}",
        r.err
    );
    // An accessor error names the node, the mesh, the primitive and the accessor.
    let bad = scene.replacen(
        r#""bufferView":1,"componentType":5126,"count":8"#,
        r#""bufferView":1,"componentType":5126,"count":0"#,
        1,
    );
    assert_ne!(bad, scene, "template changed");
    std::fs::write(
        p.join("bad.glb"),
        smoothtri_io::glb::build(bad.as_bytes(), Some(&bin)),
    )
    .expect("glb");
    let r = fails(
        p,
        &["render", "--mesh", "bad.glb"],
        &[r#"error: bad.glb: node 0 "Left", mesh 0, primitive 0: NORMAL accessor 1 has count 0"#],
    );
    assert_eq!(r.err.lines().count(), 1, "{}", r.err);
}
