//! Fuzz target `gltf_scene`: the glTF scene walk of `smoothtri-io` on structurally valid GLBs with
//! arbitrary node graphs. The fuzzer chooses up to 8 nodes (a mesh or none, children by index,
//! cycles and shared children included, a TRS or matrix transform from raw floats), the scenes
//! and the default scene, and each of two meshes' primitive mode and whether it is indexed;
//! the buffer (the host's cube with normals, u32 indices) is fixed and valid. Random bytes rarely get
//! this far, so the `glb` target does not reach the walk.
//!
//! Asserts: loading gives a mesh or a typed error, never a panic; an accepted mesh has finite
//! positions, finite normals and indices in range. Any panic is a bug.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use smoothtri_io::{glb, gltf};

#[path = "mesh_checks.rs"]
mod mesh_checks;

#[derive(Arbitrary, Debug)]
struct Node {
    mesh: Option<u8>,
    children: Vec<u8>,
    matrix: bool,
    values: [f32; 16],
    name: bool,
}

#[derive(Arbitrary, Debug)]
struct Input {
    nodes: Vec<Node>,
    scenes: Vec<Vec<u8>>,
    default_scene: Option<u8>,
    modes: [u8; 2],
    indexed: [bool; 2],
}

/// A JSON number for any float (non-finite ones as 0, which JSON cannot hold).
fn num(x: f32) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "0".into()
    }
}

fuzz_target!(|inp: Input| {
    // The cube of `smoothtri_host::scenes::cube`: 8 positions, 8 normals (as f32), 36 u32
    // indices.
    let cube = smoothtri_host::scenes::cube();
    let mut bin = Vec::new();
    for v in cube.positions.iter().chain(&cube.normals) {
        for c in v.to_array() {
            bin.extend((c as f32).to_le_bytes());
        }
    }
    for i in cube.triangles.iter().flatten() {
        bin.extend(i.to_le_bytes());
    }
    let n = inp.nodes.len().min(8);
    let nodes: Vec<String> = inp.nodes[..n]
        .iter()
        .enumerate()
        .map(|(i, nd)| {
            let mut f = Vec::new();
            if nd.name {
                f.push(format!(r#""name":"n{i}""#));
            }
            if let Some(m) = nd.mesh {
                f.push(format!(r#""mesh":{}"#, m % 2));
            }
            if !nd.children.is_empty() {
                let c: Vec<String> = nd
                    .children
                    .iter()
                    .take(4)
                    .map(|c| (*c as usize % n).to_string())
                    .collect();
                f.push(format!(r#""children":[{}]"#, c.join(",")));
            }
            let v: Vec<String> = nd.values.iter().map(|&x| num(x)).collect();
            if nd.matrix {
                f.push(format!(r#""matrix":[{}]"#, v.join(",")));
            } else {
                f.push(format!(
                    r#""translation":[{}],"rotation":[{}],"scale":[{}]"#,
                    v[0..3].join(","),
                    v[3..7].join(","),
                    v[7..10].join(",")
                ));
            }
            format!("{{{}}}", f.join(","))
        })
        .collect();
    let scenes: Vec<String> = inp
        .scenes
        .iter()
        .take(3)
        .map(|s| {
            let ns: Vec<String> = if n == 0 {
                Vec::new()
            } else {
                s.iter()
                    .take(4)
                    .map(|x| (*x as usize % n).to_string())
                    .collect()
            };
            format!(r#"{{"nodes":[{}]}}"#, ns.join(","))
        })
        .collect();
    let scene = match (inp.default_scene, scenes.len()) {
        (Some(s), k) if k > 0 => format!(r#""scene":{},"#, s as usize % k),
        _ => String::new(),
    };
    let prim = |k: usize| {
        let idx = if inp.indexed[k] {
            r#","indices":2"#
        } else {
            ""
        };
        format!(
            r#"{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}}{idx},"mode":{}}}]}}"#,
            inp.modes[k] % 7
        )
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{scene}"scenes":[{}],"nodes":[{}],"meshes":[{},{}],
"buffers":[{{"byteLength":{}}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":96}},{{"buffer":0,"byteOffset":192,"byteLength":144}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]}},
{{"bufferView":1,"componentType":5126,"count":8,"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":36,"type":"SCALAR"}}]}}"#,
        scenes.join(","),
        nodes.join(","),
        prim(0),
        prim(1),
        bin.len()
    );
    let bytes = glb::build(json.as_bytes(), Some(&bin));
    if let Ok(m) = gltf::parse(&bytes, "/nonexistent-smoothtri-fuzz/scene.glb") {
        mesh_checks::assert_well_formed(&m.mesh);
    }
});
