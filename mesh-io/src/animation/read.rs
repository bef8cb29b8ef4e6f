//! Reading a glTF document's animation data into an [`AnimatedMesh`]: the static walk's mesh, the
//! [`Rig`] that poses it (the nodes' rest state, the skins, the primitives the placements draw with
//! their morph targets and influences, each vertex's source), the [`Clip`](super::Clip)s, and the
//! per-frame [`Scratch`]. Every rule the posing relies on is checked (see the module documentation
//! of [`super`]) by the readers of each part: [`super::rest`], [`super::skin`], [`super::morph`]
//! and [`super::channels`], every accessor through [`super::numbers`].

use std::collections::HashMap;

use glam::{DMat4, DQuat, DVec3};

use super::channels::clips;
use super::morph::{morph_targets, target_counts};
use super::rest::{full_order, node_rests};
use super::skin::{influences, skins};
use super::{AnimatedMesh, Part, PartPose, Prim, Rig, Scratch};
use crate::error::{Error, Result};
use crate::gltf::{Prim as StaticPrim, Walk, mesh_label, node_label};
use crate::options::Budget;

/// The [`AnimatedMesh`] of a document whose drawn scene is `walk` (see [`super`]).
pub(super) fn animated(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    walk: Walk,
    path: &str,
) -> Result<AnimatedMesh> {
    let fail = |m: String| budget.typed(Error::format(path, m));
    let Walk {
        builder,
        mut warnings,
        placements,
        decoded,
        order,
    } = walk;
    let (mesh, computed_normals, sources) = builder.finish_sourced();
    if mesh.triangles.is_empty() {
        return Err(Error::NoTriangles {
            path: path.to_string(),
        });
    }
    let targets = target_counts(doc).map_err(fail)?;
    let mut rest_weights = Vec::new();
    let nodes = node_rests(doc, &targets, &mut rest_weights, budget).map_err(fail)?;
    let order = full_order(doc, order);
    let (skins, joint_count) = skins(doc, buffers, budget, &order).map_err(fail)?;

    // The primitives the placements draw, each read once, and the placements as parts.
    let mut prims: Vec<Prim> = Vec::new();
    let mut prim_of: HashMap<(usize, usize), usize> = HashMap::new();
    let mut parts = Vec::new();
    for pl in &placements {
        let gmesh = doc
            .meshes()
            .nth(pl.mesh)
            .ok_or_else(|| fail(format!("mesh {} does not exist", pl.mesh)))?;
        let gnode = pl.node.and_then(|n| doc.nodes().nth(n));
        let label = match &gnode {
            Some(n) => node_label(n),
            None => "no node".to_string(),
        };
        let at = format!("{label}, {}, primitive {}", mesh_label(&gmesh), pl.prim);
        let k = match prim_of.get(&(pl.mesh, pl.prim)) {
            Some(&k) => k,
            None => {
                let Some(StaticPrim::Triangles {
                    positions, normals, ..
                }) = decoded.get(&pl.mesh).and_then(|p| p.get(pl.prim))
                else {
                    return Err(fail(format!("{at}: not a triangle primitive")));
                };
                let gprim = gmesh
                    .primitives()
                    .nth(pl.prim)
                    .ok_or_else(|| fail(format!("{at}: does not exist")))?;
                let targets =
                    morph_targets(&gprim, positions.len(), normals.is_some(), buffers, budget)
                        .map_err(|m| fail(format!("{at}: {m}")))?;
                if let Some(w) = targets.1 {
                    warnings.push(format!("{at}: {w}"));
                }
                prims.push(Prim {
                    positions: positions.clone(),
                    normals: normals.clone(),
                    targets: targets.0,
                    influences: None,
                });
                prim_of.insert((pl.mesh, pl.prim), prims.len() - 1);
                prims.len() - 1
            }
        };
        let skin = gnode.as_ref().and_then(|n| n.skin()).map(|s| s.index());
        if let (Some(s), Some(n)) = (skin, &gnode) {
            let gprim = gmesh
                .primitives()
                .nth(pl.prim)
                .ok_or_else(|| fail(format!("{at}: does not exist")))?;
            if prims[k].influences.is_none() {
                let count = prims[k].positions.len();
                prims[k].influences = Some(
                    influences(&gprim, count, buffers, budget)
                        .map_err(|m| fail(format!("{at}: {m}")))?,
                );
            }
            let (max, joints) = (
                prims[k].influences.as_ref().map_or(0, |i| i.max_joint),
                skins[s].joints.len(),
            );
            if usize::from(max) >= joints {
                return Err(fail(format!(
                    "{at}: JOINTS_n names joint {max}, outside skin {s}'s {joints} joints \
                     (drawn by {})",
                    node_label(n)
                )));
            }
        }
        let weights = match (pl.node, targets.get(pl.mesh).copied().unwrap_or(0)) {
            (_, 0) => None,
            (Some(n), _) => nodes[n].weights.clone(),
            (None, t) => {
                let defaults = gmesh.weights().unwrap_or(&[]);
                let start = rest_weights.len();
                rest_weights.extend((0..t).map(|i| defaults.get(i).map_or(0.0, |&w| f64::from(w))));
                Some(start..start + t)
            }
        };
        parts.push(Part {
            node: pl.node,
            prim: k,
            skin,
            weights,
        });
    }
    // Each vertex of the mesh: the placement whose positions hold its source.
    let mut vertex = Vec::with_capacity(sources.len());
    for &src in &sources {
        let p = placements.partition_point(|pl| pl.first <= src);
        let Some(part) = p.checked_sub(1) else {
            return Err(fail(format!("vertex source {src} has no primitive")));
        };
        let local = src - placements[part].first;
        if local >= prims[parts[part].prim].positions.len() {
            return Err(fail(format!(
                "vertex source {src} is outside its primitive"
            )));
        }
        vertex.push((part as u32, local as u32));
    }
    let computed = parts.iter().any(|p| prims[p.prim].normals.is_none());
    let clips = clips(doc, buffers, budget, &nodes, &targets).map_err(fail)?;
    let widest = clips
        .iter()
        .flat_map(|c| c.channels.iter().map(|ch| ch.keys.width))
        .max()
        .unwrap_or(0);
    let n_nodes = nodes.len();
    let scratch = Scratch {
        trs: nodes
            .iter()
            .map(|n| n.trs.unwrap_or((DVec3::ZERO, DQuat::IDENTITY, DVec3::ONE)))
            .collect(),
        animated: vec![false; n_nodes],
        world: vec![DMat4::IDENTITY; n_nodes],
        weights: rest_weights.clone(),
        joints: vec![DMat4::IDENTITY; joint_count],
        parts: vec![PartPose::Skinned; parts.len()],
        computed: vec![DVec3::ZERO; if computed { mesh.positions.len() } else { 0 }],
        value: vec![0.0; widest],
    };
    Ok(AnimatedMesh {
        mesh,
        computed_normals,
        warnings,
        clips,
        rig: Rig {
            nodes,
            order,
            rest_weights,
            skins,
            prims,
            parts,
            vertex,
            computed,
        },
        scratch,
    })
}
