"""The argument types and checks that the API's functions share: array-likes, ``threads=`` and
iteration budgets (the native module checks ranges; these check types, with Python's words)."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

ArrayLike = Any
"""Anything ``numpy.asarray`` takes: arrays, lists, tuples."""


def threads_arg(threads: Optional[int]) -> Optional[int]:
    """``threads=`` as the native module takes it: ``None`` or an ``int`` (a ``TypeError``
    otherwise; the native module checks the range)."""
    if threads is None:
        return None
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)):
        raise TypeError(f"threads must be None or an integer, got {threads!r}")
    return int(threads)


def iterations_arg(iterations: int, name: str = "iterations") -> int:
    """An iteration budget (the argument ``name``) as an ``int`` (a ``TypeError`` otherwise; the
    native module checks that it is supported)."""
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {iterations!r}")
    return int(iterations)
