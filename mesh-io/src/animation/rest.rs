//! The nodes' rest state (local matrix, translation, rotation and scale, default morph weights)
//! and the order in which posing composes their world transforms.

use super::{Msg, NodeRest};
use crate::gltf::{local_matrix, local_trs, node_label};
use crate::options::Budget;

/// Every node's rest state; the default weights of each node whose mesh has morph targets
/// (the node's `weights`, else the mesh's, else zeros) go to `rest_weights`.
pub(super) fn node_rests(
    doc: &::gltf::Document,
    targets: &[usize],
    rest_weights: &mut Vec<f64>,
    budget: &Budget,
) -> Msg<Vec<NodeRest>> {
    let mut out = Vec::new();
    for n in doc.nodes() {
        let local = local_matrix(&n)?;
        let trs = local_trs(&n)?;
        let t = n
            .mesh()
            .and_then(|m| targets.get(m.index()).copied())
            .unwrap_or(0);
        let weights = if t > 0 {
            let defaults = match (n.weights(), n.mesh().and_then(|m| m.weights())) {
                (Some(w), _) => ("the node's weights", w),
                (None, Some(w)) => ("its mesh's weights", w),
                (None, None) => ("", &[][..]),
            };
            if !defaults.0.is_empty() && defaults.1.len() != t {
                return Err(format!(
                    "{}: {} has {} values for {t} morph targets",
                    node_label(&n),
                    defaults.0,
                    defaults.1.len()
                ));
            }
            if defaults.1.iter().any(|w| !w.is_finite()) {
                return Err(format!("{}: {} are not finite", node_label(&n), defaults.0));
            }
            // A node's weights cost the file a few bytes per target of its mesh, yet every
            // node drawing that mesh holds them all: charged.
            budget.charge_msg(&format!("{}: morph weights", node_label(&n)), t as u64, 8)?;
            let start = rest_weights.len();
            rest_weights.extend((0..t).map(|i| defaults.1.get(i).map_or(0.0, |&w| f64::from(w))));
            Some(start..start + t)
        } else {
            None
        };
        out.push(NodeRest {
            local,
            trs,
            weights,
        });
    }
    Ok(out)
}

/// The drawn scene's nodes in the static walk's order, then every other node reachable from a
/// root of the node forest (a skeleton kept outside the drawn scene), parents first.
pub(super) fn full_order(
    doc: &::gltf::Document,
    mut order: Vec<(usize, Option<usize>)>,
) -> Vec<(usize, Option<usize>)> {
    let n = doc.nodes().len();
    let mut seen = vec![false; n];
    for &(k, _) in &order {
        seen[k] = true;
    }
    let mut child = vec![false; n];
    for node in doc.nodes() {
        for c in node.children() {
            child[c.index()] = true;
        }
    }
    for root in doc.nodes().filter(|r| !child[r.index()]) {
        let mut stack = vec![(root, None)];
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut seen[node.index()], true) {
                continue;
            }
            order.push((node.index(), parent));
            stack.extend(node.children().map(|c| (c, Some(node.index()))));
        }
    }
    order
}
