//! End-to-end tests of the `smoothtri` binary on small meshes written into a temp dir.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use glam::DVec3;
use smoothtri_demo::commands::precision::CSV_HEADER;
use smoothtri_testkit::Camera;
use smoothtri_testkit::Mesh;
use smoothtri_testkit::scenes::{cube, icosphere};

const W: u32 = 96;
const H: u32 = 72;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_smoothtri"))
}

struct Run {
    code: i32,
    out: String,
    err: String,
}

fn run_in(dir: &Path, args: &[&str], stdin: Option<&str>) -> Run {
    let mut c = bin();
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
    let o: Output = child.wait_with_output().expect("wait");
    Run {
        code: o.status.code().unwrap_or(-1),
        out: String::from_utf8_lossy(&o.stdout).into_owned(),
        err: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

fn run(dir: &Path, args: &[&str]) -> Run {
    run_in(dir, args, None)
}

fn ok(dir: &Path, args: &[&str]) -> Run {
    let r = run(dir, args);
    assert_eq!(r.code, 0, "{args:?} failed: {}", r.err);
    r
}

/// Runs and expects failure with a message containing every `needle`.
fn fails(dir: &Path, args: &[&str], needles: &[&str]) -> Run {
    let r = run(dir, args);
    assert_ne!(r.code, 0, "{args:?} should fail; stdout {}", r.out);
    for n in needles {
        assert!(r.err.contains(n), "{args:?}: stderr lacks {n:?}: {}", r.err);
    }
    assert!(!r.err.contains("panicked"), "{args:?} panicked: {}", r.err);
    r
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("tempdir")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

fn obj_text(m: &Mesh, normals: bool) -> String {
    let mut s = String::from("# test mesh\no thing\n");
    for p in &m.positions {
        s += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    if normals {
        for n in &m.normals {
            s += &format!("vn {} {} {}\n", n.x, n.y, n.z);
        }
    }
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if normals {
            s += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
        } else {
            s += &format!("f {a} {b} {c}\n");
        }
    }
    s
}

fn ply_text(m: &Mesh) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    );
    for (p, n) in m.positions.iter().zip(&m.normals) {
        s += &format!("{} {} {} {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for t in &m.triangles {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s
}

/// glTF JSON and its binary buffer (positions, normals, u32 indices).
fn gltf_parts(m: &Mesh, uri: Option<&str>) -> (String, Vec<u8>) {
    let mut bin = Vec::new();
    for p in &m.positions {
        for c in p.to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for n in &m.normals {
        for c in n.normalize().to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for t in &m.triangles {
        for i in t {
            bin.extend(i.to_le_bytes());
        }
    }
    let nv = m.positions.len();
    let (lo, hi) = m.bounds();
    let buffer = match uri {
        Some(u) => format!(r#"{{"uri":"{u}","byteLength":{}}}"#, bin.len()),
        None => format!(r#"{{"byteLength":{}}}"#, bin.len()),
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
"buffers":[{buffer}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pv}}},{{"buffer":0,"byteOffset":{pv},"byteLength":{pv}}},{{"buffer":0,"byteOffset":{io},"byteLength":{il}}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{nv},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}},
{{"bufferView":1,"componentType":5126,"count":{nv},"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":{ni},"type":"SCALAR"}}]}}"#,
        lo.x as f32,
        lo.y as f32,
        lo.z as f32,
        hi.x as f32,
        hi.y as f32,
        hi.z as f32,
        pv = nv * 12,
        io = nv * 24,
        il = m.triangles.len() * 12,
        ni = m.triangles.len() * 3,
    );
    (json, bin)
}

fn glb_bytes(m: &Mesh) -> Vec<u8> {
    let (json, mut bin) = gltf_parts(m, None);
    let mut j = json.into_bytes();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

fn read_pbm(path: &Path) -> (u32, u32, Vec<bool>) {
    let text = std::fs::read_to_string(path).expect("mask");
    let mut it = text.split_whitespace();
    assert_eq!(it.next(), Some("P1"));
    let w: u32 = it.next().and_then(|s| s.parse().ok()).expect("w");
    let h: u32 = it.next().and_then(|s| s.parse().ok()).expect("h");
    let bits: Vec<bool> = it.map(|s| s == "1").collect();
    assert_eq!(bits.len(), (w * h) as usize);
    (w, h, bits)
}

/// Pixels where the render's mask differs from the analytic sphere's silhouette by more than
/// one pixel (no pixel within one pixel in the analytic mask has the render's value).
fn silhouette_violations(mask: &[bool], cam: &Camera, c: DVec3, r: f64) -> usize {
    let (w, h) = (cam.width as i64, cam.height as i64);
    let analytic: Vec<bool> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = cam.pixel_ray(x as u32, y as u32);
            let oc = o - c;
            let b = oc.dot(d);
            let disc = b * b - (oc.length_squared() - r * r);
            disc >= 0.0 && -b + disc.sqrt() > 0.0
        })
        .collect();
    let mut bad = 0;
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if mask[i] == analytic[i] {
                continue;
            }
            let mut near = false;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx >= 0 && yy >= 0 && xx < w && yy < h {
                        near |= analytic[(yy * w + xx) as usize] == mask[i];
                    }
                }
            }
            if !near {
                bad += 1;
            }
        }
    }
    bad
}

