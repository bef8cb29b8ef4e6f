"""``PrecisionStudy.plot(path)`` writes its file whole or not at all: a valid plot replaces an
old file (keeping its permissions) and nothing else is left in the folder; a failure while
drawing or renaming leaves the old file as it was and no temporary file; the extension names
the format."""

from __future__ import annotations

import os
import pathlib
import stat

import pytest

import smoothtri
from conftest import octahedron

OLD = b"old contents"


@pytest.fixture(scope="module")
def study() -> smoothtri.PrecisionStudy:
    pytest.importorskip("matplotlib")
    v, n, f = octahedron()
    scene = smoothtri.Scene(v, n, f)
    return smoothtri.precision_sweep(scene, smoothtri.camera_rays(v, 8, 6), iterations=[0, 2])


def old_file(path: pathlib.Path) -> None:
    path.write_bytes(OLD)
    path.chmod(0o640)


def names(folder: pathlib.Path) -> list:
    return sorted(p.name for p in folder.iterdir())


def test_a_plot_replaces_an_old_file_whole(tmp_path: pathlib.Path, study) -> None:
    import matplotlib.image
    import matplotlib.pyplot as plt

    png, svg = tmp_path / "p.png", tmp_path / "p.svg"
    old_file(png)
    study.plot(str(png))
    study.plot(svg)  # a path-like too
    plt.close("all")
    image = matplotlib.image.imread(png)
    assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100
    assert "<svg" in svg.read_text()
    assert stat.S_IMODE(png.stat().st_mode) == 0o640, "the old file's permissions"
    assert names(tmp_path) == ["p.png", "p.svg"], "no temporary file"


def test_a_failure_while_drawing_leaves_the_old_file(
    tmp_path: pathlib.Path, study, monkeypatch: pytest.MonkeyPatch
) -> None:
    import matplotlib.figure
    import matplotlib.pyplot as plt

    png = tmp_path / "p.png"
    old_file(png)

    def half_then_fail(self, fname, **kwargs):
        fname.write(b"\x89PNG half a plot")
        raise OSError("disk full")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", half_then_fail)
    with pytest.raises(OSError, match="disk full"):
        study.plot(str(png))
    plt.close("all")
    assert png.read_bytes() == OLD
    assert names(tmp_path) == ["p.png"], "no temporary file"


def test_a_failed_rename_leaves_the_target(tmp_path: pathlib.Path, study) -> None:
    import matplotlib.pyplot as plt

    folder = tmp_path / "p.png"
    folder.mkdir()
    (folder / "keep.txt").write_bytes(OLD)
    with pytest.raises(OSError):
        study.plot(str(folder))
    plt.close("all")
    assert names(tmp_path) == ["p.png"] and names(folder) == ["keep.txt"]
    assert (folder / "keep.txt").read_bytes() == OLD


def test_the_extension_names_the_format(tmp_path: pathlib.Path, study) -> None:
    import matplotlib.pyplot as plt

    for bad in ("p.unknown", "plot"):
        with pytest.raises(ValueError, match=r"chosen by its extension.*\.png.*\.svg"):
            study.plot(str(tmp_path / bad))
    plt.close("all")
    assert names(tmp_path) == []


def test_a_link_keeps_naming_the_plot(tmp_path: pathlib.Path, study) -> None:
    import matplotlib.pyplot as plt

    (tmp_path / "real").mkdir()
    old_file(tmp_path / "real" / "p.svg")
    os.symlink("real/p.svg", tmp_path / "p.svg")
    study.plot(str(tmp_path / "p.svg"))
    plt.close("all")
    assert (tmp_path / "p.svg").is_symlink()
    assert "<svg" in (tmp_path / "real" / "p.svg").read_text()
    assert names(tmp_path / "real") == ["p.svg"] and names(tmp_path) == ["p.svg", "real"]
