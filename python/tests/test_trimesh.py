"""``smoothtri.trimesh.Intersector`` against trimesh's own ``RayMeshIntersector`` on the
octahedron with radial normals, whose smooth surface is the unit sphere: the same calls
return the same types and shapes, the hits agree (the same rays hit, each engine's triangle
is the octant its point lies in, as many hits per ray), and the smooth hits lie on the sphere.
"""

from __future__ import annotations

import numpy as np
import pytest

import smoothtri
import smoothtri.trimesh
from conftest import octahedron, octant_face, rays_through_ball

trimesh = pytest.importorskip("trimesh")
from trimesh.ray.ray_triangle import RayMeshIntersector  # noqa: E402

A = smoothtri.ACCURACY


@pytest.fixture(scope="module")
def mesh():
    v, n, f = octahedron()
    m = trimesh.Trimesh(vertices=v, faces=f, vertex_normals=n, process=False)
    assert np.allclose(m.vertex_normals, n)
    return m


@pytest.fixture(scope="module", params=["f64", "f32"])
def engines(request, mesh):
    return smoothtri.trimesh.Intersector(mesh, precision=request.param), RayMeshIntersector(mesh)


def closest_approach(o: np.ndarray, d: np.ndarray) -> np.ndarray:
    return np.linalg.norm(o - d * ((o * d).sum(1) / (d * d).sum(1))[:, None], axis=1)


def on_sphere_bound(smooth) -> float:
    return A["F64_SPHERE_HIT"] if smooth.scene.precision == "f64" else A["F32_SPHERE_HIT"]


def test_intersects_first(engines) -> None:
    smooth, flat = engines
    # Rays through the inscribed ball (radius 1/sqrt(3)) hit both surfaces; rays that pass
    # farther than 1 from the centre miss both.
    o, d = rays_through_ball(400, 0.5, seed=1)
    o_miss = o + np.cross(d, [0.3, 0.4, 0.5]) / np.linalg.norm(np.cross(d, [0.3, 0.4, 0.5]), axis=1, keepdims=True) * 2.0
    assert (closest_approach(o_miss, d) > 1.05).all()
    o, d = np.vstack([o, o_miss]), np.vstack([d, d])
    ours, theirs = smooth.intersects_first(o, d), flat.intersects_first(o, d)
    assert ours.dtype == theirs.dtype == np.int64 and ours.shape == theirs.shape == (800,)
    assert ((ours >= 0) == (theirs >= 0)).all()
    assert (ours[:400] >= 0).all() and (ours[400:] == -1).all()
    # Each engine's triangle is the octant of its own hit point.
    loc_s, ray_s, tri_s = smooth.intersects_location(o, d, multiple_hits=False)
    loc_f, ray_f, tri_f = flat.intersects_location(o, d, multiple_hits=False)
    assert (ours[ray_s] == tri_s).all() and (theirs[ray_f] == tri_f).all()
    assert (tri_s == octant_face(loc_s)).all()
    assert (tri_f == octant_face(loc_f)).all()
    assert np.abs(np.linalg.norm(loc_s, axis=1) - 1).max() <= on_sphere_bound(smooth)


def test_intersects_any(engines) -> None:
    smooth, flat = engines
    o, d = rays_through_ball(300, 2.0, seed=2)
    ours, theirs = smooth.intersects_any(o, d), flat.intersects_any(o, d)
    assert ours.dtype == theirs.dtype == bool and ours.shape == theirs.shape
    c = closest_approach(o, d)
    inside, outside = c < 1 / np.sqrt(3) - 1e-9, c > 1 + 1e-9
    assert inside.any() and outside.any()
    assert ours[inside].all() and theirs[inside].all()
    assert not ours[outside].any() and not theirs[outside].any()
    # Between the flat octahedron and the sphere only the smooth surface is there.
    assert ours[(c < 1 - 1e-6)].all()
    assert (ours | ~theirs).all()


def test_intersects_location_multiple_hits(engines) -> None:
    smooth, flat = engines
    o, d = rays_through_ball(300, 0.5, seed=3)
    loc_s, ray_s, tri_s = smooth.intersects_location(o, d)
    loc_f, ray_f, tri_f = flat.intersects_location(o, d)
    for a, b in ((loc_s, loc_f), (ray_s, ray_f), (tri_s, tri_f)):
        assert a.dtype == b.dtype and a.ndim == b.ndim
    # Every ray enters and leaves both surfaces: two hits per ray each.
    assert (np.bincount(ray_s, minlength=300) == 2).all()
    assert (np.bincount(ray_f, minlength=300) == 2).all()
    assert np.abs(np.linalg.norm(loc_s, axis=1) - 1).max() <= on_sphere_bound(smooth)
    assert (tri_s == octant_face(loc_s)).all()
    # Grouped by ray, nearest first.
    assert (np.diff(ray_s) >= 0).all()
    t = ((loc_s - o[ray_s]) * d[ray_s]).sum(1)
    assert (t[0::2] < t[1::2]).all()


def test_intersects_id(engines) -> None:
    smooth, flat = engines
    o, d = rays_through_ball(100, 0.5, seed=4)
    ours, theirs = smooth.intersects_id(o, d), flat.intersects_id(o, d)
    assert len(ours) == len(theirs) == 2
    assert [a.dtype for a in ours] == [b.dtype for b in theirs]
    assert sorted(ours[1].tolist()) == sorted(theirs[1].tolist())
    tri, ray, loc = smooth.intersects_id(o, d, return_locations=True, multiple_hits=False)
    assert len(tri) == len(ray) == len(loc) == 100
    tri, ray = smooth.intersects_id(o, d, max_hits=1)
    assert len(tri) == 100


def test_empty_batch(engines) -> None:
    smooth, flat = engines
    e = np.zeros((0, 3))
    assert smooth.intersects_first(e, e).shape == flat.intersects_first(e, e).shape == (0,)
    assert smooth.intersects_any(e, e).shape == (0,)
    loc, ray, tri = smooth.intersects_location(e, e)
    assert loc.shape == (0, 3) and ray.shape == tri.shape == (0,)


def test_swap_in(mesh) -> None:
    """A trimesh user assigns it to ``mesh.ray``; trimesh's own queries then use it."""
    m = mesh.copy()
    m.ray = smoothtri.trimesh.Intersector(m)
    inside = np.array([[0.0, 0.0, 0.0], [0.45, 0.45, 0.3], [0.5, 0.5, 0.5]])  # |p| < 1
    outside = np.array([[1.2, 0.0, 0.0], [0.0, 0.9, 0.9]])
    # The last two inside points lie outside the flat octahedron (|x| + |y| + |z| > 1).
    assert m.ray.contains_points(inside).all()
    assert not m.ray.contains_points(outside).any()
    assert not RayMeshIntersector(mesh).contains_points(inside[1:]).any()
    loc, ray, tri = m.ray.intersects_location([[0, 0, 3.0]], [[0, 0, -1.0]])
    assert np.allclose(loc, [[0, 0, 1], [0, 0, -1]], atol=1e-14)
