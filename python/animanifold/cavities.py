"""Cavities of a closed surface: the parts of its boundary that enclose empty space inside
the solid (bubbles), told apart from the outer shells by their orientation."""

from __future__ import annotations

import numpy as np

from .indices import as_vertex_indices


def surface_components(vertex_count: int, faces: np.ndarray) -> np.ndarray:
    """A component label per face: faces sharing a vertex are in one component. Raises
    InputError for a face index that names no vertex.

    Union by hooking with numpy only: every vertex points at its component's root; each round
    hooks every root that a face side joins to another root under the smaller of the two, then
    compresses the pointers until each names a root. Components merge in every round or the
    next, so a frame of 100k faces takes a handful of rounds, where propagating labels along the
    faces would take as many as the surface is faces across."""
    faces = as_vertex_indices(faces, vertex_count, "the surface's faces").astype(np.int64)
    if len(faces) == 0:
        return np.zeros(0, dtype=np.int64)
    roots = np.arange(vertex_count, dtype=np.int64)
    one_end, other_end = faces.ravel(), np.roll(faces, -1, axis=1).ravel()  # the faces' sides
    while True:
        first, second = roots[one_end], roots[other_end]
        apart = first != second
        if not apart.any():
            return roots[faces[:, 0]]
        low, high = np.minimum(first[apart], second[apart]), np.maximum(first[apart], second[apart])
        np.minimum.at(roots, high, low)  # a root only ever points at a smaller one: no cycle
        while True:
            jumped = roots[roots]
            if np.array_equal(jumped, roots):
                break
            roots = jumped


def shell_volumes(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The signed volume enclosed by each connected shell of a closed, outward 3D surface:
    positive for outer shells, negative for cavities (their faces point into the bubble)."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = as_vertex_indices(faces, len(vertices), "the surface's faces").astype(np.int64)
    if len(faces) == 0:
        return np.zeros(0)
    _, shell = np.unique(surface_components(len(vertices), faces), return_inverse=True)
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    per_face = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    return np.bincount(shell, weights=per_face)


def cavities(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The volumes (positive) of the cavities of a closed, outward 3D surface, largest first."""
    volumes = shell_volumes(vertices, faces)
    return np.sort(-volumes[volumes < 0])[::-1]
