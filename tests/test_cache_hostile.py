"""The cache reader on damaged and hostile files: always a CacheError naming the file, never
another exception, a block on a FIFO or an allocation the file's size does not back; arrays
reach the core aligned."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

import animanifold as am
from animanifold import cache, cache_format
from animanifold.manifold import AnimationManifold
from helpers.cache_files import assemble, small_manifold, split


@pytest.fixture(scope="module")
def saved(tmp_path_factory) -> bytes:
    return am.save(small_manifold(), tmp_path_factory.mktemp("saved") / "a.amf").read_bytes()


def load_bytes(tmp_path, data: bytes, name: str = "hostile.amf"):
    path = tmp_path / name
    path.write_bytes(data)
    return am.load(path)


def test_fifo_directory_and_device_are_refused_before_reading(tmp_path):
    os.mkfifo(tmp_path / "pipe.amf")  # nothing ever writes to it: reading would block for ever
    (tmp_path / "folder.amf").mkdir()
    paths = [tmp_path / "pipe.amf", tmp_path / "folder.amf"] + ([ "/dev/zero"] if os.path.exists("/dev/zero") else [])
    for path in paths:
        with pytest.raises(am.CacheError, match="not a regular file") as error:
            am.load(path)
        assert str(path) in str(error.value)


HOSTILE_FIELDS = [
    ("points", 10**15), ("points", -1), ("points", 2**70), ("points", 1e308), ("points", float("inf")),
    ("points", "42"), ("points", None), ("points", True), ("points", 42.0), ("simplices", [1]),
    ("dimension", 5), ("dimension", 2), ("simplex_width", 3),
    ("vertex_attributes", None), ("vertex_attributes", [["uv", 10**12]]), ("vertex_attributes", [["uv"]]),
    ("vertex_attributes", [[1, 2]]), ("vertex_attributes", [["uv", 2], ["uv", 2]]), ("vertex_attributes", "uv"),
    ("simplex_attributes", [["m", 0]]), ("simplex_attributes", [["m", float("nan")]]),
    ("metadata", [1, 2]), ("metadata", "text"),
    ("arrays", [["hole_faces", "<i8", 1, 3]]), ("arrays", [["hole_faces", "<i4", 10**18, 3]]),
    ("arrays", [["hole_faces", "<i4", -5, 3]]), ("arrays", {"a": 1}), ("arrays", [["hole_faces", "<i4", 0, 3]]),
]


@pytest.mark.parametrize("field, value", HOSTILE_FIELDS, ids=[f"{k}={v!r}"[:40] for k, v in HOSTILE_FIELDS])
def test_hostile_header_fields_give_cache_errors(saved, tmp_path, field, value):
    _, header, payload = split(saved)
    header[field] = value
    with pytest.raises(am.CacheError, match="hostile.amf"):
        load_bytes(tmp_path, assemble(2, header, payload))


@pytest.mark.parametrize("header", [b"[]", b"42", b'"text"', b"null", b"\xff\xfe", b"{", b"1" * 5000,
                                   b'{"points": 1' + b"0" * 5000 + b"}"])
def test_headers_that_are_not_objects_give_cache_errors(saved, tmp_path, header):
    with pytest.raises(am.CacheError, match="damaged header"):
        load_bytes(tmp_path, assemble(1, header, split(saved)[2]))


@pytest.mark.parametrize("depth", [65, 10_000, 1_000_000])
def test_deeply_nested_headers_are_refused_without_recursion(saved, tmp_path, depth):
    _, header, payload = split(saved)
    raw = b'{"metadata": ' + b"[" * depth + b"]" * depth + b"}"
    with pytest.raises(am.CacheError, match="nested"):
        load_bytes(tmp_path, assemble(1, raw, payload))


def test_nesting_inside_strings_does_not_count(saved, tmp_path):
    _, header, payload = split(saved)
    header["metadata"] = {"note": "[[[[{{{{" * 100 + '\\"]]'}
    assert load_bytes(tmp_path, assemble(1, header, payload)).metadata == header["metadata"]


def test_a_huge_declared_count_is_refused_before_the_payload_is_read(saved, tmp_path, monkeypatch):
    _, header, payload = split(saved)
    header["points"] = 10**12
    allocations = []
    real_empty = np.empty
    monkeypatch.setattr(cache.np, "empty", lambda *a, **k: allocations.append(a) or real_empty(*a, **k))
    with pytest.raises(am.CacheError, match="header says"):
        load_bytes(tmp_path, assemble(1, header, payload))
    assert allocations == []


def test_a_file_larger_than_the_memory_left_gives_a_cache_error(saved, tmp_path, monkeypatch):
    def no_memory(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(cache.np, "empty", no_memory)
    with pytest.raises(am.CacheError, match="does not fit in the memory"):
        load_bytes(tmp_path, saved)


def test_new_files_put_the_payload_on_an_8_byte_boundary(saved):
    header_len = int.from_bytes(saved[12:16], "little")
    assert (16 + header_len) % cache_format.PAYLOAD_ALIGNMENT == 0


def test_arrays_reach_the_core_aligned_even_from_an_unpadded_older_file(saved, tmp_path, monkeypatch):
    version, header, payload = split(saved)
    raw = json_with_length(header, odd=True)  # as written before padding: the payload at an odd offset
    handed = []
    real = AnimationManifold.from_arrays.__func__

    def spy(cls, points, simplices, vattrs, sattrs, *rest):
        handed.extend([points, simplices, *vattrs.values(), *sattrs.values()])
        return real(cls, points, simplices, vattrs, sattrs, *rest)

    monkeypatch.setattr(AnimationManifold, "from_arrays", classmethod(spy))
    loaded = load_bytes(tmp_path, assemble(version, raw, payload))
    assert len(handed) == 4 and all(a.flags.aligned for a in handed)
    assert loaded.points.tobytes() == small_manifold().points.tobytes()


def json_with_length(header: dict, odd: bool) -> bytes:
    raw = json.dumps(header).encode()
    return raw if (16 + len(raw)) % 2 == int(odd) else raw + b" "
