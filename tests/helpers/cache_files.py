"""Hand-made .amf files for the cache reader's tests and fuzzers: valid checksums over
whatever header and payload a test wants, so the reader's later checks are reached."""

from __future__ import annotations

import json
import struct
import zlib

import numpy as np

import animanifold as am
from helpers.keyframes import TIMES, wobble
from helpers.shapes import icosphere


def small_manifold(prisms: bool = False) -> am.AnimationManifold:
    """A 4D manifold with one vertex and one simplex attribute (240 tets); without its prisms
    (the default) it saves as a version 1 file, with them as version 2 with named arrays."""
    v, f = icosphere(1)
    m = am.stitch(wobble(v, TIMES[:2]), f, TIMES[:2], vertex_attributes={"uv": v[:, :2] / 3.0},
                  face_attributes={"material_index": np.arange(len(f)) % 3})
    return m if prisms else am.AnimationManifold(m.core_complex, m.metadata)


def with_checksum(body: bytes) -> bytes:
    return body + struct.pack("<I", zlib.crc32(body))


def split(data: bytes) -> tuple[int, dict, bytes]:
    """(version, header, payload) of a cache file's bytes."""
    _, version, header_len = struct.unpack_from("<8sII", data, 0)
    return version, json.loads(data[16 : 16 + header_len]), data[16 + header_len : -4]


def assemble(version: int, header: dict | bytes, payload: bytes) -> bytes:
    """A cache file of this header (a dict, or raw bytes) and payload, with a valid checksum."""
    raw = header if isinstance(header, bytes) else json.dumps(header).encode()
    return with_checksum(struct.pack("<8sII", b"AMFCACHE", version, len(raw)) + raw + payload)
