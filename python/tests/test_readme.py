"""The READMEs' Python, run as a new user would: every ```python block of the repository's
README and of ``python/README.md`` as written (in a fresh interpreter, in a folder holding the
meshes it loads), and every name their prose uses reachable after ``import smoothtri`` alone."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
READMES = [ROOT / "README.md", ROOT / "python" / "README.md"]
# Where the meshes the READMEs load come from: Debian's assimp-testmodels.
ASSIMP = pathlib.Path("/usr/share/assimp/models")


def python_blocks() -> list:
    """Every ```python block of the READMEs, as a pytest parameter named by file and line."""
    blocks = []
    for readme in READMES:
        if not readme.exists():
            continue
        text = readme.read_text(encoding="utf-8")
        for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M):
            line = text.count("\n", 0, m.start()) + 1
            blocks.append(pytest.param(m.group(1), id=f"{readme.relative_to(ROOT)}:{line}"))
    return blocks


def cited_names() -> list:
    """The package's names the READMEs cite in backticks: ``smoothtri.…`` as written, and
    ``scene.…`` as an attribute of ``smoothtri.Scene``."""
    names = set()
    for readme in READMES:
        if readme.exists():
            text = readme.read_text(encoding="utf-8")
            names.update(re.findall(r"`(smoothtri(?:\.[A-Za-z_]\w*)+)", text))
            names.update(f"smoothtri.Scene.{a}" for a in re.findall(r"`scene\.([A-Za-z_]\w*)", text))
    return sorted(names)


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


def test_the_readme_has_a_python_block_in_from_python():
    section = (ROOT / "README.md").read_text(encoding="utf-8").split("## From Python", 1)[1]
    assert "```python\n" in section.split("\n## ", 1)[0]


def test_the_readme_names_are_reachable_after_import_smoothtri(tmp_path):
    names = cited_names()
    assert "smoothtri.trimesh.Intersector" in names, names
    # And those the README's block names in its comments.
    names += ["smoothtri.from_trimesh", "smoothtri.Scene.from_mesh"]
    code = "import smoothtri\n" + "".join(f"{n}\n" for n in names)
    r = run_fresh(code, tmp_path)
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("block", python_blocks())
def test_the_readme_block_runs_as_written(tmp_path, block):
    # The meshes it loads, linked into the folder it runs in under the names it gives.
    for name in re.findall(r"""\bload\(\s*["']([^"']+)["']""", block):
        if not ASSIMP.is_dir():
            why = f"the block loads {name}, from Debian's assimp-testmodels, which is not installed"
            if os.environ.get("SMOOTHTRI_REQUIRE_ASSETS"):
                pytest.fail(why)
            pytest.skip(why)
        found = sorted(ASSIMP.rglob(name))
        assert found, f"the block loads {name}, which {ASSIMP} does not hold: name a mesh a reader can get"
        (tmp_path / name).symlink_to(found[0])
    r = run_fresh(block, tmp_path)
    assert r.returncode == 0, r.stderr
    # The plots it saves are pictures.
    for png in re.findall(r"""["']([^"']+\.png)["']""", block):
        assert (tmp_path / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
