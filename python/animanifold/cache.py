"""The manifold cache file (.amf): a versioned, checksummed binary format.

Layout (little-endian)::

    magic      8 bytes   b"AMFCACHE"
    version    u32       FORMAT_VERSION
    header     u32 n, then n bytes of UTF-8 JSON: dimension, counts, attribute
               names and widths, free metadata; padded with spaces so the
               payload starts at a multiple of 8 bytes
    payload    points (N*D float64), simplices (M*D int32), then each vertex
               attribute (N*c float64) and each simplex attribute (M*c int32)
               in header order, then (version 2) each named array of the
               header's "arrays" list ([name, dtype "<f8" or "<i4", rows,
               columns]) in that order
    checksum   u32       CRC-32 of every byte before it

Named arrays hold the hole space of a morph (§8.6.5): "hole_vertices"
(k, D-1) float64 and "hole_faces" (l, D-1) int32; and the prisms of stitched
keyframes (prism_frames.py): "prism_times" (m, 1) float64,
"prism_key_vertices" (m, k), "prism_faces" (l, D-1), "prism_face_simplices"
(m-1, l) and "prism_gaps" (m-1, 1) int32. A file is written with the lowest
version that describes it: version 1 when it has no named arrays (so older
readers still read it), version 2 otherwise. Version 1 files, and version 2
files without the prism arrays (written before they existed), load as before,
with no hole space and no prisms: their frames between keys are the tets'
slices. Readers that predate the prism arrays skip them (they read every
named array and use the ones they know), so they still read the files this
writes.

Writing is atomic (atomic_file.py: a temporary file beside the target, fsync,
rename, fsync of the directory), so a crash never leaves a half-written cache
where a good one was; devices, FIFOs and directories at the path are refused,
symbolic links followed.

Reading treats the file as hostile: it refuses what is not a regular file
before reading, reads the fixed prefix, then the header (bounded in size and
nesting, every field checked: cache_format.py), compares the size the header
implies with the file's before allocating anything, and checks the CRC before
the data is used. Every problem is a :class:`CacheError` naming the file.
Arrays reach the core aligned: views of the read buffer where the payload is
aligned (every 4D cache this module writes), copies where it is not (older
files, or int32 tables of odd length in a 3D cache).
"""

from __future__ import annotations

import io
import os
import stat
import zlib
from pathlib import Path

import numpy as np

from ._core import Error
from .atomic_file import describe_mode, replacing
from .cache_format import (ARRAY_TYPES, CHECKSUM, FORMAT_VERSION, MAGIC, PREFIX, CacheError, Layout, check_prefix,
                           pack_prefix, padded_header, parse_header)
from .manifold import AnimationManifold
from .prism_frames import Prisms

__all__ = ["CacheError", "FORMAT_VERSION", "MAGIC", "load", "save"]


def save(manifold: AnimationManifold, path: str | os.PathLike) -> Path:
    """Writes `manifold` to `path` atomically; returns the path it was given.

    Throws: atomic_file.OutputPathError when `path` is a device, FIFO or directory; OSError
    when the file system fails (a full disk included), leaving what was at `path` untouched.
    """
    path = Path(path)
    version, chunks = _chunks(manifold)
    with replacing(path) as temporary, open(temporary, "wb") as f:
        checksum = 0
        for chunk in chunks:
            view = memoryview(chunk).cast("B")
            checksum = zlib.crc32(view, checksum)
            f.write(view)
        f.write(CHECKSUM.pack(checksum & 0xFFFFFFFF))
        f.flush()
        os.fsync(f.fileno())
    return path


def _chunks(manifold: AnimationManifold) -> tuple[int, list]:
    """(format version, the file's pieces before the checksum)."""
    points = np.ascontiguousarray(manifold.points, dtype="<f8")
    simplices = np.ascontiguousarray(manifold.simplices, dtype="<i4")
    vattrs = {k: np.ascontiguousarray(v, dtype="<f8") for k, v in manifold.vertex_attributes.items()}
    sattrs = {k: np.ascontiguousarray(v, dtype="<i4") for k, v in manifold.simplex_attributes.items()}
    arrays = {}
    if manifold.hole_space is not None:
        arrays["hole_vertices"] = np.ascontiguousarray(manifold.hole_space[0], dtype="<f8")
        arrays["hole_faces"] = np.ascontiguousarray(manifold.hole_space[1], dtype="<i4")
    if manifold.prisms is not None:
        for name, table in manifold.prisms.arrays().items():
            arrays[name] = np.ascontiguousarray(table, dtype="<f8" if table.dtype.kind == "f" else "<i4")
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
    header = padded_header(fields)
    version = 2 if arrays else 1  # the lowest version that describes it, so older readers read it
    return version, [pack_prefix(version, header), header, points, simplices, *vattrs.values(), *sattrs.values(),
                     *arrays.values()]


