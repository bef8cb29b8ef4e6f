"""The package's public names: ``smoothtri.__all__`` names what ``smoothtri`` holds, and every
public class and function of the package's modules is in it, the same object."""

from __future__ import annotations

import importlib
import inspect
import pathlib

import smoothtri

# Modules of helpers for the others (argument checks, plotting): their names are not the API.
HELPERS = {"_args", "_plot"}


def api_modules() -> list:
    """The package's private modules that define its public names."""
    folder = pathlib.Path(smoothtri.__file__).parent
    names = sorted(p.stem for p in folder.glob("_*.py") if p.stem != "__init__")
    return [importlib.import_module(f"smoothtri.{n}") for n in names if n not in HELPERS]


def test_every_name_of_all_is_in_the_package():
    missing = [n for n in smoothtri.__all__ if not hasattr(smoothtri, n)]
    assert not missing
    assert len(set(smoothtri.__all__)) == len(smoothtri.__all__)


def test_every_public_class_and_function_is_in_all():
    modules = api_modules()
    assert {m.__name__ for m in modules} >= {"smoothtri._mesh", "smoothtri._scene"}
    for module in modules:
        for name, obj in vars(module).items():
            defined_here = getattr(obj, "__module__", None) == module.__name__
            if name.startswith("_") or not defined_here:
                continue
            if inspect.isclass(obj) or inspect.isfunction(obj):
                assert name in smoothtri.__all__, f"{module.__name__}.{name}"
                assert getattr(smoothtri, name) is obj, name


def test_the_trimesh_module_comes_with_the_package():
    assert smoothtri.trimesh.Intersector.__module__ == "smoothtri.trimesh"
    assert "trimesh" not in smoothtri.__all__  # a star import would shadow the trimesh package


def test_the_old_query_names_warn_and_answer_alike() -> None:
    """``intersect`` / ``occluded`` are deprecated names of ``closest_hit`` / ``any_hit``: they
    warn and answer the same."""
    import numpy as np
    import pytest

    from conftest import octahedron, rays_through_ball

    scene = smoothtri.Scene(*octahedron(), precision="f64")
    o, d = rays_through_ball(64, 1.3, seed=3)
    want = scene.closest_hit(o, d)
    with pytest.warns(DeprecationWarning, match="closest_hit"):
        got = scene.intersect(o, d)
    assert np.array_equal(got.t, want.t, equal_nan=True)
    with pytest.warns(DeprecationWarning, match="any_hit"):
        assert np.array_equal(scene.occluded(o, d), scene.any_hit(o, d))
