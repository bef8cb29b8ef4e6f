//! Patches and BVH built from a [`Mesh`], in either precision, and the per-mode tracers.

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};
use smoothtri::{Bvh, BvhNode, Float, Hit, Patch, PatchError, Ray, flat_hit};

use crate::error::{DemoError, Result};
use crate::scenes::Mesh;

/// The two primitive precisions, with conversions from and to the `f64` mesh data.
pub trait Prec: Float + Send + Sync + std::fmt::Display + 'static {
    /// `"f32"` or `"f64"`.
    const NAME: &'static str;
    /// Rounds an `f64` vector to this precision.
    fn v(d: DVec3) -> Self::Vec3;
    /// Widens a vector of this precision to `f64`.
    fn d(v: Self::Vec3) -> DVec3;
    /// Components of a vector.
    fn arr(v: Self::Vec3) -> [Self; 3];
}

impl Prec for f32 {
    const NAME: &'static str = "f32";
    fn v(d: DVec3) -> Vec3 {
        d.as_vec3()
    }
    fn d(v: Vec3) -> DVec3 {
        v.as_dvec3()
    }
    fn arr(v: Vec3) -> [f32; 3] {
        v.to_array()
    }
}

impl Prec for f64 {
    const NAME: &'static str = "f64";
    fn v(d: DVec3) -> DVec3 {
        d
    }
    fn d(v: DVec3) -> DVec3 {
        v
    }
    fn arr(v: DVec3) -> [f64; 3] {
        v.to_array()
    }
}

/// The patches of a mesh (triangles the core rejects are skipped and recorded) and their BVH.
pub struct Scene<F: Float> {
    /// Accepted patches.
    pub patches: Vec<Patch<F>>,
    /// Mesh triangle id of each patch.
    pub tri_ids: Vec<u32>,
    /// Patch index of each mesh triangle (`None` when rejected).
    pub patch_of_tri: Vec<Option<u32>>,
    /// Rejected triangles and why (only non-finite, degenerate or overflowing input: steep or
    /// back-facing normals are repaired by the core's documented remedy instead).
    pub rejected: Vec<(u32, PatchError)>,
    /// Triangles whose normals were clamped by [`Patch::new_or_tilted`], with the clamp angle
    /// in degrees.
    pub remedied: Vec<(u32, f64)>,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
}

impl<F: Prec> Scene<F> {
    /// Builds the patches and the BVH. Fails only when no triangle is accepted.
    pub fn build(mesh: &Mesh) -> Result<Self> {
        let mut patches = Vec::with_capacity(mesh.triangles.len());
        let mut tri_ids = Vec::with_capacity(mesh.triangles.len());
        let mut patch_of_tri = vec![None; mesh.triangles.len()];
        let mut rejected = Vec::new();
        let mut remedied = Vec::new();
        for (t, slot) in patch_of_tri.iter_mut().enumerate() {
            let (p, n) = mesh.triangle(t);
            match Patch::<F>::new_or_tilted(p.map(F::v), n.map(F::v)) {
                Ok(patch) => {
                    if let Some(deg) = patch.normal_clamp() {
                        remedied.push((t as u32, deg));
                    }
                    *slot = Some(patches.len() as u32);
                    patches.push(patch);
                    tri_ids.push(t as u32);
                }
                Err(e) => rejected.push((t as u32, e)),
            }
        }
        if patches.is_empty() {
            return Err(DemoError::Empty {
                msg: format!(
                    "no usable triangles: all {} triangles were rejected{}",
                    mesh.triangles.len(),
                    rejected
                        .first()
                        .map(|(_, e)| format!(" (first: {e})"))
                        .unwrap_or_default()
                ),
            });
        }
        let mut nodes = vec![BvhNode::default(); Bvh::<F>::nodes_needed(patches.len())];
        let mut order = vec![0u32; patches.len()];
        let used = Bvh::build(&patches, &mut nodes, &mut order)
            .map_err(|e| DemoError::Empty {
                msg: format!("cannot build the BVH: {e}"),
            })?
            .node_count();
        nodes.truncate(used);
        Ok(Scene {
            patches,
            tri_ids,
            patch_of_tri,
            rejected,
            remedied,
            nodes,
            order,
        })
    }

