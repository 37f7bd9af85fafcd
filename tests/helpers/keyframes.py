"""A keyframed animation for the stitch, slice and cache tests: a sphere that travels,
squashes and twists, at times that are not uniform (so no code may assume a fixed step)."""

from __future__ import annotations

import numpy as np

TIMES = np.array([0.0, 0.3, 1.0, 1.1, 2.5])  # not uniform


def wobble(vertices: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Keyframes of a shape that travels, squashes and twists: (m, k, 3)."""
    frames = []
    for t in times:
        v = vertices * [1 + 0.3 * np.sin(3 * t), 1 - 0.2 * t, 1 + 0.1 * t]
        c, s = np.cos(0.7 * t), np.sin(0.7 * t)
        v = v @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + [0.5 * t, 0.2 * t * t, 0]
        frames.append(v)
    return np.stack(frames)
