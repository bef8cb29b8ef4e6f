"""The Python API's overhead per ray against the Rust API, and the same rays through Embree
(``embreex``) on the flat mesh.

    python python/benches/overhead.py [MESH] [--size 1000 1000] [--rounds 7] [--threads N]

On 1M camera rays of a real mesh (default: the scanned Wuson of Debian's assimp-testmodels,
y up), interleaved rounds of:

- ``rust``: the core's ``Scene::closest_hit`` over rayon's ``par_iter`` into a ``Vec``, the
  rays converted beforehand (``smoothtri._smoothtri.rust_baseline``, in this process);
- ``python``: ``scene.closest_hit(origins, directions)`` on float64 arrays: reading them,
  the same queries, eight new result arrays;
- ``python out=``: the same with the result arrays of the previous call reused;
- ``python f32 in``: float32 input arrays (no rounding per ray);
- ``rust, 1 thread`` and ``python, 1 thread``: the same on one thread;
- ``embreex``: ``EmbreeScene.run(origins, directions, output=1)`` on the flat triangles
  (float32, one thread inside embreex), when embreex is installed.

Prints the median time of each and the median over rounds of its ratio to the Rust API's
time on as many threads in the same round (the overhead; embreex against one thread). Timings only: the answers are checked by the tests.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import platform
import statistics
import time

import numpy as np

import smoothtri
from smoothtri import _smoothtri

WUSON = pathlib.Path("/usr/share/assimp/models/OBJ/WusonOBJ.obj")


def cpu_name() -> str:
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh", nargs="?", default=str(WUSON))
    ap.add_argument("--size", nargs=2, type=int, default=(1000, 1000), metavar=("W", "H"))
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--threads", type=int, default=None, help="default: every core")
    ap.add_argument("--iterations", type=int, default=4)
    ap.add_argument("--precision", default="f32", choices=["f32", "f64"])
    ap.add_argument("--up", default="y", choices=["x", "y", "z"])
    ap.add_argument("--case", choices=["python", "rust", "none"],
                    help="run one case once on one thread, for an instruction count: "
                         "valgrind --tool=callgrind --collect-atstart=no "
                         "--toggle-collect='*__pymethod_intersect__*' (python) or "
                         "--toggle-collect='*trace_prepared*' (rust)")
    a = ap.parse_args()

    mesh = smoothtri.load(a.mesh)
    scene = smoothtri.Scene.from_mesh(mesh, precision=a.precision)
    o, d = smoothtri.camera_rays(mesh.vertices, *a.size, up=a.up)
    o32, d32 = o.astype(np.float32), d.astype(np.float32)
    n = len(o)
    if a.case is not None:
        if a.case == "python":
            hits = scene.closest_hit(o, d, iterations=a.iterations, threads=1).hit.sum()
        elif a.case == "rust":
            hits = _smoothtri.rust_baseline(scene._native, o, d, iterations=a.iterations, threads=1)[1]
        else:
            hits = 0
        print(f"{a.case}: {n} rays, {hits} hits")
        return
    kw = dict(iterations=a.iterations, threads=a.threads)
    threads = a.threads or os.cpu_count()
    print(f"{a.mesh}: {scene}")
    print(f"{n} camera rays ({a.size[0]}x{a.size[1]}), N = {a.iterations}, {threads} threads, "
          f"{cpu_name()}, numpy {np.__version__}")

    runs: dict = {}

    def rust() -> float:
        secs, hits = _smoothtri.rust_baseline(scene._native, o, d, **kw)
        runs.setdefault("hits", hits)
        return secs

    def timed(f) -> float:
        start = time.perf_counter()
        f()
        return time.perf_counter() - start

    prev = scene.closest_hit(o, d, **kw)
    assert prev.hit.sum() == _smoothtri.rust_baseline(scene._native, o, d, **kw)[1]
    one = dict(kw, threads=1)
    cases = {
        "rust": rust,
        "python": lambda: timed(lambda: scene.closest_hit(o, d, **kw)),
        "python out=": lambda: timed(lambda: scene.closest_hit(o, d, out=prev, **kw)),
        "python f32 in": lambda: timed(lambda: scene.closest_hit(o32, d32, **kw)),
        "rust, 1 thread": lambda: _smoothtri.rust_baseline(scene._native, o, d, **one)[0],
        "python, 1 thread": lambda: timed(lambda: scene.closest_hit(o, d, **one)),
    }
    try:
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        flat = rtcore_scene.EmbreeScene()
        TriangleMesh(flat, mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32))
        flat.run(o32[:10], d32[:10], output=1)  # commit the scene before the clock runs
        cases["embreex (flat, 1 thread)"] = lambda: timed(lambda: flat.run(o32, d32, output=1))
        ehits = (flat.run(o32, d32) != -1).sum()
        print(f"embreex {__import__('embreex').__version__ if hasattr(__import__('embreex'), '__version__') else ''}"
              f": {ehits} hits on the flat triangles")
    except ImportError:
        print("embreex is not installed: no Embree row")

    times: dict = {k: [] for k in cases}
    for _ in range(a.rounds):
        for k, f in cases.items():
            times[k].append(f())
    print(f"{'':26} {'median ms':>10} {'ns/ray':>8} {'Mrays/s':>8} {'÷ rust, same threads':>21}")
    for k, ts in times.items():
        # Each time over the Rust API's on as many threads, in the same round.
        base = times["rust, 1 thread" if "1 thread" in k else "rust"]
        med = statistics.median(ts)
        ratio = statistics.median(t / b for t, b in zip(ts, base))
        print(f"{k:26} {med * 1e3:10.1f} {med * 1e9 / n:8.1f} {n / med / 1e6:8.2f} {ratio:21.3f}")
    print(f"{runs['hits']} hits; the Python overhead per ray is the ratio minus 1")


if __name__ == "__main__":
    main()
