"""How a manifold's slices are shown as frames (the Blender add-on's live playback and bake
use these; no Blender here): the value a scene frame slices at, the vertex positions of
a time slice or a sweep view, and the smooth normals carried along the manifold."""

from __future__ import annotations

import numpy as np

AXES = ("t", "x", "y", "z")


def slice_value(manifold, frame: float, axis: str, sweep_value: float) -> float:
    """What a scene frame slices `manifold` at: along t the frame, held at the first and last
    sample before and after them (like an action's constant extrapolation; the bake's node
    group does the same); a sweep view along x, y or z is the same at every frame."""
    if axis == "t":
        t0, t1 = manifold.time_range
        return min(max(frame, t0), t1)
    return sweep_value


def display_vertices(manifold, s, axis: str, time_scale: float) -> np.ndarray:
    """Object-space positions of a slice: (x, y, z) for a time slice; for a sweep
    slice along x, y or z, time (from the start, times `time_scale`) takes the
    place of the sliced axis (the sweep view of Figure 2.7)."""
    if axis == "t" or len(s.vertices) == 0:
        return s.vertices
    i = AXES.index(axis) - 1
    t0 = manifold.time_range[0]
    others = [c for c in range(3) if c != i]
    out = np.empty((len(s.vertices), 3), dtype=np.float64)
    out[:, others] = s.vertices[:, :2]
    out[:, i] = (s.vertices[:, 2] - t0) * time_scale
    return out


def slice_normals(s) -> np.ndarray | None:
    """Smooth normals of a time slice: the source's keyframe vertex normals (the
    'normal' vertex attribute of smooth-shaded sources), interpolated along the
    manifold edges and normalised; None for flat-shaded sources."""
    n = s.vertex_attributes.get("normal")
    if n is None or len(n) == 0:
        return None
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0, length, 1.0)


def frame_normals(s, smoothed: bool) -> np.ndarray | None:
    """Custom normals for a frame: None for flat-shaded sources; for smooth-shaded
    ones the source's normals carried along the manifold (slice_normals) or, on a
    frame refined by OpenSubdiv, the normals of its limit surface."""
    if smoothed:
        return s.normals if s.vertex_attributes.get("normal") is not None and len(s.normals) else None
    return slice_normals(s)
