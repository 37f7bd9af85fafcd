"""Morphing between closed shapes (chapters 5 and 8): numpy in, AnimationManifold out."""

from __future__ import annotations

from typing import Callable

import numpy as np

from . import _core
from .manifold import AnimationManifold

METHODS = ("skeleton", "strip")


def morph(
    source: tuple[np.ndarray, np.ndarray],
    target: tuple[np.ndarray, np.ndarray],
    t0: float = 0.0,
    t1: float = 1.0,
    method: str = "skeleton",
    progress: Callable[[str, float], bool] | None = None,
    max_push: float = 0.45,
    push_safety: float = 0.5,
    fill: str = "cgal",
) -> AnimationManifold:
    """An animation manifold that is `source` at t0 and `target` at t1.

    source, target: (vertices (k, 3), triangles (l, 3)) closed, outward
    oriented meshes — or (vertices (k, 2), edges (l, 2)) closed
    counter-clockwise polygons. `progress(stage, fraction)` is called between
    stages; returning False cancels (raises animanifold._core.Cancelled).

    method: "skeleton" (§8.6, the default) fills concavities and holes of the
    source just after t0 and opens the target's just before t1, with every
    frame a closed surface; "strip" (§8.5) removes what lies outside either
    shape — ambiguous where the genus changes (frames can pinch). Skeleton
    options: free points move up to `max_push` of the time span into the
    morph, each as far as `push_safety` of the move that would flatten one of
    its simplices. fill: the Delaunay triangulation of the fill, "cgal" (fast)
    or "qhull".

    The result's `validity` (also kept in its metadata) is the report of §8.3:
    Theorem 5.2.1's missing faces, inverted/degenerate simplices, and how far
    the end frames are from the inputs (relative to the bounding box).
    """
    if method not in METHODS:
        raise ValueError(f"unknown morph method {method!r}: available are {', '.join(METHODS)}")
    (vs, fs), (vt, ft) = source, target
    arrays = []
    for name, v, f in (("source", vs, fs), ("target", vt, ft)):
        v = np.ascontiguousarray(v, dtype=np.float64)
        f = np.asarray(f)
        if v.ndim != 2 or v.shape[1] not in (2, 3):
            raise ValueError(f"the {name}'s vertices must be (k, 3) or (k, 2), got shape {v.shape}")
        if f.ndim != 2 or f.shape[1] != v.shape[1] or (f.size and not np.issubdtype(f.dtype, np.integer)):
            raise ValueError(f"the {name}'s faces must be integer (l, {v.shape[1]}), got {f.dtype} {f.shape}")
        arrays += [v, np.ascontiguousarray(f, dtype=np.int32)]
    complex_, report = _core.morph(*arrays, t0=float(t0), t1=float(t1), method=method, progress=progress,
                                   max_push=float(max_push), push_safety=float(push_safety), fill=fill)
    report = {k: (list(map(list, v)) if k == "stage_seconds" else list(v) if isinstance(v, tuple) else v)
              for k, v in report.items()}
    return AnimationManifold(complex_, metadata={"morph": {"method": method, "fill": fill, "t0": float(t0),
                                                           "t1": float(t1)},
                                                 "validity": report})
