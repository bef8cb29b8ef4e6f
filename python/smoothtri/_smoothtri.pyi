"""Type stubs of the native module ``smoothtri._smoothtri`` (Rust, pyo3). The public API is
``smoothtri`` (gathered in ``smoothtri/__init__.py`` from its modules: ``_scene.py`` wraps
``NativeScene``, ``_mesh.py`` ``load``, ``_camera.py`` ``camera_rays``, ``_precision.py``
``precision_sweep``), which documents every argument; these are its building blocks. Arrays
are numpy arrays; ``Any`` inputs are anything ``numpy.asarray`` takes."""

from __future__ import annotations

from os import PathLike
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

class BuildError(ValueError):
    """The scene could not be built: no triangles, or every triangle rejected."""

class LoadError(ValueError):
    """A mesh file is malformed or of an unknown format (names the file and the line or
    element)."""

class LoadBudgetError(LoadError):
    """Loading the file would take more memory than ``max_bytes`` (names the file and the
    field)."""

class OutsideFolderError(LoadError):
    """A glTF buffer URI resolves outside the file's folder (names the file and the URI)."""

DEFAULT_MAX_BYTES: int
"""The default ``max_bytes`` of :func:`load`: 2 GiB."""

SUPPORTED_ITERATIONS: List[int]
"""The iteration budgets ``N`` the queries accept: 0..=16, 20, 24, 32, 40."""
HIT_FIELDS: List[str]
"""The names of ``NativeScene.closest_hit``'s arrays, in order."""
SURFACE_FIELDS: List[str]
"""The names of ``NativeScene.evaluate``'s arrays, in order."""
MAX_THREADS: int
"""The most threads ``threads=`` accepts."""
ACCURACY: Dict[str, float]
"""The core's named accuracy bounds (``smoothtri::accuracy``), by name."""
SECONDARY_RAY_OFFSET: Dict[str, float]
"""Where the renders start secondary rays, a fraction of the bounding-box diagonal, by
precision."""

FloatArray = npt.NDArray[np.floating[Any]]

class NativeScene:
    """The core's scene of a mesh in one precision; thread-safe (an immutable snapshot per
    pose), moved by ``update``."""

    def __init__(
        self,
        vertices: Any,
        normals: Any,
        faces: Any,
        *,
        precision: str = "f32",
        seams: bool = True,
        field: str = "face",
        threads: Optional[int] = None,
    ) -> None: ...
    @property
    def precision(self) -> str: ...
    @property
    def seams(self) -> bool: ...
    @property
    def field(self) -> str: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def pose(self) -> int: ...
    @property
    def report(self) -> Dict[str, Any]: ...
    def update(self, vertices: Any, normals: Any, *, threads: Optional[int] = None) -> None: ...
    def ray_query(
        self,
        query: str,
        origins: Any,
        directions: Any,
        *,
        iterations: int = 4,
        t_min: Optional[Union[float, Any]] = None,
        t_max: Optional[Union[float, Any]] = None,
        threads: Optional[int] = None,
        out: Optional[Any] = None,
    ) -> Any:
        """``query="closest_hit"``: the closest hits, a tuple of arrays in the order of
        ``HIT_FIELDS`` (``out``: such a tuple to overwrite); ``query="any_hit"``: whether each
        ray hits anything, an ``(R,)`` bool array (``out``: such an array)."""
    def evaluate(
        self,
        triangles: Any,
        barycentrics: Any,
        *,
        threads: Optional[int] = None,
        out: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]] = None,
    ) -> Tuple[FloatArray, FloatArray, FloatArray]: ...

def load(
    path: Union[str, PathLike[str]],
    *,
    allow_outside_folder: bool = False,
    max_bytes: Optional[int] = None,
) -> Dict[str, Any]:
    """``vertices`` (V, 3) float64, ``normals`` (V, 3) float64, ``faces`` (F, 3) int64,
    ``computed_normals`` bool, ``warnings`` list of str."""

def camera_rays(
    vertices: Any,
    width: int,
    height: int,
    *,
    azimuth: float = 30.0,
    elevation: float = 35.0,
    up: str = "z",
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def precision_sweep(
    scene: NativeScene,
    origins: Any,
    directions: Any,
    *,
    iterations: List[int],
    precisions: List[str],
    reference_iterations: int = 40,
    threads: Optional[int] = None,
) -> Dict[str, Any]: ...
def rust_baseline(
    scene: NativeScene,
    origins: Any,
    directions: Any,
    *,
    iterations: int = 4,
    threads: Optional[int] = None,
) -> Tuple[float, int]:
    """``(seconds, hits)`` of the rays through the Rust API (the benchmark's baseline)."""
