"""Small cuts and frames of live playback (animanifold.interval_cuts) for the tests of the
cuts and of their cache: zero arrays of the right shapes and types."""

from __future__ import annotations

import numpy as np

from animanifold import interval_cuts


def cut(corners: int = 6) -> interval_cuts.Cut:
    """An interval cut of `corners` vertices, one per corner, with UVs and rates."""
    faces = np.arange(corners, dtype=np.int32).reshape(-1, 3)
    uv = np.zeros((corners, 3), np.float32)
    return interval_cuts.Cut(5.0, faces, None, None, np.zeros((corners, 3), np.float32),
                             np.zeros(2 * corners, np.float32), rate=np.zeros((corners, 3), np.float32),
                             uv=uv, uv_rate=np.ones((corners, 3), np.float32))


def frame(value: float, corners: int = 6) -> interval_cuts.Frame:
    """A frame of such a cut at `value`."""
    return interval_cuts.Frame(value, np.zeros(3 * corners, np.float32), np.zeros(2 * corners, np.float32))
