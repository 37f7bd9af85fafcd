"""The .amf cache's fixed prefix and JSON header: parsed and checked before any payload is read.

Everything here treats the file as hostile: the header is bounded in size and in nesting
depth before ``json`` sees it (the C scanner recurses once per level), every field's type
and range is checked, and the byte count the header implies is computed with Python's
unbounded integers and compared with the file's real size, so no count in a header can make
the reader allocate more than the file holds. Every problem is a :class:`CacheError` that
names the file.
"""

from __future__ import annotations

import dataclasses
import json
import re
import struct

import numpy as np

from ._core import Error

MAGIC = b"AMFCACHE"
FORMAT_VERSION = 2  # the newest version this module reads and writes
ARRAY_TYPES = {"<f8": 8, "<i4": 4}
PREFIX = struct.Struct("<8sII")  # magic, version, header length
CHECKSUM = struct.Struct("<I")
MAX_HEADER = 16 * 1024 * 1024
MAX_NESTING = 64  # JSON levels; the reader's own fields use 3, metadata gets the rest
PAYLOAD_ALIGNMENT = 8  # save() pads the header with spaces so the payload starts here

_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"', re.DOTALL)


class CacheError(Error, ValueError):
    """A cache file is missing, damaged, truncated or from a newer version."""


@dataclasses.dataclass(frozen=True)
class Layout:
    """What the header says the payload holds, in payload order."""

    dimension: int
    points: int
    simplices: int
    vertex_attributes: list[tuple[str, int]]
    simplex_attributes: list[tuple[str, int]]
    arrays: list[tuple[str, str, int, int]]  # name, dtype, rows, columns
    metadata: dict

    def tables(self) -> list[tuple[str, str, int, int]]:
        """(kind, dtype, rows, columns) of every payload table in file order; kind names it in messages."""
        D, N, M = self.dimension, self.points, self.simplices
        return [
            ("points", "<f8", N, D),
            ("simplices", "<i4", M, D),
            *((f"vertex attribute {k!r}", "<f8", N, c) for k, c in self.vertex_attributes),
            *((f"simplex attribute {k!r}", "<i4", M, c) for k, c in self.simplex_attributes),
            *((f"array {k!r}", t, r, c) for k, t, r, c in self.arrays),
        ]

    def payload_bytes(self) -> int:
        return sum(ARRAY_TYPES[t] * r * c for _, t, r, c in self.tables())


def pack_prefix(version: int, header: bytes) -> bytes:
    return PREFIX.pack(MAGIC, version, len(header))


def padded_header(fields: dict) -> bytes:
    """The header's JSON, padded with spaces (still valid JSON, so older readers read it) so the
    payload starts on an 8-byte boundary and the arrays of a 4D manifold are loaded aligned."""
    header = json.dumps(fields, sort_keys=True).encode("utf-8")
    return header + b" " * (-(PREFIX.size + len(header)) % PAYLOAD_ALIGNMENT)


def check_prefix(path, prefix: bytes, file_bytes: int) -> tuple[int, int]:
    """(version, header length) from the file's first bytes; raises CacheError when they are wrong."""
    if file_bytes < PREFIX.size + CHECKSUM.size or len(prefix) < PREFIX.size:
        raise CacheError(f"cache file {path} is truncated ({file_bytes} bytes)")
    magic, version, header_len = PREFIX.unpack_from(prefix, 0)
    if magic != MAGIC:
        raise CacheError(f"{path} is not an animanifold cache (bad magic {magic!r})")
    if version > FORMAT_VERSION:
        raise CacheError(
            f"cache file {path} has format version {version}, newer than this animanifold reads "
            f"({FORMAT_VERSION}); update animanifold"
        )
    if version < 1:
        raise CacheError(f"cache file {path} has an invalid format version {version}")
    if header_len > min(MAX_HEADER, file_bytes - PREFIX.size - CHECKSUM.size):
        raise CacheError(f"cache file {path} is truncated or damaged (header of {header_len} bytes)")
    return version, header_len


