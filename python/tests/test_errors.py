"""Bad input raises a Python exception with a message that names the argument, never a crash
(each case of issue 50's list)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import smoothtri
from smoothtri import _smoothtri
from conftest import octahedron

V, N, F = octahedron()


@pytest.fixture(scope="module")
def scene() -> smoothtri.Scene:
    return smoothtri.Scene(V, N, F)


O = np.array([[0.1, 0.2, 3.0], [0.0, 0.0, 3.0]])
D = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, -1.0]])


# Wrong shapes or dtypes.


@pytest.mark.parametrize(
    "args, match",
    [
        ((V[:, :2], N, F), r"vertices must have shape \(V, 3\), got \(6, 2\)"),
        ((V.ravel(), N, F), r"vertices must have shape \(V, 3\), got \(18,\)"),
        ((V, N[:5], F), r"normals has 5 rows but vertices has 6"),
        ((V, N, F[:, :2]), r"faces must have shape \(F, 3\), got \(8, 2\)"),
        ((V, N, F.ravel()), r"faces must have shape \(F, 3\)"),
    ],
)
def test_wrong_shapes(args: tuple, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        smoothtri.Scene(*args)


@pytest.mark.parametrize(
    "args, exc, match",
    [
        ((V.astype(np.complex128), N, F), TypeError, r"vertices must hold real numbers, got dtype complex128"),
        ((V, N.astype(bool), F), TypeError, r"normals must hold real numbers, got dtype bool"),
        ((V.astype(str), N, F), TypeError, r"vertices must hold real numbers"),
        ((V, N, F.astype(np.float64)), TypeError, r"faces must hold integers, got dtype float64"),
        (([[1, 2]], N, F), ValueError, r"vertices must have shape"),
        (("abc", N, F), ValueError, r"vertices must have shape"),
    ],
)
def test_wrong_dtypes(args: tuple, exc: type, match: str) -> None:
    with pytest.raises(exc, match=match):
        smoothtri.Scene(*args)


def test_any_real_dtype_is_accepted() -> None:
    for dt in (np.float16, np.float32, np.float64, np.longdouble, np.int8, np.int64, np.int16):
        s = smoothtri.Scene(V.astype(dt), N.astype(dt), F.astype(np.uint8))
        assert s.report.patches == 8


def test_any_integer_index_dtype_is_accepted() -> None:
    for dt in (np.int8, np.uint8, np.int32, np.uint32, np.int64, np.uint64):
        assert smoothtri.Scene(V, N, F.astype(dt)).report.patches == 8


# NaN or infinite values.


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_mesh(bad: float) -> None:
    v = V.copy()
    v[4, 2] = bad
    with pytest.raises(ValueError, match=rf"vertices\[4, 2\] = {bad} is not finite"):
        smoothtri.Scene(v, N, F)
    n = N.copy()
    n[1, 0] = bad
    with pytest.raises(ValueError, match=rf"normals\[1, 0\] = {bad} is not finite"):
        smoothtri.Scene(V, n, F)


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_rays(scene: smoothtri.Scene, bad: float) -> None:
    o = np.repeat(O, 50, axis=0)
    d = np.repeat(D, 50, axis=0)
    o[77, 1] = bad
    o[90, 1] = bad
    with pytest.raises(ValueError, match=r"origins\[77\] = .* is not finite in float32"):
        scene.closest_hit(o, d)
    with pytest.raises(ValueError, match=r"origins\[77\]"):
        scene.any_hit(o, d)
    d2 = np.repeat(D, 50, axis=0)
    d2[5, 0] = bad
    with pytest.raises(ValueError, match=r"directions\[5\] = .* is not finite"):
        scene.closest_hit(np.repeat(O, 50, axis=0), d2)


def test_rays_that_overflow_float32(scene: smoothtri.Scene) -> None:
    o = O.copy()
    o[1, 0] = 1e39  # finite in float64, infinite in float32
    with pytest.raises(ValueError, match=r"origins\[1\] = \(1e39, 0.0, 3.0\) is not finite in float32"):
        scene.closest_hit(o, D)
    s64 = smoothtri.Scene(V, N, F, precision="f64")
    assert s64.closest_hit(o, D).hit.tolist() == [True, False]


def test_zero_direction(scene: smoothtri.Scene) -> None:
    d = D.copy()
    d[1] = 0
    with pytest.raises(ValueError, match=r"directions\[1\] = \(0.0, 0.0, 0.0\) is zero in float32: a ray needs a direction"):
        scene.closest_hit(O, d)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"t_min": math.nan}, r"t_min and t_max must be numbers with t_min <= t_max, got nan and inf"),
        ({"t_max": math.nan}, r"got 0.0 and nan"),
        ({"t_min": 2.0, "t_max": 1.0}, r"got 2.0 and 1.0"),
        ({"t_min": np.array([0.0, math.nan])}, r"t_min\[1\] is nan"),
        ({"t_max": np.array([math.nan, 1.0])}, r"t_max\[0\] is nan"),
        ({"t_max": np.ones(3)}, r"t_max must have shape \(2,\) \(one per ray\), got \(3,\)"),
        ({"t_max": np.ones((2, 1))}, r"t_max must have shape \(2,\)"),
        ({"t_min": "x"}, r"t_min must have shape \(2,\)"),
    ],
)
def test_bad_bounds(scene: smoothtri.Scene, kw: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        scene.closest_hit(O, D, **kw)


def test_mismatched_rays(scene: smoothtri.Scene) -> None:
    with pytest.raises(ValueError, match=r"origins has 2 rows but directions has 1"):
        scene.closest_hit(O, D[:1])
    with pytest.raises(ValueError, match=r"directions must have shape \(R, 3\), got \(2, 4\)"):
        scene.closest_hit(O, np.zeros((2, 4)))


def test_mismatched_rays_in_rust_baseline(scene: smoothtri.Scene) -> None:
    # The benchmark's baseline reads its rays as the queries read them.
    with pytest.raises(ValueError, match=r"origins has 2 rows but directions has 1: one of each per ray"):
        _smoothtri.rust_baseline(scene._native, O, D[:1])
    with pytest.raises(ValueError, match=r"origins has 1 rows but directions has 2"):
        _smoothtri.rust_baseline(scene._native, O[:1], D)


# Indices out of range, zero triangles.


@pytest.mark.parametrize("bad, shown", [(6, "6"), (-1, "-1"), (2**40, str(2**40))])
def test_indices_out_of_range(bad: int, shown: str) -> None:
    f = F.copy()
    f[3, 1] = bad
    with pytest.raises(ValueError, match=rf"faces\[3, 1\] = {shown} is not a vertex index \(the mesh has 6 vertices\)"):
        smoothtri.Scene(V, N, f)


def test_uint64_indices_out_of_range() -> None:
    f = F.astype(np.uint64)
    f[0, 0] = np.iinfo(np.uint64).max
    with pytest.raises(ValueError, match=r"faces\[0, 0\] = 18446744073709551615 is not a vertex index"):
        smoothtri.Scene(V, N, f)


def test_zero_triangles() -> None:
    with pytest.raises(smoothtri.BuildError, match="no triangles"):
        smoothtri.Scene(V, N, np.zeros((0, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="no triangles"):
        smoothtri.Scene(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))


def test_every_triangle_rejected() -> None:
    # Collinear vertices: every triangle degenerate.
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=np.float64)
    n = np.array([[0, 0, 1]] * 3, dtype=np.float64)
    with pytest.raises(smoothtri.BuildError, match=r"no usable triangles: all 1 triangles were rejected \(first: degenerate"):
        smoothtri.Scene(v, n, [[0, 1, 2]])


def test_some_triangles_rejected_are_reported() -> None:
    v = np.vstack([V, [[0, 0, 0], [1e-9, 0, 0]]])
    n = np.vstack([N, [[0, 0, 1], [0, 0, 1]]])
    f = np.vstack([F, [[0, 6, 7]]])
    s = smoothtri.Scene(v, n, f)
    r = s.report
    assert (r.triangles, r.patches) == (9, 8)
    assert r.rejected["degenerate triangle"] == 1 and r.first_rejected == (8, "degenerate triangle (area too small)")
    with pytest.raises(ValueError, match=r"triangles\[1\] = 8: that triangle was rejected by the build"):
        s.evaluate([0, 8], [[0.2, 0.2], [0.2, 0.2]])


# Iterations out of range.


@pytest.mark.parametrize("n", [-1, 65, 1000])
def test_iterations_out_of_range(scene: smoothtri.Scene, n: int) -> None:
    with pytest.raises(ValueError, match=rf"iterations must be one of 0..=64 .*, got {n}"):
        scene.closest_hit(O, D, iterations=n)
    with pytest.raises(ValueError, match="iterations must be one of"):
        scene.any_hit(O, D, iterations=n)


def test_iterations_must_be_integers(scene: smoothtri.Scene) -> None:
    with pytest.raises(TypeError, match="iterations must be an integer, got 4.0"):
        scene.closest_hit(O, D, iterations=4.0)
    with pytest.raises(TypeError, match="iterations must be an integer"):
        scene.closest_hit(O, D, iterations=True)


def test_every_supported_budget_runs(scene: smoothtri.Scene) -> None:
    assert smoothtri.SUPPORTED_ITERATIONS == list(range(65))
    for n in smoothtri.SUPPORTED_ITERATIONS:
        assert scene.closest_hit(O, D, iterations=n).hit.all()


# Read-only or non-contiguous arrays where one is written.


def test_read_only_out(scene: smoothtri.Scene) -> None:
    out = scene.closest_hit(O, D)
    out.t.setflags(write=False)
    with pytest.raises(ValueError, match=r"out.t is read-only: it must be a writeable C-contiguous numpy array of dtype float32 and shape \(2,\)"):
        scene.closest_hit(O, D, out=out)
    occ = np.zeros(2, dtype=bool)
    occ.setflags(write=False)
    with pytest.raises(ValueError, match=r"out is read-only"):
        scene.any_hit(O, D, out=occ)


def test_non_contiguous_out(scene: smoothtri.Scene) -> None:
    out = scene.closest_hit(O, D)
    out.point = np.zeros((2, 6), dtype=np.float32)[:, ::2]
    with pytest.raises(ValueError, match=r"out.point is not C-contiguous"):
        scene.closest_hit(O, D, out=out)
    out = scene.closest_hit(O, D)
    out.normal = np.asfortranarray(np.zeros((2, 3), dtype=np.float32))
    with pytest.raises(ValueError, match=r"out.normal is not C-contiguous"):
        scene.closest_hit(O, D, out=out)
    with pytest.raises(ValueError, match=r"out is not C-contiguous"):
        scene.any_hit(O, D, out=np.zeros(4, dtype=bool)[::2])


def test_wrong_out(scene: smoothtri.Scene) -> None:
    out = scene.closest_hit(O, D)
    out.t = np.zeros(2, dtype=np.float64)
    with pytest.raises(TypeError, match=r"out.t has dtype float64: it must be .* float32"):
        scene.closest_hit(O, D, out=out)
    out = scene.closest_hit(O, D)
    out.triangle = np.zeros(3, dtype=np.int64)
    with pytest.raises(ValueError, match=r"out.triangle has shape \(3,\)"):
        scene.closest_hit(O, D, out=out)
    out.triangle = [0, 0]
    with pytest.raises(TypeError, match=r"out.triangle must be a writeable"):
        scene.closest_hit(O, D, out=out)
    pts = scene.evaluate([0], [[0.1, 0.1]])
    pts.point = pts.point.astype(np.float64)
    with pytest.raises(TypeError, match=r"out.point has dtype float64"):
        scene.evaluate([0], [[0.1, 0.1]], out=pts)


def test_out_that_is_an_input(scene: smoothtri.Scene) -> None:
    """An output array that is also an input is refused, not raced."""
    o = O.astype(np.float32)
    out = scene.closest_hit(o, D)
    out.point = o
    with pytest.raises(ValueError, match="out.point"):
        scene.closest_hit(o, D, out=out)


# An empty ray batch returns empty arrays.


@pytest.mark.parametrize("precision, dtype", [("f32", np.float32), ("f64", np.float64)])
def test_empty_batch(precision: str, dtype: type) -> None:
    s = smoothtri.Scene(V, N, F, precision=precision)
    e = np.zeros((0, 3))
    h = s.closest_hit(e, e)
    assert len(h) == 0
    assert h.point.shape == (0, 3) and h.point.dtype == dtype
    assert h.barycentric.shape == (0, 2) and h.triangle.dtype == np.int64 and h.hit.dtype == bool
    assert s.any_hit(e, e).shape == (0,)
    assert s.any_hit([], []).shape == (0,)
    p = s.evaluate(np.zeros(0, dtype=np.int64), np.zeros((0, 2)))
    assert p.point.shape == (0, 3)
    assert s.closest_hit(e, e, t_max=np.zeros(0)).t.shape == (0,)


# Other arguments.


def test_bad_options() -> None:
    with pytest.raises(ValueError, match=r'precision must be "f32" or "f64", got "f16"'):
        smoothtri.Scene(V, N, F, precision="f16")
    with pytest.raises(ValueError, match=r'field must be "face" or "vertex", got "edge"'):
        smoothtri.Scene(V, N, F, field="edge")
    with pytest.raises(ValueError, match=r"threads must be None \(every core\) or in 1..=1024, got 0"):
        smoothtri.Scene(V, N, F, threads=0)
    with pytest.raises(TypeError, match=r"threads must be None or an integer"):
        smoothtri.Scene(V, N, F, threads=2.5)


def test_evaluate_bad_input(scene: smoothtri.Scene) -> None:
    with pytest.raises(ValueError, match=r"triangles\[1\] = 8 is not a triangle index \(the mesh has 8 triangles\)"):
        scene.evaluate([0, 8], [[0.1, 0.1], [0.1, 0.1]])
    with pytest.raises(ValueError, match=r"barycentrics\[1\] = \(nan, 0.1\) is not finite in float32"):
        scene.evaluate([0, 1], [[0.1, 0.1], [math.nan, 0.1]])
    with pytest.raises(ValueError, match=r"triangles has 1 elements but barycentrics has 2 rows"):
        scene.evaluate([0], [[0.1, 0.1], [0.1, 0.1]])
    with pytest.raises(ValueError, match=r"barycentrics must have shape \(M, 2\), got \(1, 3\)"):
        scene.evaluate([0], [[0.1, 0.1, 0.8]])
    with pytest.raises(TypeError, match=r"triangles must hold integers"):
        scene.evaluate([0.5], [[0.1, 0.1]])


def test_load_errors(tmp_path) -> None:
    with pytest.raises(FileNotFoundError, match="missing.obj"):
        smoothtri.load(tmp_path / "missing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(smoothtri.LoadError, match=r"bad.obj:4: "):
        smoothtri.load(bad)
    other = tmp_path / "mesh.stl"
    other.write_text("solid")
    with pytest.raises(smoothtri.LoadError, match=r"unknown mesh format"):
        smoothtri.load(other)
    empty = tmp_path / "empty.obj"
    empty.write_text("v 0 0 0\n")
    with pytest.raises(smoothtri.LoadError, match="the mesh has no triangles"):
        smoothtri.load(empty)
    glb = tmp_path / "x.glb"
    glb.write_bytes(b"glTF\x02\x00\x00\x00")
    with pytest.raises(smoothtri.LoadError, match="x.glb"):
        smoothtri.load(glb)


def test_camera_rays_errors() -> None:
    with pytest.raises(ValueError, match=r"width must be in 1..=16384, got 0"):
        smoothtri.camera_rays(V, 0, 10)
    with pytest.raises(ValueError, match=r'up must be "x", "y" or "z"'):
        smoothtri.camera_rays(V, 4, 4, up="w")
    with pytest.raises(ValueError, match="vertices is empty"):
        smoothtri.camera_rays(np.zeros((0, 3)), 4, 4)
    with pytest.raises(ValueError, match="azimuth and elevation must be finite"):
        smoothtri.camera_rays(V, 4, 4, azimuth=math.nan)


def test_sweep_errors() -> None:
    s = smoothtri.Scene(V, N, F)
    rays = (O, D)
    with pytest.raises(ValueError, match="iterations must be one of"):
        smoothtri.precision_sweep(s, rays, iterations=[4, 65])
    with pytest.raises(ValueError, match="reference_iterations must be one of"):
        smoothtri.precision_sweep(s, rays, reference_iterations=80)
    with pytest.raises(ValueError, match=r'precision must be "f32" or "f64"'):
        smoothtri.precision_sweep(s, rays, precision="f16")
    bad = O.copy()
    bad[0, 0] = math.nan
    with pytest.raises(ValueError, match=r"origins\[0\]"):
        smoothtri.precision_sweep(s, (bad, D))