fn mask_of(dir: &Path, extra: &[&str]) -> Vec<bool> {
    let (ws, hs) = (W.to_string(), H.to_string());
    let mut args = vec![
        "render", "--width", &ws, "--height", &hs, "--out", "m.png", "--mask", "m.pbm",
    ];
    args.extend_from_slice(extra);
    ok(dir, &args);
    let (w, h, bits) = read_pbm(&dir.join("m.pbm"));
    assert_eq!((w, h), (W, H));
    bits
}

#[test]
fn render_default_writes_png_and_reports() {
    let d = tmp();
    let r = ok(d.path(), &["render", "--width", "48", "--height", "36"]);
    assert!(r.out.contains("smoothtri.png"), "{}", r.out);
    assert!(r.out.contains("rays/s"), "{}", r.out);
    assert!(r.out.contains("N = 4"), "{}", r.out);
    let bytes = std::fs::read(d.path().join("smoothtri.png")).expect("png");
    assert_eq!(&bytes[1..4], b"PNG");
}

#[test]
fn cube_and_icosphere_silhouettes_match_the_sphere_flat_does_not() {
    let d = tmp();
    let cam = Camera::for_mesh(&cube(), 30.0, 35.0, W, H);
    let r3 = 3f64.sqrt();
    let smooth = mask_of(d.path(), &["--scene", "cube"]);
    assert_eq!(silhouette_violations(&smooth, &cam, DVec3::ZERO, r3), 0);
    let f64m = mask_of(d.path(), &["--scene", "cube", "--precision", "f64"]);
    assert_eq!(silhouette_violations(&f64m, &cam, DVec3::ZERO, r3), 0);
    let flat = mask_of(d.path(), &["--scene", "cube", "--mode", "flat"]);
    assert!(silhouette_violations(&flat, &cam, DVec3::ZERO, r3) > 50);
    let ico = icosphere(1, 1.0);
    let cam = Camera::for_mesh(&ico, 30.0, 35.0, W, H);
    let m = mask_of(d.path(), &["--scene", "sphere"]);
    assert_eq!(silhouette_violations(&m, &cam, DVec3::ZERO, 1.0), 0);
    let flat = mask_of(d.path(), &["--scene", "sphere", "--mode", "flat"]);
    assert!(silhouette_violations(&flat, &cam, DVec3::ZERO, 1.0) > 0);
    // Same cube read from files of every format.
    let c = cube();
    write(d.path(), "c.obj", &obj_text(&c, true));
    write(d.path(), "c.ply", &ply_text(&c));
    let cam = Camera::for_mesh(&c, 30.0, 35.0, W, H);
    for f in ["c.obj", "c.ply"] {
        let m = mask_of(d.path(), &["--mesh", f]);
        assert_eq!(silhouette_violations(&m, &cam, DVec3::ZERO, r3), 0, "{f}");
    }
}

#[test]
fn compare_modes_and_views() {
    let d = tmp();
    let r = ok(
        d.path(),
        &[
            "render",
            "--compare",
            "--scene",
            "torus",
            "--width",
            "40",
            "--height",
            "30",
            "--out",
            "c.png",
            "--view",
            "-20,60",
            "--iterations",
            "4",
        ],
    );
    assert!(r.out.contains("c.png"));
    for mode in ["flat", "phong", "smooth"] {
        ok(
            d.path(),
            &[
                "render", "--mode", mode, "--scene", "teapot", "--width", "32", "--height", "24",
                "--out", "t.png",
            ],
        );
    }
}

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

