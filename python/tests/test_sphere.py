"""Spheres are exact: the octahedron and the cube with radial normals are spheres for the
method, so hits, surface points and normals are checked against the analytic sphere, to the
core's named bounds (``smoothtri.ACCURACY``)."""

from __future__ import annotations

import numpy as np
import pytest

import smoothtri
from conftest import octahedron, rays_through_ball, sphere_root

A = smoothtri.ACCURACY


def cube() -> tuple:
    """The cube [-1, 1]^3 with averaged normals: every patch is the sphere of radius sqrt(3)."""
    v = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=np.float64)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    f = np.array([t for a, b, c, d in quads for t in ([a, b, c], [a, c, d])])
    return v, v / np.sqrt(3.0), f


@pytest.mark.parametrize("precision", ["f32", "f64"])
@pytest.mark.parametrize("shape", ["octahedron", "cube"])
def test_sphere_hits_are_exact(precision: str, shape: str) -> None:
    v, n, f = octahedron() if shape == "octahedron" else cube()
    radius = 1.0 if shape == "octahedron" else np.sqrt(3.0)
    scene = smoothtri.Scene(v, n, f, precision=precision)
    o, d = rays_through_ball(3000, 1.3, seed=7)
    o, d = o * radius, d * radius
    if precision == "f32":
        # The rays as the scene traces them, so the analytic roots are of the same rays.
        o, d = o.astype(np.float32).astype(np.float64), d.astype(np.float32).astype(np.float64)
    hits = scene.closest_hit(o, d, iterations=8)
    t_true = sphere_root(o / radius, d / radius)
    # Rays that miss the sphere by a margin miss; rays that cross it with a chord longer than
    # about one sampling step of the kernel hit (shorter chords, within 0.5 % of grazing, may
    # be reported as misses: the limit ``Patch::intersect`` documents).
    closest = np.linalg.norm(o - d * ((o * d).sum(1) / (d * d).sum(1))[:, None], axis=1) / radius
    assert not hits.hit[closest > 1 + 1e-6].any()
    assert hits.hit[closest < 0.98].all()
    h = hits.hit
    assert h.sum() > 1500
    hit_bound = A["F64_SPHERE_HIT"] if precision == "f64" else A["F32_SPHERE_HIT"]
    p = hits.point[h].astype(np.float64)
    assert np.abs(np.linalg.norm(p, axis=1) / radius - 1).max() <= hit_bound
    # t within its certified bound of the analytic root (f64 also to the named bound on t).
    dt = np.abs(hits.t[h].astype(np.float64) - t_true[h])
    dlen = np.linalg.norm(d[h], axis=1)
    if precision == "f64":
        assert (dt * dlen / radius).max() <= A["F64_SPHERE_HIT_T"]
        assert (dt <= hits.t_error[h]).all()
    else:
        # f32: within t_error, plus the rounding of t itself.
        assert (dt <= hits.t_error[h] + 4 * np.finfo(np.float32).eps * hits.t[h]).all()
    # Normals radial, unit length; the shading normal of a sphere is its normal.
    normal_bound = A["F64_SPHERE_NORMAL"] if precision == "f64" else A["F32_SPHERE_NORMAL"]
    radial = p / np.linalg.norm(p, axis=1, keepdims=True)
    assert np.abs(hits.normal[h] - radial).max() <= normal_bound
    assert np.abs(hits.shading_normal[h] - radial).max() <= normal_bound
    # The triangle hit is the one whose octant (or cube face) holds the point.
    assert (hits.triangle[h] >= 0).all() and (hits.triangle[~h] == -1).all()


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_surface_points_of_the_sphere(precision: str) -> None:
    v, n, f = octahedron()
    scene = smoothtri.Scene(v, n, f, precision=precision)
    rng = np.random.default_rng(3)
    tri = rng.integers(0, len(f), 2000)
    w = rng.uniform(0, 1, (2000, 2))
    w = np.where(w.sum(1, keepdims=True) > 1, 1 - w, w)
    s = scene.evaluate(tri, w)
    bound = A["F64_SPHERE_POINT"] if precision == "f64" else A["F32_SPHERE_POINT"]
    p = s.point.astype(np.float64)
    assert np.abs(np.linalg.norm(p, axis=1) - 1).max() <= bound
    normal_bound = A["F64_SPHERE_NORMAL"] if precision == "f64" else A["F32_SPHERE_NORMAL"]
    assert np.abs(s.normal - p).max() <= normal_bound + bound
    # Vertices are interpolated.
    corners = scene.evaluate([0, 0, 0], [[0, 0], [1, 0], [0, 1]])
    interp = A["F64_INTERPOLATION"] if precision == "f64" else A["F32_INTERPOLATION"]
    assert np.abs(corners.point - v[f[0]]).max() <= interp


def test_occluded_agrees_with_intersect() -> None:
    v, n, f = octahedron()
    scene = smoothtri.Scene(v, n, f, precision="f64")
    o, d = rays_through_ball(2000, 1.5, seed=11)
    hits = scene.closest_hit(o, d)
    assert (scene.any_hit(o, d) == hits.hit).all()
    # Shadow rays to just before the first hit see nothing; to just after, something.
    t = np.where(hits.hit, hits.t, 1.0)
    assert not scene.any_hit(o, d, t_max=np.where(hits.hit, 0.999 * t, 1.0))[hits.hit].any()
    assert scene.any_hit(o, d, t_max=np.where(hits.hit, 1.001 * t, 1.0))[hits.hit].all()
    # A per-ray interval that is empty is a miss, not an error.
    assert not scene.any_hit(o, d, t_min=2.0, t_max=np.ones(len(o))).any()
