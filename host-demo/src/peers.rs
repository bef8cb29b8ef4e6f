//! The other smooth surfaces and the shadow-terminator fixes in the demo: `render --mode
//! phong-tess|nagata`, `render --mode phong --terminator hanika|chiang`, `trace --mode
//! phong-tess|nagata`, and the terminator study of `benches/peers.rs`.
//!
//! Every surface here is shaded exactly as [`crate::renderer::render`] shades: the same camera
//! rays, Lambert plus ambient ([`shade`]), the light of [`light_dir`], one shadow ray per lit
//! hit from the hit point moved back along the view ray by `eps` and starting at `eps`. Only the
//! surface, its shading normal and the fix differ, so the images compare pixel for pixel.
//!
//! The two fixes renderers use on flat triangles with interpolated normals:
//! - **Hanika**, "Hacking the Shadow Terminator" (Ray Tracing Gems II, 2021): the shadow ray
//!   starts from the hit point moved out of the triangle as Phong tessellation would move it,
//!   one-sided: `p' = p − Σ_i w_i·min(0, (p − P_i)·n_i)·n_i` ([`hanika_origin`]).
//! - **Chiang, Li & Burley**, "Taming the Shadow Terminator" (SIGGRAPH 2019 talk): the light is
//!   scaled by `G' = −G³ + G² + G`, `G = min(1, (n_g·l) / ((n_s·l)(n_g·n_s)))`, `n_g` the
//!   face normal and `n_s` the shading normal ([`chiang_term`]).

use std::fmt::Write as _;

use glam::DVec3;
use smoothtri::Ray;
use smoothtri_peers::torus::Torus;
use smoothtri_peers::{Peer, PeerScene};

use crate::error::{DemoError, Result};
use crate::image::Image;
use crate::renderer::{background, shade, trace_pixels};
use crate::tracer::{Mode, Prec, Precision, Scene, smooth_tracer, tracer};
use smoothtri_host::Camera;
use smoothtri_io::Mesh;

/// A terminator fix for flat triangles with interpolated normals (`render --terminator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum TerminatorFix {
    /// Hanika's shadow-ray origin offset (Ray Tracing Gems II, 2021).
    Hanika,
    /// Chiang, Li & Burley's shadowing term (2019).
    Chiang,
}

impl TerminatorFix {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            TerminatorFix::Hanika => "hanika",
            TerminatorFix::Chiang => "chiang",
        }
    }
}

/// Phong tessellation's shape factor in the demo (the paper's default).
pub const ALPHA: f64 = smoothtri_peers::ALPHA_DEFAULT;

/// The peer surface of `mode` (`None` for the modes the core traces).
pub fn peer_of(mode: Mode) -> Option<Peer> {
    match mode {
        Mode::PhongTess => Some(Peer::PhongTess { alpha: ALPHA }),
        Mode::Nagata => Some(Peer::Nagata),
        _ => None,
    }
}

/// A closest hit of a [`Surface`], in `f64`.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// Ray parameter.
    pub t: f64,
    /// Hit point.
    pub point: DVec3,
    /// The normal the surface is shaded with (unit, not flipped toward the ray).
    pub shading: DVec3,
    /// The surface's geometric normal (unit; for flat triangles the face normal).
    pub geometric: DVec3,
    /// The ray arrives from the side the normals point to.
    pub front: bool,
    /// The mesh triangle.
    pub triangle: u32,
    /// Barycentrics of the hit on its triangle or patch.
    pub w: (f64, f64),
}

/// A surface the studies render: closest hits and shadow queries.
pub trait Surface: Sync {
    /// The closest hit of `o + t·d`, `t ≥ 0`.
    fn closest_hit(&self, o: DVec3, d: DVec3) -> Option<SurfaceHit>;
    /// Whether anything is hit for `t` in `[t_min, ∞)`.
    fn any_hit(&self, o: DVec3, d: DVec3, t_min: f64) -> bool;
}

/// Flat triangles with interpolated vertex normals (the core's Phong baseline through the
/// scene's BVH).
pub struct FlatPhong<'a, F: Prec> {
    /// The scene (its patches' vertices and normals are the triangles').
    pub scene: &'a Scene<F>,
}