    /// The BVH over [`Scene::patches`].
    pub fn bvh(&self) -> Bvh<'_, F> {
        Bvh::from_parts(&self.patches, &self.nodes, &self.order)
    }

    /// Rejection counts by reason, for reports.
    pub fn rejected_summary(&self) -> BTreeMap<String, usize> {
        let mut m = BTreeMap::new();
        for (_, e) in &self.rejected {
            *m.entry(e.to_string()).or_insert(0) += 1;
        }
        m
    }

    /// The stderr note about skipped triangles, if any were.
    pub fn rejected_note(&self) -> Option<String> {
        let mut lines = Vec::new();
        if !self.remedied.is_empty() {
            lines.push(format!(
                "note: {} of {} triangles have normals outside the method's domain; they were \
                 clamped toward the face normal ({}): {}",
                self.remedied.len(),
                self.patch_of_tri.len(),
                F::NAME,
                self.remedied_summary()
            ));
        }
        if !self.rejected.is_empty() {
            let parts: Vec<String> = self
                .rejected_summary()
                .iter()
                .map(|(k, v)| format!("{v} × {k}"))
                .collect();
            lines.push(format!(
                "note: skipped {} of {} triangles that the core rejects ({}): {}",
                self.rejected.len(),
                self.patch_of_tri.len(),
                F::NAME,
                parts.join("; ")
            ));
        }
        if lines.is_empty() {
            None
        } else {
            Some(lines.join("\n"))
        }
    }

    /// Remedied patches by clamp angle, e.g. `3 × 60°, 1 × 0° (flat)`.
    pub fn remedied_summary(&self) -> String {
        let mut m: BTreeMap<i64, usize> = BTreeMap::new();
        for (_, deg) in &self.remedied {
            *m.entry(-(*deg as i64)).or_insert(0) += 1;
        }
        m.iter()
            .map(|(d, n)| {
                let flat = if *d == 0 { " (flat)" } else { "" };
                format!("{n} × {}°{flat}", -d)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// How primary and shadow rays meet the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Mode {
    /// The smooth patches (the core's kernel).
    Smooth,
    /// Flat triangles, face normals.
    Flat,
    /// Flat triangles, interpolated vertex normals (Phong shading).
    Phong,
}

impl Mode {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Smooth => "smooth",
            Mode::Flat => "flat",
            Mode::Phong => "phong",
        }
    }
}

/// A ray-scene query strategy (smooth kernel with a fixed budget, or a flat baseline).
pub trait Tracer<F: Float>: Sync {
    /// Closest hit in `[t_min, t_max]`.
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>>;
    /// Whether anything is hit in `[t_min, t_max]`.
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool;
}

struct Smooth<const N: usize>;
impl<F: Float, const N: usize> Tracer<F> for Smooth<N> {
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_hit::<N>(ray, t_min, t_max).ok().flatten()
    }
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        bvh.any_hit::<N>(ray, t_min, t_max).unwrap_or(false)
    }
}

struct Flat {
    phong: bool,
}
impl<F: Float> Tracer<F> for Flat {
    fn closest(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        bvh.closest_with(ray, t_min, t_max, |p, a, b| {
            let ns = p.normals();
            flat_hit(&p.vertices(), self.phong.then_some(&ns), ray, a, b)
        })
        .ok()
        .flatten()
    }
    fn occluded(&self, bvh: &Bvh<'_, F>, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        self.closest(bvh, ray, t_min, t_max).is_some()
    }
}

/// Largest iteration budget accepted by `--iterations`.
pub const MAX_ITERATIONS: usize = 40;

macro_rules! smooth_dispatch {
    ($n:expr, $($k:literal)*) => {
        match $n {
            $($k => Some(&Smooth::<$k> as &'static dyn Tracer<F>),)*
            _ => None,
        }
    };
}

/// Iteration budgets the demo is compiled for (each is a separate monomorphised kernel; the
/// core takes any `N` at compile time).
pub const SUPPORTED_ITERATIONS: &str = "0..=16, 20, 24, 32, 40";

/// The smooth kernel with an iteration budget of `n` (see [`SUPPORTED_ITERATIONS`]),
/// monomorphised.
pub fn smooth_tracer<F: Float>(n: usize) -> Option<&'static dyn Tracer<F>> {
    smooth_dispatch!(n, 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 20 24 32 40)
}

/// The tracer of `mode` (the budget matters for [`Mode::Smooth`] only).
pub fn tracer<F: Float>(mode: Mode, n: usize) -> Result<&'static dyn Tracer<F>> {
    match mode {
        Mode::Smooth => smooth_tracer(n).ok_or_else(|| {
            DemoError::Usage(format!(
                "--iterations {n} is not supported (use one of {SUPPORTED_ITERATIONS})"
            ))
        }),
        Mode::Flat => Ok(&Flat { phong: false }),
        Mode::Phong => Ok(&Flat { phong: true }),
    }
}

