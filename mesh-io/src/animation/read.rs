//! Reading a glTF document's animation data into a [`Rig`] and its [`Clip`]s, every accessor
//! checked ([`crate::gltf::check_accessor`]) before the `gltf` crate reads it, every rule the
//! posing relies on checked here (see the module documentation of [`super`]).
//!
//! Channels are read from the JSON, not through the `gltf` crate's `Channel::target`: its
//! validation does not check a channel's node index or path, and its accessors `unwrap` them.

use std::collections::HashMap;

use ::gltf::accessor::{DataType, Dimensions, Item, Iter};
use ::gltf::json::animation::{Interpolation as JsonInterpolation, Property};
use ::gltf::json::validation::Checked;
use glam::{DMat4, DQuat, DVec3};

use super::keys::{Interpolation, Keys};
use super::{
    AnimatedMesh, Channel, Clip, Influences, NodeRest, Part, PartPose, Path, Prim, Rig, Scratch,
    Skin, Target, WEIGHT_SUM_TOLERANCE,
};
use crate::error::{Error, Result};
use crate::gltf::{
    Prim as StaticPrim, Walk, Want, check_accessor, local_matrix, local_trs, mesh_label, node_label,
};
use crate::options::Budget;

type Msg<T> = std::result::Result<T, String>;

/// The floats of an accessor (`f32`) or the normalised integers the specification allows.
const FLOAT: &[DataType] = &[DataType::F32];
const NORMALIZED: &[DataType] = &[
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];
const WEIGHT_TYPES: &[DataType] = &[DataType::F32, DataType::U8, DataType::U16];
const JOINT_TYPES: &[DataType] = &[DataType::U8, DataType::U16];

/// An accessor component: how it becomes a number (normalised integers as the specification
/// decodes them).
trait Component: Item + Copy {
    fn real(self, normalized: bool) -> f64;
}

impl Component for f32 {
    fn real(self, _: bool) -> f64 {
        f64::from(self)
    }
}
impl Component for u8 {
    fn real(self, normalized: bool) -> f64 {
        if normalized {
            f64::from(self) / 255.0
        } else {
            f64::from(self)
        }
    }
}
impl Component for u16 {
    fn real(self, normalized: bool) -> f64 {
        if normalized {
            f64::from(self) / 65535.0
        } else {
            f64::from(self)
        }
    }
}
impl Component for i8 {
    fn real(self, normalized: bool) -> f64 {
        if normalized {
            (f64::from(self) / 127.0).max(-1.0)
        } else {
            f64::from(self)
        }
    }
}
impl Component for i16 {
    fn real(self, normalized: bool) -> f64 {
        if normalized {
            (f64::from(self) / 32767.0).max(-1.0)
        } else {
            f64::from(self)
        }
    }
}

/// The elements of a checked accessor (zeros where it has no buffer view, as the
/// specification says, sparse values applied).
fn elements<E: Item + Copy>(acc: &::gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Msg<Vec<E>> {
    let count = acc.count();
    if acc.view().is_none() && acc.sparse().is_none() {
        return Ok(vec![E::zero(); count]);
    }
    let get = |b: ::gltf::Buffer<'_>| buffers.get(b.index()).map(Vec::as_slice);
    let items: Vec<E> = Iter::<E>::new(acc.clone(), get)
        .ok_or_else(|| format!("accessor {} could not be read", acc.index()))?
        .collect();
    if items.len() != count {
        return Err(format!(
            "accessor {} yields {} elements, not its count {count}",
            acc.index(),
            items.len()
        ));
    }
    Ok(items)
}

/// [`elements`] flattened to numbers, `dims` components each.
fn numbers<T: Component>(
    acc: &::gltf::Accessor<'_>,
    dims: Dimensions,
    normalized: bool,
    buffers: &[Vec<u8>],
) -> Msg<Vec<f64>> {
    let r = |c: T| c.real(normalized);
    Ok(match dims {
        Dimensions::Scalar => elements::<T>(acc, buffers)?.into_iter().map(r).collect(),
        Dimensions::Vec3 => elements::<[T; 3]>(acc, buffers)?
            .into_iter()
            .flatten()
            .map(r)
            .collect(),
        Dimensions::Vec4 => elements::<[T; 4]>(acc, buffers)?
            .into_iter()
            .flatten()
            .map(r)
            .collect(),
        Dimensions::Mat4 => elements::<[[T; 4]; 4]>(acc, buffers)?
            .into_iter()
            .flatten()
            .flatten()
            .map(r)
            .collect(),
        other => return Err(format!("accessor {}: {other:?} is not read", acc.index())),
    })
}

/// The numbers of accessor `acc` after checking that it holds `dims` of one of `types`
/// (integers decoded as normalised when `normalized`) and that every one is finite.
fn read_numbers(
    acc: &::gltf::Accessor<'_>,
    dims: Dimensions,
    types: &'static [DataType],
    expected: &'static str,
    normalized: bool,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> Msg<Vec<f64>> {
    check_accessor(
        acc,
        Want::Of {
            dims,
            types,
            expected,
        },
        buffers,
    )?;
    // Before anything is decoded: the elements (zeros where the accessor has no view, bounded
    // by nothing else) and the numbers they become, `f64` each.
    let per = acc.dimensions().multiplicity() as u64;
    let component = acc.data_type().size() as u64;
    budget.charge_msg(
        &format!("accessor {}", acc.index()),
        acc.count() as u64,
        per * (component + 8),
    )?;
    let v = match acc.data_type() {
        DataType::F32 => numbers::<f32>(acc, dims, normalized, buffers)?,
        DataType::U8 => numbers::<u8>(acc, dims, normalized, buffers)?,
        DataType::U16 => numbers::<u16>(acc, dims, normalized, buffers)?,
        DataType::I8 => numbers::<i8>(acc, dims, normalized, buffers)?,
        DataType::I16 => numbers::<i16>(acc, dims, normalized, buffers)?,
        other => return Err(format!("accessor {}: {other:?} is not read", acc.index())),
    };
    let per = v.len() / acc.count().max(1);
    if let Some(k) = v.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "accessor {}: element {} is not finite",
            acc.index(),
            k / per.max(1)
        ));
    }
    Ok(v)
}

