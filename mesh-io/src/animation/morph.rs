//! Morph targets: how many each mesh has, and the `POSITION` and `NORMAL` deltas of a drawn
//! primitive's targets.

use glam::DVec3;

use super::numbers::read_vec3;
use super::{Msg, Target};
use crate::gltf::mesh_label;
use crate::options::Budget;

/// The number of morph targets of each mesh (all its primitives must have the same).
pub(super) fn target_counts(doc: &::gltf::Document) -> Msg<Vec<usize>> {
    doc.meshes()
        .map(|m| {
            let counts: Vec<usize> = m.primitives().map(|p| p.morph_targets().len()).collect();
            match counts.iter().find(|&&c| c != counts[0]) {
                Some(c) => Err(format!(
                    "{}: its primitives have {} and {c} morph targets (all must have the same \
                     number)",
                    mesh_label(&m),
                    counts[0]
                )),
                None => Ok(counts.first().copied().unwrap_or(0)),
            }
        })
        .collect()
}

/// The morph targets of a primitive of `count` vertices (`POSITION` and `NORMAL` deltas; other
/// attributes are not used), and a warning when a target has normals but the primitive has
/// none (they are ignored: its normals are computed from the posed positions).
pub(super) fn morph_targets(
    prim: &::gltf::Primitive<'_>,
    count: usize,
    has_normals: bool,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> Msg<(Vec<Target>, Option<String>)> {
    let mut out = Vec::new();
    let mut warning = None;
    for (t, target) in prim.morph_targets().enumerate() {
        let read = |acc: Option<::gltf::Accessor<'_>>, what: &str| -> Msg<Option<Vec<DVec3>>> {
            let Some(acc) = acc else { return Ok(None) };
            let v =
                read_vec3(&acc, buffers, budget).map_err(|m| format!("target {t} {what} {m}"))?;
            if v.len() != count {
                return Err(format!(
                    "target {t} {what} accessor {} has {} elements for {count} vertices",
                    acc.index(),
                    v.len()
                ));
            }
            Ok(Some(v))
        };
        let positions = read(target.positions(), "POSITION")?;
        let mut normals = read(target.normals(), "NORMAL")?;
        if normals.is_some() && !has_normals {
            normals = None;
            warning = Some(
                "morph target NORMAL deltas ignored: the primitive has no NORMAL (its normals \
                 are computed from the posed positions)"
                    .to_string(),
            );
        }
        out.push(Target { positions, normals });
    }
    Ok((out, warning))
}
