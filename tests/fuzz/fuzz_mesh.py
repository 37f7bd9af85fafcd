"""Fuzzes the mesh reader (animanifold.read_mesh) with atheris; see mesh_target.py for the
input format and tests/fuzz/README.md for how to run it. For example::

    python3 tests/fuzz/fuzz_mesh.py /tmp/mesh-corpus tests/fuzz/corpus/mesh -atheris_runs=100000 -rss_limit_mb=1024
"""

from __future__ import annotations

import os
import sys
import tempfile

sys.path[:0] = [os.path.join(os.path.dirname(__file__), "..", "..", "python"), os.path.dirname(__file__)]

import atheris  # noqa: E402

with atheris.instrument_imports(include=["animanifold"]):
    import animanifold  # noqa: E402,F401

from mesh_target import read_input  # noqa: E402

FOLDER = tempfile.mkdtemp(prefix="animanifold-fuzz-mesh-", dir="/dev/shm" if os.path.isdir("/dev/shm") else None)


def test_one_input(data: bytes) -> None:
    read_input(data, FOLDER)


if __name__ == "__main__":
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()
