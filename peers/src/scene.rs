//! A mesh of peer patches in smoothtri's BVH: one [`QuadPatch`] per triangle, a [`BoxBvh`]
//! over their boxes, and queries through smoothtri's traversal with the exact patch test in
//! the leaves.

use glam::DVec3;
use smoothtri::{BoxBvh, BvhError, BvhNode, Hit, Ray};

use crate::quadratic::{PeerError, QuadPatch};
use crate::real::Real;

/// Which peer surface a [`PeerScene`] is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Peer {
    /// Phong tessellation with shape factor `alpha` ([`crate::phong_tess`]); shaded with the
    /// interpolated vertex normals, as the paper does.
    PhongTess {
        /// The shape factor `α` (the paper's default: [`crate::ALPHA_DEFAULT`]).
        alpha: f64,
    },
    /// Nagata patches ([`crate::nagata`]); shaded with the patch's own normal.
    Nagata,
}

impl Peer {
    /// The patch of one triangle.
    ///
    /// # Panics
    /// Never.
    pub fn patch<F: Real>(
        self,
        p: [F::Vec3; 3],
        n: [F::Vec3; 3],
    ) -> Result<QuadPatch<F>, PeerError> {
        match self {
            Peer::PhongTess { alpha } => crate::phong_tessellation(p, n, alpha),
            Peer::Nagata => crate::nagata(p, n),
        }
    }

    /// The normal a renderer shades this surface with at `(w1, w2)` of `patch`: the
    /// interpolated vertex normal for Phong tessellation, the geometric normal for Nagata.
    ///
    /// # Panics
    /// Never.
    pub fn shading_normal<F: Real>(self, patch: &QuadPatch<F>, w1: F, w2: F) -> F::Vec3 {
        match self {
            Peer::PhongTess { .. } => patch.interpolated_normal(w1, w2),
            Peer::Nagata => patch.normal(w1, w2),
        }
    }

    /// A short name (`phong-tess α=0.75`, `nagata`).
    pub fn name(self) -> String {
        match self {
            Peer::PhongTess { alpha } => format!("phong-tess α={alpha}"),
            Peer::Nagata => "nagata".into(),
        }
    }
}

