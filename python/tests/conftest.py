"""Shared fixtures: the Rust API's answers (written by ``python/tests/reference.rs``) and small
meshes with known smooth surfaces."""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The plots of the tests are written, never shown.
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(scope="session")
def reference_dir(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """The folder of the Rust API's answers: ``$SMOOTHTRI_PY_REFERENCE`` when it holds a
    finished set (CI points it at the one ``cargo test --workspace`` wrote), else written now
    by ``cargo test -p smoothtri-python --test reference`` (needs cargo and the repository)."""
    given = os.environ.get("SMOOTHTRI_PY_REFERENCE")
    if given and (pathlib.Path(given) / "done").exists():
        return pathlib.Path(given)
    out = pathlib.Path(given) if given else tmp_path_factory.mktemp("reference")
    cargo = shutil.which("cargo")
    if cargo is None or not (ROOT / "python" / "tests" / "reference.rs").exists():
        pytest.fail(
            "the reference tests need the Rust API's answers: run them from the repository "
            "with cargo on PATH, or set SMOOTHTRI_PY_REFERENCE to a folder that "
            "`cargo test -p smoothtri-python --test reference` wrote"
        )
    subprocess.run(
        [cargo, "test", "--quiet", "-p", "smoothtri-python", "--test", "reference"],
        cwd=ROOT,
        env={**os.environ, "SMOOTHTRI_PY_REFERENCE": str(out)},
        check=True,
    )
    assert (out / "done").exists()
    return out


def octahedron() -> tuple:
    """The octahedron with radial normals: its patches are exactly the unit sphere. Faces
    counter-clockwise from outside; face ``k`` covers the octant of sign pattern
    ``OCTANTS[k]``."""
    v = np.array(
        [[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64
    )
    f = np.array(
        [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]],
        dtype=np.int64,
    )
    return v, v.copy(), f


# The sign pattern (x, y, z) of the octant each octahedron face covers.
OCTANTS = np.array(
    [[1, 1, 1], [-1, 1, 1], [-1, -1, 1], [1, -1, 1], [1, 1, -1], [-1, 1, -1], [-1, -1, -1], [1, -1, -1]]
)


def octant_face(points: np.ndarray) -> np.ndarray:
    """The octahedron face whose octant holds each point (points off the coordinate planes)."""
    s = np.where(points >= 0, 1, -1)
    return np.array([np.flatnonzero((OCTANTS == row).all(axis=1))[0] for row in s])


def rays_through_ball(n: int, radius: float, seed: int) -> tuple:
    """``n`` rays from random points at distance 3 from the origin towards random points
    within ``radius`` of it; directions of random lengths."""
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 3))
    origins = 3.0 * u / np.linalg.norm(u, axis=1, keepdims=True)
    w = rng.normal(size=(n, 3))
    targets = radius * rng.uniform(0, 1, (n, 1)) ** (1 / 3) * w / np.linalg.norm(w, axis=1, keepdims=True)
    directions = (targets - origins) * rng.uniform(0.5, 2.0, (n, 1))
    return origins, directions


def sphere_root(origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """The first ``t > 0`` of each ray on the unit sphere (NaN on a miss), in float64."""
    a = (directions * directions).sum(axis=1)
    b = (origins * directions).sum(axis=1)
    c = (origins * origins).sum(axis=1) - 1.0
    disc = b * b - a * c
    with np.errstate(invalid="ignore"):
        q = -(b + np.sign(b) * np.sqrt(disc))
        t = np.minimum(q / a, c / q)
    return np.where(disc >= 0, t, np.nan)
