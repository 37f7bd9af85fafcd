"""The .amf cache: bit-exact round trips, atomic writes, and clear errors on damage."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

import animanifold as am
from animanifold import cache
from helpers.shapes import icosphere
from helpers.keyframes import TIMES, wobble


@pytest.fixture
def manifold():
    v, f = icosphere(1)
    return am.stitch(
        wobble(v, TIMES), f, TIMES,
        vertex_attributes={"uv": v[:, :2] / 3.0},
        face_attributes={"material_index": np.arange(len(f)) % 3},
    )


def test_round_trip_is_bit_exact(manifold, tmp_path):
    path = am.save(manifold, tmp_path / "a.amf")
    loaded = am.load(path)
    assert loaded.points.tobytes() == manifold.points.tobytes()
    assert loaded.simplices.tobytes() == manifold.simplices.tobytes()
    assert loaded.vertex_attributes["uv"].tobytes() == manifold.vertex_attributes["uv"].tobytes()
    assert loaded.simplex_attributes["material_index"].tobytes() == manifold.simplex_attributes["material_index"].tobytes()
    assert loaded.metadata == manifold.metadata
    # saving the loaded manifold gives the same bytes
    assert am.save(loaded, tmp_path / "b.amf").read_bytes() == path.read_bytes()


def test_save_leaves_no_temporary_files_and_replaces_atomically(manifold, tmp_path, monkeypatch):
    target = tmp_path / "a.amf"
    am.save(manifold, target)
    before = target.read_bytes()

    def broken_fsync(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(cache.os, "fsync", broken_fsync)
    with pytest.raises(OSError, match="No space"):
        am.save(manifold, target)
    assert target.read_bytes() == before, "a failed save must not touch the existing cache"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.amf"]


@pytest.mark.parametrize("cut", [0, 5, 20, 100, -1, -4])
def test_truncated_files_raise(manifold, tmp_path, cut):
    data = am.save(manifold, tmp_path / "a.amf").read_bytes()
    (tmp_path / "t.amf").write_bytes(data[:cut] if cut >= 0 else data[:cut])
    with pytest.raises(am.CacheError, match="t.amf"):
        am.load(tmp_path / "t.amf")


def test_flipped_byte_is_detected(manifold, tmp_path):
    data = bytearray(am.save(manifold, tmp_path / "a.amf").read_bytes())
    data[len(data) // 2] ^= 0x10
    (tmp_path / "c.amf").write_bytes(bytes(data))
    with pytest.raises(am.CacheError, match="damaged"):
        am.load(tmp_path / "c.amf")


def test_future_version_and_foreign_files_raise(manifold, tmp_path):
    data = bytearray(am.save(manifold, tmp_path / "a.amf").read_bytes())
    struct.pack_into("<I", data, 8, cache.FORMAT_VERSION + 1)
    body = bytes(data[:-4])
    (tmp_path / "future.amf").write_bytes(body + struct.pack("<I", zlib.crc32(body)))
    with pytest.raises(am.CacheError, match="newer"):
        am.load(tmp_path / "future.amf")
    (tmp_path / "x.amf").write_bytes(b"# an OBJ file\nv 0 0 0\n" * 4)
    with pytest.raises(am.CacheError, match="not an animanifold cache"):
        am.load(tmp_path / "x.amf")
    with pytest.raises(am.CacheError, match="does not exist"):
        am.load(tmp_path / "missing.amf")


def test_valid_checksum_over_invalid_contents_still_raises(manifold, tmp_path):
    """A file whose checksum matches but whose indices are out of range is refused by validation."""
    data = bytearray(am.save(manifold, tmp_path / "a.amf").read_bytes())
    (header_len,) = struct.unpack_from("<I", data, 12)
    n, d = manifold.points.shape
    first_simplex = 16 + header_len + 8 * n * d
    struct.pack_into("<i", data, first_simplex, 10**8)
    body = bytes(data[:-4])
    (tmp_path / "bad.amf").write_bytes(body + struct.pack("<I", zlib.crc32(body)))
    with pytest.raises(am.CacheError, match="simplex 0 refers to vertex 100000000"):
        am.load(tmp_path / "bad.amf")