fn parse_fields(line: &str) -> Vec<String> {
    line.split(',').map(str::to_string).collect()
}

#[test]
fn trace_csv_round_trip() {
    let d = tmp();
    let rays = "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n5,0,0,-1,0,0\n0,0,5,0,0,1\n0.3,0.2,5,0,0,-2\n";
    write(d.path(), "rays.csv", rays);
    for prec in ["f32", "f64"] {
        let r = ok(
            d.path(),
            &[
                "trace",
                "--scene",
                "cube",
                "--rays",
                "rays.csv",
                "--precision",
                prec,
            ],
        );
        let lines: Vec<&str> = r.out.lines().collect();
        assert_eq!(
            lines[0],
            "ray,hit,t,x,y,z,nx,ny,nz,snx,sny,snz,triangle,w1,w2,t_error"
        );
        assert_eq!(lines.len(), 5);
        let rows: Vec<Vec<String>> = lines[1..].iter().map(|l| parse_fields(l)).collect();
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), 16, "{row:?}");
            assert_eq!(row[0], i.to_string());
        }
        assert_eq!(rows[2][1], "0");
        assert!(rows[2][2..].iter().all(|s| s.is_empty()));
        for row in [&rows[0], &rows[1], &rows[3]] {
            assert_eq!(row[1], "1");
            let v: Vec<f64> = row[2..]
                .iter()
                .map(|s| s.parse().expect("number"))
                .collect();
            let p = DVec3::new(v[1], v[2], v[3]);
            // Every cube patch is the sphere of radius √3.
            assert!((p.length() - 3f64.sqrt()).abs() < 1e-5, "{row:?}");
            let n = DVec3::new(v[4], v[5], v[6]);
            assert!((n.length() - 1.0).abs() < 1e-5);
            // The seamless shading normal: unit, and radial like the geometric one on a
            // sphere's patches (the correction vanishes there).
            let sn = DVec3::new(v[7], v[8], v[9]);
            assert!((sn.length() - 1.0).abs() < 1e-5);
            assert!((sn - p.normalize()).length() < 1e-4, "{row:?}");
            assert!(v[10] >= 0.0 && v[10] < 12.0 && v[10].fract() == 0.0);
            assert!(v[13] >= 0.0);
            if prec == "f32" {
                // Printed floats read back exactly (shortest round trip).
                for s in &row[2..] {
                    let x: f32 = s.parse().expect("f32");
                    assert_eq!(&x.to_string(), s);
                }
            }
        }
        let t0: f64 = rows[0][2].parse().expect("t");
        assert!((t0 - (5.0 - 3f64.sqrt())).abs() < 1e-5);
        let t3: f64 = rows[3][2].parse().expect("t");
        let z3: f64 = rows[3][5].parse().expect("z");
        assert!((5.0 - 2.0 * t3 - z3).abs() < 1e-5, "t in units of dir");
        // With the geometric normal asked for, the shading columns repeat nx,ny,nz, and every
        // other column is unchanged.
        let g = ok(
            d.path(),
            &[
                "trace",
                "--scene",
                "cube",
                "--rays",
                "rays.csv",
                "--precision",
                prec,
                "--normals",
                "geometric",
            ],
        );
        for (seamless, geometric) in r.out.lines().zip(g.out.lines()).skip(1) {
            let (a, b) = (parse_fields(seamless), parse_fields(geometric));
            assert_eq!(b[6..9], b[9..12], "{geometric}");
            assert_eq!((&a[..9], &a[12..]), (&b[..9], &b[12..]));
        }
    }
    // stdin
    let r = run_in(
        d.path(),
        &["trace", "--scene", "sphere", "--rays", "-"],
        Some(rays),
    );
    assert_eq!(r.code, 0, "{}", r.err);
    assert_eq!(r.out.lines().count(), 5);
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

