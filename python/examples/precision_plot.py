"""Precision against iterations on a real mesh, from Python.

Loads a mesh, traces a million camera rays on every core, and plots the hit-point error of
f32 and f64 against the iteration budget N (the study of ``smoothtri precision``)::

    python python/examples/precision_plot.py [MESH] [--out precision.png] [--size 1000 1000]

MESH defaults to the scanned Wuson of Debian's assimp-testmodels. The picture in the
repository's README (docs/python_precision.png) is this script's output on it.
"""

from __future__ import annotations

import argparse
import pathlib
import time

import matplotlib

matplotlib.use("Agg")

import smoothtri  # noqa: E402

WUSON = pathlib.Path("/usr/share/assimp/models/OBJ/WusonOBJ.obj")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh", nargs="?", default=str(WUSON), help="OBJ, PLY, glTF or GLB")
    ap.add_argument("--out", default="precision.png", help="the plot (PNG, SVG, PDF)")
    ap.add_argument("--size", nargs=2, type=int, default=(1000, 1000), metavar=("W", "H"))
    ap.add_argument("--up", default="y", choices=["x", "y", "z"], help="the mesh's up axis")
    ap.add_argument("--sweep-size", nargs=2, type=int, default=(320, 240), metavar=("W", "H"),
                    help="camera rays of the precision study (34 runs of them)")
    a = ap.parse_args()

    mesh = smoothtri.load(a.mesh)
    scene = smoothtri.Scene.from_mesh(mesh)
    print(scene)

    origins, directions = smoothtri.camera_rays(mesh.vertices, *a.size, up=a.up)
    start = time.perf_counter()
    hits = scene.closest_hit(origins, directions)
    secs = time.perf_counter() - start
    print(f"{len(hits)} rays, {hits.hit.sum()} hits in {secs:.3f} s on every core "
          f"({len(hits) / secs / 1e6:.2f} Mrays/s), largest t_error {hits.t_error[hits.hit].max():.2e}")

    rays = smoothtri.camera_rays(mesh.vertices, *a.sweep_size, up=a.up)
    study = smoothtri.precision_sweep(scene, rays)
    print(study.table())
    study.plot(a.out, title=f"smoothtri: hit-point error vs iterations ({pathlib.Path(a.mesh).name}, "
                            f"{study.rays} camera rays)")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
