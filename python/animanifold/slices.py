"""A frame: the iso-slice of an animation manifold at one value along one axis."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from . import _core


class _NormalsOnFirstRead:
    """The Slice field `normals`, given as None by a maker that has none at hand (a prism
    frame): computed from the faces when first read and kept. Playback of a live object
    reads positions and the carried source normals only, and skips their cost."""

    def __get__(self, frame, owner=None):
        if frame is None:
            raise AttributeError("normals")  # dataclasses: the field has no default
        normals = frame.__dict__["normals"]
        if normals is None:
            normals = _core.frame_vertex_normals(frame.vertices, frame.faces)
            frame.__dict__["normals"] = normals
        return normals

    def __set__(self, frame, normals) -> None:
        frame.__dict__["normals"] = normals  # only the dataclass's __init__ gets here (frozen)


@dataclass(frozen=True)
class Slice:
    """One frame: the iso-slice of a manifold at `value` along `axis`.

    vertices (P, D-1) are the coordinates other than the slicing axis, in
    order; faces (F, 3) triangles — (F, 2) segments for 2D animations —
    oriented like the keyframes; normals (P, D-1) unit smooth normals (a maker
    may give None: they are then computed when first read).
    vertex_edges (P, 2) and edge_parameter (P,) say which manifold edge each
    vertex lies on (a == b for a manifold vertex); face_simplex (F,) which
    manifold simplex each face was cut from.
    """

    axis: int
    value: float
    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray = _NormalsOnFirstRead()  # None when made: computed on first read
    vertex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)
    face_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)
    vertex_edges: np.ndarray | None = None
    edge_parameter: np.ndarray | None = None
    face_simplex: np.ndarray | None = None

    @classmethod
    def _from_core(cls, axis: int, value: float, s: "_core.Slice") -> "Slice":
        return cls(
            axis=axis,
            value=value,
            vertices=s.vertices,
            faces=s.faces,
            normals=s.normals,
            vertex_attributes={k: squeezed(v) for k, v in s.vertex_attributes.items()},
            face_attributes={k: squeezed(v) for k, v in s.face_attributes.items()},
            vertex_edges=s.vertex_edges,
            edge_parameter=s.edge_parameter,
            face_simplex=s.face_simplex,
        )


def squeezed(table: np.ndarray) -> np.ndarray:
    """An attribute table of one column as a vector (as the Python API hands them out)."""
    table = np.asarray(table)
    return table[:, 0] if table.ndim == 2 and table.shape[1] == 1 else table
