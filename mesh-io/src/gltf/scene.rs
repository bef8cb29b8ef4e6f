//! The drawn scene: the node walk from the default scene's roots, world transforms composed in
//! `f64`, instancing, each primitive decoded once and placed per node (see [`super::parse`]).

use super::*;

/// One primitive of one mesh placement as [`walk`] added it to the builder: its vertices are
/// the builder's positions `first..first + count`, in the primitive's vertex order.
pub(crate) struct Placement {
    /// The node that draws it (`None` for a file without nodes).
    pub node: Option<usize>,
    /// The mesh and the primitive.
    pub mesh: usize,
    /// The primitive's index in its mesh.
    pub prim: usize,
    /// The first builder position of its vertices.
    pub first: usize,
}

/// What [`walk`] read: the corners of every drawn triangle, the warnings, where each
/// primitive placement's vertices went, the decoded primitives by mesh, and the nodes in the
/// order the walk visited them with their parents.
pub(crate) struct Walk {
    pub builder: Builder,
    pub warnings: Vec<String>,
    pub placements: Vec<Placement>,
    pub decoded: HashMap<usize, Vec<Prim>>,
    pub order: Vec<(usize, Option<usize>)>,
}

/// Walks the drawn scene of `doc` (see [`parse`]) into a [`Walk`].
pub(crate) fn walk(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    path: &str,
    budget: &Budget,
) -> Result<Walk> {
    let mut warnings = Vec::new();
    let (instances, order) = instances(doc, &mut warnings).map_err(|m| Error::format(path, m))?;
    let mut decoded: HashMap<usize, Vec<Prim>> = HashMap::new();
    // Skipped primitives, (mesh, primitive) → (why, the nodes that draw it), in order.
    let mut skipped: Vec<((usize, usize), String, Vec<String>)> = Vec::new();
    let mut builder = Builder {
        positions: Vec::new(),
        tris: Vec::new(),
    };
    let mut placements = Vec::new();
    for inst in &instances {
        let m = inst.mesh.index();
        let prims = match decoded.entry(m) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(
                decode_mesh(&inst.mesh, &inst.label, buffers, budget)
                    .map_err(|msg| budget.typed(Error::format(path, msg)))?,
            ),
        };
        for (p, prim) in prims.iter().enumerate() {
            if let Prim::Skipped(why) = prim {
                match skipped.iter_mut().find(|(k, _, _)| *k == (m, p)) {
                    Some((_, _, nodes)) => nodes.push(inst.label.clone()),
                    None => skipped.push(((m, p), why.clone(), vec![inst.label.clone()])),
                }
            }
        }
        for (p, prim) in prims.iter().enumerate() {
            if let Prim::Triangles {
                positions, tris, ..
            } = prim
            {
                let at = format!("{}, {}, primitive {p}", inst.label, mesh_label(&inst.mesh));
                budget
                    .charge(positions.len() as u64, BYTES_PER_POSITION)
                    .and_then(|()| budget.charge(tris.len() as u64, BYTES_PER_TRIANGLE))
                    .map_err(|()| {
                        budget.typed(Error::format(
                            path,
                            format!(
                                "{at} ({} vertices and {} triangles placed)",
                                positions.len(),
                                tris.len()
                            ),
                        ))
                    })?;
            }
        }
        let firsts = add_instance(&mut builder, prims, inst.world)
            .map_err(|msg| Error::format(path, format!("{}: {msg}", inst.label)))?;
        match firsts {
            Some(firsts) => placements.extend(firsts.into_iter().map(|(prim, first)| Placement {
                node: inst.node,
                mesh: m,
                prim,
                first,
            })),
            None => warnings.push(format!(
                "{}: its world transform is singular (a zero scale), {} skipped",
                inst.label,
                mesh_label(&inst.mesh)
            )),
        }
    }
    for ((m, p), why, nodes) in skipped {
        let mesh = doc
            .meshes()
            .nth(m)
            .map(|x| mesh_label(&x))
            .unwrap_or_default();
        let shown = nodes.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
        let more = match nodes.len() {
            0..=3 => String::new(),
            n => format!(" and {} more", n - 3),
        };
        warnings.push(format!(
            "{mesh}, primitive {p} (drawn by {shown}{more}): {why}, skipped"
        ));
    }
    Ok(Walk {
        builder,
        warnings,
        placements,
        decoded,
        order,
    })
}

/// `node 3 "Wheel"` (the name only when the node has one).
pub(crate) fn node_label(n: &::gltf::Node<'_>) -> String {
    match n.name() {
        Some(name) => format!("node {} {name:?}", n.index()),
        None => format!("node {}", n.index()),
    }
}

/// `mesh 1 "wheel"` (the name only when the mesh has one).
pub(crate) fn mesh_label(m: &::gltf::Mesh<'_>) -> String {
    match m.name() {
        Some(name) => format!("mesh {} {name:?}", m.index()),
        None => format!("mesh {}", m.index()),
    }
}

/// One placement of a mesh: the node that draws it (its label for messages) and its world
/// transform.
pub(super) struct Instance<'a> {
    mesh: ::gltf::Mesh<'a>,
    node: Option<usize>,
    label: String,
    world: DMat4,
}

