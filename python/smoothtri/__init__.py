"""Ray tracing of smooth surfaces straight from triangle meshes with vertex normals.

Each triangle and its three vertex normals define a curved patch that interpolates the
vertices and their normals and reproduces spheres exactly (the repository's
``docs/METHOD.md``). This package builds the patches from numpy arrays and traces batches of
rays on every core, the GIL released; every hit comes with a certified bound on its error,
``t_error``.

    >>> import smoothtri
    >>> mesh = smoothtri.load("bunny.obj")                      # doctest: +SKIP
    >>> scene = smoothtri.Scene.from_mesh(mesh)                 # doctest: +SKIP
    >>> origins, directions = smoothtri.camera_rays(mesh.vertices, 1000, 1000)  # doctest: +SKIP
    >>> hits = scene.closest_hit(origins, directions)             # doctest: +SKIP
    >>> smoothtri.precision_sweep(scene, (origins, directions)).plot("precision.png")  # doctest: +SKIP

Conventions, for every function:

- Arrays of points and vectors have shape ``(N, 3)``; inputs may have any real dtype (float16,
  float32, float64, integers) and any strides (views, slices, ``np.broadcast_to``); float32 and
  float64 are read where they lie, other dtypes are converted once.
- Lengths are in the mesh's units; ``t`` is in units of each ray's direction (directions need
  not be unit length).
- Outputs are in the scene's precision: float32 for ``precision="f32"``, float64 for
  ``"f64"``; they are the core's results bit for bit.
- Bad input raises ``ValueError`` or ``TypeError`` naming the argument (and the row);
  ``BuildError`` (a ``ValueError``) when no triangle can be built; nothing crashes.
- Queries release the GIL and run on ``threads`` threads (``None``: every core); results do not
  depend on the thread count. Do not modify the input arrays from another thread during a
  call.
- A :class:`Scene` may be shared by any number of Python threads: queries, ``report`` and
  :func:`precision_sweep` read an immutable snapshot of the current pose, and
  :meth:`Scene.update` replaces that snapshot when it is done; no call waits for another
  while it holds the GIL, so nothing deadlocks (see :meth:`Scene.update`).
"""

from __future__ import annotations

# One idea per module, every public name gathered here: _mesh (mesh files and trimesh meshes),
# _scene (the scene, its update and queries), _results (what it answers), _camera (camera
# rays), _precision (the precision study), _plot (its plot), _args (the argument checks the
# modules share), _smoothtri (the native module).
from . import _smoothtri  # noqa: F401

# The trimesh drop-in, imported here so that ``import smoothtri`` alone makes
# ``smoothtri.trimesh.Intersector`` reachable, as the README uses it (it needs only numpy;
# trimesh itself is imported by the caller, if at all). Not in ``__all__``: a star import
# would shadow the caller's ``trimesh`` package.
from . import trimesh  # noqa: F401
from ._args import ArrayLike  # noqa: F401
from ._camera import camera_rays
from ._mesh import Mesh, from_trimesh, load
from ._precision import PrecisionStudy, precision_sweep
from ._results import BuildReport, Hits, SurfacePoints
from ._scene import Scene
from ._smoothtri import ACCURACY, SUPPORTED_ITERATIONS, BuildError, LoadError
from ._smoothtri import DEFAULT_MAX_BYTES, LoadBudgetError, OutsideFolderError

__all__ = [
    "ACCURACY",
    "SUPPORTED_ITERATIONS",
    "BuildError",
    "BuildReport",
    "DEFAULT_MAX_BYTES",
    "Hits",
    "LoadBudgetError",
    "LoadError",
    "Mesh",
    "OutsideFolderError",
    "PrecisionStudy",
    "Scene",
    "SurfacePoints",
    "camera_rays",
    "from_trimesh",
    "load",
    "precision_sweep",
]

__version__ = "0.1.0"