#[test]
fn eval_of_vertices_is_exact() {
    let d = tmp();
    // Vertices exactly representable in f32 and f64.
    write(
        d.path(),
        "t.obj",
        "v 0.5 0.25 1.125\nv 2.75 0.5 1\nv 1 2.5 1.5\nvn 0 0 1\nvn 0.1 0 1\nvn 0 0.1 1\n\
         f 1//1 2//2 3//3\n",
    );
    let pts = "triangle,w1,w2\n0,0,0\n0,1,0\n0,0,1\n0,0.25,0.25\n";
    write(d.path(), "p.csv", pts);
    for prec in ["f32", "f64"] {
        let r = ok(
            d.path(),
            &[
                "eval",
                "--mesh",
                "t.obj",
                "--points",
                "p.csv",
                "--precision",
                prec,
            ],
        );
        let lines: Vec<&str> = r.out.lines().collect();
        assert_eq!(lines[0], "triangle,w1,w2,x,y,z,nx,ny,nz,snx,sny,snz");
        // At the vertices the shading normal is the vertex normal itself.
        for l in &lines[1..4] {
            let f = parse_fields(l);
            assert_eq!(f[6..9], f[9..12], "{l}");
        }
        let xyz = |l: &str| -> Vec<f64> {
            parse_fields(l)[3..6]
                .iter()
                .map(|s| s.parse().expect("n"))
                .collect()
        };
        assert_eq!(xyz(lines[1]), vec![0.5, 0.25, 1.125]);
        assert_eq!(xyz(lines[2]), vec![2.75, 0.5, 1.0]);
        assert_eq!(xyz(lines[3]), vec![1.0, 2.5, 1.5]);
        let inner = xyz(lines[4]);
        assert!(inner.iter().all(|v| v.is_finite()));
    }
    fails(
        d.path(),
        &["eval", "--mesh", "t.obj", "--points", "-"],
        &["<stdin>"],
    );
    write(d.path(), "bad.csv", "triangle,w1,w2\n7,0,0\n");
    fails(
        d.path(),
        &["eval", "--mesh", "t.obj", "--points", "bad.csv"],
        &["bad.csv:2", "out of range"],
    );
    write(d.path(), "bad2.csv", "triangle,w1,w2\n0,zz,0\n");
    fails(
        d.path(),
        &["eval", "--mesh", "t.obj", "--points", "bad2.csv"],
        &["bad2.csv:2", "malformed number"],
    );
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
    assert!(r.err.contains("skipped 1 of 3"), "{}", r.err);
    assert!(
        r.err.contains("1 of 3 triangles have normals outside"),
        "{}",
        r.err
    );
}

