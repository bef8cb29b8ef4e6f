"""Hostile files through ``smoothtri.load`` (issue 64): typed exceptions, bounded memory, no
read outside the asset's folder without ``allow_outside_folder=True``."""

import base64
import os
import struct

import pytest

import smoothtri


def _triangle_with_buffer(uri: str) -> str:
    return (
        '{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],'
        '"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],'
        f'"buffers":[{{"uri":"{uri}","byteLength":36}}],'
        '"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36}],'
        '"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",'
        '"min":[0,0,0],"max":[1,1,0]}]}'
    )


_TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def _sparse_viewless() -> str:
    """The issue's file: a sparse POSITION accessor without a view of count 4000000000 (it
    aborted the interpreter: "memory allocation of 96000000000 bytes failed")."""
    data = base64.b64encode(struct.pack("<I3f", 0, 1, 2, 3)).decode()
    return (
        '{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],'
        '"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],'
        f'"buffers":[{{"uri":"data:application/octet-stream;base64,{data}","byteLength":16}}],'
        '"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":4},'
        '{"buffer":0,"byteOffset":4,"byteLength":12}],'
        '"accessors":[{"componentType":5126,"count":4000000000,"type":"VEC3",'
        '"min":[0,0,0],"max":[1,2,3],"sparse":{"count":1,'
        '"indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":1}}}]}'
    )


def test_the_exceptions_are_load_errors():
    assert issubclass(smoothtri.LoadBudgetError, smoothtri.LoadError)
    assert issubclass(smoothtri.OutsideFolderError, smoothtri.LoadError)
    assert smoothtri.DEFAULT_MAX_BYTES == 2 << 30


def test_a_sparse_accessor_of_four_billion_raises_a_budget_error(tmp_path):
    path = tmp_path / "f.gltf"
    path.write_text(_sparse_viewless())
    with pytest.raises(smoothtri.LoadBudgetError, match=r"f\.gltf: .*POSITION accessor 0.*over the load budget"):
        smoothtri.load(path)


def test_huge_ply_counts_raise_a_load_error(tmp_path):
    path = tmp_path / "v.ply"
    path.write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
        b"property float x\nproperty float y\nproperty float z\nend_header\n" + bytes(12)
    )
    with pytest.raises(smoothtri.LoadError, match=r"element 'vertex' declares 4000000000"):
        smoothtri.load(path)


def test_max_bytes_bounds_a_well_formed_file(tmp_path):
    path = tmp_path / "m.obj"
    path.write_text("".join(f"v {k} 0 0\n" for k in range(100)) + "f 1 2 3\n")
    assert len(smoothtri.load(path).faces) == 1
    with pytest.raises(smoothtri.LoadBudgetError, match=r"m\.obj: line \d+: 'v' \(vertex\)"):
        smoothtri.load(path, max_bytes=2000)
    with pytest.raises(smoothtri.LoadBudgetError, match=r"the file's size"):
        smoothtri.load(path, max_bytes=10)


@pytest.mark.parametrize(
    "uri", ["/etc/passwd", "../../etc/passwd", "%2e%2e/tri.bin", "../tri.bin", "/dev/zero"]
)
def test_buffers_outside_the_folder_raise(tmp_path, uri):
    (tmp_path / "tri.bin").write_bytes(_TRIANGLE)
    asset = tmp_path / "asset"
    asset.mkdir()
    path = asset / "m.gltf"
    path.write_text(_triangle_with_buffer(uri))
    with pytest.raises(smoothtri.OutsideFolderError, match=f'm\\.gltf: buffer URI "{uri}"'):
        smoothtri.load(path)


def test_the_opt_in_reads_regular_files_only(tmp_path):
    (tmp_path / "tri.bin").write_bytes(_TRIANGLE)
    asset = tmp_path / "asset"
    asset.mkdir()
    path = asset / "m.gltf"
    path.write_text(_triangle_with_buffer("../tri.bin"))
    mesh = smoothtri.load(path, allow_outside_folder=True)
    assert len(mesh.faces) == 1
    path.write_text(_triangle_with_buffer("/dev/zero"))
    with pytest.raises(smoothtri.LoadError, match="not a regular file"):
        smoothtri.load(path, allow_outside_folder=True)


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="no symlinks")
def test_a_symlink_out_of_the_folder_raises(tmp_path):
    (tmp_path / "tri.bin").write_bytes(_TRIANGLE)
    asset = tmp_path / "asset"
    asset.mkdir()
    os.symlink(tmp_path / "tri.bin", asset / "link.bin")
    path = asset / "m.gltf"
    path.write_text(_triangle_with_buffer("link.bin"))
    with pytest.raises(smoothtri.OutsideFolderError):
        smoothtri.load(path)
    assert len(smoothtri.load(path, allow_outside_folder=True).faces) == 1
