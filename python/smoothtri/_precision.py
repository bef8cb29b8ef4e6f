"""The precision study of ``smoothtri precision`` on the caller's scene and rays: precision
against the iteration budget, as a table, CSV or plot."""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _plot, _smoothtri
from ._args import ArrayLike, iterations_arg, threads_arg
from ._scene import Scene


def _rust_exp(x: float, digits: int = 2) -> str:
    """``x`` as Rust's ``{:.2e}`` writes it: ``1.23e-5``, not Python's ``1.23e-05``."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _rust_display(v: Any) -> str:
    """``v`` as Rust's ``{}`` writes it: floats shortest round trip without an exponent."""
    if isinstance(v, float):
        return np.format_float_positional(v, unique=True, trim="-")
    return str(v)


_STUDY_COLUMNS = (
    "precision",
    "iterations",
    "hits",
    "max_error",
    "p999_error",
    "mean_error",
    "mean_t_error",
    "bound_holds",
    "disagreements",
    "ns_per_ray",
)


@dataclasses.dataclass(frozen=True)
class PrecisionStudy:
    """Precision against the iteration budget, the table ``smoothtri precision`` prints.

    One row per (budget, precision), budgets in the order given, precisions in the order
    given within each. Errors are hit-point distances to the reference hits (``f64`` at
    ``reference_iterations``) divided by the mesh's bounding-box diagonal.

    Attributes:
        precision: ``"f32"`` or ``"f64"`` per row.
        iterations: ``(rows,)`` int64, the budget ``N``.
        hits: ``(rows,)`` int64, rays that hit in both this run and the reference.
        max_error, p999_error, mean_error: ``(rows,)`` float64, the largest, the 99.9th
            percentile (rank ``ceil(0.999 n)``) and the mean hit-point error.
        mean_t_error: ``(rows,)`` float64, the mean returned ``t_error`` over the diagonal (in
            units of the diagonal for unit directions).
        bound_holds: ``(rows,)`` float64, the fraction of hits whose ``|t - t_ref|`` is within
            their ``t_error``.
        disagreements: ``(rows,)`` int64, rays that hit in one run and miss in the other.
        ns_per_ray: ``(rows,)`` float64, the batch's wall time per ray on ``threads`` threads
            (with ``threads=1``, the demo's one-thread figure).
        rays: rays traced per run.
        diagonal: the bounding-box diagonal the errors are divided by.
        reference_iterations: the reference's budget.
        threads: threads the runs used.
    """

    precision: Tuple[str, ...]
    iterations: np.ndarray
    hits: np.ndarray
    max_error: np.ndarray
    p999_error: np.ndarray
    mean_error: np.ndarray
    mean_t_error: np.ndarray
    bound_holds: np.ndarray
    disagreements: np.ndarray
    ns_per_ray: np.ndarray
    rays: int
    diagonal: float
    reference_iterations: int
    threads: int

    def __len__(self) -> int:
        return len(self.precision)

    def rows(self) -> list:
        """The rows as dicts of the column names."""
        return [
            {c: (getattr(self, c)[i] if c == "precision" else getattr(self, c)[i].item()) for c in _STUDY_COLUMNS}
            for i in range(len(self))
        ]

    def table(self) -> str:
        """The fixed-width table, as ``smoothtri precision`` prints it (numbers formatted as
        Rust formats them)."""
        e = _rust_exp
        lines = [
            f"{'prec':>4} {'N':>3} {'hits':>6} {'max err':>10} {'p99.9 err':>10} "
            f"{'mean err':>10} {'mean t_err':>12} {'bound ok':>8} {'hit/miss':>9} {'ns/ray':>9}"
        ]
        for r in self.rows():
            lines.append(
                f"{r['precision']:>4} {r['iterations']:>3} {r['hits']:>6} {e(r['max_error']):>10} "
                f"{e(r['p999_error']):>10} {e(r['mean_error']):>10} {e(r['mean_t_error']):>12} "
                f"{r['bound_holds'] * 100:>7.2f}% {r['disagreements']:>9} {r['ns_per_ray']:>9.0f}"
            )
        lines.append(
            f"errors: hit-point distance to the f64 N={self.reference_iterations} reference / "
            "bounding-box diagonal"
        )
        return "\n".join(lines) + "\n"

    def __str__(self) -> str:
        return self.table()

    def csv(self) -> str:
        """The table as CSV, as ``smoothtri precision --csv`` writes it (numbers as Rust
        writes them: shortest round trip, no exponent)."""
        header = (
            "precision,iterations,hits,max_error,p999_error,mean_error,mean_t_error,"
            "bound_holds,hit_miss_disagreements,ns_per_ray"
        )
        body = [",".join(_rust_display(v) for v in r.values()) for r in self.rows()]
        return "\n".join([header, *body]) + "\n"

    def plot(self, path: Optional[str] = None, *, ax: Any = None, title: Optional[str] = None) -> Any:
        """Draws the largest and the 99.9th-percentile error against the budget, log scale,
        one line per precision, with matplotlib (imported here; ``pip install matplotlib``).

        Args:
            path: where to save the figure, or ``None``. Its extension names the format (one
                matplotlib writes: ``.png``, ``.svg``, ``.pdf``, ...; another is a
                ``ValueError`` listing them). The file is written whole or not at all: into a
                temporary file in the same folder, then renamed over ``path``, so a failure
                (an ``OSError``) leaves an old file as it was and no temporary file behind.
            ax: the axes to draw into (default: a new figure).
            title: the title (default: the number of rays).

        Returns:
            The matplotlib axes.
        """
        return _plot.draw_study(self, path, ax, title)


def precision_sweep(
    scene: Scene,
    rays: Tuple[ArrayLike, ArrayLike],
    iterations: Iterable[int] = range(0, 17),
    precision: Union[str, Sequence[str]] = ("f32", "f64"),
    *,
    reference_iterations: int = 40,
    threads: Optional[int] = None,
) -> PrecisionStudy:
    """Precision against work on your mesh and rays: ``smoothtri precision``'s study.

    Traces ``rays`` through the scene's mesh in each precision at each budget, and compares
    every hit with an ``f64`` reference at ``reference_iterations`` (the same line field;
    seams change no hit point). ``t`` is taken in ``[0, largest finite float]``.

    Args:
        scene: the scene whose mesh is studied (it is rebuilt in the precisions it is not in).
        rays: ``(origins, directions)``, each ``(R, 3)`` (e.g. :func:`camera_rays`).
        iterations: the budgets, each one of :data:`SUPPORTED_ITERATIONS`.
        precision: ``"f32"``, ``"f64"`` or both.
        reference_iterations: the reference's budget.
        threads: threads (``None``: every core); only ``ns_per_ray`` depends on it.

    Returns:
        :class:`PrecisionStudy`; ``study.table()`` prints it, ``study.plot(path)`` draws it.
    """
    if isinstance(precision, str):
        precision = (precision,)
    origins, directions = rays
    d = _smoothtri.precision_sweep(
        scene._native,
        origins,
        directions,
        iterations=[iterations_arg(n) for n in iterations],
        precisions=list(precision),
        reference_iterations=iterations_arg(reference_iterations, "reference_iterations"),
        threads=threads_arg(threads),
    )
    d["precision"] = tuple(d["precision"])
    return PrecisionStudy(**d)

