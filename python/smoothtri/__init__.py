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
    >>> hits = scene.intersect(origins, directions)             # doctest: +SKIP
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

import dataclasses
import math
import os
from typing import Any, Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _smoothtri
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

ArrayLike = Any
"""Anything ``numpy.asarray`` takes: arrays, lists, tuples."""


@dataclasses.dataclass(frozen=True)
class Mesh:
    """An indexed triangle mesh with one normal per vertex.

    Attributes:
        vertices: ``(V, 3)`` float64 positions.
        normals: ``(V, 3)`` float64 vertex normals (any positive length).
        faces: ``(F, 3)`` int64 vertex indices, counter-clockwise seen from the side the
            normals point to.
        computed_normals: whether some normals were computed (angle-weighted) because the
            file had none for them.
        warnings: what the loader noted (skipped primitives and the like), one line each.
    """

    vertices: np.ndarray
    normals: np.ndarray
    faces: np.ndarray
    computed_normals: bool = False
    warnings: Tuple[str, ...] = ()


def load(
    path: Union[str, "os.PathLike[str]"],
    *,
    allow_outside_folder: bool = False,
    max_bytes: Optional[int] = None,
) -> Mesh:
    """Reads a mesh file: OBJ, PLY (ASCII or binary), glTF or GLB, chosen by extension.

    Polygons are fan-triangulated, vertices deduplicated per (position, normal) pair, all
    objects or primitives joined (glTF: the default scene's nodes with their transforms).
    Where the file has no normals, angle-weighted vertex normals are computed
    (``Mesh.computed_normals``).

    Loading is bounded and confined: every count in the file is checked against the bytes it
    holds, and the file, its buffers and what they decode to may take at most ``max_bytes``
    (``None``: ``DEFAULT_MAX_BYTES``, 2 GiB). A glTF buffer URI must name a regular file
    inside the file's own folder; ``allow_outside_folder=True`` lifts the folder rule for
    trusted files. Images are never read.

    Raises:
        FileNotFoundError, OSError: the file cannot be read.
        LoadBudgetError: loading would take more than ``max_bytes`` (a ``LoadError``).
        OutsideFolderError: a glTF buffer lies outside the file's folder (a ``LoadError``).
        LoadError: the file is malformed, of another format, or holds no triangle (the
            message names the file and the line or element).
    """
    d = _smoothtri.load(
        os.fspath(path), allow_outside_folder=allow_outside_folder, max_bytes=max_bytes
    )
    return Mesh(
        vertices=d["vertices"],
        normals=d["normals"],
        faces=d["faces"],
        computed_normals=d["computed_normals"],
        warnings=tuple(d["warnings"]),
    )


def from_trimesh(mesh: Any) -> Mesh:
    """The vertices, vertex normals and faces of a ``trimesh.Trimesh`` as a :class:`Mesh`.

    The normals are ``mesh.vertex_normals``: the file's when trimesh kept them, else the ones
    trimesh computes. No copy is made where trimesh's arrays can be read as they are.
    """
    return Mesh(
        vertices=np.asarray(mesh.vertices, dtype=np.float64),
        normals=np.asarray(mesh.vertex_normals, dtype=np.float64),
        faces=np.asarray(mesh.faces, dtype=np.int64),
    )