#[test]
fn precision_sweep_outputs() {
    let d = tmp();
    let r = ok(
        d.path(),
        &[
            "precision",
            "--scene",
            "sphere",
            "--width",
            "16",
            "--height",
            "12",
            "--csv",
            "p.csv",
            "--plot",
            "p.svg",
            "--strip",
            "s.png",
        ],
    );
    assert!(r.out.contains("p99.9"), "{}", r.out);
    let csv = std::fs::read_to_string(d.path().join("p.csv")).expect("csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], CSV_HEADER);
    assert_eq!(lines.len(), 1 + 14);
    for l in &lines[1..] {
        let f = parse_fields(l);
        assert_eq!(f.len(), 10);
        assert!(f[0] == "f32" || f[0] == "f64");
        let max: f64 = f[3].parse().expect("max");
        assert!(max.is_finite() && max >= 0.0);
    }
    let svg = std::fs::read_to_string(d.path().join("p.svg")).expect("svg");
    assert!(svg.contains("<svg"));
    let png = std::fs::read(d.path().join("s.png")).expect("png");
    assert_eq!(&png[1..4], b"PNG");
    // CSV to stdout.
    let r = ok(
        d.path(),
        &[
            "precision",
            "--scene",
            "cube",
            "--width",
            "8",
            "--height",
            "6",
            "--csv",
            "-",
        ],
    );
    assert!(r.out.contains(CSV_HEADER));
}

#[test]
fn bad_input_is_one_readable_error() {
    let d = tmp();
    let p = d.path();
    fails(p, &["inspect", "--mesh", "missing.obj"], &["missing.obj"]);
    write(p, "num.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n");
    fails(
        p,
        &["render", "--mesh", "num.obj"],
        &["num.obj:2", "malformed number 'x'"],
    );
    write(p, "face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
    fails(
        p,
        &["render", "--mesh", "face.obj"],
        &["face.obj:4", "face"],
    );
    write(p, "face2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n");
    fails(
        p,
        &["render", "--mesh", "face2.obj"],
        &["face2.obj:4", "'q'"],
    );
    write(p, "idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    fails(
        p,
        &["render", "--mesh", "idx.obj"],
        &["idx.obj:4", "out of range"],
    );
    write(
        p,
        "nidx.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n",
    );
    fails(
        p,
        &["render", "--mesh", "nidx.obj"],
        &["nidx.obj:5", "out of range"],
    );
    write(p, "nan.obj", "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n");
    fails(
        p,
        &["render", "--mesh", "nan.obj"],
        &["nan.obj:3", "non-finite"],
    );
    write(
        p,
        "inf.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 inf 1\nf 1//1 2//1 3//1\n",
    );
    fails(
        p,
        &["render", "--mesh", "inf.obj"],
        &["inf.obj:4", "non-finite"],
    );
    write(p, "empty.obj", "# nothing\nv 0 0 0\n");
    fails(p, &["render", "--mesh", "empty.obj"], &["no triangles"]);
    write(p, "alldeg.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    fails(
        p,
        &["render", "--mesh", "alldeg.obj"],
        &["no usable triangles"],
    );
    write(p, "x.stl", "solid x\n");
    fails(p, &["render", "--mesh", "x.stl"], &["unknown mesh format"]);
    write(
        p,
        "bad.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nzz\n",
    );
    let bad = fails(p, &["render", "--mesh", "bad.ply"], &["bad.ply", "line 6"]);
    // One readable line, without the parser's debug structures.
    assert_eq!(bad.err.trim_end().lines().count(), 1, "{}", bad.err);
    assert!(!bad.err.contains("ParseError"), "{}", bad.err);
    // A glTF 1.0 document (named dictionaries, asset version 1.0) is refused by name.
    write(
        p,
        "old.gltf",
        r#"{"asset":{"version":"1.0"},"meshes":{"m":{"primitives":[]}},"nodes":{}}"#,
    );
    fails(
        p,
        &["render", "--mesh", "old.gltf"],
        &["old.gltf", "glTF 1.0 is not supported"],
    );
    write(p, "older.gltf", r#"{"meshes":{"m":{}},"accessors":{}}"#);
    fails(
        p,
        &["render", "--mesh", "older.gltf"],
        &["glTF 1.0 is not supported"],
    );
    write(
        p,
        "range.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n",
    );
    fails(
        p,
        &["render", "--mesh", "range.ply"],
        &["range.ply", "out of range"],
    );
    write(p, "bad.gltf", "{ not json");
    fails(p, &["render", "--mesh", "bad.gltf"], &["bad.gltf", "glTF"]);
    let (json, _) = gltf_parts(&cube(), Some("nowhere.bin"));
    write(p, "nobin.gltf", &json);
    fails(p, &["render", "--mesh", "nobin.gltf"], &["nowhere.bin"]);
    fails(p, &["render", "--iterations", "65"], &["--iterations 65"]);
    fails(p, &["render", "--view", "10"], &["AZ,EL"]);
    fails(p, &["trace", "--rays", "r.csv"], &["--mesh"]);
    fails(
        p,
        &["render", "--scene", "torus", "--mesh", "x.obj"],
        &["cannot be used"],
    );
    fails(p, &["render", "--scene", "blob"], &["blob"]);
    write(p, "hdr.csv", "a,b,c\n");
    fails(
        p,
        &["trace", "--scene", "cube", "--rays", "hdr.csv"],
        &["hdr.csv:1", "header"],
    );
    write(p, "r.csv", "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n0,0,5,0,0\n");
    fails(
        p,
        &["trace", "--scene", "cube", "--rays", "r.csv"],
        &["r.csv:3", "fields"],
    );
    write(p, "r2.csv", "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,nan\n");
    fails(
        p,
        &["trace", "--scene", "cube", "--rays", "r2.csv"],
        &["r2.csv:2", "non-finite"],
    );
    fails(
        p,
        &["trace", "--scene", "cube", "--rays", "none.csv"],
        &["none.csv"],
    );
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

/// A tall y-up shape: the ellipsoid with semi-axes 1, 3, 1 (the icosphere stretched along y,
/// normals by the inverse transpose).
fn tall_y_up() -> Mesh {
    let mut m = icosphere(2, 1.0);
    for p in &mut m.positions {
        p.y *= 3.0;
    }
    for n in &mut m.normals {
        n.y /= 3.0;
    }
    m
}

/// Width and height in pixels of the hit pixels' bounding box.
fn extent(mask: &[bool]) -> (usize, usize) {
    let (w, h) = (W as usize, H as usize);
    let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
    for y in 0..h {
        for x in 0..w {
            if mask[y * w + x] {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    (x1.saturating_sub(x0) + 1, y1.saturating_sub(y0) + 1)
}

/// `--up`: mesh files default to y up, built-ins to their own axis (z); the same shape written
/// z-up and read with `--up z` gives the same mask as written y-up and read by default; the view
/// is relative to the up axis; glTF is always y-up.
#[test]
fn up_axis_stands_meshes_upright() {
    let d = tmp();
    let p = d.path();
    let tall = tall_y_up();
    write(p, "tall.obj", &obj_text(&tall, true));
    let mut z_up = tall.clone();
    for v in z_up.positions.iter_mut().chain(z_up.normals.iter_mut()) {
        *v = DVec3::new(v.x, -v.z, v.y);
    }
    write(p, "tall_z.obj", &obj_text(&z_up, true));
    std::fs::write(p.join("tall.glb"), glb_bytes(&tall)).expect("glb");

    let upright = mask_of(p, &["--mesh", "tall.obj"]);
    let (w, h) = extent(&upright);
    assert!(h as f64 > 1.5 * w as f64, "y-up shape not upright: {w}x{h}");
    assert_eq!(upright, mask_of(p, &["--mesh", "tall.obj", "--up", "y"]));
    assert_eq!(upright, mask_of(p, &["--mesh", "tall_z.obj", "--up", "z"]));
    // Read with the wrong axis it lies on its side (the issue's bunny).
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.obj", "--up", "z"]));
    assert!(w > h, "z-up reading should lie down: {w}x{h}");
    // The view is relative to the up axis: from straight above, the ellipsoid is a disc.
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.obj", "--view", "0,90"]));
    assert!(w.abs_diff(h) <= 2, "top view {w}x{h}");
    // glTF: y-up by specification (f32 positions, so compare shapes, not masks).
    let (w, h) = extent(&mask_of(p, &["--mesh", "tall.glb"]));
    assert!(h as f64 > 1.5 * w as f64, "glTF not upright: {w}x{h}");
    fails(
        p,
        &["render", "--mesh", "tall.glb", "--up", "z"],
        &["--up z", "tall.glb", "y-up by specification"],
    );
    // Built-ins keep their own axis (z): the README's pictures are unchanged.
    let torus = mask_of(p, &["--scene", "torus"]);
    assert_eq!(torus, mask_of(p, &["--scene", "torus", "--up", "z"]));
    assert_ne!(torus, mask_of(p, &["--scene", "torus", "--up", "y"]));
    // `precision` frames a camera too.
    let r = ok(
        p,
        &[
            "precision",
            "--mesh",
            "tall.obj",
            "--up",
            "y",
            "--width",
            "8",
            "--height",
            "6",
        ],
    );
    assert!(r.out.contains("precision study: tall.obj"), "{}", r.out);
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

/// Every undirected edge is used by exactly two triangles: the mesh is closed, without cracks
/// or T-junctions.
fn assert_closed(m: &Mesh, what: &str) {
    let mut uses = std::collections::HashMap::<(u32, u32), u32>::new();
    for t in &m.triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let open = uses.values().filter(|&&u| u != 2).count();
    assert_eq!(
        open, 0,
        "{what}: {open} edges not shared by exactly two triangles"
    );
}

/// The number after `key` in `text` (e.g. `"max distance to the smooth surface: "`).
fn figure(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {text}"))
        + key.len();
    let num: String = text[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '+'))
        .collect();
    num.parse()
        .unwrap_or_else(|_| panic!("bad number {num:?} after {key:?}"))
}

fn load(dir: &Path, name: &str) -> Mesh {
    let path = dir.join(name);
    smoothtri_io::load(path.to_str().expect("utf-8 path"))
        .expect("reload")
        .mesh
}

/// A sphere mesh tessellated stays on the sphere: every vertex to 1e-12 (f64) or 1e-6 (f32)
/// relative, normals radial, through every writer and the demo's own loaders.
#[test]
fn tessellated_sphere_stays_on_the_sphere() {
    let d = tmp();
    let p = d.path();
    for (out, prec, tol) in [
        ("s.obj", "f64", 1e-12),
        ("s.ply", "f64", 1e-12),
        ("s32.obj", "f32", 1e-6),
        ("s32.ply", "f32", 1e-6),
        ("s.glb", "f64", 1e-6),
    ] {
        ok(
            p,
            &[
                "tessellate",
                "--scene",
                "sphere",
                "--level",
                "5",
                "--out",
                out,
                "--precision",
                prec,
            ],
        );
        let m = load(p, out);
        assert_eq!(m.triangles.len(), 80 * 25, "{out}");
        let worst = m
            .positions
            .iter()
            .map(|x| (x.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst <= tol, "{out}: {worst:e} off the sphere");
        for (x, n) in m.positions.iter().zip(&m.normals) {
            assert!(n.normalize().dot(x.normalize()) > 1.0 - 10.0 * tol, "{out}");
        }
        assert_closed(&m, out);
    }
}

/// The output reloads through the demo's loaders (OBJ, binary PLY, GLB) with the printed
/// counts and size; the vertex count is the welding rule's: mesh vertices + shared edges ·
/// (L − 1) + triangles · (L − 1)(L − 2)/2 (torus 8×8: 64 + 192 · 2 + 128 · 1 = 576 at L = 3).
#[test]
fn tessellation_reloads_with_the_welding_rules_counts() {
    let d = tmp();
    let p = d.path();
    for out in ["t.obj", "t.ply", "t.glb"] {
        let r = ok(
            p,
            &[
                "tessellate",
                "--scene",
                "torus",
                "--level",
                "3",
                "--out",
                out,
            ],
        );
        let size = std::fs::metadata(p.join(out)).expect("output").len();
        assert!(
            r.out.contains(&format!(
                "wrote {out}: 1152 triangles, 576 vertices, {size} bytes"
            )),
            "{}",
            r.out
        );
        assert!(
            r.out
                .contains("welded 384 edge samples on 192 shared edges"),
            "{}",
            r.out
        );
        let m = load(p, out);
        assert_eq!((m.triangles.len(), m.positions.len()), (1152, 576), "{out}");
        assert_closed(&m, out);
        let r = ok(p, &["inspect", "--mesh", out]);
        assert!(
            r.out.contains("triangles: 1152   vertices: 576"),
            "{}",
            r.out
        );
    }
}

/// On the torus the tessellation converges to the smooth surface (distance ÷ ~4 per doubling of
/// L), and its distance to the true torus tends to the smooth surface's own: within 10 % at
/// L = 8. The distances to the torus are measured here, on the reloaded file, independently of
/// the command's figures.
#[test]
fn tessellated_torus_tends_to_the_smooth_surfaces_distance() {
    use smoothtri::DPatch;
    use smoothtri_testkit::scenes::{torus, torus_distance};
    let d = tmp();
    let p = d.path();
    let mesh = torus(8, 8, 1.0, 0.4);
    let mut smooth = 0.0f64;
    for t in 0..mesh.triangles.len() {
        let (pp, nn) = mesh.triangle(t);
        let patch = DPatch::new_or_tilted(pp, nn).expect("torus patch");
        for i in 0..=12 {
            for j in 0..=12 - i {
                let x = patch.point(i as f64 / 12.0, j as f64 / 12.0);
                smooth = smooth.max(torus_distance(x, 1.0, 0.4));
            }
        }
    }
    let probes = [
        [1.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    ];
    let mut last = (f64::INFINITY, f64::INFINITY);
    for l in ["2", "4", "8"] {
        let out = format!("t{l}.obj");
        let r = ok(
            p,
            &[
                "tessellate",
                "--scene",
                "torus",
                "--level",
                l,
                "--out",
                &out,
            ],
        );
        let to_surface = figure(&r.out, "max distance to the smooth surface: ");
        let m = load(p, &out);
        let mut to_torus = 0.0f64;
        for t in &m.triangles {
            let v = t.map(|i| m.positions[i as usize]);
            for rot in 0..3 {
                for w in probes {
                    let x = v[rot] * w[0] + v[(rot + 1) % 3] * w[1] + v[(rot + 2) % 3] * w[2];
                    to_torus = to_torus.max(torus_distance(x, 1.0, 0.4));
                }
            }
        }
        eprintln!(
            "L = {l}: to the smooth surface {to_surface:.3e}, to the torus {to_torus:.3e} \
             (smooth surface {smooth:.3e})"
        );
        assert!(
            to_surface < last.0 / 3.0 && to_torus < last.1,
            "L = {l}: no convergence"
        );
        let printed = figure(&r.out, "max distance to the exact torus: ");
        assert!((printed - to_torus).abs() <= 0.02 * to_torus, "{}", r.out);
        last = (to_surface, to_torus);
    }
    assert!(
        (last.1 - smooth).abs() <= 0.1 * smooth,
        "L = 8: {:.3e} vs the smooth surface's {smooth:.3e}",
        last.1
    );
}

/// `--max-error`: levels chosen per patch (powers of two), the shared edges at the larger
/// level with stitched fans, and the output still closed; the measured distance meets the
/// target.
#[test]
fn max_error_levels_differ_and_stay_watertight() {
    let d = tmp();
    let p = d.path();
    let r = ok(
        p,
        &[
            "tessellate",
            "--scene",
            "torus",
            "--max-error",
            "1e-2",
            "--out",
            "e.ply",
        ],
    );
    // The torus's patches on the outer equator are flatter than those on the inner one.
    let kinds = r.out.lines().next().unwrap_or("").matches("× L = ").count();
    assert!(kinds >= 2, "one level only: {}", r.out);
    let dist = figure(&r.out, "max distance to the smooth surface: ");
    assert!(dist <= 1e-2, "{}", r.out);
    assert_closed(&load(p, "e.ply"), "e.ply");
}

#[test]
fn tessellate_options_are_checked() {
    let d = tmp();
    let p = d.path();
    let t = ["tessellate", "--scene", "cube"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { [&t[..], extra].concat() };
    fails(
        p,
        &with(&["--level", "0", "--out", "x.obj"]),
        &["--level", "1..=256"],
    );
    fails(
        p,
        &with(&["--level", "300", "--out", "x.obj"]),
        &["--level"],
    );
    fails(
        p,
        &with(&["--max-error", "0", "--out", "x.obj"]),
        &["--max-error"],
    );
    fails(
        p,
        &with(&["--max-error", "NaN", "--out", "x.obj"]),
        &["--max-error"],
    );
    fails(
        p,
        &with(&["--max-error", "1e-3", "--max-level", "3", "--out", "x.obj"]),
        &["power of two"],
    );
    fails(
        p,
        &with(&["--level", "2", "--max-error", "1e-3", "--out", "x.obj"]),
        &["cannot be used"],
    );
    fails(
        p,
        &with(&["--out", "x.stl"]),
        &["x.stl", ".obj, .ply or .glb"],
    );
    fails(p, &with(&[]), &["--out"]);
    fails(p, &["tessellate", "--out", "x.obj"], &["--mesh"]);
    fails(
        p,
        &with(&["--out", "/nonexistent-dir/x.obj"]),
        &["/nonexistent-dir/x.obj"],
    );
    fails(
        p,
        &with(&["--out", "x.obj", "--picture", "x.obj"]),
        &["--picture x.obj", "must end in .png"],
    );
    write(p, "tri.gltf", "{ not json");
    fails(
        p,
        &["tessellate", "--mesh", "tri.gltf", "--out", "x.obj"],
        &["tri.gltf", "malformed glTF"],
    );
}

/// `--picture`: the traced smooth surface and the flat-shaded tessellation side by side.
#[test]
fn tessellate_picture_has_two_panels() {
    let d = tmp();
    let p = d.path();
    let r = ok(
        p,
        &[
            "tessellate",
            "--scene",
            "torus",
            "--level",
            "2",
            "--out",
            "t.obj",
            "--picture",
            "t.png",
            "--width",
            "40",
            "--height",
            "30",
        ],
    );
    assert!(r.out.contains("wrote t.png"), "{}", r.out);
    let png = std::fs::read(p.join("t.png")).expect("png");
    let be = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().expect("4 bytes"));
    assert_eq!((be(16), be(20)), (84, 30));
}

#[test]
fn verbose_names_the_cpu_kernel_and_smoothtri_isa_is_checked() {
    let d = tmp();
    let args = ["render", "--width", "16", "--height", "12", "--verbose"];
    let r = ok(d.path(), &args);
    let best = smoothtri_isa::Isa::best();
    assert!(r.err.contains(&format!("CPU kernel: {best}")), "{}", r.err);
    // Each instruction set this CPU has, by name; one it lacks or an unknown name is a usage
    // error of one line.
    for isa in smoothtri_isa::Isa::ALL {
        let out = bin()
            .current_dir(d.path())
            .args(args)
            .env(smoothtri_isa::ENV, isa.name())
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        if isa.supported() {
            assert!(out.status.success(), "{isa}: {err}");
            assert!(err.contains(&format!("CPU kernel: {isa}")), "{err}");
        } else {
            assert_eq!(out.status.code(), Some(1), "{isa}: {err}");
            assert!(err.contains("this CPU lacks it"), "{err}");
        }
    }
    let out = bin()
        .current_dir(d.path())
        .args(args)
        .env(smoothtri_isa::ENV, "avx3")
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("names no instruction set"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