/// A node's translation, rotation (unit) and scale in `f64`.
pub(crate) type Trs = (DVec3, DQuat, DVec3);

/// The [`Trs`] of node `n`, its rotation renormalised (a zero or non-finite quaternion is an
/// error), or `None` when the node has a `matrix`.
pub(crate) fn local_trs(n: &::gltf::Node<'_>) -> std::result::Result<Option<Trs>, String> {
    match n.transform() {
        ::gltf::scene::Transform::Matrix { .. } => Ok(None),
        ::gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let [x, y, z, w] = rotation.map(f64::from);
            let len = (x * x + y * y + z * z + w * w).sqrt();
            if !(len.is_finite() && len > 0.0) {
                return Err(format!(
                    "{}: rotation {rotation:?} is not a unit quaternion",
                    node_label(n)
                ));
            }
            Ok(Some((
                DVec3::from_array(translation.map(f64::from)),
                DQuat::from_xyzw(x / len, y / len, z / len, w / len),
                DVec3::from_array(scale.map(f64::from)),
            )))
        }
    }
}

/// A node's local transform in `f64`: its `matrix`, or `T · R · S` from its [`local_trs`].
pub(crate) fn local_matrix(n: &::gltf::Node<'_>) -> std::result::Result<DMat4, String> {
    let m = match (local_trs(n)?, n.transform()) {
        (Some((t, r, s)), _) => DMat4::from_scale_rotation_translation(s, r, t),
        (None, ::gltf::scene::Transform::Matrix { matrix }) => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        // `local_trs` is `None` for a matrix only.
        (None, _) => DMat4::IDENTITY,
    };
    if !m.is_finite() {
        return Err(format!("{}: its transform is not finite", node_label(n)));
    }
    Ok(m)
}

/// Every mesh placement of the drawn scene (see [`parse`]), depth-first in document order,
/// and the nodes visited, in that order, each with the parent it was reached from. Each node is
/// visited once: a node reached again (a cycle, or a child of two parents, which the
/// specification forbids and the `gltf` crate's validation lets through) is reported and not
/// descended into again.
#[allow(clippy::type_complexity)]
pub(super) fn instances<'a>(
    doc: &'a ::gltf::Document,
    warnings: &mut Vec<String>,
) -> std::result::Result<(Vec<Instance<'a>>, Vec<(usize, Option<usize>)>), String> {
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let roots: Vec<::gltf::Node<'a>> = match scene {
        Some(sc) => {
            let n = doc.scenes().len();
            if n > 1 {
                let name = sc.name().map(|s| format!(" {s:?}")).unwrap_or_default();
                warnings.push(format!(
                    "drawing scene {}{name}, one of {n} scenes (the default, else the first)",
                    sc.index()
                ));
            }
            sc.nodes().collect()
        }
        None if doc.nodes().len() > 0 => {
            let mut child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    if let Some(slot) = child.get_mut(c.index()) {
                        *slot = true;
                    }
                }
            }
            warnings.push("the file has no scene: drawing every root node".into());
            doc.nodes().filter(|n| !child[n.index()]).collect()
        }
        None => {
            if doc.meshes().len() > 0 {
                warnings.push(
                    "the file has no scene and no nodes: drawing each mesh once, untransformed"
                        .into(),
                );
            }
            let out = doc
                .meshes()
                .map(|m| Instance {
                    label: "no node".into(),
                    node: None,
                    mesh: m,
                    world: DMat4::IDENTITY,
                })
                .collect();
            return Ok((out, Vec::new()));
        }
    };
    let mut out = Vec::new();
    let mut order = Vec::new();
    let mut seen = vec![false; doc.nodes().len()];
    let mut stack: Vec<(::gltf::Node<'a>, DMat4, Option<usize>)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY, None))
        .collect();
    while let Some((n, parent, up)) = stack.pop() {
        match seen.get_mut(n.index()) {
            Some(s) if !*s => *s = true,
            _ => {
                warnings.push(format!(
                    "{} is reached a second time (the node hierarchy must be a forest): drawn once",
                    node_label(&n)
                ));
                continue;
            }
        }
        let world = parent * local_matrix(&n)?;
        order.push((n.index(), up));
        if let Some(mesh) = n.mesh() {
            out.push(Instance {
                mesh,
                node: Some(n.index()),
                label: node_label(&n),
                world,
            });
        }
        let first_child = stack.len();
        stack.extend(n.children().map(|c| (c, world, Some(n.index()))));
        stack[first_child..].reverse();
    }
    Ok((out, order))
}

/// A primitive read in its mesh's own coordinates, or why it is skipped.
pub(crate) enum Prim {
    /// Triangles (strips and fans already split) over `positions`.
    Triangles {
        positions: Vec<DVec3>,
        normals: Option<Vec<DVec3>>,
        tris: Vec<[u32; 3]>,
    },
    /// Not drawn, and why (for the warning).
    Skipped(String),
}

