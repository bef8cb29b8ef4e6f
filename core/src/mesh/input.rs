//! The builder's inputs: vertex attributes read from the caller's buffers ([`Vertices`]) and
//! what to build beside the patches ([`BuildOptions`]).

use super::report::{BuildError, BuildObserver};
#[cfg(doc)]
use super::{DynamicScene, Scene, SceneHit, SceneSizes};
use crate::exec::Executor;
use crate::num::real::Float;
use crate::surface::field::LineField;

/// A read-only view of one vertex attribute (three scalars per vertex) in a caller's buffer:
/// vertex `i`'s components are `data[offset + i·stride ..][..3]`, so interleaved vertex
/// buffers (position, normal, uv, …) need no copy. Strides and offsets count scalars, not
/// bytes. For `&[[f32; 3]]` use `Vertices::packed(v.as_flattened())`.
#[derive(Clone, Copy, Debug)]
pub struct Vertices<'a, T> {
    data: &'a [T],
    offset: usize,
    stride: usize,
    count: usize,
}

impl<'a, T: Float> Vertices<'a, T> {
    /// Tightly packed `x, y, z` triples: `data.len() / 3` vertices (a trailing partial triple
    /// is not a vertex).
    ///
    /// # Panics
    /// Never.
    pub const fn packed(data: &'a [T]) -> Self {
        Vertices {
            data,
            offset: 0,
            stride: 3,
            count: data.len() / 3,
        }
    }

    /// `count` vertices whose components start at `offset` and repeat every `stride` scalars.
    ///
    /// Returns [`BuildError::VertexLayout`] when `stride < 3` (with `count > 1`) or when the
    /// last vertex would end past `data`.
    ///
    /// # Panics
    /// Never.
    pub fn strided(
        data: &'a [T],
        offset: usize,
        stride: usize,
        count: usize,
    ) -> Result<Self, BuildError> {
        let bad = BuildError::VertexLayout {
            offset,
            stride,
            count,
            len: data.len(),
        };
        if count > 1 && stride < 3 {
            return Err(bad);
        }
        let end = match count.checked_sub(1) {
            None => offset,
            Some(last) => last
                .checked_mul(stride)
                .and_then(|x| x.checked_add(offset))
                .and_then(|x| x.checked_add(3))
                .ok_or(bad)?,
        };
        if end > data.len() {
            return Err(bad);
        }
        Ok(Vertices {
            data,
            offset,
            stride,
            count,
        })
    }

    /// Number of vertices.
    ///
    /// # Panics
    /// Never.
    pub const fn len(&self) -> usize {
        self.count
    }

    /// `true` when there is no vertex.
    ///
    /// # Panics
    /// Never.
    pub const fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Vertex `i`'s three components, `None` at or beyond [`Vertices::len`].
    ///
    /// # Panics
    /// Never.
    pub fn get(&self, i: usize) -> Option<[T; 3]> {
        if i >= self.count {
            return None;
        }
        let at = i.checked_mul(self.stride)?.checked_add(self.offset)?;
        match self.data.get(at..at.checked_add(3)?)? {
            &[x, y, z] => Some([x, y, z]),
            _ => None,
        }
    }

    /// Vertex `i` rounded to the precision `F` (exact when `T` is `F` or narrower).
    #[inline]
    pub(super) fn vec3<F: Float>(&self, i: usize) -> Option<F::Vec3> {
        let [x, y, z] = self.get(i)?;
        let c = |v: T| F::from_f64(v.to_f64());
        Some(F::to_glam(crate::num::vec::V3::new(c(x), c(y), c(z))))
    }
}

/// How [`Scene::build`] (and an update, [`DynamicScene::update`]) builds a scene: what beside
/// the patches and the BVH, who is told what it does, and whose threads run it. The one
/// options value of every build; [`BuildOptions::default`] is the paper's line field, no seams,
/// nothing observed, the calling thread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildOptions<O = (), E = ()> {
    /// The line field of the patches: [`LineField::Face`] (the paper's construction, the
    /// default) or [`LineField::Vertex`] (neighbours share their edges' lines, so their edge
    /// curves meet; adds the per-vertex remedy and its storage).
    pub field: LineField,
    /// Fit the seamless shading normals ([`SceneHit::shading_normal`] then differs from the
    /// geometric normal; costs `2·FIT_SAMPLES` = 16 normal evaluations per shared edge and
    /// [`SceneSizes::seams`] storage). Without it the shading normal is the geometric one.
    pub seams: bool,
    /// Told each rejected triangle and the start and progress of each step
    /// ([`BuildObserver`]; `()`: nothing; `&mut` your observer to keep what it learns).
    pub observer: O,
    /// Runs the parallel parts of each step ([`Executor`]; `()`: the calling thread). The
    /// scene is bit for bit the same whatever the executor.
    pub executor: E,
}

/// The paper's line field, no seams, no observer, the calling thread.
impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            field: LineField::Face,
            seams: false,
            observer: (),
            executor: (),
        }
    }
}

impl<O, E> BuildOptions<O, E> {
    /// These options with `observer` in place of theirs.
    ///
    /// # Panics
    /// Never.
    pub fn with_observer<P: BuildObserver>(self, observer: P) -> BuildOptions<P, E> {
        BuildOptions {
            field: self.field,
            seams: self.seams,
            observer,
            executor: self.executor,
        }
    }

    /// These options with `executor` in place of theirs.
    ///
    /// # Panics
    /// Never.
    pub fn with_executor<X: Executor>(self, executor: X) -> BuildOptions<O, X> {
        BuildOptions {
            field: self.field,
            seams: self.seams,
            observer: self.observer,
            executor,
        }
    }
}
