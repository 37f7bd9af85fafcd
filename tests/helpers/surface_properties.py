"""Properties of a triangle surface that the tests assert on frames: closed and consistently
oriented, its Euler characteristic (genus), the volume it encloses."""

from __future__ import annotations

import numpy as np


def edges_of(faces: np.ndarray) -> np.ndarray:
    """The directed edges of the triangles, (3 l, 2)."""
    return np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])


def assert_closed_oriented_surface(faces: np.ndarray) -> None:
    """Every directed edge appears once and its reverse once: closed, 2-manifold, consistently oriented."""
    directed = edges_of(faces)
    assert len(np.unique(directed, axis=0)) == len(directed), "an edge is used twice in the same direction"
    forward = {tuple(e) for e in directed}
    assert all((b, a) in forward for a, b in directed), "an edge has no opposite: the slice has a hole"


def euler_characteristic(faces: np.ndarray) -> int:
    """V - E + F over the vertices the faces use."""
    edges = np.unique(np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1), axis=0)
    return len(np.unique(faces)) - len(edges) + len(faces)


def enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume enclosed by a closed surface (positive when its normals point out)."""
    tri = vertices[faces]
    return float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6)
