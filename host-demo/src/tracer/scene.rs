//! [`Scene`]: the patches of a [`Mesh`] in one precision (triangles the core rejects skipped
//! and recorded), their BVH and their seams (the seamless shading normals' fit).

use std::collections::BTreeMap;

use smoothtri::{
    Bvh, BvhNode, CrackReport, Float, Hit, LineField, Patch, PatchError, Seam, SharedEdge,
    VertexClamp, VertexClampReport, clamp_vertex_normals, close_cracks, fit_seams,
};

use super::{Normals, Prec};
use crate::error::{DemoError, Result};
use crate::mesh::Mesh;

/// The patches of a mesh (triangles the core rejects are skipped and recorded), their BVH and
/// their seams.
pub struct Scene<F: Float> {
    /// Accepted patches.
    pub patches: Vec<Patch<F>>,
    /// Mesh triangle id of each patch.
    pub tri_ids: Vec<u32>,
    /// Patch index of each mesh triangle (`None` when rejected).
    pub patch_of_tri: Vec<Option<u32>>,
    /// Rejected triangles and why (only non-finite, degenerate or overflowing input: steep or
    /// back-facing normals are repaired by the core's documented remedy instead).
    pub rejected: Vec<(u32, PatchError)>,
    /// Triangles whose normals were clamped by [`Patch::new_or_tilted`], with the clamp angle
    /// in degrees.
    pub remedied: Vec<(u32, f64)>,
    /// The seam of each patch ([`Scene::fit_seams`]; empty until then): the correction that
    /// makes the shading normal continuous across shared edges.
    pub seams: Vec<Seam<F>>,
    /// Shared edges fitted by [`fit_seams`].
    pub seam_edges: usize,
    /// The per-vertex remedy on the shared line field ([`clamp_vertex_normals`]; `None` on the
    /// face field, whose remedy is per patch).
    pub vertex_clamps: Option<VertexClampReport>,
    /// What [`close_cracks`] measured when the scene was built: the patches reach across
    /// their shared edges by the gap between the neighbours' edge curves.
    pub cracks: CrackReport,
    /// The normal [`Scene::shading_normal`] returns: geometric after [`Scene::build`],
    /// seamless after [`Scene::fit_seams`].
    pub normals: Normals,
    nodes: Vec<BvhNode<F>>,
    order: Vec<u32>,
}

/// The accepted triangles' index buffer (same order as the patches).
fn accepted_triangles(mesh: &Mesh, tri_ids: &[u32]) -> Vec<[u32; 3]> {
    tri_ids
        .iter()
        .map(|&t| mesh.triangles[t as usize])
        .collect()
}

impl<F: Prec> Scene<F> {
    /// Builds the patches, closes the cracks between neighbours ([`close_cracks`] over the
    /// accepted triangles' index buffer) and builds the BVH (no seams: [`Scene::fit_seams`]
    /// adds them; until then the scene shades with the geometric normal). Fails only when no
    /// triangle is accepted.
    pub fn build(mesh: &Mesh) -> Result<Self> {
        Self::build_on(mesh, LineField::Face)
    }

    /// [`Scene::build`] with the patches on the line field `field` ([`LineField::Vertex`]:
    /// neighbours share their edges' lines, so their edge curves meet; docs/METHOD.md §2). On
    /// the shared field the steep-normal remedy acts per vertex first
    /// ([`clamp_vertex_normals`]: one clamped normal for all faces around a vertex), and per
    /// patch only where that does not suffice.
    pub fn build_on(mesh: &Mesh, field: LineField) -> Result<Self> {
        let (normals, vertex_clamps) = match field {
            LineField::Face => (None, None),
            LineField::Vertex => {
                let pos: Vec<F::Vec3> = mesh.positions.iter().map(|p| F::v(*p)).collect();
                let nrm: Vec<F::Vec3> = mesh.normals.iter().map(|n| F::v(*n)).collect();
                let mut out = nrm.clone();
                let mut scratch = vec![VertexClamp::<F>::default(); pos.len()];
                let report =
                    clamp_vertex_normals(&pos, &nrm, &mesh.triangles, &mut out, &mut scratch)
                        .map_err(|e| DemoError::Empty {
                            msg: format!("cannot clamp the vertex normals: {e}"),
                        })?;
                (Some(out), Some(report))
            }
        };
        let mut patches = Vec::with_capacity(mesh.triangles.len());
        let mut tri_ids = Vec::with_capacity(mesh.triangles.len());
        let mut patch_of_tri = vec![None; mesh.triangles.len()];
        let mut rejected = Vec::new();
        let mut remedied = Vec::new();
        for (t, slot) in patch_of_tri.iter_mut().enumerate() {
            let (p, n) = mesh.triangle(t);
            let n = match &normals {
                Some(shared) => mesh.triangles[t].map(|i| shared[i as usize]),
                None => n.map(F::v),
            };
            match Patch::<F>::new_or_tilted_with(p.map(F::v), n, field) {
                Ok(patch) => {
                    if let Some(deg) = patch.normal_clamp() {
                        remedied.push((t as u32, deg));
                    }
                    *slot = Some(patches.len() as u32);
                    patches.push(patch);
                    tri_ids.push(t as u32);
                }
                Err(e) => rejected.push((t as u32, e)),
            }
        }
        if patches.is_empty() {
            return Err(DemoError::Empty {
                msg: format!(
                    "no usable triangles: all {} triangles were rejected{}",
                    mesh.triangles.len(),
                    rejected
                        .first()
                        .map(|(_, e)| format!(" (first: {e})"))
                        .unwrap_or_default()
                ),
            });
        }
        let tris = accepted_triangles(mesh, &tri_ids);
        let mut scratch = vec![SharedEdge::default(); 3 * patches.len()];
        let cracks = close_cracks(&mut patches, &tris, mesh.positions.len(), &mut scratch)
            .map_err(|e| DemoError::Empty {
                msg: format!("cannot close the cracks: {e}"),
            })?;
        let mut nodes = vec![BvhNode::default(); Bvh::<F>::nodes_needed(patches.len())];
        let mut order = vec![0u32; patches.len()];
        let used = Bvh::build(&patches, &mut nodes, &mut order)
            .map_err(|e| DemoError::Empty {
                msg: format!("cannot build the BVH: {e}"),
            })?
            .node_count();
        nodes.truncate(used);
        Ok(Scene {
            patches,
            tri_ids,
            patch_of_tri,
            rejected,
            remedied,
            seams: Vec::new(),
            seam_edges: 0,
            vertex_clamps,
            cracks,
            normals: Normals::Geometric,
            nodes,
            order,
        })
    }

