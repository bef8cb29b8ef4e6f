"""``Scene.update``: an animated mesh moved in place equals a fresh scene of the same vertices
(hits within their ``t_error``; the surface itself bit for bit), a moved sphere stays exact,
and bad updates raise and leave the scene as it was."""

from __future__ import annotations

import numpy as np
import pytest

import smoothtri
from conftest import rays_through_ball, sphere_root

A = smoothtri.ACCURACY


def uv_sphere(rings: int = 10, segments: int = 20) -> tuple:
    """A latitude-longitude unit sphere with radial normals (its patches are the sphere)."""
    v = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]
    for i in range(1, rings):
        th = np.pi * i / rings
        for j in range(segments):
            ph = 2 * np.pi * j / segments
            v.append([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    v = np.array(v)

    def ring(i: int, j: int) -> int:
        return 2 + (i - 1) * segments + j % segments

    f = []
    for j in range(segments):
        f.append([0, ring(1, j), ring(1, j + 1)])
        f.append([1, ring(rings - 1, j + 1), ring(rings - 1, j)])
    for i in range(1, rings - 1):
        for j in range(segments):
            f.append([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)])
            f.append([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)])
    return v, v.copy(), np.array(f)


def pose(v: np.ndarray, n: np.ndarray, k: int) -> tuple:
    """Frame ``k``: the sphere scaled and moved (radius, centre), and a wobble that keeps
    the normals radial only for ``k`` even."""
    radius = 0.6 + 0.1 * k
    centre = np.array([0.2 * np.sin(k), 0.1 * np.cos(2 * k), 0.05 * k])
    if k % 2:
        wobble = 1 + 0.05 * np.sin(3 * v[:, :1] + k) * np.cos(2 * v[:, 2:])
        return centre + radius * wobble * v, n, radius, centre
    return centre + radius * v, n, radius, centre


@pytest.mark.parametrize("precision", ["f32", "f64"])
@pytest.mark.parametrize("seams", [True, False])
def test_updates_equal_fresh_scenes(precision: str, seams: bool) -> None:
    v, n, f = uv_sphere()
    scene = smoothtri.Scene(v, n, f, precision=precision, seams=seams)
    o, d = rays_through_ball(2000, 1.0, seed=11)
    for k in range(1, 7):
        pv, pn, radius, centre = pose(v, n, k)
        scene.update(pv, pn)
        fresh = smoothtri.Scene(pv, pn, f, precision=precision, seams=seams)
        same = ("triangles", "patches", "rejected", "remedied", "shared_edges", "open_edges", "widest_gap", "seam_edges")
        for name in same:
            assert getattr(scene.report, name) == getattr(fresh.report, name), name
        assert not fresh.report.bvh_refitted
        # The surface itself is the fresh scene's, bit for bit.
        tri = np.arange(len(f)) % len(f)
        bary = np.tile([[0.2, 0.3]], (len(f), 1))
        a, b = scene.evaluate(tri, bary), fresh.evaluate(tri, bary)
        for x, y in zip((a.point, a.normal, a.shading_normal), (b.point, b.normal, b.shading_normal)):
            assert np.array_equal(x, y)
        ro, rd = centre + radius * o, radius * d
        got, want = scene.closest_hit(ro, rd, iterations=8), fresh.closest_hit(ro, rd, iterations=8)
        assert np.array_equal(got.hit, want.hit)
        h = got.hit
        assert h.sum() > 500
        assert (np.abs(got.t[h] - want.t[h]) <= got.t_error[h] + want.t_error[h]).all()
        if k % 2 == 0:
            # A moved sphere is still exact.
            t_true = sphere_root((ro - centre) / radius, rd / radius)
            dt = np.abs(got.t[h].astype(np.float64) - t_true[h])
            slack = 0 if precision == "f64" else 8 * np.finfo(np.float32).eps * got.t[h]
            assert (dt <= got.t_error[h] + slack).all()


def test_bad_updates_leave_the_scene() -> None:
    v, n, f = uv_sphere()
    scene = smoothtri.Scene(v, n, f)
    o, d = rays_through_ball(500, 1.0, seed=3)
    before = scene.closest_hit(o, d)
    bad_nan = v.copy()
    bad_nan[5, 1] = np.nan
    with pytest.raises(ValueError, match=r"vertices\[5, 1\]"):
        scene.update(bad_nan, n)
    with pytest.raises(ValueError, match="built from"):
        scene.update(v[:-1], n[:-1])
    with pytest.raises(ValueError, match="one normal per vertex"):
        scene.update(v, n[:-1])
    with pytest.raises(ValueError):
        scene.update(v[:, :2], n)
    with pytest.raises(TypeError):
        scene.update(np.array([["a", "b", "c"]] * len(v)), n)
    after = scene.closest_hit(o, d)
    for field in ("hit", "t", "t_error", "triangle"):
        assert np.array_equal(getattr(before, field), getattr(after, field))


def test_a_collapsed_pose_misses_and_recovers() -> None:
    v, n, f = uv_sphere()
    scene = smoothtri.Scene(v, n, f)
    o, d = rays_through_ball(500, 1.0, seed=5)
    scene.update(np.zeros_like(v), n)
    assert scene.report.patches == 0
    assert not scene.closest_hit(o, d).hit.any()
    scene.update(v, n)
    assert scene.report.patches == len(f)
    assert scene.closest_hit(o, d).hit.sum() > 100
