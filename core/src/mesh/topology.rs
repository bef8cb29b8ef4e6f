//! Mesh topology: the edges two triangles share, found by sorting the triangles' edges by their
//! vertex indices in caller-provided scratch (no allocation), and the typed errors of the
//! mesh-level steps ([`MeshError`]).

use core::fmt;

/// Scratch entry of [`fit_seams`](super::fit_seams), [`close_cracks`](super::close_cracks) and
/// [`Scene::build`](crate::Scene::build): one triangle edge keyed by its two vertex indices. The
/// caller provides `3 × triangles` of them (any contents; [`SharedEdge::default`] will do).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SharedEdge {
    /// `lo << 32 | hi` of the two vertex indices.
    key: u64,
    /// `3 × triangle + local edge`.
    slot: u32,
}

/// Why a mesh-level step ([`fit_seams`](super::fit_seams), [`close_cracks`](super::close_cracks),
/// [`clamp_vertex_normals`](super::clamp_vertex_normals)) could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshError {
    /// The patches, the triangles and the seams differ in number.
    LengthMismatch {
        /// Patches given.
        patches: usize,
        /// Triangles given.
        triangles: usize,
        /// Seams given.
        seams: usize,
    },
    /// The scratch storage holds fewer than `3 × triangles` entries.
    ScratchTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// More triangles than the scratch entries can index (`3 × triangles` must fit a `u32`).
    TooManyTriangles,
    /// [`close_cracks`](crate::mesh::close_cracks): the patches and the triangles differ in
    /// number.
    PatchCount {
        /// Patches given.
        patches: usize,
        /// Triangles given.
        triangles: usize,
    },
    /// [`clamp_vertex_normals`](crate::mesh::clamp_vertex_normals): the positions, the normals
    /// and the output differ in number.
    VertexCount {
        /// Positions given.
        positions: usize,
        /// Normals given.
        normals: usize,
        /// Output entries given.
        out: usize,
    },
    /// A triangle has a vertex index at or above the vertex count, or repeats an index.
    BadIndex {
        /// The triangle.
        triangle: usize,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::LengthMismatch {
                patches,
                triangles,
                seams,
            } => write!(
                f,
                "seams: {patches} patches, {triangles} triangles and {seams} seams differ in number"
            ),
            MeshError::PatchCount { patches, triangles } => write!(
                f,
                "cracks: {patches} patches and {triangles} triangles differ in number"
            ),
            MeshError::VertexCount {
                positions,
                normals,
                out,
            } => write!(
                f,
                "vertex normals: {positions} positions, {normals} normals and {out} outputs \
                 differ in number"
            ),
            MeshError::ScratchTooSmall { needed } => {
                write!(f, "mesh: scratch too small, need {needed} edge entries")
            }
            MeshError::TooManyTriangles => f.write_str("mesh: too many triangles"),
            MeshError::BadIndex { triangle } => write!(
                f,
                "mesh: triangle {triangle} has an out-of-range or repeated vertex index"
            ),
        }
    }
}

impl core::error::Error for MeshError {}

/// One edge shared by two triangles that traverse it in opposite directions: edge `ja` of
/// triangle `ta` (from its vertex `ja` to `ja + 1`) and edge `jb` of triangle `tb`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct EdgePair {
    pub(crate) ta: usize,
    pub(crate) ja: usize,
    pub(crate) tb: usize,
    pub(crate) jb: usize,
}

/// Finds every edge shared by exactly two triangles that traverse it in opposite directions
/// and stores them, in the order of their sorted vertex keys, in the first entries of
/// `scratch` ([`edge_pair`] reads them back); returns their number. `scratch` holds at least
/// `3 × triangles.len()` entries (contents on entry ignored; past the pairs unspecified on
/// return).
///
/// Errors: [`MeshError::TooManyTriangles`], [`MeshError::ScratchTooSmall`] and
/// [`MeshError::BadIndex`] (an index at or above `vertex_count`, or repeated in a triangle).
pub(crate) fn pair_shared_edges(
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &mut [SharedEdge],
) -> Result<usize, MeshError> {
    let Some(needed) = triangles.len().checked_mul(3) else {
        return Err(MeshError::TooManyTriangles);
    };
    if u32::try_from(needed).is_err() {
        return Err(MeshError::TooManyTriangles);
    }
    let Some(edges) = scratch.get_mut(..needed) else {
        return Err(MeshError::ScratchTooSmall { needed });
    };
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = *tri;
        let ok = [a, b, c]
            .iter()
            .all(|&i| usize::try_from(i).is_ok_and(|i| i < vertex_count));
        if !ok || a == b || b == c || c == a {
            return Err(MeshError::BadIndex { triangle: t });
        }
    }
    let mut slots = edges.iter_mut();
    for (t, tri) in triangles.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = edge_ends(tri, j);
            if let Some(e) = slots.next() {
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                *e = SharedEdge {
                    key: (u64::from(lo) << 32) | u64::from(hi),
                    slot: (3 * t + j) as u32,
                };
            }
        }
    }
    heap_sort(edges);
    // Compact the pairs to the front: pair `w` is written once its group (of at least two
    // entries, starting at or after entry `2w`) has been read.
    let (mut read, mut written) = (0usize, 0usize);
    while let Some(first) = edges.get(read).copied() {
        let run = edges.get(read..).map_or(1, |rest| {
            rest.iter().take_while(|e| e.key == first.key).count()
        });
        let group = (edges.get(read).copied(), edges.get(read + 1).copied());
        read += run.max(1);
        let (2, (Some(ea), Some(eb))) = (run, group) else {
            continue;
        };
        let (ta, ja) = (ea.slot as usize / 3, ea.slot as usize % 3);
        let (tb, jb) = (eb.slot as usize / 3, eb.slot as usize % 3);
        let (Some(tri_a), Some(tri_b)) = (triangles.get(ta), triangles.get(tb)) else {
            continue;
        };
        // Opposite directions: A runs a → b, B runs b → a.
        if edge_ends(tri_a, ja).0 == edge_ends(tri_b, jb).0 {
            continue;
        }
        if let Some(slot) = edges.get_mut(written) {
            *slot = SharedEdge {
                key: u64::from(eb.slot),
                slot: ea.slot,
            };
            written += 1;
        }
    }
    Ok(written)
}

