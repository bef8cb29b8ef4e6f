//! [`write_glb`]: a mesh as a GLB file (the tessellation's output).

use super::*;

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
