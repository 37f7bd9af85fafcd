"""Barycentric coordinates of points in triangles, vectorised over many (numpy): in a triangle's
plane, and of the closest point in the triangle."""

from __future__ import annotations

import numpy as np


def plane_barycentric(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (f, k, 3) of points (f, k, 3) projected onto the planes of
    triangles (f, 3, 3), not clamped to the triangles: each face's linear map continued past its
    edges. A degenerate triangle gives its first corner."""
    a, b, c = (triangles[:, i][:, None] for i in range(3))
    normal = np.cross(b - a, c - a)
    area2 = np.sum(normal * normal, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        wa = np.sum(np.cross(c - b, points - b) * normal, axis=-1) / area2
        wb = np.sum(np.cross(a - c, points - c) * normal, axis=-1) / area2
    weights = np.stack([wa, wb, 1 - wa - wb], axis=-1)
    weights[~np.isfinite(weights).all(axis=-1)] = [1.0, 0.0, 0.0]
    return weights


def closest_in_triangles(p: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric coordinates (n, 3) and distance (n,) of the closest point to each p[k] in the
    triangle triangles[k] (n, 3, 3), by the regions of Ericson's Real-Time Collision Detection §5.1.5."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, ac, ap = b - a, c - a, p - a
    dot = lambda x, y: np.einsum("ij,ij->i", x, y)  # noqa: E731
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp, cp = p - b, p - c
    d3, d4, d5, d6 = dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    w = np.zeros((len(p), 3))
    with np.errstate(divide="ignore", invalid="ignore"):
        inside = 1.0 / (va + vb + vc)
        w[:] = np.column_stack([1 - (vb + vc) * inside, vb * inside, vc * inside])  # interior
        edge = {  # barycentric coordinates on an edge, s along it
            "ab": lambda s: np.column_stack([1 - s, s, np.zeros_like(s)]),
            "ac": lambda s: np.column_stack([1 - s, np.zeros_like(s), s]),
            "bc": lambda s: np.column_stack([np.zeros_like(s), 1 - s, s]),
        }
        corner = lambda k: lambda s: np.tile(np.eye(3)[k], (len(s), 1))  # noqa: E731
        # Ericson's tests in reverse, each overriding the ones after it, as his early exits do.
        regions = [
            ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), edge["bc"], (d4 - d3) / ((d4 - d3) + (d5 - d6))),
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), edge["ac"], d2 / (d2 - d6)),
            ((d6 >= 0) & (d5 <= d6), corner(2), d6),
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), edge["ab"], d1 / (d1 - d3)),
            ((d3 >= 0) & (d4 <= d3), corner(1), d3),
            ((d1 <= 0) & (d2 <= 0), corner(0), d1),
        ]
        for where, weights, s in regions:
            if where.any():
                w[where] = weights(s[where])
    w[~np.isfinite(w).all(axis=1)] = [1.0, 0.0, 0.0]  # a degenerate triangle: its first corner
    closest = np.einsum("ij,ijk->ik", w, triangles)
    return w, np.linalg.norm(closest - p, axis=1)
