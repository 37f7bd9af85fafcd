"""2D inputs for the morph tests: closed polygons (points (n, 2), edges (n, 2)) and the
signed area of a 2D slice, whose sign tells the orientation."""

from __future__ import annotations

import numpy as np


def blob(n, radius, centre, wobble=0.0, lobes=3):
    """n points on a circle of the radius about centre, its radius waved by `lobes` lobes."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = radius * (1 + wobble * np.cos(lobes * a))
    return np.stack([centre[0] + r * np.cos(a), centre[1] + r * np.sin(a)], 1)


def polygons(*loops):
    """The loops (each (n_i, 2), in order) as one contour: points and closing edges."""
    points, edges, offset = [], [], 0
    for loop in loops:
        n = len(loop)
        points.append(loop)
        edges.append(np.stack([offset + np.arange(n), offset + (np.arange(n) + 1) % n], 1))
        offset += n
    return np.concatenate(points), np.concatenate(edges).astype(np.int32)


def polygon_area(s):
    """Signed area enclosed by a 2D slice's edges (positive when counter-clockwise)."""
    p, q = s.vertices[s.faces[:, 0]], s.vertices[s.faces[:, 1]]
    return 0.5 * np.sum(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0])
