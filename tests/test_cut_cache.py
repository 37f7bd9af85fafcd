"""The cuts and frames live playback keeps (cut_cache): budgets and what goes with what."""

from __future__ import annotations

from animanifold.cut_cache import CutCache
from helpers.cuts import cut, frame


class Manifold:  # stands for a loaded manifold: the cache keys by identity and holds weak references
    pass


def test_frames_are_kept_within_their_budget_and_nothing_is_evicted_for_them():
    m = Manifold()
    size = frame(0.0).nbytes()
    cache = CutCache(frame_budget=2 * size)
    cache.put(m, "a", cut())
    six = frame(6.0)
    assert cache.keep_frame(m, "a", six) and cache.keep_frame(m, "a", frame(7.0))
    assert not cache.frame_room(m, "a", size)
    assert not cache.keep_frame(m, "a", frame(8.0))  # full: 6 and 7 stay
    assert cache.frame(m, "a", 6.0) is six and cache.frame(m, "a", 7.0) is not None
    assert cache.frame(m, "a", 8.0) is None
    assert cache.frame_nbytes == 2 * size
    assert not cache.keep_frame(m, "b", frame(6.0))  # no cut "b" kept: nothing to keep it with


def test_frames_go_with_their_cut():
    m = Manifold()
    one = cut()
    cache = CutCache(budget=one.nbytes() + 1, frame_budget=10 * frame(0.0).nbytes())
    cache.put(m, "a", one)
    assert cache.keep_frame(m, "a", frame(6.0))
    cache.put(m, "b", cut())  # over the cut budget: "a" is evicted, its frames with it
    assert cache.get(m, "a") is None and cache.frame(m, "a", 6.0) is None
    assert cache.frame_nbytes == 0
    assert cache.keep_frame(m, "b", frame(6.0))
    cache.put(m, "b", cut())  # a new cut for the key: the old one's frames are not its frames
    assert cache.frame(m, "b", 6.0) is None and cache.frame_nbytes == 0
    cache.keep_frame(m, "b", frame(6.0))
    cache.clear()
    assert cache.frame_nbytes == 0 and len(cache) == 0