def parse_header(path, raw: bytes, version: int) -> Layout:
    """The header's JSON checked field by field; raises CacheError naming the first bad field."""
    depth = nesting_depth(raw)
    if depth > MAX_NESTING:
        raise CacheError(f"cache file {path} has a damaged header: nested {depth} levels deep (at most {MAX_NESTING})")
    try:
        header = json.loads(raw.decode("utf-8"))
    except (ValueError, RecursionError) as e:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
        raise CacheError(f"cache file {path} has a damaged header: {e}") from None
    fields = _Fields(path, header)
    dimension = fields.count("dimension", low=3, high=4)
    fields.count("simplex_width", low=dimension, high=dimension)  # simplices have D corners
    return Layout(
        dimension=dimension,
        points=fields.count("points"),
        simplices=fields.count("simplices"),
        vertex_attributes=fields.named_widths("vertex_attributes"),
        simplex_attributes=fields.named_widths("simplex_attributes"),
        arrays=fields.named_arrays() if version >= 2 else [],
        metadata=fields.metadata(),
    )


def nesting_depth(raw: bytes) -> int:
    """The deepest nesting of [ and { outside JSON strings (an upper bound when a string is unterminated)."""
    codes = np.frombuffer(_STRING.sub(b'""', raw), dtype=np.uint8)
    steps = np.isin(codes, (ord("["), ord("{"))).astype(np.int64) - np.isin(codes, (ord("]"), ord("}")))
    return int(np.cumsum(steps).max(initial=0))


class _Fields:
    """Typed access to the header's fields; every failure is a CacheError naming the field."""

    def __init__(self, path, header: object):
        if not isinstance(header, dict):
            self.fail(path, "the header", f"is a JSON {type(header).__name__}, not an object")
        self.path, self.header = path, header

    @staticmethod
    def fail(path, field: str, problem: str):
        raise CacheError(f"cache file {path} has a damaged header: {field} {problem}")

    def count(self, key: str, low: int = 0, high: int | None = None) -> int:
        if key not in self.header:
            self.fail(self.path, f"field {key!r}", "is missing")
        return self.integer(f"field {key!r}", self.header[key], low, high)

    def integer(self, field: str, value: object, low: int, high: int | None = None) -> int:
        if type(value) is not int:  # bool is an int subclass, and floats would be truncated
            self.fail(self.path, field, f"must be an integer, got {_shown(value)}")
        if value < low or (high is not None and value > high):
            bounds = f"{low}..{high}" if high is not None else f">= {low}"
            self.fail(self.path, field, f"is {value}, outside {bounds}")
        return value

    def entries(self, key: str, width: int, required: bool = True) -> list[list]:
        value = self.header.get(key, None if required else [])
        if not isinstance(value, list):
            self.fail(self.path, f"field {key!r}", f"must be a list, got {_shown(value)}")
        for i, entry in enumerate(value):
            if not (isinstance(entry, list) and len(entry) == width and isinstance(entry[0], str)):
                self.fail(self.path, f"{key}[{i}]", f"must be a list of a name and {width - 1} values, got {_shown(entry)}")
        names = [entry[0] for entry in value]
        if len(set(names)) != len(names):
            self.fail(self.path, f"field {key!r}", f"names an entry twice: {names}")
        return value

    def named_widths(self, key: str) -> list[tuple[str, int]]:
        return [(name, self.integer(f"{key}[{i}] width", c, 1)) for i, (name, c) in enumerate(self.entries(key, 2))]

    def named_arrays(self) -> list[tuple[str, str, int, int]]:
        arrays = []
        for i, (name, dtype, rows, cols) in enumerate(self.entries("arrays", 4, required=False)):
            if dtype not in ARRAY_TYPES:
                self.fail(self.path, f"arrays[{i}] type", f"must be one of {sorted(ARRAY_TYPES)}, got {_shown(dtype)}")
            arrays.append((name, dtype, self.integer(f"arrays[{i}] rows", rows, 0),
                           self.integer(f"arrays[{i}] columns", cols, 1)))
        return arrays

    def metadata(self) -> dict:
        value = self.header.get("metadata", {})
        if not isinstance(value, dict):
            self.fail(self.path, "field 'metadata'", f"must be an object, got {_shown(value)}")
        return value


def _shown(value: object) -> str:
    text = json.dumps(value) if isinstance(value, (int, float, str, bool, type(None))) else type(value).__name__
    return text if len(text) <= 40 else text[:37] + "..."
