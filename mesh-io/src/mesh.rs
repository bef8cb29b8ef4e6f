//! [`Mesh`], the indexed triangle mesh with vertex normals every loader returns and every
//! writer takes, [`LoadedMesh`] (a mesh with what its loader noted), and [`FloatWidth`] (the
//! numbers a writer stores).

use glam::DVec3;
use smoothtri::{BuildError, BuildObserver, BuildOptions, Executor, Float, OwnedScene, Vertices};

/// An indexed triangle mesh with per-vertex normals, in `f64`.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex normals (one per position, any positive length).
    pub normals: Vec<DVec3>,
    /// Triangles as indices into `positions`/`normals`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The three corners and normals of triangle `t`.
    ///
    /// # Panics
    /// When `t` is not a triangle of the mesh or one of its indices is not a vertex (the
    /// loaders never make such a mesh).
    pub fn triangle(&self, t: usize) -> ([DVec3; 3], [DVec3; 3]) {
        let [a, b, c] = self.triangles[t].map(|i| i as usize);
        (
            [self.positions[a], self.positions[b], self.positions[c]],
            [self.normals[a], self.normals[b], self.normals[c]],
        )
    }

    /// Axis-aligned bounds (min, max) of the vertices; `(+∞, −∞)` for a mesh without vertices.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Length of the bounding-box diagonal (NaN for a mesh without vertices).
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).length()
    }

    /// The core's scene of this mesh in precision `F` ([`OwnedScene::build`]: patches, crack
    /// closure, seams when `options` asks, BVH), its observer told of rejected triangles and of
    /// the build's steps, its executor running the parallel parts (`()` for the calling
    /// thread). The scene is the same bit for bit whatever the executor.
    ///
    /// Returns the builder's [`BuildError`] when no triangle is accepted or the mesh is too
    /// large for the builder's counters.
    pub fn build_scene<F: Float, O: BuildObserver, E: Executor>(
        &self,
        options: &mut BuildOptions<O, E>,
    ) -> Result<OwnedScene<F>, BuildError> {
        let packed = |v: &[DVec3]| -> Vec<f64> { v.iter().flat_map(|p| p.to_array()).collect() };
        let (positions, normals) = (packed(&self.positions), packed(&self.normals));
        OwnedScene::build(
            Vertices::packed(&positions),
            Vertices::packed(&normals),
            &self.triangles,
            options,
        )
    }
}

/// A mesh read from a file.
#[derive(Clone, Debug)]
pub struct LoadedMesh {
    /// The mesh (vertices deduplicated per (position, normal) pair).
    pub mesh: Mesh,
    /// `true` when some or all vertex normals were computed (angle-weighted) because the file
    /// had none for them.
    pub computed_normals: bool,
    /// Warnings to show the user (skipped primitives and the like), one line each.
    pub warnings: Vec<String>,
}

/// The floating-point width a writer stores numbers in, where the format has a choice (OBJ's
/// decimal text, PLY's `float` or `double`; glTF always stores `f32`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatWidth {
    /// `f32`: OBJ numbers printed shortest-round-trip in `f32`, PLY `float` properties.
    F32,
    /// `f64`: OBJ numbers printed shortest-round-trip in `f64`, PLY `double` properties.
    F64,
}