/// The edges of a mesh that two triangles share, as the builder pairs them for crack closure
/// and seams: every edge shared by exactly two triangles that traverse it in opposite
/// directions. Writes them into the first entries of `scratch` (at least `3 × triangles.len()`
/// entries, contents on entry ignored) in the order of their sorted vertex indices, and returns
/// that prefix; read each with [`SharedEdge::sides`]. For a port of the edge pass (the GPU's),
/// which must pair exactly the edges the CPU pairs.
///
/// Errors: [`MeshError::TooManyTriangles`], [`MeshError::ScratchTooSmall`] and
/// [`MeshError::BadIndex`] (an index at or above `vertex_count`, or repeated in a triangle).
///
/// Work: one heapsort of the `3 × triangles.len()` edges (`O(n log n)`, in place, no
/// allocation).
/// # Panics
/// Never.
pub fn shared_edges<'s>(
    triangles: &[[u32; 3]],
    vertex_count: usize,
    scratch: &'s mut [SharedEdge],
) -> Result<&'s [SharedEdge], MeshError> {
    let n = pair_shared_edges(triangles, vertex_count, scratch)?;
    Ok(scratch.get(..n).unwrap_or(&[]))
}

impl SharedEdge {
    /// The two sides of a shared edge returned by [`shared_edges`]: `3 × triangle + local
    /// edge` of each (local edge `j` runs from the triangle's vertex `j` to `j + 1`; the two
    /// triangles run the edge in opposite directions). Meaningless for entries not returned by
    /// [`shared_edges`].
    ///
    /// # Panics
    /// Never.
    pub fn sides(&self) -> [u32; 2] {
        [self.slot, self.key as u32]
    }
}

/// The pair stored at `scratch[k]` by [`pair_shared_edges`] (`k` below its count).
#[inline(always)]
pub(crate) fn edge_pair(pairs: &[SharedEdge], k: usize) -> Option<EdgePair> {
    let e = pairs.get(k)?;
    let (a, b) = (e.slot as usize, e.key as usize);
    Some(EdgePair {
        ta: a / 3,
        ja: a % 3,
        tb: b / 3,
        jb: b % 3,
    })
}

/// `true` when entry `a` sorts before entry `b` (by key, then slot); `false` out of range.
#[inline(always)]
fn before(v: &[SharedEdge], a: usize, b: usize) -> bool {
    match (v.get(a), v.get(b)) {
        (Some(x), Some(y)) => (x.key, x.slot) < (y.key, y.slot),
        _ => false,
    }
}

/// Swaps entries `a` and `b` when both are in range.
#[inline(always)]
fn swap_in(v: &mut [SharedEdge], a: usize, b: usize) {
    if a < v.len() && b < v.len() {
        v.swap(a, b);
    }
}

/// Moves entry `root` down the max-heap `v[..end]`.
fn sift_down(v: &mut [SharedEdge], mut root: usize, end: usize) {
    loop {
        let mut child = 2 * root + 1;
        if child >= end {
            return;
        }
        if child + 1 < end && before(v, child, child + 1) {
            child += 1;
        }
        if !before(v, root, child) {
            return;
        }
        swap_in(v, root, child);
        root = child;
    }
}

/// Sorts the edges by key, then slot: an in-place heapsort, `O(n log n)`, no recursion. (Core's
/// `sort_unstable_by` keeps a panic path for inconsistent orderings, which the crate's no-panic
/// link proof rejects.)
fn heap_sort(v: &mut [SharedEdge]) {
    let n = v.len();
    let mut start = n / 2;
    while start > 0 {
        start -= 1;
        sift_down(v, start, n);
    }
    let mut end = n;
    while end > 1 {
        end -= 1;
        swap_in(v, 0, end);
        sift_down(v, 0, end);
    }
}

/// Vertex indices `(start, end)` of local edge `j` of a triangle (`j` mod 3).
#[inline(always)]
fn edge_ends(tri: &[u32; 3], j: usize) -> (u32, u32) {
    let [a, b, c] = *tri;
    match j % 3 {
        0 => (a, b),
        1 => (b, c),
        _ => (c, a),
    }
}

/// `x` with `x_j = 1 − t`, `x_{j+1} = t` (the point at `t` on edge `j`), the third zero.
#[inline(always)]
pub(crate) fn edge_bary(j: usize, t: f64) -> [f64; 3] {
    match j % 3 {
        0 => [1.0 - t, t, 0.0],
        1 => [0.0, 1.0 - t, t],
        _ => [t, 0.0, 1.0 - t],
    }
}