@dataclasses.dataclass(frozen=True)
class BuildReport:
    """What building a :class:`Scene` did.

    Attributes:
        triangles: triangles given.
        patches: patches built (triangles accepted).
        rejected: triangles rejected, by reason (their sum is ``triangles - patches``).
        first_rejected: the first rejected triangle and why, or ``None``.
        remedied: patches whose normals the per-patch remedy clamped (steep normals).
        first_remedied: the first remedied triangle, or ``None``.
        vertex_clamps: with ``field="vertex"``: ``(vertices whose normal the per-vertex
            remedy changed, triangles it left to the per-patch remedy)``; else ``None``.
        shared_edges: edges shared by exactly two patches.
        open_edges: of those, edges whose two edge curves part (cracks the kernel closes).
        widest_gap: the widest such gap, in the mesh's length unit.
        seam_edges: shared edges whose seamless normals were fitted (``None`` without seams).
        bvh_nodes: BVH nodes.
        bvh_refitted: whether the last :meth:`Scene.update` refitted the BVH's boxes (``False``
            after a build, or where the update built the tree anew).
        memory_bytes: bytes the scene holds (patches, BVH, seams; not the input arrays).
    """

    triangles: int
    patches: int
    rejected: dict
    first_rejected: Optional[Tuple[int, str]]
    remedied: int
    first_remedied: Optional[int]
    vertex_clamps: Optional[Tuple[int, int]]
    shared_edges: int
    open_edges: int
    widest_gap: float
    seam_edges: Optional[int]
    bvh_nodes: int
    bvh_refitted: bool
    memory_bytes: int


@dataclasses.dataclass
class Hits:
    """The closest hit of each ray; arrays of length ``R`` (the rays), in the scene's precision.

    Attributes:
        hit: ``(R,)`` bool, whether the ray hit.
        t: ``(R,)`` the hit's ray parameter, in units of the ray's direction (``inf`` on a
            miss).
        t_error: ``(R,)`` a certified bound on ``|t - t_true|`` (same units; 0 on a miss).
        point: ``(R, 3)`` the hit point ``origin + t * direction`` (0 on a miss).
        normal: ``(R, 3)`` the patch's exact unit normal, oriented like the vertex normals
            (not flipped toward the ray; ``front face = dot(normal, direction) < 0``).
        shading_normal: ``(R, 3)`` the seamless shading normal (continuous across shared
            edges) when the scene has seams, else ``normal``.
        triangle: ``(R,)`` int64 index of the input triangle hit, ``-1`` on a miss.
        barycentric: ``(R, 2)`` ``(w1, w2)`` of the hit on its triangle, the weights of its
            second and third vertex (``w0 = 1 - w1 - w2``).
    """

    hit: np.ndarray
    t: np.ndarray
    t_error: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    shading_normal: np.ndarray
    triangle: np.ndarray
    barycentric: np.ndarray

    def __len__(self) -> int:
        return len(self.hit)


@dataclasses.dataclass
class SurfacePoints:
    """Points on the smooth surface; arrays ``(M, 3)`` in the scene's precision.

    Attributes:
        point: the surface point.
        normal: the patch's exact unit normal there, oriented like the vertex normals.
        shading_normal: the seamless shading normal when the scene has seams, else
            ``normal``.
    """

    point: np.ndarray
    normal: np.ndarray
    shading_normal: np.ndarray

    def __len__(self) -> int:
        return len(self.point)


def _threads(threads: Optional[int]) -> Optional[int]:
    if threads is None:
        return None
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)):
        raise TypeError(f"threads must be None or an integer, got {threads!r}")
    return int(threads)


def _iterations(iterations: int, name: str = "iterations") -> int:
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {iterations!r}")
    return int(iterations)


