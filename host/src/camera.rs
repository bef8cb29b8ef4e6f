//! The pinhole camera of the demo's renders (`render`, `precision`, `view`), of the benchmarks'
//! camera rays and of the GPU frames: auto-framing on a mesh, ray generation, and the light
//! the renders are lit with ([`Camera::light_dir`], [`SHADOW_OFFSET_F32`]), so that a benchmark
//! traces the rays and frames the demo draws.

use glam::DVec3;
use smoothtri::Ray;
use smoothtri_io::Mesh;

/// A pinhole camera auto-framed on a bounding box, z up (the demo turns meshes with another up
/// axis first: its `Up::mesh_to_z_up`).
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
        let (c, r) = Camera::mesh_sphere(mesh);
        Camera::look_at_sphere(c, r, az, el, width, height)
    }

    /// The sphere [`Camera::for_mesh`] frames: the bounding box's centre and the distance to
    /// the farthest vertex, enlarged by 10%.
    pub fn mesh_sphere(mesh: &Mesh) -> (DVec3, f64) {
        let (lo, hi) = mesh.bounds();
        let c = (lo + hi) * 0.5;
        let r = mesh
            .positions
            .iter()
            .map(|p| (*p - c).length())
            .fold(0.0, f64::max);
        (c, r * 1.1)
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

    /// The `f32` rays through the centres of all pixels, row by row from the top
    /// ([`Camera::pixel_ray`] rounded): the camera rays the benchmarks and GPU tests trace.
    pub fn rays_f32(&self) -> Vec<Ray<f32>> {
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (o, d) = self.pixel_ray(x, y);
                Ray::new(o.as_vec3(), d.as_vec3())
            })
            .collect()
    }

    /// The unit direction towards the renders' directional light: upper left, slightly behind
    /// the viewer (`−0.55 right + 0.75 up − 0.35 forward`, normalised).
    pub fn light_dir(&self) -> DVec3 {
        (self.right * -0.55 + self.up * 0.75 - self.forward * 0.35).normalize()
    }
}

/// Where a shadow ray starts in the renders traced in `f32` (the CPU renderer's and the GPU
/// frames'): this fraction of the scene's bounding-box diagonal before the hit along the
/// primary ray; occluders nearer than that are ignored.
pub const SHADOW_OFFSET_F32: f64 = 2e-4;
/// [`SHADOW_OFFSET_F32`] in `f64`.
pub const SHADOW_OFFSET_F64: f64 = 1e-7;
