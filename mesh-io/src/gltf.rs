//! glTF 2.0 through the `gltf` crate: JSON (`.gltf`, buffers in external files or base64 data
//! URIs) or binary (`.glb`, or any file that starts with the GLB magic).
//!
//! Everything the `gltf` crate would index blindly is checked here first, so malformed input
//! is an [`Error`], never a panic: the GLB container ([`crate::glb`]; the crate's own GLB
//! reader is not used), each primitive's POSITION accessor index before the crate's validation
//! (which looks it up unchecked), and, before a primitive is read, the type, count, stride and
//! byte range of each accessor the loader reads (POSITION, NORMAL, indices), sparse parts
//! included. The crate's accessor reader trusts all of these: it asserts on short strides, takes
//! `count - 1`, adds offsets unchecked, and has an `unreachable!()` for float indices. Sparse
//! indices are also checked to increase strictly (the reader would drop the others silently).
//!
//! The default scene is walked node by node ([`parse`] has the rules: transforms composed in
//! `f64`, instancing, normals by the inverse transpose, mirrored nodes re-wound, strips and fans
//! split, other modes skipped with a warning naming mesh, primitive and nodes); errors name the
//! node, mesh, primitive and accessor. [`write_glb`] writes a mesh as GLB (the tessellation's
//! output).

use std::collections::HashMap;
use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use glam::{DMat3, DMat4, DQuat, DVec3};

use crate::error::{Error, Result};
use crate::glb;
use crate::mesh::{LoadedMesh, Mesh};
use crate::options::{
    BYTES_PER_POSITION, BYTES_PER_TRIANGLE, Budget, LoadOptions, read_buffer, read_file,
};
use crate::weld::{Builder, Corner};

/// Reads a `.gltf` or `.glb` file (see the module documentation) within the default
/// [`LoadOptions`] ([`crate::load_with`] takes others).
pub fn load(path: &str) -> Result<LoadedMesh> {
    let options = LoadOptions::default();
    let budget = Budget::new(path, &options);
    let bytes = read_file(path, &budget)?;
    parse_budgeted(&bytes, path, &options, &budget)
}

/// Parses the bytes of a glTF or GLB file. `path` names the file in messages, tells `.glb` by
/// its extension, and anchors relative buffer URIs.
///
/// What is drawn is the default scene (`scene`), or the first scene when there is no default:
/// every node reached from its root nodes, each mesh placed by its node's world transform (the
/// node's `matrix`, or `translation · rotation · scale`, composed down the hierarchy in `f64`),
/// once per node that references it (instancing). Positions are transformed by the world
/// matrix, normals by the inverse transpose of its 3×3 part (correct under non-uniform scale)
/// and renormalised, and triangles of a node whose transform mirrors (negative determinant) are
/// re-wound so that they stay counter-clockwise, as the specification says. Without scenes,
/// every root node is drawn; without nodes, every mesh once, untransformed (both with a
/// warning). Primitives in `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` mode are read,
/// indexed or not, their accessors sparse or not; other modes are skipped with a warning naming
/// the mesh, the primitive and the nodes that draw it. Errors name the node, mesh, primitive and
/// accessor.
///
/// External buffers are read within the default [`LoadOptions`]: inside the file's folder
/// only, regular files of at least their `byteLength` ([`crate::parse_with`] takes others).
pub fn parse(bytes: &[u8], path: &str) -> Result<LoadedMesh> {
    let options = LoadOptions::default();
    parse_budgeted(bytes, path, &options, &Budget::new(path, &options))
}

