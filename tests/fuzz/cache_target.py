"""The cache reader's fuzz target, shared by the atheris harness (fuzz_cache.py) and the
pytest replay of the corpora (tests/test_fuzz_corpus.py).

An input's first byte picks how the rest is used: even, as the file's bytes unchanged (most
mutations then fail the checksum, as random damage does); odd, as the file without its last
four bytes, the CRC-32 appended, so mutations reach the header and payload checks as a
hostile file with a valid checksum would. The only allowed outcomes are a manifold or a
CacheError; anything else (another exception, a crash, a hang, an allocation beyond the
file's size) is a finding.
"""

from __future__ import annotations

import os
import struct
import zlib

import animanifold as am


def file_bytes(data: bytes) -> bytes:
    """The file an input stands for (rule in the module doc)."""
    if not data:
        return b""
    body = data[1:]
    if data[0] % 2 == 0:
        return body
    body = body[:-4] if len(body) >= 4 else body
    return body + struct.pack("<I", zlib.crc32(body))


def load_input(data: bytes, path: str) -> am.AnimationManifold | None:
    """Loads the input's file from `path`; None when the reader refuses it with a CacheError."""
    with open(path, "wb") as f:
        f.write(file_bytes(data))
    try:
        return am.load(path)
    except am.CacheError:
        return None


def seed(file: bytes, fix_checksum: bool = True) -> bytes:
    """The input that stands for a file (with its checksum recomputed by the target when asked)."""
    return (b"\x01" if fix_checksum else b"\x00") + file


def scratch_path() -> str:
    """A file in memory where there is one (/dev/shm), written once per execution."""
    folder = "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else "/tmp"
    return os.path.join(folder, f"animanifold-fuzz-{os.getpid()}.amf")
