//! Skins: each skin's joints and inverse bind matrices, and the joints and weights
//! (`JOINTS_n`/`WEIGHTS_n`) of each skinned primitive's vertices.

use glam::DMat4;

use super::numbers::{JOINTS, MATRICES, WEIGHTS, read_numbers};
use super::{Influences, Msg, Skin, WEIGHT_SUM_TOLERANCE};
use crate::options::Budget;

/// Every skin with its inverse bind matrices (identity when absent), and the number of joint
/// matrices of all skins. Each joint must be a node whose world transform
/// [`full_order`](super::rest::full_order) computes.
pub(super) fn skins(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    order: &[(usize, Option<usize>)],
) -> Msg<(Vec<Skin>, usize)> {
    let mut placed = vec![false; doc.nodes().len()];
    for &(k, _) in order {
        placed[k] = true;
    }
    let mut out = Vec::new();
    let mut first = 0;
    for skin in doc.skins() {
        let at = match skin.name() {
            Some(n) => format!("skin {} {n:?}", skin.index()),
            None => format!("skin {}", skin.index()),
        };
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        if joints.is_empty() {
            return Err(format!("{at}: it has no joints"));
        }
        if joints.len() > usize::from(u16::MAX) + 1 {
            return Err(format!("{at}: {} joints (at most 65536)", joints.len()));
        }
        if let Some(j) = joints.iter().find(|&&j| !placed[j]) {
            return Err(format!(
                "{at}: joint node {j} is in a cycle of the node hierarchy"
            ));
        }
        let inverse_bind = match skin.inverse_bind_matrices() {
            None => vec![DMat4::IDENTITY; joints.len()],
            Some(acc) => {
                let v = read_numbers(&acc, &MATRICES, buffers, budget)
                    .map_err(|m| format!("{at}: inverseBindMatrices {m}"))?;
                if acc.count() < joints.len() {
                    return Err(format!(
                        "{at}: inverseBindMatrices accessor {} has {} matrices for {} joints",
                        acc.index(),
                        acc.count(),
                        joints.len()
                    ));
                }
                v.chunks_exact(16)
                    .take(joints.len())
                    .map(|c| {
                        let mut a = [0.0; 16];
                        a.copy_from_slice(c);
                        DMat4::from_cols_array(&a)
                    })
                    .collect()
            }
        };
        out.push(Skin {
            first,
            joints,
            inverse_bind,
        });
        first += out.last().map_or(0, |s| s.joints.len());
    }
    Ok((out, first))
}

/// The joints and weights of a skinned primitive of `count` vertices: every
/// `JOINTS_n`/`WEIGHTS_n` set from 0 on, the weights non-negative and, per vertex, summing to
/// one within [`WEIGHT_SUM_TOLERANCE`] (then divided by their sum).
pub(super) fn influences(
    prim: &::gltf::Primitive<'_>,
    count: usize,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> Msg<Influences> {
    use ::gltf::Semantic;
    let mut sets: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    for set in 0.. {
        let (j, w) = (
            prim.get(&Semantic::Joints(set)),
            prim.get(&Semantic::Weights(set)),
        );
        let (j, w) = match (j, w) {
            (None, None) => break,
            (Some(j), Some(w)) => (j, w),
            (Some(_), None) => return Err(format!("JOINTS_{set} has no WEIGHTS_{set}")),
            (None, Some(_)) => return Err(format!("WEIGHTS_{set} has no JOINTS_{set}")),
        };
        let joints =
            read_numbers(&j, &JOINTS, buffers, budget).map_err(|m| format!("JOINTS_{set} {m}"))?;
        let weights = read_numbers(&w, &WEIGHTS, buffers, budget)
            .map_err(|m| format!("WEIGHTS_{set} {m}"))?;
        for (what, acc, v) in [("JOINTS", &j, &joints), ("WEIGHTS", &w, &weights)] {
            if v.len() != 4 * count {
                return Err(format!(
                    "{what}_{set} accessor {} has {} elements for {count} vertices",
                    acc.index(),
                    v.len() / 4
                ));
            }
        }
        sets.push((joints, weights));
    }
    if sets.is_empty() {
        return Err("the node has a skin but the primitive has no JOINTS_0 and WEIGHTS_0".into());
    }
    let per_vertex = 4 * sets.len();
    budget.charge_msg("joints and weights", (per_vertex * count) as u64, 2 + 8)?;
    let mut joints = Vec::with_capacity(per_vertex * count);
    let mut weights = Vec::with_capacity(per_vertex * count);
    for v in 0..count {
        for (j, w) in &sets {
            joints.extend(j[4 * v..4 * v + 4].iter().map(|&x| x as u16));
            weights.extend_from_slice(&w[4 * v..4 * v + 4]);
        }
        let ws = &mut weights[per_vertex * v..];
        if let Some(w) = ws.iter().find(|&&w| w < 0.0) {
            return Err(format!("vertex {v} has the negative weight {w}"));
        }
        let sum: f64 = ws.iter().sum();
        if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
            return Err(format!(
                "the weights of vertex {v} sum to {sum}, not 1 (tolerance {WEIGHT_SUM_TOLERANCE})"
            ));
        }
        for w in ws.iter_mut() {
            *w /= sum;
        }
    }
    let max_joint = joints.iter().copied().max().unwrap_or(0);
    Ok(Influences {
        per_vertex,
        joints,
        weights,
        max_joint,
    })
}