/// Why a [`PeerScene`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneError {
    /// A triangle's index is out of range.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
    },
    /// No triangle gave a patch.
    NoUsableTriangles,
    /// The BVH could not be built.
    Bvh(BvhError),
}

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SceneError::IndexOutOfRange { triangle } => {
                write!(f, "triangle {triangle} has an index out of range")
            }
            SceneError::NoUsableTriangles => f.write_str("no triangle gave a patch"),
            SceneError::Bvh(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SceneError {}

/// A mesh of peer patches with its BVH (owned storage).
#[derive(Clone, Debug)]
pub struct PeerScene<F: Real = f32> {
    peer: Peer,
    patches: Vec<QuadPatch<F>>,
    triangles: Vec<u32>,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
    skipped: usize,
}

impl<F: Real> PeerScene<F> {
    /// One `peer` patch per triangle of `positions`/`normals`/`triangles` (a triangle whose
    /// patch fails, [`PeerError`], is skipped and counted: [`PeerScene::skipped`]), and smoothtri's
    /// BVH over their boxes ([`BoxBvh::build`]).
    ///
    /// # Panics
    /// Never.
    pub fn build(
        peer: Peer,
        positions: &[DVec3],
        normals: &[DVec3],
        triangles: &[[u32; 3]],
    ) -> Result<Self, SceneError> {
        let mut patches = Vec::with_capacity(triangles.len());
        let mut ids = Vec::with_capacity(triangles.len());
        let mut skipped = 0;
        for (k, t) in triangles.iter().enumerate() {
            let get = |s: &[DVec3], i: u32| s.get(i as usize).copied();
            let (Some(p0), Some(p1), Some(p2)) = (
                get(positions, t[0]),
                get(positions, t[1]),
                get(positions, t[2]),
            ) else {
                return Err(SceneError::IndexOutOfRange { triangle: k });
            };
            let (Some(n0), Some(n1), Some(n2)) =
                (get(normals, t[0]), get(normals, t[1]), get(normals, t[2]))
            else {
                return Err(SceneError::IndexOutOfRange { triangle: k });
            };
            let r = |v: DVec3| F::from_dvec3(v);
            match peer.patch::<F>([p0, p1, p2].map(r), [n0, n1, n2].map(r)) {
                Ok(p) => {
                    patches.push(p);
                    ids.push(k as u32);
                }
                Err(_) => skipped += 1,
            }
        }
        if patches.is_empty() {
            return Err(SceneError::NoUsableTriangles);
        }
        let boxes: Vec<_> = patches.iter().map(|p| p.bounds()).collect();
        let mut nodes = vec![BvhNode::default(); BoxBvh::<F>::nodes_needed(boxes.len())];
        let mut order = vec![0u32; boxes.len()];
        let used = BoxBvh::build(&boxes, &mut nodes, &mut order)
            .map_err(SceneError::Bvh)?
            .node_count();
        nodes.truncate(used);
        Ok(PeerScene {
            peer,
            patches,
            triangles: ids,
            nodes,
            order,
            skipped,
        })
    }

    /// The surface.
    pub fn peer(&self) -> Peer {
        self.peer
    }

    /// The patches (a hit's `patch` indexes them).
    pub fn patches(&self) -> &[QuadPatch<F>] {
        &self.patches
    }

    /// The input triangle of patch `patch` (`u32::MAX` out of range).
    pub fn triangle(&self, patch: u32) -> u32 {
        self.triangles
            .get(patch as usize)
            .copied()
            .unwrap_or(u32::MAX)
    }

    /// Triangles skipped (their patch failed).
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// Bytes of the patches and the BVH.
    pub fn memory_bytes(&self) -> usize {
        core::mem::size_of_val(self.patches.as_slice())
            + core::mem::size_of_val(self.nodes.as_slice())
            + core::mem::size_of_val(self.order.as_slice())
    }

    /// The queries (the BVH checked once: [`BoxBvh::from_parts`]).
    ///
    /// # Panics
    /// Never.
    pub fn tracer(&self) -> Result<Tracer<'_, F>, SceneError> {
        let tree = BoxBvh::from_parts(self.patches.len(), &self.nodes, &self.order)
            .map_err(SceneError::Bvh)?;
        Ok(Tracer {
            patches: &self.patches,
            tree,
        })
    }
}

/// The queries of a [`PeerScene`]: smoothtri's BVH traversal with [`QuadPatch::closest_hit`]
/// in the leaves.
#[derive(Clone, Copy, Debug)]
pub struct Tracer<'a, F: Real> {
    patches: &'a [QuadPatch<F>],
    tree: BoxBvh<'a, F>,
}

impl<F: Real> Tracer<'_, F> {
    /// The closest hit in `[t_min, t_max]`; `patch` is the patch's index.
    ///
    /// # Panics
    /// Never.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray<F>, t_min: F, t_max: F) -> Option<Hit<F>> {
        let patches = self.patches;
        self.tree.closest_with(ray, t_min, t_max, |i, a, b| {
            patches.get(i as usize)?.closest_hit(ray, a, b)
        })
    }

    /// Whether anything is hit in `[t_min, t_max]`.
    ///
    /// # Panics
    /// Never.
    #[inline]
    pub fn any_hit(&self, ray: &Ray<F>, t_min: F, t_max: F) -> bool {
        let patches = self.patches;
        self.tree.any_with(ray, t_min, t_max, |i, a, b| {
            patches
                .get(i as usize)
                .and_then(|p| p.closest_hit(ray, a, b))
                .is_some()
        })
    }
}