class Scene:
    """The smooth surface of a triangle mesh with vertex normals, ready for ray queries.

    Args:
        vertices: ``(V, 3)`` vertex positions, any real dtype.
        normals: ``(V, 3)`` vertex normals (any positive length), any real dtype.
        faces: ``(F, 3)`` vertex indices (any integer dtype), counter-clockwise seen from the
            side the normals point to.
        precision: ``"f32"`` (the real-time path) or ``"f64"``: the precision of the patches,
            the queries and their results. Input is rounded to it once.
        seams: fit the seamless shading normals (``Hits.shading_normal`` then is continuous
            across shared edges; costs 16 normal evaluations per shared edge at build time).
        field: ``"face"`` (the paper's construction) or ``"vertex"`` (neighbours share their
            edges' lines, so their edge curves meet).
        threads: threads for the build (``None``: every core); the scene is the same bit for
            bit on any number.

    Triangles the construction cannot use (degenerate, non-finite, overflowing) are skipped
    and counted in :attr:`report`; steep normals are clamped (``report.remedied``).

    Accuracy (named bounds of ``smoothtri.ACCURACY``, asserted by the repository's tests):
    surface points of a sphere's patches lie on it to ``F64_SPHERE_POINT`` (``f64``) and
    ``F32_SPHERE_POINT`` (``f32``) of the radius; hits at ``iterations=8`` to
    ``F64_SPHERE_HIT`` and ``F32_SPHERE_HIT``; ``f32`` points within ``F32_VS_F64_POINT`` of
    the coordinates' scale of ``f64``; every hit's ``t`` is within its ``t_error`` of the
    crossing its final bracket holds.

    Raises:
        ValueError: wrong shapes, non-finite values, indices out of range, bad options.
        TypeError: arrays that do not hold real numbers (faces: integers).
        BuildError: no triangles, or every triangle rejected.
    """

    def __init__(
        self,
        vertices: ArrayLike,
        normals: ArrayLike,
        faces: ArrayLike,
        *,
        precision: str = "f32",
        seams: bool = True,
        field: str = "face",
        threads: Optional[int] = None,
    ) -> None:
        self._native = _smoothtri.NativeScene(
            vertices,
            normals,
            faces,
            precision=precision,
            seams=bool(seams),
            field=field,
            threads=_threads(threads),
        )
        # The report of one pose, and the pose's number (NativeScene.pose): valid while the
        # scene is at that pose.
        self._report: Optional[Tuple[int, BuildReport]] = None

    @classmethod
    def from_mesh(cls, mesh: Mesh, **options: Any) -> "Scene":
        """The scene of a :class:`Mesh` (from :func:`load` or :func:`from_trimesh`);
        ``options`` as for :class:`Scene`."""
        return cls(mesh.vertices, mesh.normals, mesh.faces, **options)

    @property
    def precision(self) -> str:
        """``"f32"`` or ``"f64"``."""
        return self._native.precision

    @property
    def dtype(self) -> np.dtype:
        """The dtype of the results: float32 or float64."""
        return np.dtype(np.float32 if self.precision == "f32" else np.float64)

    @property
    def seams(self) -> bool:
        """Whether the seamless shading normals were fitted."""
        return self._native.seams

    @property
    def field(self) -> str:
        """``"face"`` or ``"vertex"``."""
        return self._native.field

    @property
    def report(self) -> BuildReport:
        """What the build (or the last :meth:`update`) did: patches, rejected triangles by
        reason, remedied triangles, cracks, memory. The current pose's, also while other
        threads update the scene (the cached report is tagged with its pose)."""
        cached = self._report
        if cached is None or cached[0] != self._native.pose:
            d = dict(self._native.report)
            cached = (d.pop("pose"), BuildReport(**d))
            self._report = cached
        return cached[1]

    def update(self, vertices: ArrayLike, normals: ArrayLike, *, threads: Optional[int] = None) -> None:
        """Moves the scene to new vertex positions and normals in place (an animated mesh's
        next pose): the same faces, the same number of vertices.

        The patches, crack closure and seams afterwards equal those of a fresh
        ``Scene(vertices, normals, faces, ...)`` bit for bit; the BVH's boxes are refitted (or
        the tree rebuilt when a refit has grown too costly), so hits agree with a fresh
        scene's within their ``t_error``. A triangle that degenerates is skipped until it is a
        triangle again (counted in :attr:`report`).

        Threads: queries running on other threads are not waited for, nor do they wait for the
        update: each query answers the pose current when it started, whole (never a mix of
        two poses), and queries started after ``update`` returned answer the new pose. Updates
        from several threads run one at a time; the last to run wins. While an update runs,
        the scene is held twice in memory (the pose being read and the one being made).

        Args:
            vertices: ``(V, 3)`` positions, any real dtype; ``V`` as at the build.
            normals: ``(V, 3)`` normals, any real dtype.
            threads: threads for the update (``None``: every core); the same scene on any
                number.

        Raises:
            ValueError: wrong shapes, another vertex count, non-finite values. The scene is
                then unchanged.
            TypeError: arrays that do not hold real numbers.
        """
        self._native.update(vertices, normals, threads=_threads(threads))
        self._report = None

    def __repr__(self) -> str:
        r = self.report
        return (
            f"Scene({r.patches} patches of {r.triangles} triangles, precision={self.precision!r}, "
            f"seams={self.seams}, field={self.field!r}, {r.memory_bytes / 1024:.1f} KiB)"
        )

    def intersect(
        self,
        origins: ArrayLike,
        directions: ArrayLike,
        *,
        iterations: int = 4,
        t_min: Union[float, ArrayLike] = 0.0,
        t_max: Union[float, ArrayLike] = math.inf,
        threads: Optional[int] = None,
        out: Optional[Hits] = None,
    ) -> Hits:
        """The closest hit of each ray with ``t`` in ``[t_min, t_max]``.

        Args:
            origins: ``(R, 3)`` ray origins.
            directions: ``(R, 3)`` ray directions, non-zero (any length: ``t`` is in units of
                it). ``np.broadcast_to`` shares one origin or direction among all rays without
                a copy.
            iterations: ``N``, the kernel's refinement steps (eight height evaluations each;
                0 brackets only), one of :data:`SUPPORTED_ITERATIONS`. Work per ray is bounded
                by it; ``f64`` hits on curved meshes reach rounding from about 4, spheres from
                8 (``smoothtri.precision_sweep`` measures it on your mesh).
            t_min, t_max: the interval of ``t``: floats, or ``(R,)`` arrays (one per ray; a
                ray whose ``t_min > t_max`` misses).
            threads: threads (``None``: every core); the results do not depend on it.
            out: a :class:`Hits` from an earlier call with as many rays, in the scene's
                precision, whose arrays are overwritten (writeable and C-contiguous) instead
                of allocating new ones.

        Returns:
            :class:`Hits`, the core's ``Scene::closest_hit`` bit for bit.

        Raises:
            ValueError: shapes, a non-finite origin or direction (after rounding to the
                scene's precision), a zero direction, NaN bounds, ``iterations`` not supported,
                a bad ``out`` array.
            TypeError: arrays that do not hold real numbers.
        """
        arrays = self._native.intersect(
            origins,
            directions,
            iterations=_iterations(iterations),
            t_min=t_min,
            t_max=t_max,
            threads=_threads(threads),
            out=None if out is None else tuple(getattr(out, f) for f in _smoothtri.HIT_FIELDS),
        )
        if out is not None:
            return out
        return Hits(*arrays)

    def occluded(
        self,
        origins: ArrayLike,
        directions: ArrayLike,
        *,
        iterations: int = 4,
        t_min: Union[float, ArrayLike] = 0.0,
        t_max: Union[float, ArrayLike] = math.inf,
        threads: Optional[int] = None,
        out: Optional[np.ndarray] = None,
    ) -> np.ndarray:
        """Whether each ray hits anything with ``t`` in ``[t_min, t_max]`` (shadow rays):
        stops at the first crossing found and evaluates no normal.

        Arguments as for :meth:`intersect`; ``out`` is an ``(R,)`` bool array to overwrite.

        Returns:
            ``(R,)`` bool, the core's ``Scene::any_hit``.
        """
        return self._native.occluded(
            origins,
            directions,
            iterations=_iterations(iterations),
            t_min=t_min,
            t_max=t_max,
            threads=_threads(threads),
            out=out,
        )

    def evaluate(
        self,
        triangles: ArrayLike,
        barycentrics: ArrayLike,
        *,
        threads: Optional[int] = None,
        out: Optional[SurfacePoints] = None,
    ) -> SurfacePoints:
        """Points of the smooth surface and their normals.

        Args:
            triangles: ``(M,)`` input triangle indices (any integer dtype).
            barycentrics: ``(M, 2)`` ``(w1, w2)`` on each triangle, as in
                :attr:`Hits.barycentric` (``w0 = 1 - w1 - w2``); outside the triangle,
                negative weights are taken as 0 and the others rescaled to sum 1.
            threads: threads (``None``: every core).
            out: a :class:`SurfacePoints` whose arrays are overwritten.

        Returns:
            :class:`SurfacePoints`: the core's ``Patch::point_normal`` (and, with seams,
            ``Seam::correct``) bit for bit. ``scene.evaluate(hits.triangle[hits.hit],
            hits.barycentric[hits.hit])`` gives the hit points' surface points again, to
            rounding.

        Raises:
            ValueError: shapes, indices out of range, a triangle the build rejected, non-finite
                barycentrics.
        """
        arrays = self._native.evaluate(
            triangles,
            barycentrics,
            threads=_threads(threads),
            out=None
            if out is None
            else tuple(getattr(out, f) for f in _smoothtri.SURFACE_FIELDS),
        )
        if out is not None:
            return out
        return SurfacePoints(*arrays)


