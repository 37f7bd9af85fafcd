"""Subdivision of an animation manifold (§4.3, §10.2.2): smooth shape and motion together.

:func:`subdivide` refines the whole manifold with the tetrahedral scheme of
Schaefer, Hakenberg and Warren (2004): shape *and* motion paths become smooth
together. One level multiplies the tets by 8 (triangles by 4 for 2D
animations). The first and last keyframe stay the boundary, on their time
hyperplanes; ``keep_keyframe_times=True`` keeps every keyframe's points at
its time. Single frames are smoothed by :mod:`animanifold.frame_smoothing`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from . import _core
from .choices import checked, names
from .manifold import AnimationManifold
from .option_keywords import options_from
from ._core import InputError

MANIFOLD_SCHEMES = names(_core.ManifoldScheme)


@dataclass(frozen=True)
class SubdivideOptions:
    """How :func:`subdivide` subdivides.

    scheme: "schaefer" (default; split and average: smooth) or "linear"
      (split only).
    keep_keyframe_times: keep every keyframe's points at its time (default
      False: only the first and last keyframe stay on their hyperplanes).
    keyframe_times: the times whose hyperplanes count as keyframes; None
      (default) takes the manifold's metadata ``keyframe_times`` (set by
      :func:`stitch`), else the core infers them from facets lying on time
      hyperplanes.
    """

    scheme: str = "schaefer"
    keep_keyframe_times: bool = False
    keyframe_times: tuple[float, ...] | None = None

    def __post_init__(self):
        # Frozen: the checked name replaces an enum member, a tuple any sequence of times.
        object.__setattr__(self, "scheme", checked(self.scheme, _core.ManifoldScheme, "scheme"))
        if not isinstance(self.keep_keyframe_times, (bool, np.bool_)):
            raise InputError(f"keep_keyframe_times must be True or False, got {self.keep_keyframe_times!r}")
        if self.keyframe_times is not None:
            times = np.asarray(self.keyframe_times, dtype=np.float64).reshape(-1)
            if not np.isfinite(times).all():
                raise InputError(f"keyframe_times must be finite numbers, got {self.keyframe_times!r}")
            object.__setattr__(self, "keyframe_times", tuple(float(t) for t in times))


def subdivided_simplex_count(manifold: AnimationManifold, levels: int) -> int:
    """Simplices after `levels` of :func:`subdivide`, without subdividing: each level
    splits a tet into 8 (a triangle of a 2D animation into 4)."""
    return len(manifold.simplices) * (2 ** (manifold.dimension - 1)) ** int(levels)


def subdivide(
    manifold: AnimationManifold,
    levels: int = 1,
    *,
    options: SubdivideOptions | None = None,
    scheme: str | None = None,
    keep_keyframe_times: bool | None = None,
    keyframe_times: Sequence[float] | None = None,
    return_parents: bool = False,
    progress: Callable[[str, float], bool] | None = None,
    interrupted: Callable[[], bool] | None = None,
):
    """A new manifold: `levels` of subdivision of `manifold`.

    options: a :class:`SubdivideOptions` (scheme, keep_keyframe_times,
    keyframe_times); or give those as keywords (not both: ValueError).
    The result's metadata records the subdivision (``subdivisions``) and the
    keyframe times used. With ``return_parents`` the result is
    ``(manifold, vertex_parents, simplex_parent)``: vertex_parents (V', 2)
    relative to the previous level — (v, v) for a kept vertex (same id),
    (a, b) for the midpoint of edge (a, b), (-1, -1) for an octahedron
    centre — and simplex_parent (S',) the input simplex of each output one.
    ``progress(step, fraction)`` and ``interrupted()`` follow the core's steps
    (each level); False from the one or True from the other raises
    :class:`animanifold.Cancelled`.
    """
    options = options_from(SubdivideOptions, options, scheme=scheme, keep_keyframe_times=keep_keyframe_times,
                           keyframe_times=keyframe_times)
    scheme, keep_keyframe_times = options.scheme, options.keep_keyframe_times
    if isinstance(levels, bool) or int(levels) != levels or levels < 0:
        raise InputError(f"levels must be a non-negative integer, got {levels!r}")
    keyframe_times = options.keyframe_times
    if keyframe_times is None:
        keyframe_times = manifold.metadata.get("keyframe_times") or []
    times = [float(t) for t in keyframe_times]
    result = _core.subdivide_manifold(manifold.core_complex, int(levels), scheme, bool(keep_keyframe_times), times,
                                      progress=progress, interrupted=interrupted)
    metadata = {k: v for k, v in manifold.metadata.items() if k not in ("keyframe_vertices", "keyframe_faces")}
    metadata["keyframe_times"] = np.asarray(result.keyframe_times).tolist()
    history = list(manifold.metadata.get("subdivisions", []))
    history.append({"levels": int(levels), "scheme": scheme, "keep_keyframe_times": bool(keep_keyframe_times)})
    metadata["subdivisions"] = history
    out = AnimationManifold(result.manifold, metadata)
    if return_parents:
        return out, result.vertex_parents, result.simplex_parent
    return out
