"""One scene under concurrent callers: queries from four threads, ``report`` and
``precision_sweep`` from a fifth, updates from a sixth, all at once. Nothing may hang, and every
answer must be the answer of one whole pose (never a mix of two, never a pose that was not
given). The workload runs in a child interpreter with a time limit, so a deadlock fails the
test (with the child's tracebacks) instead of hanging pytest.

The poses are the octahedron with radial normals scaled by ``RADII``: its patches are exactly
the sphere of that radius, so each pose's hits are known analytically. The rays pass the centre
at distances (``OFFSETS``) that lie between the radii with a wide margin, so each pose hits a
different set of rays; a batch's hit mask names its pose and its ``t`` must lie within the
certified ``t_error`` of that sphere's root (``f64``: the bound ``test_sphere.py`` asserts).
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import subprocess
import sys
import threading
import time
import traceback

import numpy as np

import smoothtri
from conftest import octahedron, sphere_root

# The poses' radii, and the rays' distances from the centre: each offset is at least 0.1
# (a tenth of the unit radius) from every radius, so no ray grazes any pose.
RADII = (0.5, 0.75, 1.0, 1.25)
OFFSETS = (0.25, 0.62, 0.87, 1.12, 1.4)
RAYS_PER_OFFSET = 6

# How long the child runs its threads, and the limit after which it counts as hung (it then
# dumps every thread's traceback and exits). A run takes about STRESS_S plus start-up.
STRESS_S = 3.0
HANG_S = 40.0

HERE = pathlib.Path(__file__).resolve().parent


def pose(k: int) -> tuple:
    """The vertices and normals of pose ``k``: the octahedron scaled by ``RADII[k]``."""
    v, n, _ = octahedron()
    return RADII[k] * v, n


def rays() -> tuple:
    """``RAYS_PER_OFFSET`` rays at each of ``OFFSETS`` from the centre, from distance 3 on a
    random side, directions of random lengths (fixed seed)."""
    rng = np.random.default_rng(64)
    origins, directions = [], []
    for p in OFFSETS:
        for _ in range(RAYS_PER_OFFSET):
            u = rng.normal(size=3)
            u /= np.linalg.norm(u)
            w = np.cross(u, rng.normal(size=3))
            w /= np.linalg.norm(w)
            origins.append(-3.0 * u + p * w)
            directions.append(u * rng.uniform(0.5, 2.0))
    return np.array(origins), np.array(directions)


@dataclasses.dataclass
class Expected:
    """The answers of every pose, computed before the threads start (one thread)."""

    origins: np.ndarray
    directions: np.ndarray
    # Per pose: which rays hit, the analytic roots, the surface points of `tri`/`bary` on a
    # fresh scene of the pose, and the sweep's diagonal.
    masks: list
    roots: list
    surfaces: list
    diagonals: list
    tri: np.ndarray
    bary: np.ndarray


def expected() -> Expected:
    """The answer of each pose: hit masks and roots from the sphere, surface points and the
    sweep's diagonal from a fresh scene of the pose (the update's surface equals a fresh
    build's bit for bit; the diagonal is the pose's bounding box)."""
    o, d = rays()
    offsets = np.repeat(OFFSETS, RAYS_PER_OFFSET)
    _, _, f = octahedron()
    tri = np.arange(len(f))
    bary = np.tile([[0.2, 0.3]], (len(f), 1))
    masks, roots, surfaces, diagonals = [], [], [], []
    for k, r in enumerate(RADII):
        masks.append(offsets < r)
        roots.append(sphere_root(o / r, d / r))
        fresh = smoothtri.Scene(*pose(k), f, precision="f64")
        surfaces.append(fresh.evaluate(tri, bary).point)
        diagonals.append(smoothtri.precision_sweep(fresh, (o, d), iterations=[2], precision="f64").diagonal)
    # The poses are told apart by their masks.
    assert len({m.tobytes() for m in masks}) == len(RADII)
    return Expected(o, d, masks, roots, surfaces, diagonals, tri, bary)


def pose_of_hits(e: Expected, hits: smoothtri.Hits, rays: slice = slice(None)) -> int:
    """The first pose whose answer `hits` (of the rays `rays` of `e`) is: its mask, every
    ``t`` within ``t_error`` of the pose's root; -1 if none."""
    for k in range(len(RADII)):
        h, root = e.masks[k][rays], e.roots[k][rays]
        if np.array_equal(hits.hit, h) and (np.abs(hits.t[h] - root[h]) <= hits.t_error[h]).all():
            return k
    return -1


