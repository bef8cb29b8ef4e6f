//! A mesh's flat triangles in `f32`, as a flat renderer (or an Embree user geometry) holds
//! them: the corners and the boxes that a box tree over them is built from.

use glam::Vec3;
use smoothtri::Aabb;
use smoothtri_io::Mesh;

/// The corners of each triangle of `mesh`, in order, rounded from `f64` to `f32`.
pub fn flat_triangles32(mesh: &Mesh) -> Vec<[Vec3; 3]> {
    (0..mesh.triangles.len())
        .map(|t| mesh.triangle(t).0.map(|p| p.as_vec3()))
        .collect()
}

/// The bounding box of each triangle of `tris`, in order (the corners' componentwise minimum
/// and maximum; no padding).
pub fn triangle_boxes(tris: &[[Vec3; 3]]) -> Vec<Aabb> {
    tris.iter()
        .map(|t| Aabb::new(t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2])))
        .collect()
}
