//! The renderer behind `render` and the `precision` strip: primary rays through the camera,
//! Lambert + ambient shading (smooth hits with the scene's shading normal, seamless by
//! default: [`Scene::shading_normal`]), one directional light with shadow rays, in parallel
//! (rayon) with an optional progress bar (indicatif).

use std::io::IsTerminal;

use glam::DVec3;
use rayon::prelude::*;
use smoothtri::{Hit, Ray};
use smoothtri_host::{Camera, SHADOW_OFFSET_F32, SHADOW_OFFSET_F64};

use crate::image::Image;
use crate::tracer::{Prec, Precision, Scene, Tracer};

/// What one pixel saw.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelHit {
    /// Whether the primary ray hit.
    pub hit: bool,
    /// Hit point (f64 widened).
    pub point: DVec3,
    /// Mesh triangle id.
    pub triangle: u32,
    /// The hit's certified bound on its `t` error (`Hit::t_error`), in units of the ray's
    /// direction (unit length here); 0 on a miss.
    pub t_error: f64,
}

/// The result of [`render`].
pub struct Rendered {
    /// The shaded image.
    pub image: Image,
    /// Per pixel (row-major) primary hit.
    pub hits: Vec<PixelHit>,
    /// Rays traced (primary + shadow).
    pub rays: u64,
    /// Wall time, seconds.
    pub seconds: f64,
}

/// Background colour at row `y` of `h`.
pub fn background(y: u32, h: u32) -> [u8; 3] {
    let s = y as f64 / h.max(1) as f64;
    [
        (48.0 - 24.0 * s) as u8,
        (54.0 - 26.0 * s) as u8,
        (66.0 - 30.0 * s) as u8,
    ]
}

fn to_u8(x: f64) -> u8 {
    (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8
}

/// The colour of a hit: orange front faces, blue back faces, ambient plus Lambert times the
/// light's visibility (`vis`, 0 or 1).
pub fn shade(front_face: bool, lambert: f64, vis: f64) -> [u8; 3] {
    let albedo: [f64; 3] = if front_face {
        [0.85, 0.50, 0.22]
    } else {
        [0.25, 0.45, 0.80]
    };
    let ambient = 0.12;
    let s = ambient + (1.0 - ambient) * lambert * vis;
    albedo.map(|a| to_u8(a * s))
}

/// Traces every pixel of `cam`'s image, the rows in parallel: `pixel(x, y)` gives the colour
/// of pixel `(x, y)` (`y` from the top), its record and the number of rays it cast; `row_done`
/// runs after each row. Returns the RGB bytes and the records, both row by row from the top,
/// and the total number of rays.
pub(crate) fn trace_pixels<P: Send>(
    cam: &Camera,
    pixel: impl Fn(u32, u32) -> ([u8; 3], P, u64) + Sync,
    row_done: impl Fn() + Sync,
) -> (Vec<u8>, Vec<P>, u64) {
    let (w, h) = (cam.width, cam.height);
    let rows: Vec<(Vec<u8>, Vec<P>, u64)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut px = Vec::with_capacity(w as usize * 3);
            let mut records = Vec::with_capacity(w as usize);
            let mut rays = 0u64;
            for x in 0..w {
                let (rgb, record, r) = pixel(x, y);
                px.extend(rgb);
                records.push(record);
                rays += r;
            }
            row_done();
            (px, records, rays)
        })
        .collect();
    let mut data = Vec::with_capacity(w as usize * h as usize * 3);
    let mut records = Vec::with_capacity(w as usize * h as usize);
    let mut rays = 0;
    for (p, r, n) in rows {
        data.extend(p);
        records.extend(r);
        rays += n;
    }
    (data, records, rays)
}

