"""Smoothing one frame: subdivision of a frame mesh (§10.3.1).

:func:`subdivide_frame` refines one frame mesh with OpenSubdiv (Loop for
triangles, Catmull-Clark for triangles or quads), with infinitely sharp
creases on edges whose dihedral angle exceeds ``crease_angle`` degrees (or
given as ``crease_edges``). Frames of 2D animations are polylines, which
OpenSubdiv does not refine: they get cubic B-spline subdivision with corners
where they turn by more than ``crease_angle``. :func:`smooth_slice` does this
for a sliced frame (what ``AnimationManifold.slice(t, smooth_levels=n)``
returns for a frame the hole space cut). The whole manifold is smoothed by
:func:`animanifold.subdivide` (:mod:`animanifold.subdivision`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from . import _core
from .choices import checked, names
from .indices import as_indices
from .seams import weld_copies
from .slices import Slice
from ._core import InputError

FRAME_SCHEMES = names(_core.FrameScheme)
# The scheme a mesh gets when none is named, by vertices per face.
_DEFAULT_SCHEME = {2: "bspline", 3: "loop", 4: "catmull_clark"}


@dataclass(frozen=True)
class SmoothFrame:
    """A frame mesh refined by OpenSubdiv.

    vertices (P, 3); faces (F, 3) triangles (Loop) or (F, 4) quads
    (Catmull-Clark), oriented like the input; normals (P, 3) unit;
    face_parent (F,) the input face each face came from; crease_count the
    number of input edges made sharp.
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    face_parent: np.ndarray
    crease_count: int
    vertex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)
    face_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)


def subdivide_frame(
    vertices: np.ndarray,
    faces: np.ndarray,
    levels: int = 1,
    scheme: str | None = None,
    crease_angle: float = 30.0,
    crease_edges: np.ndarray | None = None,
    limit: bool = True,
    vertex_attributes: Mapping[str, np.ndarray] | None = None,
    face_attributes: Mapping[str, np.ndarray] | None = None,
    *,
    progress: Callable[[str, float], bool] | None = None,
    interrupted: Callable[[], bool] | None = None,
) -> SmoothFrame:
    """Refines a frame mesh with OpenSubdiv (or a polyline with B-splines).

    vertices (V, 3) — (V, d) for polylines; faces (F, 3) triangles, (F, 4)
    quads or (F, 2) directed segments. scheme: "loop" (triangles; the default
    for them), "catmull_clark" (triangles or quads; the default for quads) or
    "bspline" (segments; their default and only scheme). Edges whose faces
    meet at more than `crease_angle` degrees, and `crease_edges` (C, 2),
    become infinitely sharp creases; polylines keep corners where they turn
    by more than `crease_angle` (crease_angle <= 0 or >= 180 disables the
    angle test). With `limit` the points are projected onto the limit surface
    (curve). crease_count is the number of creased edges (corners for curves).
    progress(step, fraction) and interrupted() follow the core's steps; False
    from the one or True from the other raises :class:`animanifold.Cancelled`.
    """
    if isinstance(levels, bool) or int(levels) != levels or levels < 0:
        raise InputError(f"levels must be a non-negative integer, got {levels!r}")
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] not in (2, 3, 4):
        raise InputError(f"faces must be (F, 3), (F, 4) or (F, 2) segments, got shape {faces.shape}")
    if faces.size and not np.issubdtype(faces.dtype, np.integer):
        raise InputError(f"faces must be integer vertex indices, got {faces.dtype}")
    scheme = _DEFAULT_SCHEME[faces.shape[1]] if scheme is None else checked(scheme, _core.FrameScheme, "scheme")
    if (scheme == "bspline") != (faces.shape[1] == 2):
        raise InputError(f"scheme {scheme!r} does not apply to faces of {faces.shape[1]} vertices")
    if vertices.ndim != 2 or (vertices.shape[1] != 3 and scheme != "bspline"):
        raise InputError(f"vertices must be (V, 3), got shape {vertices.shape}")
    creases = None
    if crease_edges is not None:
        creases = np.asarray(crease_edges)
        if creases.size == 0:
            creases = np.zeros((0, 2), np.int32)
        if creases.ndim != 2 or creases.shape[1] != 2 or not np.issubdtype(creases.dtype, np.integer):
            raise InputError(f"crease_edges must be (C, 2) integer vertex pairs, got {creases.shape} {creases.dtype}")
        creases = as_indices(creases, "crease_edges")
    va = {k: _table(v, np.float64) for k, v in (vertex_attributes or {}).items()}
    fa = {k: _table(v, np.int32) for k, v in (face_attributes or {}).items()}
    faces = as_indices(faces, "faces")
    if scheme == "bspline":
        if creases is not None:
            raise InputError("crease_edges apply to surfaces; polylines take corners from crease_angle")
        r = _core.subdivide_polyline(vertices, faces, int(levels), float(crease_angle), bool(limit), va, fa,
                                     progress=progress, interrupted=interrupted)
    else:
        r = _core.subdivide_frame(vertices, faces, int(levels), scheme, float(crease_angle), creases, bool(limit), va, fa,
                                  progress=progress, interrupted=interrupted)
    return SmoothFrame(
        vertices=r.vertices,
        faces=r.faces,
        normals=r.normals,
        face_parent=r.face_parent,
        crease_count=int(r.crease_count),
        vertex_attributes={k: _squeeze(v) for k, v in r.vertex_attributes.items()},
        face_attributes={k: _squeeze(v) for k, v in r.face_attributes.items()},
    )


def _table(values: np.ndarray, dtype) -> np.ndarray:
    table = np.asarray(values)
    if table.ndim == 1:
        table = table[:, None]
    if table.ndim != 2:
        raise InputError(f"attribute tables must be 1D or 2D, got shape {table.shape}")
    return np.ascontiguousarray(table, dtype=dtype)


def _squeeze(table: np.ndarray) -> np.ndarray:
    return table[:, 0] if table.ndim == 2 and table.shape[1] == 1 else table


def smooth_slice(s: Slice, levels: int, crease_angle: float = 30.0) -> Slice:
    """A frame refined by OpenSubdiv (:func:`subdivide_frame`) after welding
    its split copies (UV seams would otherwise be boundaries and open); the
    result keeps `s`'s value and axis, with face_simplex mapped through the
    refinement and no vertex_edges (its points are not on manifold edges)."""
    if not len(s.faces):
        return dataclasses.replace(s, vertex_edges=None, edge_parameter=None)
    weld = weld_copies(s.vertices, s.faces)
    kept, faces = weld if weld is not None else (np.arange(len(s.vertices)), s.faces)
    r = subdivide_frame(
        s.vertices[kept], faces, levels, crease_angle=crease_angle,
        vertex_attributes={k: np.asarray(v)[kept] for k, v in s.vertex_attributes.items()},
        face_attributes=dict(s.face_attributes))
    face_simplex = None if s.face_simplex is None else np.asarray(s.face_simplex)[r.face_parent]
    return dataclasses.replace(s, vertices=r.vertices, faces=r.faces, normals=r.normals,
                               vertex_attributes=dict(r.vertex_attributes), face_attributes=dict(r.face_attributes),
                               vertex_edges=None, edge_parameter=None, face_simplex=face_simplex)