/// [`parse`] within `options`, what it reads and decodes charged to `budget`.
pub(crate) fn parse_budgeted(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<LoadedMesh> {
    let (doc, buffers) = open(bytes, path, options, budget)?;
    let w = walk(&doc, &buffers, path, budget)?;
    Ok(w.builder.into_loaded(w.warnings))
}

/// The validated document of a glTF or GLB file and the bytes of its buffers (see [`parse`]),
/// the buffers charged to `budget`.
pub(crate) fn open(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<(::gltf::Document, Vec<Vec<u8>>)> {
    let is_glb = bytes.starts_with(&glb::MAGIC)
        || Path::new(path)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json, blob) = if is_glb {
        let g = glb::parse(bytes)
            .map_err(|e| Error::format(path, format!("malformed glTF binary: {e}")))?;
        (g.json, g.bin)
    } else {
        (bytes, None)
    };
    if let Some(v) = version_1(json) {
        return Err(Error::format(
            path,
            format!("glTF {v} is not supported (only glTF 2.0; convert the file to 2.0 first)"),
        ));
    }
    let doc = document(json).map_err(|e| Error::format(path, format!("malformed glTF: {e}")))?;
    let buffers = buffers(&doc, blob, path, options, budget)?;
    Ok((doc, buffers))
}

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
struct Instance<'a> {
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
fn instances<'a>(
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
fn decode_mesh(
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
fn add_instance(
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

/// A GLB of `mesh`: one scene with one node and one mesh of one indexed `TRIANGLES` primitive,
/// `POSITION` (`f32`, with the `min`/`max` the specification requires) and `NORMAL` (`f32`,
/// unit length), `u32` indices, all in the BIN chunk. glTF stores `f32` only; the JSON is
/// written by hand (it is small and fixed). `generator` goes into `asset.generator`. An empty
/// mesh is an error (glTF accessors need at least one element).
pub fn write_glb(mesh: &Mesh, generator: &str) -> Result<Vec<u8>> {
    if mesh.positions.is_empty() || mesh.triangles.is_empty() {
        return Err(Error::EmptyGltf);
    }
    let nv = mesh.positions.len();
    let mut bin = Vec::with_capacity(nv * 24 + mesh.triangles.len() * 12);
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &mesh.positions {
        for (k, c) in p.as_vec3().to_array().into_iter().enumerate() {
            lo[k] = lo[k].min(c);
            hi[k] = hi[k].max(c);
            bin.extend(c.to_le_bytes());
        }
    }
    for n in &mesh.normals {
        for c in n.normalize_or_zero().as_vec3().to_array() {
            bin.extend(c.to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        for i in t {
            bin.extend(i.to_le_bytes());
        }
    }
    let pv = nv * 12;
    let json = format!(
        concat!(
            r#"{{"asset":{{"version":"2.0","generator":{gen:?}}},"scene":0,"scenes":[{{"nodes":[0]}}],"#,
            r#""nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2,"mode":4}}]}}],"#,
            r#""buffers":[{{"byteLength":{bl}}}],"bufferViews":["#,
            r#"{{"buffer":0,"byteOffset":0,"byteLength":{pv},"target":34962}},"#,
            r#"{{"buffer":0,"byteOffset":{pv},"byteLength":{pv},"target":34962}},"#,
            r#"{{"buffer":0,"byteOffset":{io},"byteLength":{il},"target":34963}}],"accessors":["#,
            r#"{{"bufferView":0,"componentType":5126,"count":{nv},"type":"VEC3","min":[{l0},{l1},{l2}],"max":[{h0},{h1},{h2}]}},"#,
            r#"{{"bufferView":1,"componentType":5126,"count":{nv},"type":"VEC3"}},"#,
            r#"{{"bufferView":2,"componentType":5125,"count":{ni},"type":"SCALAR"}}]}}"#
        ),
        gen = generator.replace(['"', '\\'], "'"),
        bl = bin.len(),
        pv = pv,
        io = 2 * pv,
        il = mesh.triangles.len() * 12,
        nv = nv,
        ni = mesh.triangles.len() * 3,
        l0 = lo[0],
        l1 = lo[1],
        l2 = lo[2],
        h0 = hi[0],
        h1 = hi[1],
        h2 = hi[2],
    );
    Ok(glb::build(json.as_bytes(), Some(&bin)))
}

/// The version of a glTF 1.x document (`asset.version` "1…", or, when absent, the 1.0 layout
/// of named dictionaries where 2.0 has arrays), `None` for anything else (glTF 2.0, or JSON
/// that the 2.0 parser will judge).
fn version_1(json: &[u8]) -> Option<String> {
    let root: serde_json::Value = serde_json::from_slice(json).ok()?;
    let version = match root.get("asset").and_then(|a| a.get("version")) {
        Some(serde_json::Value::String(v)) => Some(v.clone()),
        Some(serde_json::Value::Number(n)) => Some(n.to_string()),
        _ => None,
    };
    match version {
        Some(v) if v.starts_with('1') => Some(v),
        Some(_) => None,
        None => ["meshes", "accessors", "nodes", "buffers"]
            .iter()
            .any(|k| root.get(*k).is_some_and(serde_json::Value::is_object))
            .then(|| "1.0".to_owned()),
    }
}

/// Deserialises and validates a glTF JSON document (the `gltf` crate's checks: indices in
/// range, required fields, enum values).
fn document(json: &[u8]) -> std::result::Result<::gltf::Document, ::gltf::Error> {
    use ::gltf::json::validation::{Checked, Error};
    let root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json)?;
    // The crate's validation looks up each primitive's POSITION accessor without a bounds check
    // (`root.accessors[i]` in its primitive hook, which panics when `i` is out of range), so
    // those indices are checked first, reported as the validation would.
    let position = Checked::Valid(::gltf::json::mesh::Semantic::Positions);
    let mut bad = Vec::new();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if let Some(i) = prim.attributes.get(&position)
                && i.value() >= root.accessors.len()
            {
                let at = ::gltf::json::Path::new()
                    .field("meshes")
                    .index(m)
                    .field("primitives")
                    .index(p)
                    .field("attributes")
                    .key("POSITION");
                bad.push((at, Error::IndexOutOfBounds));
            }
        }
    }
    if !bad.is_empty() {
        return Err(::gltf::Error::Validation(bad));
    }
    ::gltf::Document::from_json(root)
}

/// The data of every buffer, in index order: the GLB's BIN chunk, a base64 data URI, or a file
/// relative to the glTF file (confined and size-checked as `options` says: [`read_buffer`]).
/// Each must hold at least its declared `byteLength`; each is charged to `budget` before it is
/// copied or read.
fn buffers(
    doc: &::gltf::Document,
    blob: Option<&[u8]>,
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let field = |len: usize| format!("buffer {} ({len} bytes)", b.index());
        let data = match b.source() {
            ::gltf::buffer::Source::Bin => {
                let blob = blob.ok_or_else(|| Error::format(path, "GLB has no binary chunk"))?;
                budget
                    .charge(blob.len() as u64, 1)
                    .map_err(|()| budget.typed(Error::format(path, field(blob.len()))))?;
                blob.to_vec()
            }
            ::gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let b64 = rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        Error::format(path, "unsupported data URI (expected base64)")
                    })?;
                    let len = b64.len() / 4 * 3 + 3;
                    budget
                        .charge(len as u64, 1)
                        .map_err(|()| budget.typed(Error::format(path, field(len))))?;
                    base64_decode(b64)
                        .ok_or_else(|| Error::format(path, "malformed base64 data URI"))?
                } else {
                    read_buffer(path, uri, b.length(), options, budget)?
                }
            }
        };
        if data.len() < b.length() {
            return Err(Error::format(
                path,
                format!(
                    "buffer {} is shorter ({} bytes) than declared ({})",
                    b.index(),
                    data.len(),
                    b.length()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// What the loader reads from an accessor.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Want {
    /// `VEC3` of `FLOAT` (POSITION, NORMAL).
    Vec3F32,
    /// `SCALAR` of an unsigned integer type (indices).
    Index,
    /// Elements of `dims` of one of `types` (the animation's accessors); `expected` names them
    /// in the message.
    Of {
        dims: Dimensions,
        types: &'static [DataType],
        expected: &'static str,
    },
}

/// Checks that the `gltf` crate can read `acc` as `want` without panicking and without
/// falling short: element type, `count ≥ 1`, strides at least the element size, and every
/// byte read (base, sparse indices and sparse values) inside its buffer view and buffer.
pub(crate) fn check_accessor(
    acc: &::gltf::Accessor<'_>,
    want: Want,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let i = acc.index();
    let (dims, ty) = (acc.dimensions(), acc.data_type());
    let (ok, expected) = match want {
        Want::Vec3F32 => (
            dims == Dimensions::Vec3 && ty == DataType::F32,
            "Vec3 of F32",
        ),
        Want::Index => (
            dims == Dimensions::Scalar
                && matches!(ty, DataType::U8 | DataType::U16 | DataType::U32),
            "Scalar of U8, U16 or U32",
        ),
        Want::Of {
            dims: d,
            types,
            expected,
        } => (dims == d && types.contains(&ty), expected),
    };
    if !ok {
        return Err(format!(
            "accessor {i} holds {dims:?} of {ty:?}, expected {expected}"
        ));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("accessor {i} has count 0"));
    }
    let elem = acc.size();
    if let Some(view) = acc.view() {
        check_view(&view, acc.offset(), count, elem, buffers)
            .map_err(|m| format!("accessor {i}: {m}"))?;
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!(
                "accessor {i}: sparse count {n} is outside 1..={count}"
            ));
        }
        let ix = sparse.indices();
        check_view(&ix.view(), ix.offset(), n, ix.index_type().size(), buffers)
            .map_err(|m| format!("accessor {i}, sparse indices: {m}"))?;
        let vals = sparse.values();
        check_view(&vals.view(), vals.offset(), n, elem, buffers)
            .map_err(|m| format!("accessor {i}, sparse values: {m}"))?;
        check_sparse_indices(&ix, n, count, buffers)
            .map_err(|m| format!("accessor {i}, sparse indices: {m}"))?;
    }
    Ok(())
}

