"""Hole spaces (§8.6.5) and the solid Booleans that make frames honour them.

A solid is a pair (vertices, faces): (k, 3) points and (l, 3) triangles of a
closed, outward mesh, or (k, 2) points and (l, 2) oriented edges of closed
polygons (counter-clockwise around the solid, clockwise around its holes).
An empty solid has no rows. The operations are exact (CGAL, exact
constructions) and round to doubles once, at the end.

Malformed arrays raise ValueError; an operand CGAL cannot work on (open, an
edge in more than two faces, inconsistently oriented, self-intersecting, a
loop that crosses itself) or a result that would not be a manifold raises
:class:`BooleanError` (a RuntimeError) naming the operand and the problem.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from . import _core
from .indices import as_indices, as_vertex_indices
from ._core import InputError

BooleanError = _core.BooleanError

Solid = tuple[np.ndarray, np.ndarray]
Interrupted = Callable[[], bool] | None  # True stops a Boolean while CGAL runs (Cancelled)


def _solid(solid, name: str) -> Solid:
    try:
        vertices, faces = solid
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a pair (vertices, faces)") from None
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] not in (2, 3):
        raise InputError(f"{name}'s vertices must be (k, 3) or (k, 2), got shape {v.shape}")
    if f.size == 0:
        f = f.reshape(0, v.shape[1])
    if f.ndim != 2 or f.shape[1] != v.shape[1] or (f.size and not np.issubdtype(f.dtype, np.integer)):
        raise InputError(f"{name}'s faces must be integer (l, {v.shape[1]}), got {f.dtype} {f.shape}")
    return v, as_indices(f, f"{name}'s faces")


def is_empty(solid: Solid | None) -> bool:
    return solid is None or len(solid[1]) == 0


def hole_space(vertices: np.ndarray, faces: np.ndarray, *, interrupted: Interrupted = None) -> Solid:
    """H_C = CH(C) \\ C for the closed outward shape C: the part of its convex
    hull it does not fill, as a closed outward solid (empty when C is convex).
    Slivers of rounding thickness where C lies on its hull (a planar quad
    split along the other diagonal) do not count; where dents of C's own
    triangulation would make the result non-manifold, they are flipped away
    (see cpp/include/animanifold/hole_space.hpp for the retries). CGAL runs in a child process:
    `interrupted()` returning True, or Ctrl-C, stops it with Cancelled, and a loop in CGAL ends
    in a TimeLimitError after a minute and more."""
    return _core.hole_space(*_solid((vertices, faces), "the shape"), interrupted=interrupted)


def intersect_solids(a: Solid, b: Solid, *, interrupted: Interrupted = None) -> Solid:
    """A ∩ B (both 3D or both 2D); empty when they do not overlap. `interrupted` as in hole_space."""
    return _core.intersect_solids(*_solid(a, "the first solid"), *_solid(b, "the second solid"),
                                  interrupted=interrupted)


def subtract_solid(frame: Solid, hole: Solid, *, interrupted: Interrupted = None) -> Solid:
    """frame \\ hole. When the hole cannot touch the frame (it is empty, the
    bounding boxes do not overlap, or the boundaries do not meet and neither
    contains the other), returns the frame's own arrays, unchanged. `interrupted` as in
    hole_space."""
    v, f = _solid(frame, "the frame")
    if is_empty(hole):
        return frame
    hv, hf = _solid(hole, "the subtracted solid")
    out_v, out_f, unchanged = _core.subtract_solid(v, f, hv, hf, interrupted=interrupted)
    return frame if unchanged else (out_v, out_f)


def solid_measure(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Volume (3D) or area (2D) enclosed by a closed outward boundary (0 when empty)."""
    v, f = _solid((vertices, faces), "the solid")
    return float(_core.solid_measure(v, f)) if len(f) else 0.0


def inside_solid(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each point lies inside the closed outward solid (or on it): in 3D CGAL's exact side
    test over an AABB tree (the core's points_inside_solid); in 2D, and for a 3D boundary that is
    not a 2-manifold, by winding_numbers."""
    v, f = _solid((vertices, faces), "the solid")
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, v.shape[1])
    if v.shape[1] == 3:
        try:
            return np.asarray(_core.points_inside_solid(v, f, points), dtype=bool)
        except _core.NotManifoldError:  # pinched where two parts touch: the solid angles still count it right
            pass
    return winding_numbers(v, f, points) > 0.5


def winding_numbers(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The winding number of the closed outward surface (triangles in R^3, edges in R^2) around each
    point: 1 inside, 0 outside, whatever holes or cavities it has (solid angles, Van Oosterom and
    Strackee; turning angles in 2D). Exact enough away from the surface; O(points x faces). Raises
    InputError for a face index that names no vertex."""
    vertices, faces = _solid((vertices, faces), "the surface")
    faces = as_vertex_indices(faces, len(vertices), "the surface's faces")
    points = np.asarray(points, float).reshape(-1, vertices.shape[1])
    out = np.zeros(len(points))
    for start in range(0, len(points), 256):
        p = points[start:start + 256, None, :]
        if faces.shape[1] == 3:
            a, b, c = (vertices[faces[:, i]][None] - p for i in range(3))
            la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
            numerator = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
            denominator = (la * lb * lc + np.einsum("pfi,pfi->pf", a, b) * lc + np.einsum("pfi,pfi->pf", b, c) * la
                           + np.einsum("pfi,pfi->pf", c, a) * lb)
            out[start:start + 256] = 2 * np.arctan2(numerator, denominator).sum(1) / (4 * np.pi)
        else:
            a, b = (vertices[faces[:, i]][None] - p for i in range(2))
            cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
            out[start:start + 256] = np.arctan2(cross, np.einsum("pfi,pfi->pf", a, b)).sum(1) / (2 * np.pi)
    return out


def points_inside(vertices: np.ndarray, faces: np.ndarray, depth: float) -> np.ndarray:
    """A point just inside the solid behind each face: its centroid moved `depth` against the face's
    outward normal. Raises InputError for a face index that names no vertex."""
    vertices, faces = _solid((vertices, faces), "the solid")
    corners = vertices[as_vertex_indices(faces, len(vertices), "the solid's faces")]
    centre = corners.mean(1)
    if faces.shape[1] == 3:
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    else:
        edge = corners[:, 1] - corners[:, 0]
        normal = np.stack([edge[:, 1], -edge[:, 0]], 1)  # right of a counter-clockwise edge: outward
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    keep = length[:, 0] > 0
    return centre[keep] - depth * normal[keep] / length[keep]
