//! A mesh's patches built one by one, without the scene builder (no crack closure): what the
//! kernel's tests trace by brute force or through a BVH of their own.

use smoothtri::Patch;
use smoothtri_io::Mesh;

/// The `f32` patches of `mesh`, one per triangle in order, corners and normals rounded from
/// `f64`.
///
/// # Panics
/// When a triangle is rejected ([`Patch::new`]): the tests that call this need every one.
pub fn patches32(mesh: &Mesh) -> Vec<Patch> {
    (0..mesh.triangles.len())
        .map(|t| {
            let (p, n) = mesh.triangle(t);
            Patch::new(p.map(|x| x.as_vec3()), n.map(|x| x.as_vec3()))
                .unwrap_or_else(|e| panic!("triangle {t}: {e}"))
        })
        .collect()
}