def camera_rays(
    vertices: ArrayLike,
    width: int,
    height: int,
    *,
    azimuth: float = 30.0,
    elevation: float = 35.0,
    up: str = "z",
) -> Tuple[np.ndarray, np.ndarray]:
    """The rays of the demo's pinhole camera (35° vertical field of view) framed on the
    vertices: through the centre of each pixel of a ``width × height`` image, row by row from
    the top.

    Args:
        vertices: ``(V, 3)`` positions to frame (the bounding box's centre, from far enough
            that the sphere through the farthest vertex, 10 % larger, fits the image).
        width, height: pixels, 1 to 16384.
        azimuth, elevation: where the camera stands, in degrees: azimuth about the up axis,
            elevation above the plane perpendicular to it (the demo's ``--view``).
        up: the mesh's up axis, ``"z"``, ``"y"`` (glTF; Blender's OBJ and PLY exports) or
            ``"x"`` (the demo's ``--up``).

    Returns:
        ``(origins, directions)``, two ``(width * height, 3)`` float64 arrays; directions are
        unit vectors. With ``up="z"`` they are the rays ``smoothtri precision`` and
        ``smoothtri render`` trace.
    """
    return _smoothtri.camera_rays(
        vertices, int(width), int(height), azimuth=float(azimuth), elevation=float(elevation), up=up
    )


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
        import matplotlib

        if ax is None and path is not None and os.environ.get("MPLBACKEND") is None:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7.2, 4.8))
        floor = 1e-17
        colors = {"f32": ("#dc501e", "#f0a078"), "f64": ("#1e5ac8", "#78a0e6")}
        precision = np.asarray(self.precision)
        for p in dict.fromkeys(self.precision):
            rows = precision == p
            n = self.iterations[rows]
            strong, light = colors.get(p, ("k", "grey"))
            ax.plot(n, np.maximum(self.max_error[rows], floor), "o-", color=strong, lw=2, label=f"{p} max")
            ax.plot(
                n,
                np.maximum(self.p999_error[rows], floor),
                "o-",
                color=light,
                lw=1,
                ms=3,
                label=f"{p} 99.9th pct",
            )
        ax.set_yscale("log")
        ax.set_xlabel("iteration budget N")
        ax.set_ylabel(f"hit-point error / bounding-box diagonal (0 drawn at {floor:.0e})")
        ax.set_title(title or f"smoothtri: error vs iterations ({self.rays} rays)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend()
        if path is not None:
            _save_figure(ax.figure, path, dpi=100, bbox_inches="tight")
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


def _save_figure(figure: Any, path: Any, **savefig: Any) -> None:
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
        iterations=[_iterations(n) for n in iterations],
        precisions=list(precision),
        reference_iterations=_iterations(reference_iterations, "reference_iterations"),
        threads=_threads(threads),
    )
    d["precision"] = tuple(d["precision"])
    return PrecisionStudy(**d)


# The trimesh drop-in, imported here so that ``import smoothtri`` alone makes
# ``smoothtri.trimesh.Intersector`` reachable, as the README uses it (it needs only numpy;
# trimesh itself is imported by the caller, if at all). Last: it imports names defined above.
from . import trimesh  # noqa: E402
