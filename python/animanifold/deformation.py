"""Laplacian deformation of an animation manifold through space and time (chapter 4).

::

    moved = am.deform(m, anchors, handles, am.handle_transform(translation=[0, 0, 1, 0]))
    split = am.deform(m, anchors, handles, T,
                      options=am.DeformOptions(regularise=am.RegulariseOptions()))  # §4.5.1

The solve itself is :mod:`animanifold.laplacian`'s; the offline
regularisation :mod:`animanifold.regularisation`'s.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .interrupting import InterruptedCallback, ProgressCallback
from .laplacian import LaplacianOptions, laplacian_deform
from .manifold import AnimationManifold
from .regularisation import RegulariseOptions, regularise
from ._core import InputError


@dataclass(frozen=True)
class DeformOptions:
    """How :func:`deform` moves a manifold.

    laplacian: the method, boundary rule, restore and Laplacian parameters
      (:class:`~animanifold.LaplacianOptions`; default: dual, grown
      boundary, restored, steps "auto").
    regularise: None (default) keeps the simplices; a
      :class:`~animanifold.RegulariseOptions` splits the edges the motion
      stretched (§4.5.1), so the result has more vertices and simplices.
    """

    laplacian: LaplacianOptions = field(default_factory=LaplacianOptions)
    regularise: RegulariseOptions | None = None

    def __post_init__(self):
        if not isinstance(self.laplacian, LaplacianOptions):
            raise InputError(f"laplacian must be a LaplacianOptions, got {self.laplacian!r}")
        if self.regularise is not None and not isinstance(self.regularise, RegulariseOptions):
            raise InputError(f"regularise must be None or a RegulariseOptions, got {self.regularise!r}")


def deform(
    manifold: AnimationManifold,
    anchors,
    handles,
    transform: np.ndarray | None = None,
    *,
    handle_positions: np.ndarray | None = None,
    options: DeformOptions = DeformOptions(),
    progress: ProgressCallback | None = None,
    interrupted: InterruptedCallback | None = None,
) -> AnimationManifold:
    """A new manifold: anchors stay, handles move by `transform` ((D+1)x(D+1)
    affine) or to `handle_positions` (H, D), solved as ``options`` say.

    Without regularisation the result has the same simplices, attributes and
    metadata, and keeps the prisms of stitched keyframes while every key's
    vertices stay at its time (a motion through time drops them). With ``options.regularise`` it has more vertices (the input's
    first) and simplices, attributes interpolated / inherited, and
    metadata["regularisation"] saying how it ended (iterations, splits,
    converged, ...). Either way the hole space is dropped: the shape changed.

    A vertex whose time the solve changed by round-off only (less than 1e-9
    of the time range; a transform that keeps time leaves it unchanged in
    exact arithmetic for the primal methods) keeps its exact time, so slicing
    at a keyframe still returns the keyframe.

    ``progress(step, fraction)`` and ``interrupted()`` are those of
    :func:`~animanifold.laplacian_deform` or, with ``options.regularise``,
    :func:`~animanifold.regularise`: False from the one or True from the other
    raises :class:`animanifold.Cancelled`.
    """
    if options.regularise is not None:
        points, simplices, maps = regularise(
            manifold.points, manifold.simplices, anchors, handles, transform, handle_positions=handle_positions,
            laplacian=options.laplacian, options=options.regularise,
            vertex_attributes=manifold.vertex_attributes, simplex_attributes=manifold.simplex_attributes,
            progress=progress, interrupted=interrupted,
        )
        points = np.array(points)
        points[: len(manifold.points)] = _keep_times(manifold.points, points[: len(manifold.points)])
        metadata = dict(manifold.metadata)
        metadata["regularisation"] = maps.summary()
        return AnimationManifold.from_arrays(points, simplices, maps.vertex_attributes, maps.simplex_attributes,
                                             metadata)
    points = laplacian_deform(manifold.points, manifold.simplices, anchors, handles, transform,
                              handle_positions=handle_positions, options=options.laplacian, progress=progress,
                              interrupted=interrupted)
    points = _keep_times(manifold.points, points)
    prisms = None if manifold.prisms is None else manifold.prisms.holds_for(points, len(manifold.simplices))
    return AnimationManifold.from_arrays(points, manifold.simplices,
                                         dict(manifold.vertex_attributes), dict(manifold.simplex_attributes),
                                         manifold.metadata, prisms=prisms)


def _keep_times(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """`after` with the time column reset to `before`'s where it moved by round-off only."""
    after = np.array(after)
    t0, t1 = before[:, -1], after[:, -1]
    span = float(t0.max() - t0.min()) if len(t0) else 0.0
    same = np.abs(t1 - t0) <= 1e-9 * max(span, 1.0)
    after[same, -1] = t0[same]
    return after
