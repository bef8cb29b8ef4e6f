//! The pinhole camera of `render` and `precision`: auto-framing on a mesh and ray generation,
//! and the up axis ([`Up`]) that says which way a mesh stands.

use glam::DVec3;

use crate::mesh::Mesh;

/// Which coordinate axis points up in a mesh (`--up`).
///
/// The camera works in a z-up frame; a mesh with another up axis is first turned into it by
/// [`Up::to_z_up`], an exact rotation (a permutation of the coordinates with one sign change),
/// so `--view AZ,EL` is always relative to the chosen up axis: elevation is the angle above the
/// plane perpendicular to it, and azimuth turns about it.
///
/// | `--up` | z-up frame `(x', y', z')` | azimuth 0° looks from | default for |
/// |---|---|---|---|
/// | `z` | `(x, y, z)` | `+x` | the built-in scenes |
/// | `y` | `(x, −z, y)` | `+x` | mesh files (OBJ, PLY); glTF always |
/// | `x` | `(y, z, x)` | `+y` | |
///
/// The `y` row is the inverse of the conversion Blender's OBJ, PLY and glTF exporters apply to a
/// z-up scene by default (`(x, y, z)` written as `(x, z, −y)`), so a Blender model exported y-up
/// and read with `--up y` looks as it does in Blender, from the same `--view`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Up {
    /// `+x` is up.
    X,
    /// `+y` is up (glTF, and Blender's default for OBJ and PLY exports).
    #[default]
    Y,
    /// `+z` is up (the built-in scenes, most CAD and scanning tools).
    Z,
}

impl Up {
    /// Lower-case name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Up::X => "x",
            Up::Y => "y",
            Up::Z => "z",
        }
    }

    /// The point or direction `v` in the z-up frame of the table above: an exact rotation
    /// (no rounding) that takes this axis to `+z`.
    pub fn to_z_up(self, v: DVec3) -> DVec3 {
        match self {
            Up::X => DVec3::new(v.y, v.z, v.x),
            Up::Y => DVec3::new(v.x, -v.z, v.y),
            Up::Z => v,
        }
    }

    /// The inverse of [`Up::to_z_up`].
    pub fn from_z_up(self, v: DVec3) -> DVec3 {
        match self {
            Up::X => DVec3::new(v.z, v.x, v.y),
            Up::Y => DVec3::new(v.x, v.z, -v.y),
            Up::Z => v,
        }
    }

    /// `mesh` turned so that this axis points along `+z` (positions and normals rotated by
    /// [`Up::to_z_up`]; triangles unchanged, so orientation is kept).
    pub fn mesh_to_z_up(self, mesh: &Mesh) -> Mesh {
        Mesh {
            positions: mesh.positions.iter().map(|&p| self.to_z_up(p)).collect(),
            normals: mesh.normals.iter().map(|&n| self.to_z_up(n)).collect(),
            triangles: mesh.triangles.clone(),
        }
    }
}

impl std::fmt::Display for Up {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// A pinhole camera auto-framed on a bounding box, z up (turn other meshes with
/// [`Up::mesh_to_z_up`] first).
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn up_axes_are_exact_rotations_to_z() {
        let v = DVec3::new(0.1, -2.5, 7.0);
        for up in [Up::X, Up::Y, Up::Z] {
            assert_eq!(up.from_z_up(up.to_z_up(v)), v, "{up}");
            let axis = match up {
                Up::X => DVec3::X,
                Up::Y => DVec3::Y,
                Up::Z => DVec3::Z,
            };
            assert_eq!(up.to_z_up(axis), DVec3::Z, "{up}");
            // A rotation: right-handed bases stay right-handed.
            let (a, b) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-4.0, 0.5, 2.0));
            assert_eq!(up.to_z_up(a).cross(up.to_z_up(b)), up.to_z_up(a.cross(b)));
        }
        // Blender's y-up export writes (x, y, z) as (x, z, -y); --up y undoes it.
        let blender = DVec3::new(v.x, v.z, -v.y);
        assert_eq!(Up::Y.to_z_up(blender), v);
    }
}
