"""A contact sheet: several frames side by side in one PNG, rendered with matplotlib.

Rendering uses matplotlib's object API on the Agg canvas (no pyplot, no
display, no global state), so it works headless and inside Blender alike.
Faces are shaded by the slice's smooth normals (the 4D normals of §2.3.2
projected into the frame), which is what makes a slice look like the
keyframed surface rather than a faceted polyhedron.
"""

from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from .slices import Slice
from ._core import InputError

# Light from the upper front left, as in a default 3-point setup's key light.
_LIGHT = np.array([-0.4, -0.6, 0.7]) / np.linalg.norm([-0.4, -0.6, 0.7])
_BASE_COLOUR = np.array([0.85, 0.55, 0.25])


def face_shading(frame: Slice) -> np.ndarray:
    """(F, 4) RGBA per face: Lambert shading of the mean of its corners' smooth normals."""
    normals = frame.normals[frame.faces].mean(axis=1)
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = normals / np.maximum(lengths, 1e-300)
    lambert = np.clip(normals @ _LIGHT, 0.0, 1.0)
    intensity = 0.2 + 0.8 * lambert  # ambient keeps faces turned away readable
    rgb = _BASE_COLOUR[None, :] * intensity[:, None]
    return np.concatenate([rgb, np.ones((len(rgb), 1))], axis=1)


def render_contact_sheet(
    frames: Sequence[Slice],
    path: str | os.PathLike,
    bounds: tuple[np.ndarray, np.ndarray],
    columns: int = 4,
    panel_inches: float = 3.0,
) -> None:
    """Writes `frames` (t-slices of a surface animation) side by side to a PNG at `path`.

    bounds: (low, high) spatial corners shared by every panel, so motion
    between frames shows as motion on the sheet.
    """
    # Imported here: matplotlib is needed only for pictures, not for the core workflow.
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if not frames:
        raise InputError("a contact sheet needs at least one frame")
    low, high = (np.asarray(b, dtype=np.float64)[:3] for b in bounds)
    # A small margin, and a minimum extent so a flat animation still gets a box.
    margin = 0.05 * max(float((high - low).max()), 1e-12)
    low, high = low - margin, high + margin
    columns = max(1, min(columns, len(frames)))
    rows = -(-len(frames) // columns)

    figure = Figure(figsize=(panel_inches * columns, panel_inches * rows), dpi=100)
    for i, frame in enumerate(frames):
        axes = figure.add_subplot(rows, columns, i + 1, projection="3d")
        triangles = frame.vertices[frame.faces]
        colours = face_shading(frame)
        # Edges in the face colour hide the anti-aliasing seams between triangles.
        axes.add_collection3d(Poly3DCollection(triangles, facecolors=colours, edgecolors=colours, linewidths=0.3))
        # The box around the whole animation, at equal scale on every axis and the same
        # view in every panel, so travel between frames shows as travel on the sheet.
        for set_limits, lo, hi in zip((axes.set_xlim, axes.set_ylim, axes.set_zlim), low, high):
            set_limits(lo, hi)
        axes.set_box_aspect(tuple(high - low), zoom=1.3)  # zoom: mplot3d pads generously
        axes.view_init(elev=18, azim=-70)
        axes.set_axis_off()
        axes.set_title(f"t = {frame.value:.3f}", fontsize=10)
    figure.subplots_adjust(left=0, right=1, bottom=0, top=0.95, wspace=0, hspace=0.05)
    figure.savefig(os.fspath(path), format="png")
