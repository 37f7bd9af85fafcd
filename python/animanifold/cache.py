"""The manifold cache file (.amf): a versioned, checksummed binary format.

Layout (little-endian)::

    magic      8 bytes   b"AMFCACHE"
    version    u32       FORMAT_VERSION
    header     u32 n, then n bytes of UTF-8 JSON: dimension, counts, attribute
               names and widths, free metadata
    payload    points (N*D float64), simplices (M*D int32), then each vertex
               attribute (N*c float64) and each simplex attribute (M*c int32)
               in header order, then (version 2) each named array of the
               header's "arrays" list ([name, dtype "<f8" or "<i4", rows,
               columns]) in that order
    checksum   u32       CRC-32 of every byte before it

Named arrays hold the hole space of a morph (§8.6.5): "hole_vertices"
(k, D-1) float64 and "hole_faces" (l, D-1) int32. A file is written with the
lowest version that describes it: version 1 when it has no named arrays (so
older readers still read it), version 2 otherwise. Version 1 files load as
before, with no hole space.

Writing is atomic (a temporary file beside the target, fsync, rename), so a
crash never leaves a half-written cache where a good one was. Reading checks
magic, version, sizes and checksum before touching the data and raises
:class:`CacheError` naming the file and the problem.
"""

from __future__ import annotations

import json
import os
import struct
import tempfile
import zlib
from pathlib import Path

import numpy as np

from ._core import Error
from .manifold import AnimationManifold

MAGIC = b"AMFCACHE"
FORMAT_VERSION = 2  # the newest version this module reads and writes
_ARRAY_TYPES = {"<f8": 8, "<i4": 4}
_PREFIX = struct.Struct("<8sII")  # magic, version, header length
_CHECKSUM = struct.Struct("<I")
_MAX_HEADER = 16 * 1024 * 1024


class CacheError(Error, ValueError):
    """A cache file is missing, damaged, truncated or from a newer version."""


def save(manifold: AnimationManifold, path: str | os.PathLike) -> Path:
    """Writes `manifold` to `path` atomically; returns the path."""
    path = Path(path)
    points = np.ascontiguousarray(manifold.points, dtype="<f8")
    simplices = np.ascontiguousarray(manifold.simplices, dtype="<i4")
    vattrs = {k: np.ascontiguousarray(v, dtype="<f8") for k, v in manifold.vertex_attributes.items()}
    sattrs = {k: np.ascontiguousarray(v, dtype="<i4") for k, v in manifold.simplex_attributes.items()}
    arrays = {}
    if manifold.hole_space is not None:
        arrays["hole_vertices"] = np.ascontiguousarray(manifold.hole_space[0], dtype="<f8")
        arrays["hole_faces"] = np.ascontiguousarray(manifold.hole_space[1], dtype="<i4")
    fields = {
        "dimension": int(points.shape[1]),
        "points": int(points.shape[0]),
        "simplices": int(simplices.shape[0]),
        "simplex_width": int(simplices.shape[1]),
        "vertex_attributes": [[k, int(v.shape[1])] for k, v in vattrs.items()],
        "simplex_attributes": [[k, int(v.shape[1])] for k, v in sattrs.items()],
        "metadata": manifold.metadata,
    }
    if arrays:
        fields["arrays"] = [[k, v.dtype.str, int(v.shape[0]), int(v.shape[1])] for k, v in arrays.items()]
    header = json.dumps(fields, sort_keys=True).encode("utf-8")
    version = 2 if arrays else 1

    chunks = [_PREFIX.pack(MAGIC, version, len(header)), header, points, simplices, *vattrs.values(), *sattrs.values(),
              *arrays.values()]
    checksum = 0
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            for chunk in chunks:
                view = memoryview(chunk).cast("B")
                checksum = zlib.crc32(view, checksum)
                f.write(view)
            f.write(_CHECKSUM.pack(checksum & 0xFFFFFFFF))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