/// Checks that the `n` sparse indices are strictly increasing and below `count`, as the
/// specification requires (the `gltf` crate's reader would silently drop the values of
/// indices out of order or out of range). The caller has checked that they lie in their view.
fn check_sparse_indices(
    ix: &::gltf::accessor::sparse::Indices<'_>,
    n: usize,
    count: usize,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let view = ix.view();
    let size = ix.index_type().size();
    let stride = view.stride().unwrap_or(size);
    let data = buffers
        .get(view.buffer().index())
        .map_or(&[][..], Vec::as_slice);
    let base = view.offset().saturating_add(ix.offset());
    let mut prev: Option<u64> = None;
    for k in 0..n {
        let at = base.saturating_add(k.saturating_mul(stride));
        let Some(b) = data.get(at..at.saturating_add(size)) else {
            return Err(format!("index {k} lies outside its buffer"));
        };
        let v = b.iter().rev().fold(0u64, |acc, &x| acc << 8 | x as u64);
        if v >= count as u64 {
            return Err(format!(
                "index {k} is {v}, outside the accessor's 0..{count}"
            ));
        }
        if let Some(p) = prev.filter(|&p| p >= v) {
            return Err(format!(
                "index {k} is {v}, not above the previous {p} (they must strictly increase)"
            ));
        }
        prev = Some(v);
    }
    Ok(())
}

