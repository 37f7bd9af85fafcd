"""Resident memory does not grow with use: slicing a manifold 2,000 times ends at the same
resident set size as slicing it 200 times (within 5 %), so nothing a slice allocates — frames,
the slicer's index, the hole cut, the Python wrappers — is kept. Linux only (/proc/self/statm)."""

from __future__ import annotations

import gc
import os

import numpy as np
import pytest

import animanifold as am
from helpers.keyframes import TIMES, wobble
from helpers.shapes import icosphere

pytestmark = pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="reads RSS from /proc/self/statm (Linux)")


def resident_bytes() -> int:
    gc.collect()
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def slice_loop(manifold: am.AnimationManifold, count: int) -> int:
    """Slices `count` frames spread over the time range (every interval visited); the RSS after."""
    low, high = manifold.time_range
    for t in np.linspace(low, high, count):
        frame = manifold.slice(float(t))
        assert len(frame.faces) > 0
    return resident_bytes()


def test_2000_slices_end_at_the_resident_size_of_200():
    v, f = icosphere(2)
    manifold = am.stitch(wobble(v, TIMES), f, TIMES, vertex_attributes={"uv": v[:, :2]})
    slice_loop(manifold, 200)  # warm up: the slicer's index, numpy's and the allocator's pools
    after_200 = slice_loop(manifold, 200)
    after_2000 = slice_loop(manifold, 2000)
    assert after_2000 <= after_200 * 1.05, f"RSS grew from {after_200 / 2**20:.1f} to {after_2000 / 2**20:.1f} MiB"