def stress(seconds: float) -> dict:
    """The workload (run in the child): four query threads, one thread of ``report``, small
    queries and ``precision_sweep``, one thread of updates through every pose, for
    ``seconds``. Returns the counts of calls and the problems found (answers of no pose,
    exceptions)."""
    e = expected()
    _, _, f = octahedron()
    scene = smoothtri.Scene(*pose(0), f, precision="f64")
    stop = threading.Event()
    lock = threading.Lock()
    problems: list = []
    counts = {"intersect": 0, "occluded": 0, "evaluate": 0, "report": 0, "sweep": 0, "update": 0}

    def tally(name: str, problem: str = "") -> None:
        with lock:
            counts[name] += 1
            if problem:
                problems.append(f"{name}: {problem}")

    def guarded(body):  # type: ignore[no-untyped-def]
        def run() -> None:
            try:
                body()
            except BaseException:  # noqa: BLE001 - every failure is reported
                with lock:
                    problems.append(traceback.format_exc())
                stop.set()

        return run

    def query(i: int) -> None:
        n = 0
        while not stop.is_set():
            threads = 1 if (n + i) % 2 else None
            kind = (n + i) % 3
            if kind == 0:
                k = pose_of_hits(e, scene.closest_hit(e.origins, e.directions, iterations=8, threads=threads))
                tally("intersect", "" if k >= 0 else "hits of no pose")
            elif kind == 1:
                got = scene.any_hit(e.origins, e.directions, iterations=8, threads=threads)
                ok = any(np.array_equal(got, m) for m in e.masks)
                tally("occluded", "" if ok else "occlusion of no pose")
            else:
                got = scene.evaluate(e.tri, e.bary, threads=threads).point
                ok = any(np.array_equal(got, s) for s in e.surfaces)
                tally("evaluate", "" if ok else "surface of no pose")
            n += 1

    def reporter() -> None:
        n = 0
        while not stop.is_set():
            r = scene.report
            tally("report", "" if (r.patches, r.triangles) == (8, 8) else f"report {r}")
            # A small query between two reads of the report (the rays of the two smallest
            # offsets).
            few = slice(0, 2 * RAYS_PER_OFFSET)
            hits = scene.closest_hit(e.origins[few], e.directions[few], iterations=8, threads=1)
            tally("intersect", "" if pose_of_hits(e, hits, few) >= 0 else "small query: hits of no pose")
            if n % 4 == 0:
                s = smoothtri.precision_sweep(
                    scene, (e.origins, e.directions), iterations=[2, 4], precision=("f32", "f64"), threads=1 + n % 2
                )
                ks = [k for k in range(len(RADII)) if s.diagonal == e.diagonals[k]]
                ok = len(ks) == 1 and (s.hits == e.masks[ks[0]].sum()).all()
                tally("sweep", "" if ok else f"sweep of no pose: diagonal {s.diagonal}, hits {s.hits}")
            n += 1

    def updater() -> None:
        n = 0
        while not stop.is_set():
            n += 1
            scene.update(*pose(n % len(RADII)), threads=1 if n % 2 else None)
            tally("update")

    workers = [threading.Thread(target=guarded(lambda i=i: query(i))) for i in range(4)]
    workers += [threading.Thread(target=guarded(reporter)), threading.Thread(target=guarded(updater))]
    for w in workers:
        w.start()
    time.sleep(seconds)
    stop.set()
    for w in workers:
        w.join()
    # Quiet now: the scene and its report are the last pose's.
    last = counts["update"] % len(RADII)
    k = pose_of_hits(e, scene.closest_hit(e.origins, e.directions, iterations=8))
    if k != last:
        problems.append(f"after the threads: hits of pose {k}, the last update was to pose {last}")
    if scene.report.bvh_refitted != scene._native.report["bvh_refitted"]:
        problems.append("after the threads: the cached report is not the scene's")
    return {"counts": counts, "problems": problems}


def test_threads_neither_hang_nor_mix_poses() -> None:
    code = (
        "import faulthandler, json, sys\n"
        f"faulthandler.dump_traceback_later({HANG_S}, exit=True)\n"
        f"sys.path.insert(0, {str(HERE)!r})\n"
        "import test_threads\n"
        f"print(json.dumps(test_threads.stress({STRESS_S})))\n"
    )
    try:
        run = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=HANG_S + 30
        )
    except subprocess.TimeoutExpired as e:
        raise AssertionError(f"the threads hung (no exit within {HANG_S + 30} s): {e.stderr}") from None
    assert run.returncode == 0, (
        f"the child failed (exit {run.returncode}; a hang is reported as 'Timeout' with every "
        f"thread's traceback):\n{run.stderr[-6000:]}"
    )
    result = json.loads(run.stdout.strip().splitlines()[-1])
    assert result["problems"] == []
    counts = result["counts"]
    # Every kind of call ran, many times, while the others did.
    for name in ("intersect", "occluded", "evaluate", "report", "update"):
        assert counts[name] >= 10, counts
    assert counts["sweep"] >= 2, counts


class _UpdateDuringReport:
    """The native scene, except that reading ``report`` moves the scene to ``pose`` (through
    ``scene.update``) after the native report was read: another thread's update landing
    between the read and the cache's store."""

    def __init__(self, scene: smoothtri.Scene, pose: tuple) -> None:
        self._scene = scene
        self._inner = scene._native
        self._pose = pose

    def __getattr__(self, name: str):  # type: ignore[no-untyped-def]
        return getattr(self._inner, name)

    @property
    def report(self) -> dict:
        d = self._inner.report
        if self._pose is not None:
            p, self._pose = self._pose, None
            self._scene.update(*p)
        return d


def test_report_follows_updates() -> None:
    v, n, f = octahedron()
    scene = smoothtri.Scene(v, n, f)
    assert scene.report.patches == 8 and not scene.report.bvh_refitted
    scene.update(np.zeros_like(v), n)
    assert scene.report.patches == 0
    scene.update(2 * v, n)
    # An update between the read of the report and its caching (the first read after an
    # update reads the native report): the stale report may be the answer of that call (the
    # pose at its start), never of a later one.
    scene._native = _UpdateDuringReport(scene, (np.zeros_like(v), n))  # type: ignore[assignment]
    assert scene.report.patches == 8
    assert scene.report.patches == 0