/// Checks that `count` elements of `elem` bytes, `offset` bytes into `view` and its stride
/// apart, lie inside the view, and the view inside its buffer's data (overflow-free).
fn check_view(
    view: &::gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "buffer view {v} has byteStride {stride}, less than the {elem}-byte elements"
        ));
    }
    let end = count
        .checked_sub(1)
        .and_then(|c| stride.checked_mul(c))
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{count} elements of {elem} bytes (stride {stride}) from byte {offset} do not fit \
             in buffer view {v} ({} bytes)",
            view.length()
        ));
    }
    let b = view.buffer().index();
    let have = buffers.get(b).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|e| e > have)
    {
        return Err(format!(
            "buffer view {v} ({} bytes from byte {}) reaches past the end of buffer {b} \
             ({have} bytes)",
            view.length(),
            view.offset()
        ));
    }
    Ok(())
}

/// Decodes standard or URL-safe base64 (padding optional, whitespace skipped).
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        } as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// `count` copies of `good`, each with one to four random bytes changed (half the time a digit
/// by a digit, so that JSON numbers change but stay numbers), from a xorshift generator seeded
/// with `seed`: the corrupted files the never-panic tests feed the loaders.
#[cfg(test)]
pub(crate) fn corruptions(good: &[u8], seed: u64, count: usize) -> impl Iterator<Item = Vec<u8>> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let good = good.to_vec();
    (0..count).map(move |_| {
        let mut b = good.clone();
        for _ in 0..1 + next() % 4 {
            let at = (next() % b.len() as u64) as usize;
            b[at] = if next() % 2 == 0 && b[at].is_ascii_digit() {
                b"0123456789"[(next() % 10) as usize]
            } else {
                next() as u8
            };
        }
        b
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube `[-1, 1]³` with radial unit normals, 12 triangles counter-clockwise seen from
    /// outside (the data of the built-in `cube` scene).
    pub(super) fn cube() -> Mesh {
        const X: [f64; 8] = [-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0];
        const Y: [f64; 8] = [-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0];
        const Z: [f64; 8] = [-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0];
        let positions: Vec<DVec3> = (0..8).map(|k| DVec3::new(X[k], Y[k], Z[k])).collect();
        Mesh {
            normals: positions.iter().map(|p| p.normalize()).collect(),
            positions,
            triangles: vec![
                [0, 2, 3],
                [0, 3, 1],
                [4, 5, 7],
                [4, 7, 6],
                [0, 1, 5],
                [0, 5, 4],
                [2, 6, 7],
                [2, 7, 3],
                [0, 4, 6],
                [0, 6, 2],
                [1, 3, 7],
                [1, 7, 5],
            ],
        }
    }

    /// [`cube`]: 8 positions, 8 normals (`f32`), 36 `u32` indices.
    fn cube_bin() -> Vec<u8> {
        let m = cube();
        let mut bin = Vec::new();
        for v in m.positions.iter().chain(&m.normals) {
            for c in v.to_array() {
                bin.extend((c as f32).to_le_bytes());
            }
        }
        for t in &m.triangles {
            for i in t {
                bin.extend(i.to_le_bytes());
            }
        }
        bin
    }

    /// glTF JSON of [`cube_bin`] in buffer 0 (`buffer` is its JSON object); `edit` rewrites
    /// the text to inject a fault.
    fn cube_json(buffer: &str, edit: impl Fn(String) -> String) -> String {
        edit(format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0,"children":[1]}},{{"translation":[3,0,0]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
"buffers":[{buffer}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":96}},{{"buffer":0,"byteOffset":192,"byteLength":144}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]}},
{{"bufferView":1,"componentType":5126,"count":8,"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":36,"type":"SCALAR"}}]}}"#
        ))
    }

    /// A GLB of `json` and `bin`, both padded as the specification requires.
    fn glb_file(json: &str, bin: &[u8]) -> Vec<u8> {
        glb::build(json.as_bytes(), Some(bin))
    }

    /// The cube as a glTF with its buffer in a base64 data URI, with `edit` applied.
    fn embedded(edit: impl Fn(String) -> String) -> Vec<u8> {
        const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let bin = cube_bin();
        let mut b64 = String::new();
        for c in bin.chunks(3) {
            let n = c.iter().fold(0u32, |a, &x| a << 8 | x as u32) << (8 * (3 - c.len()));
            for k in 0..=c.len() {
                b64.push(B64[(n >> (18 - 6 * k) & 63) as usize] as char);
            }
        }
        let buffer = format!(
            r#"{{"uri":"data:application/octet-stream;base64,{b64}","byteLength":{}}}"#,
            bin.len()
        );
        cube_json(&buffer, edit).into_bytes()
    }

    fn assert_is_the_cube(m: &LoadedMesh) {
        let cube = cube();
        assert_eq!(m.mesh.triangles.len(), 12);
        assert_eq!(m.mesh.positions.len(), 8);
        assert!(!m.computed_normals && m.warnings.is_empty());
        for t in 0..12 {
            let (p, n) = m.mesh.triangle(t);
            let (q, k) = cube.triangle(t);
            for c in 0..3 {
                assert!((p[c] - q[c]).length() < 1e-6 && (n[c] - k[c]).length() < 1e-6);
            }
        }
    }

    #[test]
    fn a_valid_glb_loads() {
        let bin = cube_bin();
        let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
        let bytes = glb_file(&json, &bin);
        assert_is_the_cube(&parse(&bytes, "cube.glb").unwrap());
        // The magic decides, not the extension.
        assert_is_the_cube(&parse(&bytes, "cube.gltf").unwrap());
    }

    #[test]
    fn a_valid_embedded_gltf_loads() {
        assert_is_the_cube(&parse(&embedded(|s| s), "cube.gltf").unwrap());
    }

    #[test]
    fn a_glb_with_a_bad_container_is_one_error() {
        let bin = cube_bin();
        let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
        let mut bytes = glb_file(&json, &bin);
        bytes.truncate(bytes.len() - 4);
        let e = parse(&bytes, "m.glb").unwrap_err().to_string();
        assert!(
            e.starts_with("m.glb: malformed glTF binary: the GLB header declares a length of"),
            "{e}"
        );
        let e = parse(&embedded(|s| s), "m.glb").unwrap_err().to_string();
        assert!(e.contains("not the GLB magic"), "{e}");
    }

    /// Documents the `gltf` crate accepts (its validation passes) but whose accessors its
    /// reader would panic on, or read out of range: each is one error naming the problem.
    #[test]
    fn accessors_the_gltf_reader_would_panic_on_are_errors() {
        let cases: [(&str, &str, &str, &str); 7] = [
            (
                r#""componentType":5125"#,
                r#""componentType":5126"#,
                "indices accessor 2 holds Scalar of F32",
                "float indices: unreachable!() in Reader::read_indices",
            ),
            (
                r#""bufferView":1,"componentType":5126,"count":8"#,
                r#""bufferView":1,"componentType":5126,"count":0"#,
                "NORMAL accessor 1 has count 0",
                "count 0: count - 1 overflows",
            ),
            (
                r#""byteOffset":0,"byteLength":96}"#,
                r#""byteOffset":0,"byteLength":96,"byteStride":4}"#,
                "byteStride 4, less than the 12-byte elements",
                "stride below the element size: assertion",
            ),
            (
                r#""componentType":5126,"count":8,"type":"VEC3","min""#,
                r#""componentType":5121,"count":8,"type":"SCALAR","min""#,
                "POSITION accessor 0 holds Scalar of U8, expected Vec3 of F32",
                "element size mismatch: assertion",
            ),
            (
                r#""byteOffset":0,"byteLength":96}"#,
                r#""byteOffset":18446744073709551615,"byteLength":96}"#,
                "reaches past the end of buffer 0",
                "offset + length overflows",
            ),
            (
                r#""bufferView":1,"componentType":5126,"count":8,"type":"VEC3"}"#,
                r#""bufferView":1,"componentType":5126,"count":8,"type":"VEC3","sparse":{"count":0,"indices":{"bufferView":2,"componentType":5125},"values":{"bufferView":1}}}"#,
                "sparse count 0 is outside 1..=8",
                "sparse count 0: count - 1 overflows",
            ),
            (
                r#""byteOffset":192,"byteLength":144"#,
                r#""byteOffset":300,"byteLength":144"#,
                "buffer view 2 (144 bytes from byte 300) reaches past the end of buffer 0",
                "view past the buffer: indices silently missing",
            ),
        ];
        for (from, to, msg, why) in cases {
            let bytes = embedded(|s| {
                assert!(s.contains(from), "{why}: template lacks {from}");
                s.replacen(from, to, 1)
            });
            let e = parse(&bytes, "m.gltf").map(|_| ()).unwrap_err().to_string();
            assert!(
                e.starts_with("m.gltf: node 0, mesh 0, primitive 0: "),
                "{why}: {e}"
            );
            assert!(e.contains(msg), "{why}: {e}");
        }
    }

    /// A node hierarchy with a cycle passes the `gltf` crate's validation; walking it used to
    /// overflow the stack.
    #[test]
    fn a_node_cycle_ends() {
        let bytes =
            embedded(|s| s.replacen(r#"{"translation":[3,0,0]}"#, r#"{"children":[0]}"#, 1));
        let mut m = parse(&bytes, "m.gltf").unwrap();
        assert_eq!(
            m.warnings,
            ["node 0 is reached a second time (the node hierarchy must be a forest): drawn once"]
        );
        m.warnings.clear();
        assert_is_the_cube(&m);
    }

    /// Random byte corruptions of a valid GLB (header, chunk headers, JSON text and binary
    /// data alike) load or fail with an error, never panic.
    #[test]
    fn corrupted_glbs_never_panic() {
        let bin = cube_bin();
        let json = cube_json(&format!(r#"{{"byteLength":{}}}"#, bin.len()), |s| s);
        let good = glb_file(&json, &bin);
        for b in corruptions(&good, 0x9e37_79b9_7f4a_7c15, 3000) {
            let _ = parse(&b, "/nonexistent-smoothtri-test/m.glb");
        }
    }

    /// A POSITION index past the accessors made the `gltf` crate's validation itself panic
    /// (found by [`corrupted_glbs_never_panic`]).
    #[test]
    fn a_position_index_out_of_range_is_an_error() {
        let bytes = embedded(|s| s.replacen(r#""POSITION":0"#, r#""POSITION":7"#, 1));
        let e = parse(&bytes, "m.gltf").map(|_| ()).unwrap_err().to_string();
        assert_eq!(
            e,
            "m.gltf: malformed glTF: invalid glTF: \
             meshes[0].primitives[0].attributes[\"POSITION\"]: Index out of bounds;"
        );
    }
}

/// Scenes: nodes, transforms, instancing, sparse accessors, primitive modes. Each test writes a
/// small GLB with [`scene_tests::Doc`].
#[cfg(test)]
pub(crate) mod scene_tests {
    use super::*;

    /// A glTF document under construction: one binary buffer, its views and accessors (also
    /// the animation tests' documents).
    #[derive(Default)]
    pub(crate) struct Doc {
        bin: Vec<u8>,
        views: Vec<String>,
        accessors: Vec<String>,
    }

    impl Doc {
        /// A buffer view over `bytes` (appended to the buffer, 4-byte aligned).
        fn view(&mut self, bytes: &[u8]) -> usize {
            let at = self.bin.len();
            self.bin.extend(bytes);
            self.bin.resize(self.bin.len().div_ceil(4) * 4, 0);
            self.views.push(format!(
                r#"{{"buffer":0,"byteOffset":{at},"byteLength":{}}}"#,
                bytes.len()
            ));
            self.views.len() - 1
        }

        fn f32s(v: &[[f32; 3]]) -> Vec<u8> {
            v.iter().flatten().flat_map(|c| c.to_le_bytes()).collect()
        }

        /// A `VEC3`/`FLOAT` accessor of `v` (with `min`/`max`).
        pub(crate) fn vec3(&mut self, v: &[[f32; 3]]) -> usize {
            let view = self.view(&Self::f32s(v));
            let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for p in v {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            self.accessor(format!(
                r#"{{"bufferView":{view},"componentType":5126,"count":{},"type":"VEC3","min":{lo:?},"max":{hi:?}}}"#,
                v.len()
            ))
        }

        /// A `VEC3`/`FLOAT` accessor of `count` elements: `base` (or zeros when `None`, no
        /// buffer view) with the sparse `values` at `at` (u16 indices, in the given order).
        pub(super) fn sparse_vec3(
            &mut self,
            count: usize,
            base: Option<&[[f32; 3]]>,
            at: &[u16],
            values: &[[f32; 3]],
            minmax: &str,
        ) -> usize {
            let base = base
                .map(|b| format!(r#""bufferView":{},"#, self.view(&Self::f32s(b))))
                .unwrap_or_default();
            let ix: Vec<u8> = at.iter().flat_map(|x| x.to_le_bytes()).collect();
            let iv = self.view(&ix);
            let vv = self.view(&Self::f32s(values));
            self.accessor(format!(
                r#"{{{base}"componentType":5126,"count":{count},"type":"VEC3"{minmax},"sparse":{{"count":{},"indices":{{"bufferView":{iv},"componentType":5123}},"values":{{"bufferView":{vv}}}}}}}"#,
                at.len()
            ))
        }

        /// An accessor of `count` elements of `ty` (`SCALAR`, `VEC4`…) and `component` (5126
        /// float, 5123 unsigned short…) over `bytes`, in a view of its own.
        pub(crate) fn raw(
            &mut self,
            bytes: &[u8],
            component: u32,
            count: usize,
            ty: &str,
        ) -> usize {
            let view = self.view(bytes);
            self.accessor(format!(
                r#"{{"bufferView":{view},"componentType":{component},"count":{count},"type":"{ty}"}}"#
            ))
        }

        fn accessor(&mut self, json: String) -> usize {
            self.accessors.push(json);
            self.accessors.len() - 1
        }

        /// The GLB with `rest` (scenes, nodes, meshes: JSON members without braces).
        pub(crate) fn glb(&self, rest: &str) -> Vec<u8> {
            let json = format!(
                r#"{{"asset":{{"version":"2.0"}},{rest},"buffers":[{{"byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
                self.bin.len(),
                self.views.join(","),
                self.accessors.join(",")
            );
            glb::build(json.as_bytes(), Some(&self.bin))
        }
    }

    /// The unit right triangle in the xy plane, normals `+z`: (POSITION, NORMAL) accessors.
    fn triangle(d: &mut Doc) -> (usize, usize) {
        (
            d.vec3(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
            d.vec3(&[[0.0, 0.0, 1.0]; 3]),
        )
    }

    fn load(d: &Doc, rest: &str) -> LoadedMesh {
        parse(&d.glb(rest), "s.glb").unwrap()
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-6
    }

    /// The unit face normal of loaded triangle `t`.
    fn face(m: &Mesh, t: usize) -> DVec3 {
        let (p, _) = m.triangle(t);
        (p[1] - p[0]).cross(p[2] - p[0]).normalize()
    }

    #[test]
    fn instanced_meshes_are_drawn_once_per_node() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"translation":[5,0,0]}},{{"mesh":0,"translation":[0,5,0]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
            ),
        );
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        assert_eq!(m.mesh.triangles.len(), 2);
        let (a, _) = m.mesh.triangle(0);
        let (b, _) = m.mesh.triangle(1);
        assert!(close(a[1], DVec3::new(6.0, 0.0, 0.0)), "{a:?}");
        assert!(close(b[2], DVec3::new(0.0, 6.0, 0.0)), "{b:?}");
    }

    #[test]
    fn transforms_compose_down_the_hierarchy() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        // Parent: translate (1, 0, 0) after a 90° turn about z; child: scale 2; grandchild: a
        // matrix translating (0, 0, 3) (column-major). Vertex (1, 0, 0) of the grandchild:
        // (1, 0, 3) → scale (2, 0, 6) → turn (0, 2, 6) → translate (1, 2, 6).
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"translation":[1,0,0],"rotation":[0,0,{h},{h}],"children":[1]}},{{"scale":[2,2,2],"children":[2]}},
{{"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,3,1]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
            ),
        );
        let (v, nn) = m.mesh.triangle(0);
        assert!(close(v[0], DVec3::new(1.0, 0.0, 6.0)), "{v:?}");
        assert!(close(v[1], DVec3::new(1.0, 2.0, 6.0)), "{v:?}");
        assert!(close(v[2], DVec3::new(-1.0, 0.0, 6.0)), "{v:?}");
        assert!(close(nn[0], DVec3::Z), "{nn:?}");
    }

    #[test]
    fn non_uniform_scale_transforms_normals_by_the_inverse_transpose() {
        let mut d = Doc::default();
        let p = d.vec3(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let k = 1.0 / 3f32.sqrt();
        let n = d.vec3(&[[k, k, k]; 3]);
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"scale":[1,2,4]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
            ),
        );
        let (v, nn) = m.mesh.triangle(0);
        // M = diag(1, 2, 4): (M⁻¹)ᵀ n ∝ (1, 1/2, 1/4), the normal of the scaled plane
        // x + y/2 + z/4 = 1 through the scaled vertices.
        let want = DVec3::new(1.0, 0.5, 0.25).normalize();
        for x in nn {
            assert!(close(x, want), "{x:?} vs {want:?}");
        }
        assert!(close(face(&m.mesh, 0), want));
        assert!(close(v[2], DVec3::new(0.0, 0.0, 4.0)));
        // The plain (wrong) transform M n would not be perpendicular to the surface.
        let wrong = DVec3::new(1.0, 2.0, 4.0).normalize();
        assert!(wrong.dot(want) < 0.8);
    }

    #[test]
    fn mirroring_transforms_keep_triangles_counter_clockwise() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"scale":[-1,1,1]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
            ),
        );
        let (_, nn) = m.mesh.triangle(0);
        assert!(close(nn[0], DVec3::Z), "{nn:?}");
        assert!(close(face(&m.mesh, 0), DVec3::Z), "winding flipped");
    }

    #[test]
    fn sparse_accessors_are_applied() {
        let mut d = Doc::default();
        // Positions: base triangle, vertex 2 replaced by (0, 3, 0); normals: no base (zeros),
        // every element given sparsely.
        let base = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = d.sparse_vec3(
            3,
            Some(&base),
            &[2],
            &[[0.0, 3.0, 0.0]],
            r#","min":[0,0,0],"max":[1,3,0]"#,
        );
        let n = d.sparse_vec3(3, None, &[0, 1, 2], &[[0.0, 0.0, 1.0]; 3], "");
        let rest = format!(
            r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
        );
        let m = load(&d, &rest);
        let (v, nn) = m.mesh.triangle(0);
        assert!(close(v[2], DVec3::new(0.0, 3.0, 0.0)), "{v:?}");
        assert!(close(v[1], DVec3::X), "{v:?}");
        assert!(nn.iter().all(|&x| close(x, DVec3::Z)), "{nn:?}");
        assert!(!m.computed_normals);
        // Sparse indices must strictly increase: out of order is an error naming the accessor.
        let mut d = Doc::default();
        let p = d.sparse_vec3(
            3,
            Some(&base),
            &[2, 1],
            &[[0.0, 3.0, 0.0]; 2],
            r#","min":[0,0,0],"max":[1,3,0]"#,
        );
        // This document has one accessor: it serves as POSITION and NORMAL.
        assert_eq!(p, 0);
        let e = parse(
            &d.glb(&rest.replace(&format!(r#""NORMAL":{n}"#), r#""NORMAL":0"#)),
            "s.glb",
        )
        .map(|_| ())
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("node 0, mesh 0, primitive 0: POSITION accessor 0, sparse indices: index 1 is 1, not above the previous 2"),
            "{e}"
        );
    }

    #[test]
    fn non_indexed_strips_and_fans_are_triangles() {
        let mut d = Doc::default();
        // Two triangles, non-indexed.
        let list = d.vec3(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        // A strip and a fan over the unit square, 4 vertices each (2 triangles each).
        let strip = d.vec3(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ]);
        let fan = d.vec3(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{list}}}}},
{{"attributes":{{"POSITION":{strip}}},"mode":5}},{{"attributes":{{"POSITION":{fan}}},"mode":6}}]}}]"#
            ),
        );
        assert_eq!(m.mesh.triangles.len(), 6);
        assert!(m.computed_normals);
        for t in 0..6 {
            assert!(
                close(face(&m.mesh, t), DVec3::Z),
                "triangle {t} is not counter-clockwise"
            );
        }
    }

    #[test]
    fn skipped_modes_name_the_mesh_and_its_nodes() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0,1,2]}}],
