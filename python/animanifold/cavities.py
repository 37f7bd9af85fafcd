"""Cavities of a closed surface: the parts of its boundary that enclose empty space inside
the solid (bubbles), told apart from the outer shells by their orientation."""

from __future__ import annotations

import numpy as np

from .indices import as_vertex_indices


def surface_components(vertex_count: int, faces: np.ndarray) -> np.ndarray:
    """A component label per face: faces sharing a vertex are in one component (label
    propagation with pointer jumping; numpy only). Raises InputError for a face index that names
    no vertex."""
    faces = as_vertex_indices(faces, vertex_count, "the surface's faces").astype(np.int64)
    labels = np.arange(vertex_count, dtype=np.int64)
    if len(faces) == 0:
        return np.zeros(0, dtype=np.int64)
    while True:
        smallest = labels[faces].min(axis=1)
        before = labels.copy()
        for c in range(faces.shape[1]):
            np.minimum.at(labels, faces[:, c], smallest)
        labels = labels[labels]  # jump towards each component's root
        if np.array_equal(labels, before):
            break
    return labels[faces[:, 0]]


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
