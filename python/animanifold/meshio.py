"""Mesh files (OFF, OBJ, PLY, STL) through CGAL's IO in the core."""

from __future__ import annotations

import os

import numpy as np

from . import _core
from .indices import as_indices


def read_mesh(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (k, 3) float64, triangles (l, 3) int32); polygons are fan-split."""
    vertices, faces, _ = _core.read_mesh(os.fspath(path))
    return vertices, faces


def write_mesh(path: str | os.PathLike, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Writes a triangle mesh; the format comes from the extension (.obj, .ply, .off, .stl)."""
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must be (k, 3), got shape {vertices.shape}")
    _core.write_mesh(os.fspath(path), vertices, as_indices(faces, "faces"))
