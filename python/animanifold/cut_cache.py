"""The cuts and frames live playback keeps between frames (interval_cuts), so that playback
coming back to a topology interval (or a vertex time: a keyframe) neither slices again nor
makes Blender compute the mesh's edges again.

Cuts are kept least recently used first out, within a budget (the add-on's Frame Cache
Budget preference; BUDGET_BYTES by default), per loaded manifold (a reloaded or subdivided
manifold is another object and gets its own cuts).

Beside an interval's cut, each of its integer frames (interval_cuts.Frame): copying a kept
frame into the mesh is two copies, where the live modifier would move every vertex and
rebuild the UV map on every corner (600k corners for a 50k-triangle source) on every frame
(bench/bench_playback.py measures both). Frames are computed on their first visit and kept
within a budget of their own (the same preference; FRAME_BUDGET_BYTES by default); when that
is full, no more are kept (a loop longer than the budget would otherwise evict every frame
before it comes back) and the modifier moves the others. They go with their cut.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from typing import Callable

from .interval_cuts import Cut, Frame

# Defaults (preferences.DEFAULT_BUDGET_MB in the add-on). ~12 intervals of a 200k-face frame
# (a 50k-triangle source): a typical action's keyframes fit, and scrubbing back and forth
# over them slices nothing.
BUDGET_BYTES = 256 * 2**20
# ~44 integer frames of that frame (100k positions, 600k corners: 6 MB each): the 40
# of the bench's 48-frame loop fit.
FRAME_BUDGET_BYTES = 256 * 2**20


class CutCache:
    """Cuts and their frames, each within a budget (see the module). Each budget is a byte
    count, or a function giving it that is asked each time the cache decides what to keep
    (the add-on's Frame Cache Budget preference)."""

    def __init__(self, budget: int | Callable[[], int] = BUDGET_BYTES,
                 frame_budget: int | Callable[[], int] = FRAME_BUDGET_BYTES):
        self._budget = budget
        self._frame_budget = frame_budget
        self._entries: OrderedDict = OrderedDict()  # (id(manifold), key) -> (weakref, Cut, nbytes)
        self._bytes = 0
        self._frames: dict = {}  # (id(manifold), key) -> {frame value: Frame}, for kept cuts only
        self._frame_bytes = 0

    @property
    def budget(self) -> int:
        return self._budget() if callable(self._budget) else self._budget

    @property
    def frame_budget(self) -> int:
        return self._frame_budget() if callable(self._frame_budget) else self._frame_budget

    def get(self, manifold, key) -> Cut | None:
        entry = self._entries.get((id(manifold), key))
        if entry is None:
            return None
        if entry[0]() is not manifold:  # an id reused by another manifold
            self._drop((id(manifold), key))
            return None
        self._entries.move_to_end((id(manifold), key))
        return entry[1]

    def put(self, manifold, key, cut: Cut) -> None:
        self._drop((id(manifold), key))
        size = cut.nbytes()
        if size > self.budget:
            return
        self._entries[(id(manifold), key)] = (weakref.ref(manifold), cut, size)
        self._bytes += size
        self._shrink()

    def resized(self, manifold, key) -> None:
        """A kept cut grew (its edges were added): account for it."""
        entry = self._entries.get((id(manifold), key))
        if entry is not None:
            ref, cut, size = entry
            self._bytes += cut.nbytes() - size
            self._entries[(id(manifold), key)] = (ref, cut, cut.nbytes())
            self._shrink()

    def _shrink(self) -> None:
        budget = self.budget
        while self._bytes > budget and len(self._entries) > 1:
            self._drop(next(iter(self._entries)))
        for k in [k for k, (ref, _, _) in self._entries.items() if ref() is None]:
            self._drop(k)

    def room(self, nbytes: int, share: float = 1.0) -> bool:
        """Whether a cut of `nbytes` fits within `share` of the budget beside those kept."""
        return self._bytes + nbytes <= share * self.budget

    def frame(self, manifold, key, value: float) -> Frame | None:
        """The kept frame `value` of the kept cut `key`, if any."""
        if self.get(manifold, key) is None:
            return None
        return self._frames.get((id(manifold), key), {}).get(value)

    def frame_room(self, manifold, key, nbytes: int) -> bool:
        """Whether a frame of `nbytes` for the kept cut `key` would be kept."""
        return (id(manifold), key) in self._entries and self._frame_bytes + nbytes <= self.frame_budget

    def keep_frame(self, manifold, key, frame: Frame) -> bool:
        """Keeps `frame` of the kept cut `key` if the frame budget has room (nothing is
        evicted for it); False if not kept."""
        if not self.frame_room(manifold, key, frame.nbytes()):
            return False
        frames = self._frames.setdefault((id(manifold), key), {})
        if frame.value not in frames:
            frames[frame.value] = frame
            self._frame_bytes += frame.nbytes()
        return True

    def _drop(self, k) -> None:
        entry = self._entries.pop(k, None)
        if entry is not None:
            self._bytes -= entry[2]
        for frame in self._frames.pop(k, {}).values():
            self._frame_bytes -= frame.nbytes()

    def clear(self) -> None:
        self._entries.clear()
        self._bytes = 0
        self._frames.clear()
        self._frame_bytes = 0

    def __len__(self) -> int:
        return len(self._entries)

    @property
    def nbytes(self) -> int:
        return self._bytes

    @property
    def frame_nbytes(self) -> int:
        return self._frame_bytes