def load(path: str | os.PathLike) -> AnimationManifold:
    """Reads a cache written by :func:`save`; raises CacheError when it is damaged."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise CacheError(f"cache file {path} does not exist") from None
    except OSError as e:
        raise CacheError(f"cache file {path} cannot be read: {e.strerror}") from None

    if len(data) < _PREFIX.size + _CHECKSUM.size:
        raise CacheError(f"cache file {path} is truncated ({len(data)} bytes)")
    magic, version, header_len = _PREFIX.unpack_from(data, 0)
    if magic != MAGIC:
        raise CacheError(f"{path} is not an animanifold cache (bad magic {magic!r})")
    if version > FORMAT_VERSION:
        raise CacheError(
            f"cache file {path} has format version {version}, newer than this animanifold reads "
            f"({FORMAT_VERSION}); update animanifold"
        )
    if version < 1:
        raise CacheError(f"cache file {path} has an invalid format version {version}")
    if header_len > min(_MAX_HEADER, len(data)):
        raise CacheError(f"cache file {path} is truncated or damaged (header of {header_len} bytes)")
    body_end = len(data) - _CHECKSUM.size
    (stored,) = _CHECKSUM.unpack_from(data, body_end)
    actual = zlib.crc32(memoryview(data)[:body_end]) & 0xFFFFFFFF
    if stored != actual:
        raise CacheError(f"cache file {path} is damaged or truncated (checksum {actual:08x}, expected {stored:08x})")

    try:
        header = json.loads(data[_PREFIX.size : _PREFIX.size + header_len].decode("utf-8"))
        D, N, M, W = (int(header[k]) for k in ("dimension", "points", "simplices", "simplex_width"))
        vspec = [(str(k), int(c)) for k, c in header["vertex_attributes"]]
        sspec = [(str(k), int(c)) for k, c in header["simplex_attributes"]]
        aspec = [(str(k), str(t), int(r), int(c)) for k, t, r, c in header.get("arrays", [])] if version >= 2 else []
        metadata = header.get("metadata", {})
    except (ValueError, KeyError, TypeError) as e:
        raise CacheError(f"cache file {path} has a damaged header: {e}") from None
    if D not in (3, 4) or W != D or min(N, M) < 0 or any(c < 1 for _, c in vspec + sspec):
        raise CacheError(f"cache file {path} has an inconsistent header (dimension {D}, simplex width {W})")
    if any(t not in _ARRAY_TYPES or r < 0 or c < 1 for _, t, r, c in aspec):
        raise CacheError(f"cache file {path} has an inconsistent header (named arrays {aspec})")

    offset = _PREFIX.size + header_len
    expected = offset + 8 * N * D + 4 * M * W + sum(8 * N * c for _, c in vspec) + sum(4 * M * c for _, c in sspec)
    expected += sum(_ARRAY_TYPES[t] * r * c for _, t, r, c in aspec)
    if expected != body_end:
        raise CacheError(f"cache file {path} is truncated or damaged ({body_end} bytes of data, header says {expected})")

    def take(dtype: str, rows: int, cols: int) -> np.ndarray:
        nonlocal offset
        count = rows * cols
        array = np.frombuffer(data, dtype=dtype, count=count, offset=offset).reshape(rows, cols)
        offset += array.nbytes
        return array

    points = take("<f8", N, D)
    simplices = take("<i4", M, W)
    vattrs = {k: take("<f8", N, c) for k, c in vspec}
    sattrs = {k: take("<i4", M, c) for k, c in sspec}
    arrays = {k: take(t, r, c) for k, t, r, c in aspec}
    hole_space = None
    if "hole_vertices" in arrays or "hole_faces" in arrays:
        if "hole_vertices" not in arrays or "hole_faces" not in arrays:
            raise CacheError(f"cache file {path} has half a hole space (hole_vertices and hole_faces go together)")
        hole_space = (arrays["hole_vertices"], arrays["hole_faces"])
    try:
        return AnimationManifold.from_arrays(points, simplices, vattrs, sattrs, metadata, hole_space)
    except ValueError as e:
        raise CacheError(f"cache file {path} holds an invalid manifold: {e}") from None
