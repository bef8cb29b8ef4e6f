//! Shared by the `gltf_scene` and `tessellate` targets: what every mesh they accept must be.

use smoothtri_io::Mesh;

/// Asserts that `mesh` has finite positions, finite normals and vertex indices in range.
pub fn assert_well_formed(mesh: &Mesh) {
    assert!(
        mesh.positions.iter().all(|p| p.is_finite()),
        "non-finite position"
    );
    assert!(
        mesh.normals.iter().all(|n| n.is_finite()),
        "non-finite normal"
    );
    let nv = mesh.positions.len() as u32;
    assert!(
        mesh.triangles.iter().flatten().all(|&i| i < nv),
        "index out of range"
    );
}