/// A pinhole camera auto-framed on a bounding box (z up).
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit right vector.
    pub right: DVec3,
    /// Unit up vector.
    pub up: DVec3,
    /// `tan(vertical fov / 2)`.
    pub tan_half: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// Vertical field of view of [`Camera::framed`], degrees.
pub const FOV_DEG: f64 = 35.0;

impl Camera {
    /// Looks at the centre of `bounds` from azimuth `az` and elevation `el` (degrees; azimuth
    /// from +x towards +y, elevation above the xy plane), far enough that the box's bounding
    /// sphere fits the image.
    pub fn framed(bounds: (DVec3, DVec3), az: f64, el: f64, width: u32, height: u32) -> Camera {
        let (lo, hi) = bounds;
        Camera::look_at_sphere(
            (lo + hi) * 0.5,
            (hi - lo).length() * 0.5,
            az,
            el,
            width,
            height,
        )
    }

    /// Frames a mesh: looks at its bounding box's centre, far enough that the sphere around
    /// that centre through the farthest vertex, enlarged by 10% (the smooth surface may bulge
    /// past the vertices), fits the image. This is the camera of `render` and `precision`.
    pub fn for_mesh(mesh: &Mesh, az: f64, el: f64, width: u32, height: u32) -> Camera {
        let (lo, hi) = mesh.bounds();
        let c = (lo + hi) * 0.5;
        let r = mesh
            .positions
            .iter()
            .map(|p| (*p - c).length())
            .fold(0.0, f64::max);
        Camera::look_at_sphere(c, r * 1.1, az, el, width, height)
    }

    /// Looks at `c` from azimuth `az` and elevation `el` (degrees) so that the sphere of radius
    /// `r` around `c` fits the image.
    pub fn look_at_sphere(c: DVec3, r: f64, az: f64, el: f64, width: u32, height: u32) -> Camera {
        let r = if r.is_finite() { r.max(1e-12) } else { 1.0 };
        let (az, el) = (az.to_radians(), el.to_radians());
        let dir = DVec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let width = width.max(1);
        let height = height.max(1);
        let tan_half = (FOV_DEG.to_radians() * 0.5).tan();
        let aspect = width as f64 / height as f64;
        let half_min = tan_half.min(tan_half * aspect).atan();
        let dist = r / half_min.sin() * 1.02;
        let eye = c + dir * dist;
        let forward = -dir;
        let world_up = if forward.z.abs() > 0.999 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let right = forward.cross(world_up).normalize();
        let up = right.cross(forward);
        Camera {
            eye,
            forward,
            right,
            up,
            tan_half,
            width,
            height,
        }
    }

    /// The unit-direction ray through image point `(px, py)` (pixels, continuous; pixel
    /// `(x, y)` has its centre at `(x + 0.5, y + 0.5)`, `y` down).
    pub fn ray(&self, px: f64, py: f64) -> (DVec3, DVec3) {
        let aspect = self.width as f64 / self.height as f64;
        let sx = (2.0 * px / self.width as f64 - 1.0) * self.tan_half * aspect;
        let sy = (1.0 - 2.0 * py / self.height as f64) * self.tan_half;
        let d = (self.forward + self.right * sx + self.up * sy).normalize();
        (self.eye, d)
    }

    /// The ray through the centre of pixel `(x, y)`.
    pub fn pixel_ray(&self, x: u32, y: u32) -> (DVec3, DVec3) {
        self.ray(x as f64 + 0.5, y as f64 + 0.5)
    }
}

/// `"AZ,EL"` in degrees.
pub fn parse_view(s: &str) -> std::result::Result<(f64, f64), String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("expected AZ,EL in degrees, got '{s}'"))?;
    let a: f64 = a
        .trim()
        .parse()
        .map_err(|_| format!("malformed azimuth '{a}'"))?;
    let e: f64 = e
        .trim()
        .parse()
        .map_err(|_| format!("malformed elevation '{e}'"))?;
    if !a.is_finite() || !e.is_finite() || e.abs() > 90.0 {
        return Err(format!(
            "view angles must be finite, elevation within [-90, 90]: '{s}'"
        ));
    }
    Ok((a, e))
}
