"""What a :class:`~smoothtri.Scene` answers: its build report and the results of its queries,
arrays in the scene's precision."""

from __future__ import annotations

import dataclasses
from typing import Optional, Tuple

import numpy as np


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
