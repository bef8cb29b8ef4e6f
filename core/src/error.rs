//! Typed construction errors.

use core::fmt;

/// Why [`Patch::new`](crate::Patch::new) rejected its input.
///
/// Every variant names the offending vertex where there is one (0, 1 or 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchError {
    /// A vertex or normal coordinate is NaN or infinite.
    NonFinite,
    /// The triangle's area is below the relative tolerance
    /// (twice the area below `√ε · longest_edge²`, `√ε` = 3.45e-4 in `f32`, 1.49e-8 in `f64`;
    /// below it barycentric coordinates lose more than half their digits): collinear or coincident vertices.
    DegenerateTriangle,
    /// A vertex normal has zero (or subnormal) length.
    ZeroNormal {
        /// The vertex (0, 1 or 2).
        vertex: u8,
    },
    /// A vertex normal is at or beyond 90° from the face normal, or within the tolerance
    /// [`MIN_NORMAL_COS`](crate::patch::MIN_NORMAL_COS) of it. With counter-clockwise vertices
    /// seen from the normals' side this means the normal faces away from the triangle (or the
    /// triangle's winding is reversed).
    BackFacingNormal {
        /// The vertex (0, 1 or 2).
        vertex: u8,
    },
    /// The normals diverge so much that the shell's cross-section triangle flips (or
    /// the surface leaves the region where it is defined): outside the method's domain
    /// (docs/METHOD.md §7).
    InvalidShell,
    /// The coordinates are finite but so large (or so spread) that the construction overflows
    /// this precision; scale the mesh or use `f64`.
    OutOfRange,
}

impl fmt::Display for PatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PatchError::NonFinite => f.write_str("non-finite vertex or normal coordinate"),
            PatchError::DegenerateTriangle => f.write_str("degenerate triangle (area too small)"),
            PatchError::ZeroNormal { vertex } => write!(f, "zero normal at vertex {vertex}"),
            PatchError::BackFacingNormal { vertex } => write!(
                f,
                "normal at vertex {vertex} is at or beyond 90 degrees from the face normal"
            ),
            PatchError::InvalidShell => {
                f.write_str("normals diverge too much: the patch's shell is not valid")
            }
            PatchError::OutOfRange => {
                f.write_str("coordinates overflow the precision (scale the mesh or use f64)")
            }
        }
    }
}

impl core::error::Error for PatchError {}
