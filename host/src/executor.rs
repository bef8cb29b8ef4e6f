//! The scene builder on rayon's pool: [`RayonExecutor`] (the core's [`Executor`]) and
//! [`build_scene`], a mesh's scene as the demo's renders build it.

use rayon::prelude::*;
use smoothtri::{BuildError, BuildOptions, Executor, Float, LineField, OwnedScene};
use smoothtri_io::Mesh;

/// The core builder's [`Executor`] over rayon's global pool: each slice in chunks of at least
/// the caller's grain, a few per thread.
#[derive(Clone, Copy, Debug, Default)]
pub struct RayonExecutor;

impl Executor for RayonExecutor {
    fn run_chunks<T: Send>(
        &self,
        items: &mut [T],
        grain: usize,
        work: &(dyn Fn(usize, &mut [T]) + Sync),
    ) {
        let chunk = (items.len() / (4 * rayon::current_num_threads())).max(grain.max(1));
        items
            .par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(i, c)| work(i * chunk, c));
    }
}

/// The scene of `mesh` in precision `F` as the demo's renders build it ([`Mesh::build_scene`]
/// on rayon's pool): patches on `field`, cracks closed, seams fitted when `seams`, BVH. The same
/// bit for bit as a build on one thread.
///
/// Returns the builder's [`BuildError`] when no triangle is accepted.
pub fn build_scene<F: Float>(
    mesh: &Mesh,
    field: LineField,
    seams: bool,
) -> Result<OwnedScene<F>, BuildError> {
    mesh.build_scene(&mut BuildOptions {
        field,
        seams,
        observer: (),
        executor: RayonExecutor,
    })
}