/// Renders `scene` through `cam` with `tracer`; `diag` is the scene's bounding-box diagonal
/// (for ray offsets). Shows a progress bar on stderr when `progress` and stderr is a terminal.
pub fn render<F: Prec>(
    scene: &Scene<F>,
    cam: &Camera,
    tracer: &dyn Tracer<F>,
    diag: f64,
    progress: bool,
) -> Rendered {
    let start = std::time::Instant::now();
    let bvh = scene.bvh();
    let core = scene.core();
    let seamless = tracer.smooth() && scene.normals == crate::tracer::Normals::Seamless;
    let light = cam.light_dir();
    let eps = diag
        * match F::PRECISION {
            Precision::F32 => SHADOW_OFFSET_F32,
            Precision::F64 => SHADOW_OFFSET_F64,
        };
    let (w, h) = (cam.width, cam.height);
    let bar = if progress && std::io::stderr().is_terminal() {
        indicatif::ProgressBar::new(h as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    let (data, hits, rays) = trace_pixels(
        cam,
        |x, y| {
            let (o, d) = cam.pixel_ray(x, y);
            let ray = Ray::<F>::new(F::from_dvec3(o), F::from_dvec3(d));
            let mut rays = 1;
            // Smooth hits shade with the scene's choice of normal (seamless by default).
            let shaded: Option<(Hit<F>, F::Vec3)> = if seamless {
                tracer.closest_shaded(&core, &ray, F::ZERO, F::MAX)
            } else {
                tracer
                    .closest_hit(&bvh, &ray, F::ZERO, F::MAX)
                    .map(|hit| (hit, hit.normal))
            };
            let Some((hit, normal)) = shaded else {
                return (background(y, h), PixelHit::default(), rays);
            };
            let p = F::to_dvec3(hit.point);
            let mut n = F::to_dvec3(normal);
            if n.dot(d) > 0.0 {
                n = -n;
            }
            let lambert = n.dot(light).max(0.0);
            let mut vis = 0.0;
            if lambert > 0.0 {
                rays += 1;
                let so = p - d * eps;
                let sray = Ray::<F>::new(F::from_dvec3(so), F::from_dvec3(light));
                if !tracer.any_hit(&bvh, &sray, F::from_f64(eps), F::MAX) {
                    vis = 1.0;
                }
            }
            let record = PixelHit {
                hit: true,
                point: p,
                t_error: hit.t_error.to_f64(),
                triangle: scene
                    .tri_ids()
                    .get(hit.patch as usize)
                    .copied()
                    .unwrap_or(u32::MAX),
            };
            (shade(hit.front_face, lambert, vis), record, rays)
        },
        || bar.inc(1),
    );
    bar.finish_and_clear();
    Rendered {
        image: Image {
            width: w,
            height: h,
            data,
        },
        hits,
        rays,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// Counts pixels whose primary ray hit the flat mesh with all four neighbours also hitting it
/// (inside its silhouette), and among them those the smooth surface missed: rays slipping
/// through cracks between neighbouring patches, or legitimately outside the smooth silhouette
/// where the flat mesh sticks out (e.g. chords across a torus's hole). Also counts isolated
/// holes: misses whose four neighbours all hit the smooth surface. Returns
/// `(missed, isolated_holes, inside)`.
pub fn crack_misses(
    width: u32,
    height: u32,
    smooth: &[PixelHit],
    flat: &[PixelHit],
) -> (usize, usize, usize) {
    let (w, h) = (width as usize, height as usize);
    let hit = |m: &[PixelHit], x: usize, y: usize| m.get(y * w + x).is_some_and(|p| p.hit);
    let (mut missed, mut holes, mut inside) = (0, 0, 0);
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let interior = hit(flat, x, y)
                && hit(flat, x - 1, y)
                && hit(flat, x + 1, y)
                && hit(flat, x, y - 1)
                && hit(flat, x, y + 1);
            if interior {
                inside += 1;
                if !hit(smooth, x, y) {
                    missed += 1;
                    let ring = hit(smooth, x - 1, y)
                        && hit(smooth, x + 1, y)
                        && hit(smooth, x, y - 1)
                        && hit(smooth, x, y + 1);
                    holes += usize::from(ring);
                }
            }
        }
    }
    (missed, holes, inside)
}

/// Plain PBM (P1) text of a hit mask: `1` where the primary ray hit.
pub fn mask_pbm(width: u32, height: u32, hits: &[PixelHit]) -> String {
    let mut s = format!("P1\n{width} {height}\n");
    for row in hits.chunks(width.max(1) as usize) {
        let line: Vec<&str> = row.iter().map(|h| if h.hit { "1" } else { "0" }).collect();
        s.push_str(&line.join(" "));
        s.push('\n');
    }
    s
}