impl<F: Prec> Surface for FlatPhong<'_, F> {
    fn closest_hit(&self, o: DVec3, d: DVec3) -> Option<SurfaceHit> {
        let t = tracer::<F>(Mode::Phong, 0).ok()?;
        let h = t.closest_hit(
            &self.scene.bvh(),
            &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
            F::ZERO,
            F::MAX,
        )?;
        let patch = self.scene.patches().get(h.patch as usize)?;
        let [p0, p1, p2] = patch.vertices().map(F::to_dvec3);
        let face = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        Some(SurfaceHit {
            t: h.t.to_f64(),
            point: F::to_dvec3(h.point),
            shading: F::to_dvec3(h.normal),
            geometric: face,
            front: h.front_face,
            triangle: self.scene.tri_ids().get(h.patch as usize).copied()?,
            w: (h.w1.to_f64(), h.w2.to_f64()),
        })
    }
    fn any_hit(&self, o: DVec3, d: DVec3, t_min: f64) -> bool {
        tracer::<F>(Mode::Phong, 0).is_ok_and(|t| {
            t.any_hit(
                &self.scene.bvh(),
                &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
                F::from_f64(t_min),
                F::MAX,
            )
        })
    }
}

/// smoothtri's patches with `N` refinement steps, shaded with the scene's shading normal
/// (seamless when the scene was built with seams).
pub struct Smooth<'a, F: Prec> {
    /// The scene.
    pub scene: &'a Scene<F>,
    /// Refinement steps.
    pub n: usize,
}

impl<F: Prec> Surface for Smooth<'_, F> {
    fn closest_hit(&self, o: DVec3, d: DVec3) -> Option<SurfaceHit> {
        let t = smooth_tracer::<F>(self.n)?;
        let core = self.scene.core();
        let (h, sn) = t.closest_shaded(
            &core,
            &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
            F::ZERO,
            F::MAX,
        )?;
        Some(SurfaceHit {
            t: h.t.to_f64(),
            point: F::to_dvec3(h.point),
            shading: F::to_dvec3(sn),
            geometric: F::to_dvec3(h.normal),
            front: h.front_face,
            triangle: self.scene.tri_ids().get(h.patch as usize).copied()?,
            w: (h.w1.to_f64(), h.w2.to_f64()),
        })
    }
    fn any_hit(&self, o: DVec3, d: DVec3, t_min: f64) -> bool {
        smooth_tracer::<F>(self.n).is_some_and(|t| {
            t.any_hit(
                &self.scene.bvh(),
                &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
                F::from_f64(t_min),
                F::MAX,
            )
        })
    }
}

/// A mesh of peer patches (`smoothtri_peers`), shaded with the peer's shading normal.
pub struct Peers<F: Prec + smoothtri_peers::Real> {
    /// The patches and their BVH.
    pub scene: PeerScene<F>,
}

impl<F: Prec + smoothtri_peers::Real> Peers<F> {
    /// The `peer` surface of `mesh`.
    pub fn build(peer: Peer, mesh: &Mesh) -> Result<Self> {
        let scene = PeerScene::build(peer, &mesh.positions, &mesh.normals, &mesh.triangles)
            .map_err(|e| DemoError::Usage(format!("{}: {e}", peer.name())))?;
        Ok(Peers { scene })
    }
}

impl<F: Prec + smoothtri_peers::Real> Surface for Peers<F> {
    fn closest_hit(&self, o: DVec3, d: DVec3) -> Option<SurfaceHit> {
        let tr = self.scene.tracer().ok()?;
        let h = tr.closest_hit(
            &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
            F::ZERO,
            F::MAX,
        )?;
        let patch = self.scene.patches().get(h.patch as usize)?;
        Some(SurfaceHit {
            t: h.t.to_f64(),
            point: F::to_dvec3(h.point),
            shading: F::to_dvec3(self.scene.peer().shading_normal(patch, h.w1, h.w2)),
            geometric: F::to_dvec3(h.normal),
            front: h.front_face,
            triangle: self.scene.triangle(h.patch),
            w: (h.w1.to_f64(), h.w2.to_f64()),
        })
    }
    fn any_hit(&self, o: DVec3, d: DVec3, t_min: f64) -> bool {
        self.scene.tracer().is_ok_and(|tr| {
            tr.any_hit(
                &Ray::new(F::from_dvec3(o), F::from_dvec3(d)),
                F::from_f64(t_min),
                F::MAX,
            )
        })
    }
}

/// The analytic torus (the reference of the terminator study; `f64`, exact normal).
pub struct Analytic(pub Torus);

