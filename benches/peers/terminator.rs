//! The shadow-terminator table: the torus under `render`'s light through each surface against
//! the analytic torus, and the row of images.

use glam::DVec3;
use smoothtri::LineField;
use smoothtri_demo::Scene;
use smoothtri_demo::peers::{Analytic, FlatPhong, Peers, Pixel, Smooth, TerminatorFix};
use smoothtri_peers::Peer;
use smoothtri_testkit::Camera;
use smoothtri_testkit::scenes::torus;

use crate::TORUS;

/// Pixels of a study against the analytic torus's: (both hit, lit/shadowed differs, in band,
/// differs in band, mean |ΔI| in band, max |ΔI| in band).
fn compare(p: &[Pixel], truth: &[Pixel], light: DVec3) -> (usize, usize, usize, usize, f64, f64) {
    let (mut both, mut diff, mut band, mut bdiff, mut sum, mut max) = (0, 0, 0, 0, 0.0, 0.0f64);
    for (a, t) in p.iter().zip(truth) {
        if !(a.hit && t.hit) {
            continue;
        }
        both += 1;
        diff += usize::from(a.lit != t.lit);
        if t.normal.dot(light).abs() <= 0.4 {
            band += 1;
            bdiff += usize::from(a.lit != t.lit);
            let e = (a.intensity - t.intensity).abs();
            sum += e;
            max = max.max(e);
        }
    }
    (both, diff, band, bdiff, sum / band.max(1) as f64, max)
}

/// Prints the terminator table and writes its images.
pub(crate) fn terminator() {
    let mesh = torus(8, 8, 1.0, 0.4);
    let (w, h) = (640, 480);
    let cam = Camera::for_mesh(&mesh, 30.0, 35.0, w, h);
    let eps = smoothtri_demo::peers::shadow_eps(mesh.diagonal(), smoothtri_demo::Precision::F32);
    let light = cam.light_dir();
    let truth = smoothtri_demo::peers::render_study(&Analytic(TORUS), &mesh, &cam, None, eps);
    let flat = Scene::<f32>::build_with(&mesh, LineField::Face, false).expect("builds");
    let seams = Scene::<f32>::build_with(&mesh, LineField::Face, true).expect("builds");
    let pt = Peers::<f32>::build(Peer::PhongTess { alpha: 0.75 }, &mesh).expect("builds");
    let ng = Peers::<f32>::build(Peer::Nagata, &mesh).expect("builds");
    let fp = FlatPhong { scene: &flat };
    let sm = Smooth {
        scene: &seams,
        n: 4,
    };
    let rows: [(
        &str,
        &dyn smoothtri_demo::peers::Surface,
        Option<TerminatorFix>,
    ); 6] = [
        ("flat, Phong normals", &fp, None),
        (
            "flat, Phong normals, Hanika's offset",
            &fp,
            Some(TerminatorFix::Hanika),
        ),
        (
            "flat, Phong normals, Chiang et al.'s term",
            &fp,
            Some(TerminatorFix::Chiang),
        ),
        ("Phong tessellation α = 0.75 (Phong normals)", &pt, None),
        ("Nagata (its normal)", &ng, None),
        ("smoothtri N = 4 (seamless normal)", &sm, None),
    ];
    println!(
        "\n## The shadow terminator: the 8×8 torus, {w}×{h}, `render`'s light and view, one shadow ray per lit hit (f32), against the analytic torus rendered the same way (f64)\n"
    );
    println!(
        "| surface | pixels both hit | lit/shadowed differs | band pixels (\\|n·l\\| ≤ 0.4) | differs in band | mean \\|ΔI\\| in band | max \\|ΔI\\| in band |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut images = vec![(truth.image.clone(), "ANALYTIC".to_string())];
    for (name, s, fix) in rows {
        let st = smoothtri_demo::peers::render_study(s, &mesh, &cam, fix, eps);
        let (both, diff, band, bdiff, mean, max) = compare(&st.pixels, &truth.pixels, light);
        println!(
            "| {name} | {both} | {diff} ({:.2} %) | {band} | {bdiff} ({:.2} %) | {mean:.4} | {max:.3} |",
            100.0 * diff as f64 / both.max(1) as f64,
            100.0 * bdiff as f64 / band.max(1) as f64
        );
        let label = match (name, fix) {
            (_, Some(TerminatorFix::Hanika)) => "HANIKA",
            (_, Some(TerminatorFix::Chiang)) => "CHIANG",
            (n, _) if n.starts_with("flat") => "PHONG",
            (n, _) if n.starts_with("Phong tess") => "PHONG TESS",
            (n, _) if n.starts_with("Nagata") => "NAGATA",
            _ => "SMOOTHTRI",
        };
        images.push((st.image, label.to_string()));
    }
    println!(
        "\nIntensity I = ambient + (1 − ambient)·(n·l)·visibility (·G for Chiang et al.), ambient 0.12; the band is where the analytic torus's own normal has |n·l| ≤ 0.4."
    );
    // The row of images, each frame halved (2×2 pixels averaged).
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("..")
        .join("peers");
    let _ = std::fs::create_dir_all(&dir);
    let crop = |img: &smoothtri_demo::image::Image| {
        let (cw, ch) = (img.width / 2, img.height / 2);
        let mut c = smoothtri_demo::image::Image::new(cw, ch, [0, 0, 0]);
        for y in 0..ch {
            for x in 0..cw {
                let px =
                    [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| img.get(2 * x + i, 2 * y + j));
                let avg: [u8; 3] = core::array::from_fn(|k| {
                    (px.iter().map(|p| u32::from(p[k])).sum::<u32>() / 4) as u8
                });
                c.put(x as i64, y as i64, avg);
            }
        }
        c
    };
    let crops: Vec<(smoothtri_demo::image::Image, String)> =
        images.iter().map(|(i, l)| (crop(i), l.clone())).collect();
    let refs: Vec<(&smoothtri_demo::image::Image, String)> =
        crops.iter().map(|(i, l)| (i, l.clone())).collect();
    let row = smoothtri_demo::commands::render::side_by_side(&refs);
    let path = dir.join("terminator.png");
    if row.write_png(&path.to_string_lossy()).is_ok() {
        println!("\nImages: {}", path.display());
    }
}
