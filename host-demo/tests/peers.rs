//! `render --mode phong-tess|nagata`, `render --terminator hanika|chiang` and `trace --mode
//! phong-tess|nagata` end to end: images written, hits on the peer's own patch (checked against
//! `smoothtri_peers` directly), usage errors for what does not combine.

use std::io::Write;
use std::process::{Command, Stdio};

use glam::DVec3;
use smoothtri_peers::Peer;
use smoothtri_testkit::scenes::torus;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_smoothtri"))
}

#[test]
fn render_peers_and_fixes() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["--mode", "phong-tess"][..],
        &["--mode", "nagata"],
        &["--mode", "phong", "--terminator", "hanika"],
        &["--mode", "phong", "--terminator", "chiang"],
    ] {
        let out = dir.path().join("p.png");
        let o = bin()
            .args(["render", "--width", "64", "--height", "48", "--out"])
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(std::fs::metadata(&out).unwrap().len() > 100);
        assert!(String::from_utf8_lossy(&o.stdout).contains("rays/s"));
    }
    // What does not combine: a usage error, one line, exit 1.
    for args in [
        &["--mode", "nagata", "--terminator", "chiang"][..],
        &["--mode", "smooth", "--terminator", "hanika"],
        &["--mode", "nagata", "--gpu"],
    ] {
        let o = bin()
            .args(["render", "--width", "8", "--height", "8", "--out", "-"])
            .args(args)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn trace_peers_columns_and_points() {
    let mesh = torus(8, 8, 1.0, 0.4);
    let rays =
        "ox,oy,oz,dx,dy,dz\n0,-3,0.2,0,1,0\n3,0.1,0.1,-1,0,0\n0,0,3,0.35,0.02,-1\n0,0,5,0,0,1\n";
    for (mode, peer) in [
        ("phong-tess", Peer::PhongTess { alpha: 0.75 }),
        ("nagata", Peer::Nagata),
    ] {
        for prec in ["f32", "f64"] {
            let mut child = bin()
                .args([
                    "trace",
                    "--scene",
                    "torus",
                    "--rays",
                    "-",
                    "--mode",
                    mode,
                    "--precision",
                    prec,
                ])
                .stdin(Stdio::piped())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            child
                .stdin
                .take()
                .unwrap()
                .write_all(rays.as_bytes())
                .unwrap();
            let o = child.wait_with_output().unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let text = String::from_utf8_lossy(&o.stdout);
            let mut lines = text.lines();
            assert_eq!(
                lines.next(),
                Some("ray,hit,t,x,y,z,nx,ny,nz,snx,sny,snz,triangle,w1,w2,t_error")
            );
            let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
            assert_eq!(rows.len(), 4);
            for r in &rows[..3] {
                assert_eq!(r[1], "1", "{mode} {prec}: {r:?}");
                let f = |k: usize| r[k].parse::<f64>().unwrap();
                let tri: usize = r[12].parse().unwrap();
                let (w1, w2) = (f(13), f(14));
                // The printed point is the peer patch's point at the printed barycentrics.
                let (p, n) = mesh.triangle(tri);
                let q = peer.patch::<f64>(p, n).unwrap();
                let x = DVec3::new(f(3), f(4), f(5));
                assert!((q.point(w1, w2) - x).length() < 1e-4, "{mode} {prec}");
                assert_eq!(f(15), 0.0);
            }
            assert_eq!(rows[3][1], "0");
        }
    }
}