impl Surface for Analytic {
    fn closest_hit(&self, o: DVec3, d: DVec3) -> Option<SurfaceHit> {
        let (t, n) = self.0.closest_hit(o, d, 0.0, f64::INFINITY)?;
        Some(SurfaceHit {
            t,
            point: o + d * t,
            shading: n,
            geometric: n,
            front: n.dot(d) < 0.0,
            triangle: 0,
            w: (0.0, 0.0),
        })
    }
    fn any_hit(&self, o: DVec3, d: DVec3, t_min: f64) -> bool {
        self.0.closest_hit(o, d, t_min, f64::INFINITY).is_some()
    }
}

/// Hanika's shadow-ray origin for a hit at `p` with barycentrics `w` on the flat triangle
/// `tri` with unit vertex normals `n`: `p − Σ_i w_i·min(0, (p − P_i)·n_i)·n_i` (the point moved
/// onto each vertex's tangent plane where it lies below it, blended like Phong tessellation).
pub fn hanika_origin(p: DVec3, w: (f64, f64), tri: [DVec3; 3], n: [DVec3; 3]) -> DVec3 {
    let b = [1.0 - w.0 - w.1, w.0, w.1];
    let mut out = p;
    for i in 0..3 {
        let below = (p - tri[i]).dot(n[i]).min(0.0);
        out -= n[i] * (b[i] * below);
    }
    out
}

/// Chiang, Li & Burley's smoothed shadowing term for light direction `l`, geometric normal
/// `ng` and shading normal `ns` (both on the viewer's side): `G = min(1, (ng·l)/((ns·l)(ng·ns)))`
/// clamped to `[0, 1]`, then `−G³ + G² + G`; 1 where `ns·l` or `ng·ns` is not positive.
pub fn chiang_term(l: DVec3, ng: DVec3, ns: DVec3) -> f64 {
    let (a, b) = (ns.dot(l), ng.dot(ns));
    if !(a > 0.0 && b > 0.0) {
        return 1.0;
    }
    let g = (ng.dot(l) / (a * b)).clamp(0.0, 1.0);
    -g * g * g + g * g + g
}

/// What one pixel of a study shows.
#[derive(Clone, Copy, Debug, Default)]
pub struct Pixel {
    /// The primary ray hit.
    pub hit: bool,
    /// Lit: the shading normal faces the light and the shadow ray is free.
    pub lit: bool,
    /// The shaded intensity `ambient + (1 − ambient)·(n·l)·visibility·G` (0 on a miss).
    pub intensity: f64,
    /// The shading normal used (toward the viewer).
    pub normal: DVec3,
}

/// A rendered study: the image, each pixel, and the rays traced.
pub struct Study {
    /// The shaded image.
    pub image: Image,
    /// Per pixel, row by row.
    pub pixels: Vec<Pixel>,
    /// Primary and shadow rays.
    pub rays: u64,
    /// Wall time, seconds.
    pub seconds: f64,
}

/// Ambient share of [`shade`] (the renderer's).
const AMBIENT: f64 = 0.12;

