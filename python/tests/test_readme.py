"""The README's Python usage, run as a new user would: the lines of its ``From Python`` block as
written (in a fresh interpreter, in a folder holding the mesh it names), and every name its prose
uses reachable after ``import smoothtri`` alone."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
ASSIMP = pathlib.Path("/usr/share/assimp/models")


def readme_python_block() -> str:
    """The first ```python block after the README's ``## From Python`` heading."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("## From Python", 1)[1]
    m = re.search(r"```python\n(.*?)```", section, re.S)
    assert m, "the README's From Python section has no python block"
    return m.group(1)


def run_fresh(code: str, cwd: pathlib.Path) -> subprocess.CompletedProcess:
    """``code`` in a fresh interpreter (so nothing a test imported before helps it)."""
    return subprocess.run(
        [sys.executable, "-c", code],
        cwd=cwd,
        env={**os.environ, "MPLBACKEND": "Agg"},
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_the_readme_names_are_reachable_after_import_smoothtri(tmp_path):
    names = ["smoothtri.trimesh.Intersector", "smoothtri.Scene.from_mesh", "smoothtri.load",
             "smoothtri.camera_rays", "smoothtri.precision_sweep", "smoothtri.from_trimesh"]
    code = "import smoothtri\n" + "".join(f"{n}\n" for n in names)
    r = run_fresh(code, tmp_path)
    assert r.returncode == 0, r.stderr


def test_the_readme_block_runs_as_written(tmp_path):
    mesh = ASSIMP / "OBJ" / "WusonOBJ.obj"
    if not mesh.exists():
        if os.environ.get("SMOOTHTRI_REQUIRE_ASSETS"):
            pytest.fail(f"{mesh} is missing: install Debian's assimp-testmodels")
        pytest.skip(f"{mesh} is not installed (Debian's assimp-testmodels)")
    (tmp_path / mesh.name).symlink_to(mesh)
    block = readme_python_block()
    assert "WusonOBJ.obj" in block
    r = run_fresh(block, tmp_path)
    assert r.returncode == 0, r.stderr
    png = tmp_path / "precision.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
