"""The scene: the smooth surface of a triangle mesh with vertex normals, built once (or moved
to a new pose), then traced by batches of rays and evaluated at surface points."""

from __future__ import annotations

import math
import warnings
from typing import Any, Dict, Optional, Sequence, Tuple, Union

import numpy as np

from . import _smoothtri
from ._args import ArrayLike, iterations_arg, threads_arg
from ._mesh import Mesh
from ._results import BuildReport, Hits, SurfacePoints


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
            threads=threads_arg(threads),
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
        self._native.update(vertices, normals, threads=threads_arg(threads))
        self._report = None

    def __repr__(self) -> str:
        r = self.report
        return (
            f"Scene({r.patches} patches of {r.triangles} triangles, precision={self.precision!r}, "
            f"seams={self.seams}, field={self.field!r}, {r.memory_bytes / 1024:.1f} KiB)"
        )

    def closest_hit(
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
        arrays = self._native.ray_query(
            "closest_hit",
            origins,
            directions,
            **_ray_options(iterations, t_min, t_max, threads),
            out=_out_arrays(out, _smoothtri.HIT_FIELDS),
        )
        if out is not None:
            return out
        return Hits(*arrays)

    def any_hit(
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

        Arguments as for :meth:`closest_hit`; ``out`` is an ``(R,)`` bool array to overwrite.

        Returns:
            ``(R,)`` bool, the core's ``Scene::any_hit``.
        """
        return self._native.ray_query(
            "any_hit", origins, directions, **_ray_options(iterations, t_min, t_max, threads), out=out
        )

    def intersect(self, *args: Any, **kwargs: Any) -> Hits:
        """Deprecated name of :meth:`closest_hit` (the Rust and GPU layers' name); warns
        ``DeprecationWarning``."""
        warnings.warn("Scene.intersect is Scene.closest_hit", DeprecationWarning, stacklevel=2)
        return self.closest_hit(*args, **kwargs)

    def occluded(self, *args: Any, **kwargs: Any) -> np.ndarray:
        """Deprecated name of :meth:`any_hit` (the Rust and GPU layers' name); warns
        ``DeprecationWarning``."""
        warnings.warn("Scene.occluded is Scene.any_hit", DeprecationWarning, stacklevel=2)
        return self.any_hit(*args, **kwargs)

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
            threads=threads_arg(threads),
            out=_out_arrays(out, _smoothtri.SURFACE_FIELDS),
        )
        if out is not None:
            return out
        return SurfacePoints(*arrays)


def _ray_options(
    iterations: int, t_min: Union[float, ArrayLike], t_max: Union[float, ArrayLike], threads: Optional[int]
) -> Dict[str, Any]:
    """The options of the native ray queries (``ray_query``), checked."""
    return {
        "iterations": iterations_arg(iterations),
        "t_min": t_min,
        "t_max": t_max,
        "threads": threads_arg(threads),
    }


def _out_arrays(out: Any, fields: Sequence[str]) -> Optional[Tuple[np.ndarray, ...]]:
    """The arrays of a result given as ``out=`` (a :class:`Hits` or :class:`SurfacePoints`), in
    the native module's order ``fields``."""
    return None if out is None else tuple(getattr(out, f) for f in fields)
