//! The up axis ([`Up`], `--up`) that says which way a mesh stands, and the exact rotation that
//! turns a mesh into the camera's z-up frame ([`smoothtri_host::Camera`]).

use glam::DVec3;
use smoothtri_io::Mesh;

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

/// The up axis of a built-in scene ([`smoothtri_host::scenes::builtin`]), the default of
/// `--up` for it: `z` for all four (the torus lies in the xy plane, the teapot stands on it, the
/// sphere and the cube are symmetric).
pub fn builtin_up(_name: &str) -> Up {
    Up::Z
}

impl std::fmt::Display for Up {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
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
