"""Fuzzes the array entry points (stitch, slice, interval frames, refine, Deformer,
voronoi_skeleton, morph's input check, hole_space, subdivide_frame) with atheris, round-robin by
the input's first byte; see arrays_target.py for the input format and tests/fuzz/README.md for how
to run it. For example::

    python3 tests/fuzz/fuzz_arrays.py /tmp/arrays-corpus tests/fuzz/corpus/arrays -atheris_runs=100000 -rss_limit_mb=1024
"""

from __future__ import annotations

import os
import sys

sys.path[:0] = [os.path.join(os.path.dirname(__file__), "..", "..", "python"), os.path.dirname(__file__)]

import atheris  # noqa: E402

with atheris.instrument_imports(include=["animanifold"]):
    import animanifold  # noqa: E402,F401

from arrays_target import run_input  # noqa: E402


def test_one_input(data: bytes) -> None:
    run_input(data)


if __name__ == "__main__":
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()
