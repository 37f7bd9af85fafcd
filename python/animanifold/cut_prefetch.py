"""Playback's first pass made as cheap as the later ones: when the live modifier first
plays a manifold whose frames are its prisms' (prism_frames: a key is a gather, an
in-between frame a lerp, no slicing), the cuts of the scene's frame range and the integer
frames kept beside them (cut_cache) are made then, ahead of playback, instead of on each
frame's first visit.

Each is kept while it fits in half of its budget (the other half is left to what
playback keeps later; nothing kept is evicted for them). Manifolds whose frames are the
tets' slices are left to playback: their cuts cost a slice each (tens of milliseconds on
a production manifold), too much to make ahead for a whole range.
"""

from __future__ import annotations

import math
from typing import Iterable

from . import interval_cuts
from .cut_cache import CutCache

SHARE = 0.5  # of each budget, at most, made ahead


def plays_prisms(manifold) -> bool:
    """Whether every frame of `manifold` is its prisms' (cheap to make ahead)."""
    prisms = manifold.prisms
    return prisms is not None and bool(prisms.gaps.all())


def prefetch(manifold, values: Iterable[float], cuts: CutCache) -> tuple[int, int]:
    """Makes and keeps the cuts of the time slices at `values` (the scene's integer
    frames, as slice values, in playback order) and, inside an interval, the frame at
    each value, as playback's first visit would. Returns (cuts made, frames made)."""
    made, frames = 0, 0
    if not plays_prisms(manifold):
        return made, frames
    for value in values:
        interval = manifold.topology_interval(value, "t")
        key = interval or ("at", value)
        cut = cuts.get(manifold, key)
        if cut is None:
            key, cut = interval_cuts.time_cut(manifold, value)
            if not cuts.room(cut.nbytes(), SHARE):
                break
            cuts.put(manifold, key, cut)
            made += 1
        # Playback keeps the integer frames of an interval (the add-on's playback._frame), but its
        # cut's own.
        if (interval is None or value != math.floor(value) or value == cut.value
                or cuts.frame(manifold, key, value) is not None):
            continue
        size = interval_cuts.frame_nbytes(cut)
        if cuts.frame_nbytes + size > SHARE * cuts.frame_budget:
            continue
        cuts.keep_frame(manifold, key, interval_cuts.interval_frame(cut, value))
        frames += 1
    return made, frames
