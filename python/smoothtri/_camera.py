"""Camera rays: the demo's pinhole camera framed on a mesh, as numpy arrays of rays."""

from __future__ import annotations

from typing import Tuple

import numpy as np

from . import _smoothtri
from ._args import ArrayLike


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
