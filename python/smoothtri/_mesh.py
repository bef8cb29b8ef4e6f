"""Meshes: the indexed triangle mesh with vertex normals that a :class:`~smoothtri.Scene` is
built from, read from a file (:func:`load`) or taken from trimesh (:func:`from_trimesh`)."""

from __future__ import annotations

import dataclasses
import os
from typing import Any, Optional, Tuple, Union

import numpy as np

from . import _smoothtri


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
