"""A drop-in for trimesh's ray intersectors that traces the smooth surface of the mesh.

``trimesh.ray.ray_triangle.RayMeshIntersector`` (and the Embree one) intersect the flat
triangles; :class:`Intersector` answers the same calls, with the same return types, on the
smooth patches the mesh's vertex normals define::

    import trimesh, smoothtri.trimesh
    mesh = trimesh.load("bunny.obj")
    mesh.ray = smoothtri.trimesh.Intersector(mesh)     # every mesh.ray.* call now smooth
    locations, index_ray, index_tri = mesh.ray.intersects_location(origins, directions)

Differences from the flat intersectors, all consequences of the smooth surface: silhouettes
are curved (a ray can hit the patches just outside the flat triangles, or miss them just
inside), and ``index_tri`` is the triangle whose patch was hit. trimesh is not needed to use
it: any object with ``vertices``, ``vertex_normals`` and ``faces`` works.
"""

from __future__ import annotations

from typing import Any, List, Optional, Tuple

import numpy as np

from . import _smoothtri
from ._mesh import from_trimesh
from ._scene import Scene

__all__ = ["Intersector"]


class Intersector:
    """Ray queries on the smooth surface of a trimesh mesh, with trimesh's interface.

    Args:
        mesh: a ``trimesh.Trimesh`` (or anything with ``vertices``, ``vertex_normals`` and
            ``faces``); its arrays are read once, here.
        precision: ``"f64"`` (default, as trimesh computes) or ``"f32"``.
        iterations: the kernel's refinement steps ``N`` (default 8: ``f64`` sphere hits to
            ``ACCURACY["F64_SPHERE_HIT"]`` of the radius).
        field: ``"face"`` or ``"vertex"``, as for :class:`smoothtri.Scene`.
        threads: threads per query (``None``: every core).

    Attributes:
        mesh: the mesh given.
        scene: the :class:`smoothtri.Scene` of it (no seams: trimesh asks for no normals).
    """

    def __init__(
        self,
        mesh: Any,
        *,
        precision: str = "f64",
        iterations: int = 8,
        field: str = "face",
        threads: Optional[int] = None,
    ) -> None:
        self.mesh = mesh
        m = from_trimesh(mesh)
        self.scene = Scene.from_mesh(m, precision=precision, seams=False, field=field, threads=threads)
        self.iterations = iterations
        self.threads = threads
        lo, hi = m.vertices.min(axis=0), m.vertices.max(axis=0)
        # Where a ray is re-cast beyond a hit (multiple hits): the renders' offset for
        # secondary rays, a fraction of the bounding-box diagonal.
        self._step = float(np.linalg.norm(hi - lo)) * _smoothtri.SECONDARY_RAY_OFFSET[self.scene.precision]

    def _rays(self, ray_origins: Any, ray_directions: Any) -> Tuple[np.ndarray, np.ndarray]:
        o = np.asarray(ray_origins, dtype=np.float64)
        d = np.asarray(ray_directions, dtype=np.float64)
        return o.reshape(-1, 3) if o.size == 0 else o, d.reshape(-1, 3) if d.size == 0 else d

    def _first(self, o: np.ndarray, d: np.ndarray, t_min: Any = 0.0):
        return self.scene.closest_hit(o, d, iterations=self.iterations, t_min=t_min, threads=self.threads)

    def intersects_first(self, ray_origins: Any, ray_directions: Any, **kwargs: Any) -> np.ndarray:
        """The index of the first triangle each ray hits.

        Args:
            ray_origins: ``(n, 3)`` float ray origins.
            ray_directions: ``(n, 3)`` float ray directions.

        Returns:
            ``(n,)`` int64 triangle index, ``-1`` where the ray misses.
        """
        o, d = self._rays(ray_origins, ray_directions)
        return np.asarray(self._first(o, d).triangle, dtype=np.int64)

    def intersects_any(self, ray_origins: Any, ray_directions: Any, **kwargs: Any) -> np.ndarray:
        """Whether each ray hits the surface.

        Returns:
            ``(n,)`` bool.
        """
        o, d = self._rays(ray_origins, ray_directions)
        return self.scene.any_hit(o, d, iterations=self.iterations, threads=self.threads)

    def _all_hits(
        self, o: np.ndarray, d: np.ndarray, multiple_hits: bool, max_hits: int
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every hit of every ray in front of its origin, nearest first per ray: the closest
        hit, then the ray cast again from just beyond it (the renders' secondary-ray offset),
        up to ``max_hits`` per ray."""
        tris: List[np.ndarray] = []
        rays: List[np.ndarray] = []
        points: List[np.ndarray] = []
        active = np.arange(len(o))
        t_min = np.zeros(len(o))
        step = self._step / np.maximum(np.linalg.norm(d, axis=1), np.finfo(np.float64).tiny)
        for _ in range(max(1, max_hits) if multiple_hits else 1):
            if len(active) == 0:
                break
            h = self._first(o[active], d[active], t_min[active])
            hit = h.hit
            tris.append(h.triangle[hit])
            rays.append(active[hit])
            points.append(np.asarray(h.point[hit], dtype=np.float64))
            t_next = np.asarray(h.t[hit], dtype=np.float64) + np.maximum(
                4.0 * np.asarray(h.t_error[hit], dtype=np.float64), step[active[hit]]
            )
            active = active[hit]
            t_min[active] = t_next
        if not tris:
            return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3))
        index_tri = np.concatenate(tris).astype(np.int64)
        index_ray = np.concatenate(rays).astype(np.int64)
        locations = np.concatenate(points).reshape(-1, 3)
        order = np.argsort(index_ray, kind="stable")
        return index_tri[order], index_ray[order], locations[order]

    def intersects_id(
        self,
        ray_origins: Any,
        ray_directions: Any,
        return_locations: bool = False,
        multiple_hits: bool = True,
        max_hits: int = 20,
        **kwargs: Any,
    ):
        """The triangles the rays hit.

        Args:
            ray_origins: ``(m, 3)`` float ray origins.
            ray_directions: ``(m, 3)`` float ray directions.
            return_locations: also return the hit points.
            multiple_hits: every hit along each ray (up to ``max_hits``), or the first only.
            max_hits: the most hits per ray.

        Returns:
            ``(index_tri, index_ray)`` or, with ``return_locations``, ``(index_tri, index_ray,
            locations)``: ``(h,)`` int64, ``(h,)`` int64, ``(h, 3)`` float64; grouped by ray,
            nearest first.
        """
        o, d = self._rays(ray_origins, ray_directions)
        index_tri, index_ray, locations = self._all_hits(o, d, multiple_hits, max_hits)
        if return_locations:
            return index_tri, index_ray, locations
        return index_tri, index_ray

    def intersects_location(
        self, ray_origins: Any, ray_directions: Any, multiple_hits: bool = True, **kwargs: Any
    ):
        """Where the rays hit.

        Returns:
            ``(locations, index_ray, index_tri)``: ``(n, 3)`` float64 points on the smooth
            surface, ``(n,)`` int64 ray indices, ``(n,)`` int64 triangle indices.
        """
        index_tri, index_ray, locations = self.intersects_id(
            ray_origins, ray_directions, return_locations=True, multiple_hits=multiple_hits, **kwargs
        )
        return locations, index_ray, index_tri

    def contains_points(self, points: Any) -> np.ndarray:
        """Whether each point is inside the (closed) smooth surface, by trimesh's ray test
        (``trimesh.ray.ray_util.contains_points``; needs trimesh).

        Returns:
            ``(n,)`` bool.
        """
        from trimesh.ray.ray_util import contains_points

        return contains_points(self, points)
