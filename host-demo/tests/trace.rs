//! The commands that answer in CSV, end to end: `trace` (rays in, hits out, from a file or
//! stdin), `eval` (surface points of barycentric coordinates) and `precision` (its table, CSV,
//! plot and strip).

mod common;

use common::{fails, ok, run_in, tmp, with, words, write};
use glam::DVec3;
use smoothtri_demo::commands::precision::CSV_HEADER;

fn parse_fields(line: &str) -> Vec<String> {
    line.split(',').map(str::to_string).collect()
}

#[test]
fn trace_csv_round_trip() {
    let d = tmp();
    let rays = "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n5,0,0,-1,0,0\n0,0,5,0,0,1\n0.3,0.2,5,0,0,-2\n";
    write(d.path(), "rays.csv", rays);
    for prec in ["f32", "f64"] {
        let trace = format!("trace --scene cube --rays rays.csv --precision {prec}");
        let r = ok(d.path(), &words(&trace));
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
        let g = ok(d.path(), &with(&words(&trace), &["--normals", "geometric"]));
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
            &words(&format!(
                "eval --mesh t.obj --points p.csv --precision {prec}"
            )),
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

#[test]
fn precision_sweep_outputs() {
    let d = tmp();
    let outputs = "--csv p.csv --plot p.svg --strip s.png";
    let sweep = format!("precision --scene sphere --width 16 --height 12 {outputs}");
    let r = ok(d.path(), &words(&sweep));
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
        &words("precision --scene cube --width 8 --height 6 --csv -"),
    );
    assert!(r.out.contains(CSV_HEADER));
}
