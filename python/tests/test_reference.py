"""Every answer of the Python API equals the Rust API's bit for bit, on the built-in scenes
(``tests/reference.rs`` writes the Rust side): hits, occlusion, surface points, the build
report, whatever the input dtype, strides, thread count or output arrays."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import smoothtri

SCENES = ["torus", "sphere", "cube", "teapot"]
CONFIGS = [
    ("f32", "face", True),
    ("f64", "face", True),
    ("f32", "vertex", False),
    ("f64", "vertex", True),
]
BUDGETS = [0, 4, 8]
HIT_FIELDS = ["hit", "t", "t_error", "point", "normal", "shading_normal", "triangle", "barycentric"]


def tag(precision: str, field: str, seams: bool) -> str:
    return f"{precision}-{field}-{'seams' if seams else 'noseams'}"


def mesh(ref: pathlib.Path, name: str) -> tuple:
    return tuple(np.load(ref / f"{name}-{part}.npy") for part in ("vertices", "normals", "faces"))


def rays(ref: pathlib.Path, name: str) -> tuple:
    return np.load(ref / f"{name}-origins.npy"), np.load(ref / f"{name}-directions.npy")


def bits(a: np.ndarray) -> np.ndarray:
    """The bit patterns of an array (so that -0.0 and 0.0, and NaN payloads, differ)."""
    a = np.ascontiguousarray(a)
    return a.view({1: np.uint8, 4: np.uint32, 8: np.uint64}[a.dtype.itemsize])


def assert_bits(got: np.ndarray, want: np.ndarray, what: str) -> None:
    assert got.dtype == want.dtype, f"{what}: dtype {got.dtype}, want {want.dtype}"
    assert got.shape == want.shape, f"{what}: shape {got.shape}, want {want.shape}"
    diff = np.flatnonzero((bits(got) != bits(want)).reshape(len(got), -1).any(axis=1))
    assert len(diff) == 0, f"{what}: {len(diff)} rows differ, first {diff[0]}: {got[diff[0]]} != {want[diff[0]]}"


def assert_hits(hits: smoothtri.Hits, want: np.ndarray, what: str) -> None:
    for f in HIT_FIELDS:
        assert_bits(getattr(hits, f), want[f], f"{what}: {f}")


_scenes: dict = {}


def scene(ref: pathlib.Path, name: str, precision: str, field: str, seams: bool) -> smoothtri.Scene:
    key = (name, precision, field, seams)
    if key not in _scenes:
        v, n, f = mesh(ref, name)
        _scenes[key] = smoothtri.Scene(v, n, f, precision=precision, field=field, seams=seams)
    return _scenes[key]


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("config", CONFIGS, ids=[tag(*c) for c in CONFIGS])
@pytest.mark.parametrize("n", BUDGETS)
def test_hits_equal_the_rust_api(reference_dir: pathlib.Path, name: str, config: tuple, n: int) -> None:
    s = scene(reference_dir, name, *config)
    want = np.load(reference_dir / f"{name}-{tag(*config)}-N{n}.npy")
    o, d = rays(reference_dir, name)
    hits = s.closest_hit(o, d, iterations=n)
    assert 0 < want["hit"].sum() < len(want), "the rays should both hit and miss"
    assert_hits(hits, want, f"{name} {tag(*config)} N={n}")
    assert_bits(s.any_hit(o, d, iterations=n), want["occluded"], "occluded")


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("config", CONFIGS, ids=[tag(*c) for c in CONFIGS])
def test_surface_points_equal_the_rust_api(reference_dir: pathlib.Path, name: str, config: tuple) -> None:
    s = scene(reference_dir, name, *config)
    want = np.load(reference_dir / f"{name}-{tag(*config)}-eval.npy")
    got = s.evaluate(want["triangle"], want["w"])
    for f in ("point", "normal", "shading_normal"):
        assert_bits(getattr(got, f), want[f], f"{name} evaluate {f}")


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("config", CONFIGS, ids=[tag(*c) for c in CONFIGS])
def test_report_equals_the_rust_api(reference_dir: pathlib.Path, name: str, config: tuple) -> None:
    s = scene(reference_dir, name, *config)
    text = (reference_dir / f"{name}-{tag(*config)}-report.txt").read_text()
    want = dict(line.split("=") for line in text.splitlines())
    r = s.report
    for key, value in want.items():
        got = getattr(r, key)
        assert (float(value) if key == "widest_gap" else int(value)) == got, key
    assert r.rejected == {k: 0 for k in r.rejected} and r.first_rejected is None
    assert (r.seam_edges is not None) == config[2]
    assert (r.vertex_clamps is not None) == (config[1] == "vertex")


def record_field(a: np.ndarray) -> np.ndarray:
    """``a`` as a field of a packed structured array: unaligned, strides of 25 bytes."""
    rec = np.zeros(len(a), dtype=[("pad", "u1"), ("v", a.dtype, (3,))])
    rec["v"] = a
    v = rec["v"]
    assert not v.flags.aligned and v.strides[0] % v.itemsize != 0
    return v


def layouts(a: np.ndarray, precision: str) -> dict:
    """The same rays in other memory layouts and dtypes that must give the same answers."""
    wide = np.zeros((len(a), 7), dtype=a.dtype)
    wide[:, 1:7:2] = a
    out = {
        "strided": wide[:, 1:7:2],
        "fortran": np.asfortranarray(a),
        "reversed": a[::-1][::-1],
        "list": a.tolist(),
        "longdouble": a.astype(np.longdouble),
        "record field": record_field(a),
    }
    if precision == "f32":
        # float32 input is the value the scene traces anyway.
        out["float32"] = a.astype(np.float32)
    return out


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_layouts_and_dtypes_give_the_same_hits(reference_dir: pathlib.Path, precision: str) -> None:
    name, config = "teapot", (precision, "face", True)
    s = scene(reference_dir, name, *config)
    want = np.load(reference_dir / f"{name}-{tag(*config)}-N4.npy")
    o, d = rays(reference_dir, name)
    if precision == "f32":
        # Round once here so that every layout below holds the values the scene traces.
        o, d = o.astype(np.float32).astype(np.float64), d.astype(np.float32).astype(np.float64)
        want = s.closest_hit(o, d)
        want = {f: getattr(want, f) for f in HIT_FIELDS}
    for (lo, oo), (ld, dd) in zip(layouts(o, precision).items(), layouts(d, precision).items()):
        assert_hits(s.closest_hit(oo, dd), want, f"{precision} {lo}")


def test_broadcast_origin(reference_dir: pathlib.Path) -> None:
    """One origin for every ray through ``np.broadcast_to`` (stride 0) without a copy."""
    s = scene(reference_dir, "torus", "f64", "face", True)
    _, d = rays(reference_dir, "torus")
    eye = np.array([0.3, -2.5, 1.7])
    shared = s.closest_hit(np.broadcast_to(eye, d.shape), d)
    copied = s.closest_hit(np.tile(eye, (len(d), 1)), d)
    assert shared.hit.any()
    for f in HIT_FIELDS:
        assert_bits(getattr(shared, f), getattr(copied, f), f)


@pytest.mark.parametrize("precision", ["f32", "f64"])
def test_threads_give_the_results_of_one_thread(reference_dir: pathlib.Path, precision: str) -> None:
    v, n, f = mesh(reference_dir, "teapot")
    o, d = rays(reference_dir, "teapot")
    # Enough rays that every thread gets many chunks.
    o, d = np.tile(o, (20, 1)), np.tile(d, (20, 1))
    one = smoothtri.Scene(v, n, f, precision=precision, threads=1)
    many = smoothtri.Scene(v, n, f, precision=precision, threads=3)
    assert one.report == many.report
    want = one.closest_hit(o, d, threads=1)
    for threads in (None, 2, 3, 7):
        assert_hits(many.closest_hit(o, d, threads=threads), {f: getattr(want, f) for f in HIT_FIELDS}, f"threads={threads}")
        assert_bits(many.any_hit(o, d, threads=threads), one.any_hit(o, d, threads=1), "occluded")
    hit = want.hit
    points = one.evaluate(want.triangle[hit], want.barycentric[hit], threads=1)
    for threads in (None, 3):
        got = many.evaluate(want.triangle[hit], want.barycentric[hit], threads=threads)
        for fld in ("point", "normal", "shading_normal"):
            assert_bits(getattr(got, fld), getattr(points, fld), fld)


def test_out_arrays_are_overwritten_in_place(reference_dir: pathlib.Path) -> None:
    s = scene(reference_dir, "cube", "f32", "face", True)
    want = np.load(reference_dir / f"cube-{tag('f32', 'face', True)}-N8.npy")
    o, d = rays(reference_dir, "cube")
    out = s.closest_hit(o[::-1], d[::-1], iterations=8)  # other results, then overwritten
    ids = {f: id(getattr(out, f)) for f in HIT_FIELDS}
    got = s.closest_hit(o, d, iterations=8, out=out)
    assert got is out and {f: id(getattr(out, f)) for f in HIT_FIELDS} == ids
    assert_hits(out, want, "out=")
    occ = np.ones(len(o), dtype=bool)
    assert s.any_hit(o, d, iterations=8, out=occ) is occ
    assert_bits(occ, want["occluded"], "occluded out=")


def test_evaluate_round_trips_the_hits(reference_dir: pathlib.Path) -> None:
    """A hit's triangle and barycentrics evaluate to the hit's surface point (the hit point
    is ``origin + t·direction``, within its ``t_error`` of the surface along the ray)."""
    s = scene(reference_dir, "torus", "f64", "face", True)
    o, d = rays(reference_dir, "torus")
    h = s.closest_hit(o, d, iterations=8)
    p = s.evaluate(h.triangle[h.hit], h.barycentric[h.hit])
    gap = np.linalg.norm(p.point - h.point[h.hit], axis=1)
    bound = h.t_error[h.hit] * np.linalg.norm(d[h.hit], axis=1) + 1e-12
    assert (gap <= bound).all()
