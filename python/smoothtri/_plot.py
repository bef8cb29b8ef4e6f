"""Plots: the precision study drawn with matplotlib (imported only when a plot is drawn), and
the figure saved whole or not at all."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

if TYPE_CHECKING:
    from ._precision import PrecisionStudy


def draw_study(study: PrecisionStudy, path: Optional[str], ax: Any, title: Optional[str]) -> Any:
    """:meth:`PrecisionStudy.plot <smoothtri.PrecisionStudy.plot>`: the study's largest and
    99.9th-percentile errors against the budget into ``ax`` (default: a new figure), saved to
    ``path`` when given; returns the axes."""
    import matplotlib

    if ax is None and path is not None and os.environ.get("MPLBACKEND") is None:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7.2, 4.8))
    floor = 1e-17
    colors = {"f32": ("#dc501e", "#f0a078"), "f64": ("#1e5ac8", "#78a0e6")}
    precision = np.asarray(study.precision)
    for p in dict.fromkeys(study.precision):
        rows = precision == p
        n = study.iterations[rows]
        strong, light = colors.get(p, ("k", "grey"))
        ax.plot(n, np.maximum(study.max_error[rows], floor), "o-", color=strong, lw=2, label=f"{p} max")
        ax.plot(
            n,
            np.maximum(study.p999_error[rows], floor),
            "o-",
            color=light,
            lw=1,
            ms=3,
            label=f"{p} 99.9th pct",
        )
    ax.set_yscale("log")
    ax.set_xlabel("iteration budget N")
    ax.set_ylabel(f"hit-point error / bounding-box diagonal (0 drawn at {floor:.0e})")
    ax.set_title(title or f"smoothtri: error vs iterations ({study.rays} rays)")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend()
    if path is not None:
        save_figure(ax.figure, path, dpi=100, bbox_inches="tight")
    return ax


def _umask() -> int:
    """The process's umask, read without changing it where Linux tells it (``os.umask`` sets
    it, which another thread could see)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def save_figure(figure: Any, path: Any, **savefig: Any) -> None:
    """Saves a matplotlib ``figure`` to ``path`` whole or not at all.

    The format is the extension's (``ValueError`` naming the extensions matplotlib writes
    otherwise). The figure is drawn into a temporary file in the target's folder (a symbolic
    link's target, so the link keeps naming the plot), flushed and synced, given the old file's
    permissions (a new file's: read and write for all, less the umask), then renamed over the
    target with ``os.replace``. On any failure the temporary file is removed, the old file is
    left as it was, and the error is raised.
    """
    import stat
    import tempfile

    name = os.fspath(path)
    ext = os.path.splitext(name)[1][1:].lower()
    supported = figure.canvas.get_supported_filetypes()
    if ext not in supported:
        expected = ", ".join("." + e for e in sorted(supported))
        raise ValueError(f"{name}: the plot's format is chosen by its extension, one of {expected}")
    target = os.path.realpath(name)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    tmp = tempfile.NamedTemporaryFile(
        dir=os.path.dirname(target), prefix=f".{os.path.basename(target)}.", suffix=".tmp", delete=False
    )
    try:
        with tmp:
            figure.savefig(tmp, format=ext, **savefig)
            tmp.flush()
            os.fsync(tmp.fileno())
        os.chmod(tmp.name, mode)
        os.replace(tmp.name, target)
    except BaseException:
        try:
            os.unlink(tmp.name)
        except FileNotFoundError:
            pass
        raise
