//! Scenes: nodes, transforms, instancing, sparse accessors, primitive modes. Each test writes a
//! small GLB with [`Doc`].

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
    pub(crate) fn raw(&mut self, bytes: &[u8], component: u32, count: usize, ty: &str) -> usize {
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

/// The `meshes` member of one mesh with one primitive of POSITION `p` and NORMAL `n`.
fn one_mesh(p: usize, n: usize) -> String {
    format!(r#""meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}]"#)
}

/// [`triangle`] as mesh 0 ([`one_mesh`]), drawn by `nodes` (the scenes and nodes: JSON
/// members without braces).
fn load_triangle(nodes: &str) -> LoadedMesh {
    let mut d = Doc::default();
    let (p, n) = triangle(&mut d);
    load(&d, &format!("{nodes},{}", one_mesh(p, n)))
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
    let m = load_triangle(
        r#""scene":0,"scenes":[{"nodes":[0,1]}],
"nodes":[{"mesh":0,"translation":[5,0,0]},{"mesh":0,"translation":[0,5,0]}]"#,
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
    // Parent: translate (1, 0, 0) after a 90° turn about z; child: scale 2; grandchild: a
    // matrix translating (0, 0, 3) (column-major). Vertex (1, 0, 0) of the grandchild:
    // (1, 0, 3) → scale (2, 0, 6) → turn (0, 2, 6) → translate (1, 2, 6).
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let m = load_triangle(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"translation":[1,0,0],"rotation":[0,0,{h},{h}],"children":[1]}},{{"scale":[2,2,2],"children":[2]}},
{{"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,3,1]}}]"#
    ));
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
            r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"scale":[1,2,4]}}],{}"#,
            one_mesh(p, n)
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
    let m = load_triangle(
        r#""scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"scale":[-1,1,1]}]"#,
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
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],{}"#,
        one_mesh(p, n)
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
    let meshes = one_mesh(p, n);
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
        [r#"node 0 "Flat": its world transform is singular (a zero scale), mesh 0 "tri" skipped"#]
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