/// Reads every primitive of `mesh` (see [`parse`] for the modes); `node` labels the first node
/// that draws it, for messages. Accessors are checked ([`check_accessor`]) before the `gltf`
/// crate reads them.
pub(super) fn decode_mesh(
    mesh: &::gltf::Mesh<'_>,
    node: &str,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> std::result::Result<Vec<Prim>, String> {
    use ::gltf::mesh::Mode;
    let mut out = Vec::new();
    for prim in mesh.primitives() {
        let at = format!("{node}, {}, primitive {}", mesh_label(mesh), prim.index());
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            out.push(Prim::Skipped(format!("mode {mode:?} is not triangles")));
            continue;
        }
        let checks = [
            (
                "POSITION",
                prim.get(&::gltf::Semantic::Positions),
                Want::Vec3F32,
            ),
            (
                "NORMAL",
                prim.get(&::gltf::Semantic::Normals),
                Want::Vec3F32,
            ),
            ("indices", prim.indices(), Want::Index),
        ];
        for (what, acc, want) in checks {
            if let Some(acc) = acc {
                check_accessor(&acc, want, buffers).map_err(|m| format!("{at}: {what} {m}"))?;
                // What the loader decodes it to, before it does: DVec3 positions and normals
                // (24 bytes), u32 indices and the triangles they become (4 + 4).
                let size = if what == "indices" { 8 } else { 24 };
                budget
                    .charge_msg(
                        &format!("accessor {}", acc.index()),
                        acc.count() as u64,
                        size,
                    )
                    .map_err(|m| format!("{at}: {what} {m}"))?;
            }
        }
        if prim.get(&::gltf::Semantic::Positions).is_some() && prim.indices().is_none() {
            // The generated indices of a non-indexed primitive.
            let n = prim
                .get(&::gltf::Semantic::Positions)
                .map_or(0, |a| a.count());
            budget
                .charge_msg("generated indices", n as u64, 8)
                .map_err(|m| format!("{at}: {m}"))?;
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
        let Some(pos) = reader.read_positions() else {
            out.push(Prim::Skipped("no POSITION attribute".into()));
            continue;
        };
        let positions: Vec<DVec3> = pos.map(|p| DVec3::from_array(p.map(f64::from))).collect();
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(format!("{at}: non-finite vertex position"));
        }
        let count = positions.len();
        let normals: Option<Vec<DVec3>> = reader
            .read_normals()
            .map(|it| it.map(|n| DVec3::from_array(n.map(f64::from))).collect());
        if let Some(ns) = &normals {
            if ns.len() != count {
                return Err(format!("{at}: NORMAL and POSITION counts differ"));
            }
            if ns.iter().any(|n| !n.is_finite()) {
                return Err(format!("{at}: non-finite vertex normal"));
            }
        }
        let idx: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some(&i) = idx.iter().find(|&&i| i as usize >= count) {
            return Err(format!("{at}: index {i} out of range (0..{count})"));
        }
        let tris: Vec<[u32; 3]> = match mode {
            Mode::Triangles => {
                if !idx.len().is_multiple_of(3) {
                    return Err(format!(
                        "{at}: index count {} is not a multiple of 3",
                        idx.len()
                    ));
                }
                idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
            // The specification's strip order: p_i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}).
            Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
                .map(|i| [idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]])
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect(),
            _ => (1..idx.len().saturating_sub(1))
                .map(|i| [idx[i], idx[i + 1], idx[0]])
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect(),
        };
        out.push(Prim::Triangles {
            positions,
            normals,
            tris,
        });
    }
    Ok(out)
}

/// Appends one placement of a decoded mesh to `b`: positions through `world`, normals through
/// the inverse transpose of its 3×3 part (renormalised), winding reversed where `world`
/// mirrors. Returns, for each primitive added, its index and its first position in `b`; `None`
/// (nothing added) when `world` is singular; an error when a vertex lands on a non-finite
/// position.
#[allow(clippy::type_complexity)]
pub(super) fn add_instance(
    b: &mut Builder,
    prims: &[Prim],
    world: DMat4,
) -> std::result::Result<Option<Vec<(usize, usize)>>, String> {
    let m3 = DMat3::from_mat4(world);
    let det = m3.determinant();
    let nxf = m3.inverse().transpose();
    if det == 0.0 || !det.is_finite() || !nxf.is_finite() {
        return Ok(None);
    }
    let mut firsts = Vec::new();
    for (k, prim) in prims.iter().enumerate() {
        let Prim::Triangles {
            positions,
            normals,
            tris,
        } = prim
        else {
            continue;
        };
        let first = b.positions.len();
        firsts.push((k, first));
        for p in positions {
            let q = world.transform_point3(*p);
            if !q.is_finite() {
                return Err("a vertex position is not finite after the node transforms".into());
            }
            b.positions.push(q);
        }
        let normal = |i: u32| {
            normals
                .as_ref()
                .and_then(|ns| ns.get(i as usize))
                .map(|n| (nxf * *n).normalize_or_zero())
        };
        for t in tris {
            let mut c: [Corner; 3] = t.map(|i| (first + i as usize, normal(i)));
            if det < 0.0 {
                c.swap(1, 2);
            }
            b.tris.push(c);
        }
    }
    Ok(Some(firsts))
}