def load(path: str | os.PathLike) -> AnimationManifold:
    """Reads a cache written by :func:`save`; raises CacheError when it is missing, damaged or hostile."""
    path = Path(path)
    with _open_regular_file(path) as f:
        layout, data, offset = _read(path, f)
    tables = [_table(data, dtype, rows, cols, start) for start, (_, dtype, rows, cols) in zip(offset, layout.tables())]
    return _manifold(path, layout, tables)


def _open_regular_file(path: Path) -> io.RawIOBase:
    """The file opened unbuffered; CacheError, before any read, when it is missing or not a
    regular file (a FIFO would block, /dev/zero never end, a directory not read)."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)  # O_NONBLOCK: opening a FIFO must not wait for a writer
    except FileNotFoundError:
        raise CacheError(f"cache file {path} does not exist") from None
    except OSError as e:
        raise CacheError(f"cache file {path} cannot be read: {e.strerror}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise CacheError(f"cache file {path} is {describe_mode(mode)}, not a regular file")
    return os.fdopen(fd, "rb", buffering=0)


def _read(path: Path, f: io.RawIOBase) -> tuple[Layout, np.ndarray, list[int]]:
    """(the header's layout, the whole file in a fresh buffer, each table's offset), all checked."""
    size = os.fstat(f.fileno()).st_size
    version, header_len = check_prefix(path, _read_at(path, f, 0, PREFIX.size), size)
    layout = parse_header(path, _read_at(path, f, PREFIX.size, header_len), version)
    start = PREFIX.size + header_len
    expected = start + layout.payload_bytes() + CHECKSUM.size
    if expected != size:
        raise CacheError(f"cache file {path} is truncated or damaged ({size - CHECKSUM.size} bytes of data, header "
                         f"says {expected - CHECKSUM.size})")
    try:
        data = np.empty(size, dtype=np.uint8)  # numpy's allocation is aligned for float64
    except MemoryError:
        raise CacheError(f"cache file {path} ({size:,} bytes) does not fit in the memory left") from None
    _read_into(path, f, data)
    (stored,) = CHECKSUM.unpack_from(data, size - CHECKSUM.size)
    actual = zlib.crc32(memoryview(data)[: size - CHECKSUM.size]) & 0xFFFFFFFF
    if stored != actual:
        raise CacheError(f"cache file {path} is damaged or truncated (checksum {actual:08x}, expected {stored:08x})")
    offsets = []
    for _, dtype, rows, cols in layout.tables():
        offsets.append(start)
        start += ARRAY_TYPES[dtype] * rows * cols
    return layout, data, offsets


def _read_at(path: Path, f: io.RawIOBase, offset: int, count: int) -> bytes:
    raw = bytearray(count)
    _read_into(path, f, raw, offset)
    return bytes(raw)


def _read_into(path: Path, f: io.RawIOBase, buffer, offset: int = 0) -> None:
    """Fills `buffer` from the file's byte `offset` on; CacheError when the file ends first."""
    view, done = memoryview(buffer).cast("B"), 0
    try:
        f.seek(offset)
        while done < len(view):  # one read returns at most ~2 GiB
            got = f.readinto(view[done:])
            if not got:
                raise CacheError(f"cache file {path} is truncated ({offset + done} bytes)")
            done += got
    except OSError as e:
        raise CacheError(f"cache file {path} cannot be read: {e.strerror}") from None


def _table(data: np.ndarray, dtype: str, rows: int, cols: int, offset: int) -> np.ndarray:
    """A (rows, cols) table of the buffer: a view when aligned, else an aligned copy."""
    table = data[offset : offset + ARRAY_TYPES[dtype] * rows * cols].view(dtype).reshape(rows, cols)
    return table if table.flags.aligned else table.copy()


def _manifold(path: Path, layout: Layout, tables: list[np.ndarray]) -> AnimationManifold:
    points, simplices, *rest = tables
    vattrs = {k: rest.pop(0) for k, _ in layout.vertex_attributes}
    sattrs = {k: rest.pop(0) for k, _ in layout.simplex_attributes}
    arrays = {k: table for (k, *_), table in zip(layout.arrays, rest)}
    hole_space = None
    if "hole_vertices" in arrays or "hole_faces" in arrays:
        if "hole_vertices" not in arrays or "hole_faces" not in arrays:
            raise CacheError(f"cache file {path} has half a hole space (hole_vertices and hole_faces go together)")
        hole_space = (arrays["hole_vertices"], arrays["hole_faces"])
    try:
        prisms = Prisms.from_arrays(arrays)
        return AnimationManifold.from_arrays(points, simplices, vattrs, sattrs, layout.metadata, hole_space, prisms)
    except (Error, ValueError, TypeError) as e:
        raise CacheError(f"cache file {path} holds an invalid manifold: {' '.join(str(e).split())}") from None
