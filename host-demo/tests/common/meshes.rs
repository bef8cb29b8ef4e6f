//! Test meshes as files of each format the demo reads: OBJ, PLY, glTF with its buffer, GLB.

use smoothtri_testkit::Mesh;

/// `m` as an OBJ file's text, with its vertex normals when `normals`.
pub fn obj_text(m: &Mesh, normals: bool) -> String {
    let mut s = String::from("# test mesh\no thing\n");
    for p in &m.positions {
        s += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    if normals {
        for n in &m.normals {
            s += &format!("vn {} {} {}\n", n.x, n.y, n.z);
        }
    }
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if normals {
            s += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
        } else {
            s += &format!("f {a} {b} {c}\n");
        }
    }
    s
}

/// `m` as an ASCII PLY file's text, positions and normals.
pub fn ply_text(m: &Mesh) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    );
    for (p, n) in m.positions.iter().zip(&m.normals) {
        s += &format!("{} {} {} {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for t in &m.triangles {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s
}

/// glTF JSON and its binary buffer (positions, normals, u32 indices).
pub fn gltf_parts(m: &Mesh, uri: Option<&str>) -> (String, Vec<u8>) {
    let mut bin = Vec::new();
    for p in &m.positions {
        for c in p.to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for n in &m.normals {
        for c in n.normalize().to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for t in &m.triangles {
        for i in t {
            bin.extend(i.to_le_bytes());
        }
    }
    let nv = m.positions.len();
    let (lo, hi) = m.bounds();
    let buffer = match uri {
        Some(u) => format!(r#"{{"uri":"{u}","byteLength":{}}}"#, bin.len()),
        None => format!(r#"{{"byteLength":{}}}"#, bin.len()),
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
"buffers":[{buffer}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pv}}},{{"buffer":0,"byteOffset":{pv},"byteLength":{pv}}},{{"buffer":0,"byteOffset":{io},"byteLength":{il}}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{nv},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}},
{{"bufferView":1,"componentType":5126,"count":{nv},"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":{ni},"type":"SCALAR"}}]}}"#,
        lo.x as f32,
        lo.y as f32,
        lo.z as f32,
        hi.x as f32,
        hi.y as f32,
        hi.z as f32,
        pv = nv * 12,
        io = nv * 24,
        il = m.triangles.len() * 12,
        ni = m.triangles.len() * 3,
    );
    (json, bin)
}

/// `m` as a GLB file: [`gltf_parts`] in the binary container.
pub fn glb_bytes(m: &Mesh) -> Vec<u8> {
    let (json, mut bin) = gltf_parts(m, None);
    let mut j = json.into_bytes();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}