/// `VEC3` float data as vectors.
fn read_vec3(acc: &::gltf::Accessor<'_>, buffers: &[Vec<u8>], budget: &Budget) -> Msg<Vec<DVec3>> {
    let v = read_numbers(
        acc,
        Dimensions::Vec3,
        FLOAT,
        "Vec3 of F32",
        false,
        buffers,
        budget,
    )?;
    Ok(v.chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect())
}

/// The accessor of index `i`, or a message naming `what`.
fn accessor<'a>(doc: &'a ::gltf::Document, i: usize, what: &str) -> Msg<::gltf::Accessor<'a>> {
    doc.accessors()
        .nth(i)
        .ok_or_else(|| format!("{what}: accessor {i} does not exist"))
}

/// `animation 0 "Walk"` (the name only when it has one).
fn animation_label(i: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("animation {i} {n:?}"),
        None => format!("animation {i}"),
    }
}

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

/// The number of morph targets of each mesh (all its primitives must have the same).
fn target_counts(doc: &::gltf::Document) -> Msg<Vec<usize>> {
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

/// Every node's rest state; the default weights of each node whose mesh has morph targets
/// (the node's `weights`, else the mesh's, else zeros) go to `rest_weights`.
fn node_rests(
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
fn full_order(
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

/// Every skin with its inverse bind matrices (identity when absent), and the number of joint
/// matrices of all skins. Each joint must be a node whose world transform [`full_order`]
/// computes.
fn skins(
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
                let v = read_numbers(
                    &acc,
                    Dimensions::Mat4,
                    FLOAT,
                    "Mat4 of F32",
                    false,
                    buffers,
                    budget,
                )
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

/// The morph targets of a primitive of `count` vertices (`POSITION` and `NORMAL` deltas; other
/// attributes are not used), and a warning when a target has normals but the primitive has
/// none (they are ignored: its normals are computed from the posed positions).
fn morph_targets(
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

/// The joints and weights of a skinned primitive of `count` vertices: every
/// `JOINTS_n`/`WEIGHTS_n` set from 0 on, the weights non-negative and, per vertex, summing to
/// one within [`WEIGHT_SUM_TOLERANCE`] (then divided by their sum).
fn influences(
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
        let joints = read_numbers(
            &j,
            Dimensions::Vec4,
            JOINT_TYPES,
            "Vec4 of U8 or U16",
            false,
            buffers,
            budget,
        )
        .map_err(|m| format!("JOINTS_{set} {m}"))?;
        let weights = read_numbers(
            &w,
            Dimensions::Vec4,
            WEIGHT_TYPES,
            "Vec4 of F32 or normalized U8 or U16",
            true,
            buffers,
            budget,
        )
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

/// Every animation of the document as a [`Clip`], its channels checked (see [`super`]).
fn clips(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    nodes: &[NodeRest],
    targets: &[usize],
) -> Msg<Vec<Clip>> {
    let json = doc.as_json();
    let mut out = Vec::new();
    for (a, anim) in json.animations.iter().enumerate() {
        let name = doc
            .animations()
            .nth(a)
            .and_then(|x| x.name().map(str::to_owned));
        let alabel = animation_label(a, name.as_deref());
        let mut channels = Vec::new();
        let mut used: Vec<(usize, Path)> = Vec::new();
        for (c, ch) in anim.channels.iter().enumerate() {
            let node = ch.target.node.value();
            let path = match ch.target.path {
                Checked::Valid(Property::Translation) => Path::Translation,
                Checked::Valid(Property::Rotation) => Path::Rotation,
                Checked::Valid(Property::Scale) => Path::Scale,
                Checked::Valid(Property::MorphTargetWeights) => Path::Weights,
                Checked::Invalid => {
                    return Err(format!(
                        "{alabel}, channel {c}: its target path is not valid"
                    ));
                }
            };
            let at = format!(
                "{alabel}, channel {c} (node {node} {})",
                match path {
                    Path::Translation => "translation",
                    Path::Rotation => "rotation",
                    Path::Scale => "scale",
                    Path::Weights => "weights",
                }
            );
            let Some(rest) = nodes.get(node) else {
                return Err(format!("{at}: node {node} does not exist"));
            };
            if used.contains(&(node, path)) {
                return Err(format!(
                    "{at}: a second channel of the animation targets it"
                ));
            }
            used.push((node, path));
            let width = match path {
                Path::Translation | Path::Scale => 3,
                Path::Rotation => 4,
                Path::Weights => {
                    let t = doc
                        .nodes()
                        .nth(node)
                        .and_then(|n| n.mesh())
                        .and_then(|m| targets.get(m.index()).copied())
                        .unwrap_or(0);
                    if t == 0 {
                        return Err(format!("{at}: the node has no mesh with morph targets"));
                    }
                    t
                }
            };
            if path != Path::Weights && rest.trs.is_none() {
                return Err(format!(
                    "{at}: the node has a matrix (an animated node must have translation, \
                     rotation and scale)"
                ));
            }
            let s = ch.sampler.value();
            let Some(sampler) = anim.samplers.get(s) else {
                return Err(format!("{at}: sampler {s} does not exist"));
            };
            let at = format!("{at}, sampler {s}");
            let keys = read_keys(doc, buffers, budget, sampler, path, width)
                .map_err(|m| format!("{at}: {m}"))?;
            channels.push(Channel { node, path, keys });
        }
        let duration = channels.iter().map(|c| c.keys.end()).fold(0.0, f64::max);
        out.push(Clip {
            name,
            duration,
            channels,
        });
    }
    Ok(out)
}

/// The keys of one sampler for a channel of `path` with `width` numbers per value.
fn read_keys(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    budget: &Budget,
    sampler: &::gltf::json::animation::Sampler,
    path: Path,
    width: usize,
) -> Msg<Keys> {
    let interpolation = match sampler.interpolation {
        Checked::Valid(JsonInterpolation::Step) => Interpolation::Step,
        Checked::Valid(JsonInterpolation::Linear) => Interpolation::Linear,
        Checked::Valid(JsonInterpolation::CubicSpline) => Interpolation::CubicSpline,
        Checked::Invalid => return Err("its interpolation is not valid".into()),
    };
    let input = accessor(doc, sampler.input.value(), "input")?;
    let times = read_numbers(
        &input,
        Dimensions::Scalar,
        FLOAT,
        "Scalar of F32",
        false,
        buffers,
        budget,
    )
    .map_err(|m| format!("input {m}"))?;
    if let Some(k) = (1..times.len()).find(|&k| times[k] <= times[k - 1]) {
        return Err(format!(
            "input accessor {}: key time {k} ({} s) is not after key time {} ({} s): times must \
             increase",
            input.index(),
            times[k],
            k - 1,
            times[k - 1]
        ));
    }
    let cubic = interpolation == Interpolation::CubicSpline;
    if cubic && times.len() < 2 {
        return Err("CUBICSPLINE needs at least two keys".into());
    }
    let output = accessor(doc, sampler.output.value(), "output")?;
    let mut values = match path {
        Path::Translation | Path::Scale => read_numbers(
            &output,
            Dimensions::Vec3,
            FLOAT,
            "Vec3 of F32",
            false,
            buffers,
            budget,
        ),
        Path::Rotation => read_numbers(
            &output,
            Dimensions::Vec4,
            NORMALIZED,
            "Vec4 of F32 or normalized I8, U8, I16 or U16",
            true,
            buffers,
            budget,
        ),
        Path::Weights => read_numbers(
            &output,
            Dimensions::Scalar,
            NORMALIZED,
            "Scalar of F32 or normalized I8, U8, I16 or U16",
            true,
            buffers,
            budget,
        ),
    }
    .map_err(|m| format!("output {m}"))?;
    let per_key = width * if cubic { 3 } else { 1 };
    if values.len() != times.len() * per_key {
        return Err(format!(
            "output accessor {} has {} values for {} key times ({} per key{})",
            output.index(),
            values.len() / if path == Path::Weights { 1 } else { width },
            times.len(),
            per_key / if path == Path::Weights { 1 } else { width },
            match path {
                Path::Weights => format!(" of {width} morph targets"),
                _ => String::new(),
            }
        ));
    }
    if path == Path::Rotation {
        // Rotation values are unit quaternions: renormalised (a rounded or quantised file is a
        // hair off), a zero one is an error. Tangents of the cubic spline are left as stored.
        for (k, q) in values.chunks_exact_mut(4).enumerate() {
            if cubic && k % 3 != 1 {
                continue;
            }
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(len > 0.0 && len.is_finite()) {
                return Err(format!(
                    "output accessor {}: rotation key {} is not a unit quaternion",
                    output.index(),
                    if cubic { k / 3 } else { k }
                ));
            }
            for x in q.iter_mut() {
                *x /= len;
            }
        }
    }
    Ok(Keys {
        times,
        values,
        width,
        interpolation,
        rotation: path == Path::Rotation,
    })
}
