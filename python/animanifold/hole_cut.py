"""Frames cut by a morph's hole space (validity 3 of §8.3), keeping their attributes.

A morph that carries its inputs' UV maps (morph_surface.py) has its vertices split where the
charts differ, so its raw frames are split along those seams: open surfaces, which a boolean
cannot cut. The copies are welded for the cut, and the cut frame takes its attributes back from
the raw frame: every face from the raw face it lies in (or, on the hole's walls, the raw face
nearest to it), its corners' vertex attributes interpolated in that face (continued past its
edges on the walls). Its vertices are then split again where their corners' values differ, so
the seams come back where they were.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _core
from .barycentric import plane_barycentric
from .seams import weld_copies

# Corner values that agree to this share of their magnitude (and absolutely, near zero) are one
# vertex's: interpolating one chart from neighbouring raw faces differs only by rounding.
_SAME_VALUE = 1e-9


@dataclass
class CutFrame:
    vertices: np.ndarray
    faces: np.ndarray
    vertex_attributes: dict
    face_attributes: dict


def cut_frame(vertices: np.ndarray, faces: np.ndarray, vertex_attributes: dict, face_attributes: dict,
              hole: tuple[np.ndarray, np.ndarray]) -> CutFrame | None:
    """frame \\ hole, with the frame's attributes carried (see the module doc); None when the hole
    cannot touch the frame (the frame is then its own cut). Raises _core.BooleanError when the
    frame cannot be cut."""
    weld = weld_copies(vertices, faces)
    kept, welded_faces = weld if weld is not None else (np.arange(len(vertices)), faces)
    cut_vertices, cut_faces, unchanged = _core.subtract_solid(np.ascontiguousarray(vertices[kept]),
                                                              np.ascontiguousarray(welded_faces, dtype=np.int32),
                                                              hole[0], hole[1])
    if unchanged:
        return None
    if not len(cut_faces) or not (vertex_attributes or face_attributes):
        return CutFrame(cut_vertices, cut_faces, {}, {})
    source = _raw_faces_under(cut_vertices, cut_faces, vertices[kept], welded_faces)
    carried_faces = {name: np.asarray(table)[source] for name, table in face_attributes.items()}
    if not vertex_attributes:
        return CutFrame(cut_vertices, cut_faces, {}, carried_faces)
    corners = cut_vertices[cut_faces]  # (f, 3, 3)
    weights = plane_barycentric(corners, vertices[faces[source]])  # (f, 3 corners, 3 raw corners)
    names = list(vertex_attributes)
    tables = [np.asarray(vertex_attributes[n], dtype=np.float64).reshape(len(vertices), -1) for n in names]
    values = np.concatenate([np.einsum("fkc,fcd->fkd", weights, table[faces[source]]) for table in tables], axis=2)
    split_vertices, split_faces, vertex_values = _split_by_corner_values(cut_vertices, cut_faces, values)
    carried_vertices, column = {}, 0
    for name, table in zip(names, tables):
        width = table.shape[1]
        carried = vertex_values[:, column:column + width]
        carried_vertices[name] = carried[:, 0] if np.asarray(vertex_attributes[name]).ndim == 1 else carried
        column += width
    return CutFrame(split_vertices, split_faces, carried_vertices, carried_faces)


def _raw_faces_under(cut_vertices: np.ndarray, cut_faces: np.ndarray, raw_vertices: np.ndarray,
                     raw_faces: np.ndarray) -> np.ndarray:
    """The raw face each cut face lies in (the one nearest to its centre)."""
    centres = np.ascontiguousarray(cut_vertices[cut_faces].mean(axis=1))
    return _core.closest_points(centres, np.ascontiguousarray(raw_vertices),
                                np.ascontiguousarray(raw_faces, dtype=np.int32))[1].astype(np.int64)


def _split_by_corner_values(vertices: np.ndarray, faces: np.ndarray,
                            values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One vertex per (vertex, corner value): (vertices, faces, per-vertex values)."""
    corner_vertex = faces.reshape(-1).astype(np.int64)
    corner_values = values.reshape(len(corner_vertex), -1)
    scale = np.maximum(np.abs(corner_values).max(axis=0), 1.0)
    rounded = np.round(corner_values / (_SAME_VALUE * scale)).astype(np.int64)
    key = np.column_stack([corner_vertex, rounded])
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = np.asarray(inverse).reshape(-1)
    return vertices[corner_vertex[first]], inverse.reshape(faces.shape).astype(np.int32), corner_values[first]
