"""``smoothtri.load`` (OBJ, PLY, glTF, GLB through the ``smoothtri-io`` loaders),
``from_trimesh``, and real exports of Debian's ``assimp-testmodels``."""

from __future__ import annotations

import os
import pathlib

import numpy as np
import pytest

import smoothtri
from conftest import octahedron

ASSIMP = pathlib.Path("/usr/share/assimp/models")


def assimp() -> pathlib.Path:
    """The assimp test models; a skip where they are not installed, a failure when
    ``SMOOTHTRI_REQUIRE_ASSETS`` is set (CI installs them)."""
    if ASSIMP.is_dir():
        return ASSIMP
    if os.environ.get("SMOOTHTRI_REQUIRE_ASSETS"):
        pytest.fail(f"{ASSIMP} is missing: install Debian's assimp-testmodels")
    pytest.skip(f"no {ASSIMP}")


def test_obj_with_normals(tmp_path: pathlib.Path) -> None:
    v, n, f = octahedron()
    lines = [f"v {x} {y} {z}" for x, y, z in v] + [f"vn {x} {y} {z}" for x, y, z in n]
    lines += ["f " + " ".join(f"{i + 1}//{i + 1}" for i in tri) for tri in f]
    path = tmp_path / "octahedron.obj"
    path.write_text("\n".join(lines) + "\n")
    m = smoothtri.load(path)
    assert m.vertices.dtype == m.normals.dtype == np.float64 and m.faces.dtype == np.int64
    assert not m.computed_normals and m.warnings == ()
    # The same triangles, corner by corner (the loader numbers vertices as it meets them).
    assert (m.vertices[m.faces] == v[f]).all() and (m.normals[m.faces] == n[f]).all()
    s = smoothtri.Scene.from_mesh(m, precision="f64")
    h = s.closest_hit([[0.1, 0.2, 3.0]], [[0, 0, -1.0]], iterations=8)
    assert abs(np.linalg.norm(h.point[0]) - 1) <= smoothtri.ACCURACY["F64_SPHERE_HIT"]


def test_obj_without_normals(tmp_path: pathlib.Path) -> None:
    v, _, f = octahedron()
    path = tmp_path / "flat.obj"
    path.write_text("\n".join([f"v {x} {y} {z}" for x, y, z in v] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f]))
    m = smoothtri.load(str(path))
    assert m.computed_normals
    # Angle-weighted normals of the octahedron's vertices are radial.
    assert np.allclose(m.normals / np.linalg.norm(m.normals, axis=1, keepdims=True), m.vertices, atol=1e-12)


@pytest.mark.parametrize("ext", ["ply", "glb"])
def test_formats_from_trimesh(tmp_path: pathlib.Path, ext: str) -> None:
    trimesh = pytest.importorskip("trimesh")
    v, n, f = octahedron()
    mesh = trimesh.Trimesh(vertices=v, faces=f, vertex_normals=n, process=False)
    path = tmp_path / f"octahedron.{ext}"
    mesh.export(path)
    m = smoothtri.load(path)
    assert len(m.faces) == 8 and m.vertices.shape[1] == 3
    s = smoothtri.Scene.from_mesh(m)
    assert s.report.patches == 8
    # from_trimesh gives the same surface.
    t = smoothtri.from_trimesh(mesh)
    assert (t.vertices == v).all() and (t.faces == f).all() and np.allclose(t.normals, n)
    o, d = smoothtri.camera_rays(v, 20, 20)
    a = smoothtri.Scene.from_mesh(t).closest_hit(o, d)
    b = s.closest_hit(o, d)
    assert (a.hit == b.hit).sum() >= 398  # the same sphere, up to the file's rounding


@pytest.mark.parametrize(
    "name, up",
    [
        ("OBJ/WusonOBJ.obj", "y"),
        ("PLY/Wuson.ply", "y"),
        ("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "y"),
    ],
)
def test_real_exports(name: str, up: str) -> None:
    path = assimp() / name
    m = smoothtri.load(path)
    assert len(m.faces) > 1000
    s = smoothtri.Scene.from_mesh(m)
    r = s.report
    assert r.patches + sum(r.rejected.values()) == r.triangles == len(m.faces)
    assert r.patches > 0.9 * r.triangles
    o, d = smoothtri.camera_rays(m.vertices, 64, 48, up=up)
    h = s.closest_hit(o, d)
    assert 200 < h.hit.sum() < len(o)
    assert np.isfinite(h.point).all() and (h.t_error[h.hit] >= 0).all()
    # Shading normals are unit vectors facing like the geometric ones.
    sn = h.shading_normal[h.hit].astype(np.float64)
    assert np.abs(np.linalg.norm(sn, axis=1) - 1).max() < 1e-5