"nodes":[{{"name":"Body","mesh":0}},{{"name":"Wire","mesh":1}},{{"name":"Wire.001","mesh":1,"translation":[0,0,1]}}],
"meshes":[{{"name":"body","primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}},
{{"name":"wire","primitives":[{{"attributes":{{"POSITION":{p}}},"mode":1}},{{"attributes":{{"POSITION":{p}}},"mode":0}}]}}]"#
            ),
        );
        assert_eq!(m.mesh.triangles.len(), 1);
        assert_eq!(
            m.warnings,
            [
                r#"mesh 1 "wire", primitive 0 (drawn by node 1 "Wire", node 2 "Wire.001"): mode Lines is not triangles, skipped"#,
                r#"mesh 1 "wire", primitive 1 (drawn by node 1 "Wire", node 2 "Wire.001"): mode Points is not triangles, skipped"#,
            ]
        );
    }

    #[test]
    fn the_default_scene_is_drawn_and_its_absence_handled() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        let meshes = format!(
            r#""meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
        );
        let nodes = r#""nodes":[{"mesh":0,"children":[1]},{"mesh":0,"translation":[0,0,2]},{"mesh":0,"translation":[0,0,9]}]"#;
        // Scene 1 is the default: node 2 only.
        let m = load(
            &d,
            &format!(r#""scene":1,"scenes":[{{"nodes":[0]}},{{"nodes":[2]}}],{nodes},{meshes}"#),
        );
        assert_eq!(m.mesh.triangles.len(), 1);
        assert_eq!(m.mesh.triangle(0).0[0].z, 9.0);
        assert!(
            m.warnings[0].starts_with("drawing scene 1, one of 2"),
            "{:?}",
            m.warnings
        );
        // No default: the first scene (node 0 and its child).
        let m = load(
            &d,
            &format!(r#""scenes":[{{"nodes":[0]}},{{"nodes":[2]}}],{nodes},{meshes}"#),
        );
        assert_eq!(m.mesh.triangles.len(), 2);
        // No scene: every root node (0 with its child 1, and 2).
        let m = load(&d, &format!("{nodes},{meshes}"));
        assert_eq!(m.mesh.triangles.len(), 3);
        assert_eq!(
            m.warnings,
            ["the file has no scene: drawing every root node"]
        );
        // No nodes: each mesh once.
        let m = load(&d, &meshes);
        assert_eq!(m.mesh.triangles.len(), 1);
    }

    #[test]
    fn singular_and_invalid_transforms() {
        let mut d = Doc::default();
        let (p, n) = triangle(&mut d);
        let meshes = format!(
            r#""meshes":[{{"name":"tri","primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#
        );
        let m = load(
            &d,
            &format!(
                r#""scene":0,"scenes":[{{"nodes":[0,1]}}],"nodes":[{{"name":"Flat","mesh":0,"scale":[1,0,1]}},{{"mesh":0}}],{meshes}"#
            ),
        );
        assert_eq!(m.mesh.triangles.len(), 1);
        assert_eq!(
            m.warnings,
            [
                r#"node 0 "Flat": its world transform is singular (a zero scale), mesh 0 "tri" skipped"#
            ]
        );
        let e = parse(
            &d.glb(&format!(
                r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"name":"Spin","mesh":0,"rotation":[0,0,0,0]}}],{meshes}"#
            )),
            "s.glb",
        )
        .map(|_| ())
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            r#"s.glb: node 0 "Spin": rotation [0.0, 0.0, 0.0, 0.0] is not a unit quaternion"#
        );
    }

    #[test]
    fn written_glbs_load_back() {
        // The cube with normals of length √3: written unit length.
        let mut m = super::tests::cube();
        m.normals.clone_from(&m.positions);
        let bytes = write_glb(&m, "test \"quoted\"").unwrap();
        let back = parse(&bytes, "t.glb").unwrap();
        assert!(back.warnings.is_empty() && !back.computed_normals);
        assert_eq!(back.mesh.triangles.len(), m.triangles.len());
        for t in 0..m.triangles.len() {
            let ((p, n), (q, k)) = (back.mesh.triangle(t), m.triangle(t));
            for c in 0..3 {
                assert!(close(p[c], q[c]) && close(n[c], k[c].normalize()));
            }
        }
        assert!(write_glb(&Mesh::default(), "x").is_err());
    }
}