    /// Fits the seams of the accepted patches ([`fit_seams`] over their index buffer in
    /// `mesh`, the mesh the scene was built from) and shades with the seamless normal from then
    /// on. Only what shades needs them (`render`, `inspect`): fitting costs 98 `f64` normal
    /// evaluations per shared edge, seconds on meshes of 100k triangles.
    pub fn fit_seams(&mut self, mesh: &Mesh) -> Result<()> {
        let tris = accepted_triangles(mesh, &self.tri_ids);
        let mut scratch = vec![SharedEdge::default(); 3 * self.patches.len()];
        let mut seams = vec![Seam::default(); self.patches.len()];
        self.seam_edges = fit_seams(
            &self.patches,
            &tris,
            mesh.positions.len(),
            &mut scratch,
            &mut seams,
        )
        .map_err(|e| DemoError::Empty {
            msg: format!("cannot fit the seams: {e}"),
        })?;
        self.seams = seams;
        self.normals = Normals::Seamless;
        Ok(())
    }

    /// The normal to shade a smooth hit with: with [`Normals::Seamless`] the hit's geometric
    /// normal corrected by its patch's seam ([`Seam::correct`]), with [`Normals::Geometric`]
    /// the hit's normal as it is. Oriented like the vertex normals.
    pub fn shading_normal(&self, hit: &Hit<F>) -> F::Vec3 {
        let i = hit.patch as usize;
        match (self.normals, self.seams.get(i), self.patches.get(i)) {
            (Normals::Seamless, Some(seam), Some(patch)) => {
                seam.correct(patch, hit.w1, hit.w2, hit.normal)
            }
            _ => hit.normal,
        }
    }

    /// The BVH over [`Scene::patches`].
    pub fn bvh(&self) -> Bvh<'_, F> {
        Bvh::from_parts(&self.patches, &self.nodes, &self.order)
    }

    /// Rejection counts by reason, for reports.
    pub fn rejected_summary(&self) -> BTreeMap<String, usize> {
        let mut m = BTreeMap::new();
        for (_, e) in &self.rejected {
            *m.entry(e.to_string()).or_insert(0) += 1;
        }
        m
    }

    /// The stderr note about skipped triangles, if any were.
    pub fn rejected_note(&self) -> Option<String> {
        let mut lines = Vec::new();
        if !self.remedied.is_empty() {
            lines.push(format!(
                "note: {} of {} triangles have normals outside the method's domain; they were \
                 clamped toward the face normal ({}): {}",
                self.remedied.len(),
                self.patch_of_tri.len(),
                F::PRECISION,
                self.remedied_summary()
            ));
        }
        if !self.rejected.is_empty() {
            let parts: Vec<String> = self
                .rejected_summary()
                .iter()
                .map(|(k, v)| format!("{v} × {k}"))
                .collect();
            lines.push(format!(
                "note: skipped {} of {} triangles that the core rejects ({}): {}",
                self.rejected.len(),
                self.patch_of_tri.len(),
                F::PRECISION,
                parts.join("; ")
            ));
        }
        if lines.is_empty() {
            None
        } else {
            Some(lines.join("\n"))
        }
    }

    /// Remedied patches by clamp angle, e.g. `3 × 60°, 1 × 0° (flat)`.
    pub fn remedied_summary(&self) -> String {
        let mut m: BTreeMap<i64, usize> = BTreeMap::new();
        for (_, deg) in &self.remedied {
            *m.entry(-(*deg as i64)).or_insert(0) += 1;
        }
        m.iter()
            .map(|(d, n)| {
                let flat = if *d == 0 { " (flat)" } else { "" };
                format!("{n} × {}°{flat}", -d)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}
