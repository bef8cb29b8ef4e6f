//! Posing: the channels of a clip sampled into the nodes' properties and morph weights, the
//! world and joint matrices composed, and each vertex morphed, then skinned or carried rigidly
//! by its node, its normal by the inverse transpose (or the signed cofactor where that does not
//! exist), into the caller's buffers without allocating.

use glam::{DMat3, DMat4, DQuat, DVec3};

use super::{AnimatedMesh, Clip, PartPose, Path, PoseError, Rig, Scratch};
use crate::error::Result;
use crate::weld::angle_weighted_normals_into;

impl AnimatedMesh {
    /// Writes the pose at `at` (a clip and a time, checked by the caller), or the rest pose,
    /// as [`AnimatedMesh::pose`] describes.
    pub(super) fn pose_at(
        &mut self,
        at: Option<(usize, f64)>,
        positions: &mut [DVec3],
        normals: &mut [DVec3],
    ) -> Result<(), PoseError> {
        let n = self.mesh.positions.len();
        if positions.len() != n || normals.len() != n {
            return Err(PoseError::Buffers {
                vertices: n,
                positions: positions.len(),
                normals: normals.len(),
            });
        }
        let rig = &self.rig;
        let s = &mut self.scratch;
        s.animated.fill(false);
        s.weights.copy_from_slice(&rig.rest_weights);
        if let Some((clip, time)) = at {
            apply_channels(rig, &self.clips[clip], time, s);
        }
        pose_nodes(rig, s);
        pose_parts(rig, s);
        for (k, &(part, i)) in rig.vertex.iter().enumerate() {
            let (p, nrm) = pose_vertex(rig, s, part as usize, i as usize);
            positions[k] = p;
            normals[k] = nrm;
        }
        if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
            return Err(PoseError::NonFinite { vertex: k });
        }
        if rig.computed {
            angle_weighted_normals_into(
                positions,
                self.mesh.triangles.iter().map(|t| t.map(|i| i as usize)),
                &mut s.computed,
            );
            for (k, &(part, _)) in rig.vertex.iter().enumerate() {
                if rig.prims[rig.parts[part as usize].prim].normals.is_none() {
                    normals[k] = s.computed[k];
                }
            }
        }
        Ok(())
    }
}

/// Samples every channel of `clip` at `time` into the nodes' properties and weights.
fn apply_channels(rig: &Rig, clip: &Clip, time: f64, s: &mut Scratch) {
    for ch in &clip.channels {
        let v = &mut s.value[..ch.keys.width];
        ch.keys.sample(time, v);
        let node = ch.node;
        if ch.path == Path::Weights {
            if let Some(r) = &rig.nodes[node].weights {
                s.weights[r.clone()].copy_from_slice(v);
            }
            continue;
        }
        if !s.animated[node] {
            s.animated[node] = true;
            if let Some(trs) = rig.nodes[node].trs {
                s.trs[node] = trs;
            }
        }
        let t = &mut s.trs[node];
        match ch.path {
            Path::Translation => t.0 = DVec3::new(v[0], v[1], v[2]),
            Path::Rotation => t.1 = DQuat::from_xyzw(v[0], v[1], v[2], v[3]),
            Path::Scale => t.2 = DVec3::new(v[0], v[1], v[2]),
            Path::Weights => {}
        }
    }
}

/// The world matrix of every node of [`Rig::order`] and every joint matrix.
fn pose_nodes(rig: &Rig, s: &mut Scratch) {
    for &(node, parent) in &rig.order {
        let local = if s.animated[node] {
            let (t, r, sc) = s.trs[node];
            DMat4::from_scale_rotation_translation(sc, r, t)
        } else {
            rig.nodes[node].local
        };
        let up = parent.map_or(DMat4::IDENTITY, |p| s.world[p]);
        s.world[node] = up * local;
    }
    for skin in &rig.skins {
        for (j, (&node, ibm)) in skin.joints.iter().zip(&skin.inverse_bind).enumerate() {
            s.joints[skin.first + j] = s.world[node] * *ibm;
        }
    }
}

/// How each part is posed this frame (see [`PartPose`]).
fn pose_parts(rig: &Rig, s: &mut Scratch) {
    for (k, part) in rig.parts.iter().enumerate() {
        s.parts[k] = if part.skin.is_some() {
            PartPose::Skinned
        } else {
            let m = part.node.map_or(DMat4::IDENTITY, |n| s.world[n]);
            PartPose::Rigid {
                m,
                normal: normal_matrix(DMat3::from_mat4(m)),
            }
        };
    }
}

/// The matrix that carries normals under `m`: its inverse transpose, as the static loader
/// uses; where `m` is singular (or its inverse overflows), [`signed_cofactor`].
pub(super) fn normal_matrix(m: DMat3) -> DMat3 {
    let det = m.determinant();
    let inv = m.inverse().transpose();
    if det != 0.0 && det.is_finite() && inv.is_finite() {
        inv
    } else {
        signed_cofactor(m)
    }
}

/// The cofactor matrix of `m` times the sign of its determinant: `|det m| · m⁻ᵀ` where `m` is
/// invertible, so it turns normals as the inverse transpose does (up to their length), without
/// a division, and stays finite where `m` is singular. Its columns are the cross products of
/// `m`'s columns.
pub(super) fn signed_cofactor(m: DMat3) -> DMat3 {
    let c = DMat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    if m.x_axis.dot(c.x_axis) < 0.0 { -c } else { c }
}

/// The posed position and normal of vertex `i` of part `part` (the normal zero where the
/// primitive has none: computed afterwards).
fn pose_vertex(rig: &Rig, s: &Scratch, part: usize, i: usize) -> (DVec3, DVec3) {
    let pt = &rig.parts[part];
    let prim = &rig.prims[pt.prim];
    let mut p = prim.positions[i];
    let mut n = prim.normals.as_ref().map_or(DVec3::ZERO, |ns| ns[i]);
    if let Some(r) = &pt.weights {
        for (target, &w) in prim.targets.iter().zip(&s.weights[r.clone()]) {
            if w == 0.0 {
                continue;
            }
            if let Some(d) = &target.positions {
                p += d[i] * w;
            }
            if let (Some(d), Some(_)) = (&target.normals, &prim.normals) {
                n += d[i] * w;
            }
        }
    }
    match s.parts[part] {
        PartPose::Rigid { m, normal } => (m.transform_point3(p), (normal * n).normalize_or_zero()),
        PartPose::Skinned => {
            let (Some(inf), Some(skin)) = (&prim.influences, pt.skin.map(|k| &rig.skins[k])) else {
                return (p, n.normalize_or_zero());
            };
            let at = i * inf.per_vertex;
            let mut m = DMat4::ZERO;
            for (&j, &w) in inf.joints[at..at + inf.per_vertex]
                .iter()
                .zip(&inf.weights[at..at + inf.per_vertex])
            {
                if w != 0.0 {
                    m += s.joints[skin.first + j as usize] * w;
                }
            }
            (
                m.transform_point3(p),
                (signed_cofactor(DMat3::from_mat4(m)) * n).normalize_or_zero(),
            )
        }
    }
}