/// Renders `surface` through `cam` as the renderer does (module docs), with `fix` applied
/// (Hanika needs `mesh`'s triangles and vertex normals); `eps` is the shadow rays' offset.
pub fn render_study(
    surface: &dyn Surface,
    mesh: &Mesh,
    cam: &Camera,
    fix: Option<TerminatorFix>,
    eps: f64,
) -> Study {
    let start = std::time::Instant::now();
    let light = cam.light_dir();
    let (w, h) = (cam.width, cam.height);
    let (data, pixels, rays) = trace_pixels(
        cam,
        |x, y| {
            let (o, d) = cam.pixel_ray(x, y);
            let mut rays = 1;
            let Some(hit) = surface.closest_hit(o, d) else {
                return (background(y, h), Pixel::default(), rays);
            };
            let flip = |n: DVec3| if n.dot(d) > 0.0 { -n } else { n };
            let n = flip(hit.shading);
            let mut lambert = n.dot(light).max(0.0);
            let mut vis = 0.0;
            if lambert > 0.0 {
                rays += 1;
                let mut p = hit.point;
                if fix == Some(TerminatorFix::Hanika) {
                    let t = mesh.triangles.get(hit.triangle as usize).copied();
                    if let Some(t) = t {
                        let tri = t.map(|i| mesh.positions[i as usize]);
                        let nv = t.map(|i| mesh.normals[i as usize].normalize_or_zero());
                        p = hanika_origin(p, hit.w, tri, nv);
                    }
                }
                if fix == Some(TerminatorFix::Chiang) {
                    lambert *= chiang_term(light, flip(hit.geometric), n);
                }
                if !surface.any_hit(p - d * eps, light, eps) {
                    vis = 1.0;
                }
            }
            let pixel = Pixel {
                hit: true,
                lit: lambert > 0.0 && vis > 0.0,
                intensity: AMBIENT + (1.0 - AMBIENT) * lambert * vis,
                normal: n,
            };
            (shade(hit.front, lambert, vis), pixel, rays)
        },
        || {},
    );
    Study {
        image: Image {
            width: w,
            height: h,
            data,
        },
        pixels,
        rays,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The shadow rays' offset of the renderer for `diag` (the scene's bounding-box diagonal) in
/// `prec`.
pub fn shadow_eps(diag: f64, prec: Precision) -> f64 {
    diag * match prec {
        Precision::F32 => 2e-4,
        Precision::F64 => 1e-7,
    }
}

/// `render` for the modes and fixes of this module: a peer surface (`mode` phong-tess or
/// nagata) or flat triangles with Phong normals and `fix`. Returns the image and the rays and
/// seconds it took.
pub fn render_image(
    mesh: &Mesh,
    cam: &Camera,
    mode: Mode,
    fix: Option<TerminatorFix>,
    prec: Precision,
) -> Result<Study> {
    let eps = shadow_eps(mesh.diagonal(), prec);
    match prec {
        Precision::F32 => render_in::<f32>(mesh, cam, mode, fix, eps),
        Precision::F64 => render_in::<f64>(mesh, cam, mode, fix, eps),
    }
}

fn render_in<F: Prec + smoothtri_peers::Real>(
    mesh: &Mesh,
    cam: &Camera,
    mode: Mode,
    fix: Option<TerminatorFix>,
    eps: f64,
) -> Result<Study> {
    if let Some(peer) = peer_of(mode) {
        if fix.is_some() {
            return Err(DemoError::Usage(
                "--terminator applies to --mode phong (flat triangles with vertex normals)".into(),
            ));
        }
        let s = Peers::<F>::build(peer, mesh)?;
        if s.scene.skipped() > 0 {
            eprintln!(
                "note: {} skipped {} degenerate triangles",
                peer.name(),
                s.scene.skipped()
            );
        }
        return Ok(render_study(&s, mesh, cam, None, eps));
    }
    if mode != Mode::Phong {
        return Err(DemoError::Usage(
            "--terminator applies to --mode phong (flat triangles with vertex normals)".into(),
        ));
    }
    let scene = Scene::<F>::build_with(mesh, smoothtri::LineField::Face, false)?;
    Ok(render_study(
        &FlatPhong { scene: &scene },
        mesh,
        cam,
        fix,
        eps,
    ))
}

/// `trace --mode phong-tess|nagata`: the closest hit with `t > 0` of each ray, in `trace`'s
/// columns (`n…` the patch's geometric normal, `sn…` the peer's shading normal, `w1,w2` the
/// barycentrics on the patch, `t_error` 0: the peers certify nothing).
pub fn trace_csv<F: Prec + smoothtri_peers::Real>(
    mesh: &Mesh,
    peer: Peer,
    rays: &[Ray<F>],
) -> Result<String> {
    let scene = PeerScene::<F>::build(peer, &mesh.positions, &mesh.normals, &mesh.triangles)
        .map_err(|e| DemoError::Usage(format!("{}: {e}", peer.name())))?;
    let tr = scene
        .tracer()
        .map_err(|e| DemoError::Usage(format!("{}: {e}", peer.name())))?;
    let v = |x: F::Vec3| {
        let [a, b, c] = F::to_array3(x);
        format!("{a},{b},{c}")
    };
    let mut out = String::from("ray,hit,t,x,y,z,nx,ny,nz,snx,sny,snz,triangle,w1,w2,t_error\n");
    for (i, ray) in rays.iter().enumerate() {
        match tr.closest_hit(ray, F::MIN_POSITIVE, F::MAX) {
            Some(h) => {
                let sn = scene
                    .patches()
                    .get(h.patch as usize)
                    .map_or(h.normal, |p| peer.shading_normal(p, h.w1, h.w2));
                let _ = writeln!(
                    out,
                    "{i},1,{},{},{},{},{},{},{},0",
                    h.t,
                    v(h.point),
                    v(h.normal),
                    v(sn),
                    scene.triangle(h.patch),
                    h.w1,
                    h.w2
                );
            }
            None => {
                let _ = writeln!(out, "{i},0,,,,,,,,,,,,,,");
            }
        }
    }
    Ok(out)
}
