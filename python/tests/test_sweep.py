"""``precision_sweep`` returns what ``smoothtri precision`` prints: the demo's study of the
torus on the same camera rays (written by ``tests/reference.rs``) equals it column by column,
the time per ray aside; ``camera_rays`` are the demo's rays bit for bit; the plot draws."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import smoothtri

BUDGETS = [0, 1, 2, 4, 8, 16, 24]  # the demo's


@pytest.fixture(scope="module")
def torus(reference_dir: pathlib.Path) -> tuple:
    return tuple(np.load(reference_dir / f"torus-{p}.npy") for p in ("vertices", "normals", "faces"))


def test_camera_rays_are_the_demos(reference_dir: pathlib.Path, torus: tuple) -> None:
    o, d = smoothtri.camera_rays(torus[0], 48, 36)
    assert o.dtype == d.dtype == np.float64 and o.shape == d.shape == (48 * 36, 3)
    assert (o == np.load(reference_dir / "study-origins.npy")).all()
    assert (d == np.load(reference_dir / "study-directions.npy")).all()
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)


def test_camera_up_axis(torus: tuple) -> None:
    """A y-up copy of the mesh seen with ``up="y"`` gives the same rays, turned."""
    v = torus[0]
    y_up = np.column_stack([v[:, 0], v[:, 2], -v[:, 1]])  # the inverse of (x, -z, y)
    o, d = smoothtri.camera_rays(v, 8, 6)
    oy, dy = smoothtri.camera_rays(y_up, 8, 6, up="y")
    turn = lambda a: np.column_stack([a[:, 0], a[:, 2], -a[:, 1]])  # noqa: E731
    assert (turn(o) == oy).all() and (turn(d) == dy).all()


def test_sweep_equals_the_demos_study(reference_dir: pathlib.Path, torus: tuple) -> None:
    scene = smoothtri.Scene(*torus, precision="f32", seams=False)
    rays = smoothtri.camera_rays(torus[0], 48, 36)
    study = smoothtri.precision_sweep(scene, rays, iterations=BUDGETS, threads=2)
    lines = (reference_dir / "study.csv").read_text().splitlines()
    header, rows = lines[0].split(","), [line.split(",") for line in lines[1:]]
    assert len(study) == len(rows) == 2 * len(BUDGETS)
    assert study.rays == 48 * 36 and study.reference_iterations == 40 and study.threads == 2
    assert study.csv().splitlines()[0].split(",") == header
    ours = [line.split(",") for line in study.csv().splitlines()[1:]]
    for got, want in zip(ours, rows):
        # Every column but the time per ray, as the demo writes it.
        assert got[:-1] == want[:-1]
    # The printed table too, but for the time per ray.
    demo = (reference_dir / "study.txt").read_text().splitlines()
    mine = study.table().splitlines()
    assert len(mine) == len(demo)
    for got, want in zip(mine, demo):
        assert got[:-10] == want[:-10]
    assert study.hits.dtype == np.int64 and study.max_error.dtype == np.float64
    # f64 reaches rounding by N = 8 on the torus.
    f64 = np.array(study.precision) == "f64"
    assert study.max_error[f64][study.iterations[f64] >= 8].max() < 1e-13


def test_sweep_defaults_and_threads(torus: tuple) -> None:
    scene = smoothtri.Scene(*torus, precision="f64", field="vertex")
    rays = smoothtri.camera_rays(torus[0], 24, 18)
    one = smoothtri.precision_sweep(scene, rays, threads=1)
    assert one.iterations.tolist() == [n for n in range(17) for _ in (0, 1)]
    assert one.precision == ("f32", "f64") * 17
    many = smoothtri.precision_sweep(scene, rays)
    for c in ("hits", "max_error", "p999_error", "mean_error", "mean_t_error", "bound_holds", "disagreements"):
        assert (getattr(one, c) == getattr(many, c)).all(), c
    only = smoothtri.precision_sweep(scene, rays, iterations=[4], precision="f32")
    assert only.precision == ("f32",) and (only.max_error == one.max_error[8]).all()


def test_plot(tmp_path: pathlib.Path, torus: tuple) -> None:
    pytest.importorskip("matplotlib")
    scene = smoothtri.Scene(*torus)
    study = smoothtri.precision_sweep(scene, smoothtri.camera_rays(torus[0], 16, 12), iterations=[0, 2, 4, 8])
    path = tmp_path / "precision.png"
    ax = study.plot(str(path))
    assert path.stat().st_size > 10_000
    assert len(ax.lines) == 4 and ax.get_yscale() == "log"
