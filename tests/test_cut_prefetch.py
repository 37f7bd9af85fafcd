"""Playback's cuts and integer frames made ahead for prism frames (cut_prefetch)."""

from __future__ import annotations

import numpy as np

import animanifold as am
from animanifold import interval_cuts, procedural
from animanifold.cut_cache import CutCache
from animanifold.cut_prefetch import prefetch


def _stitched(prisms: bool = True):
    v, f = procedural.icosphere(2)
    frames = [v * (1.0 + 0.1 * i) for i in range(4)]
    m = am.stitch(frames, f, [1.0, 5.0, 9.0, 13.0], vertex_attributes={"uv": v[:, :2]})
    return m if prisms else am.AnimationManifold(m.core_complex, m.metadata)


def test_prefetch_makes_every_cut_and_integer_frame_of_the_range_as_playback_would():
    m, cuts = _stitched(), CutCache()
    values = [float(f) for f in range(1, 14)]
    assert prefetch(m, values, cuts) == (4 + 3, 3 * 3 - 3)  # 4 keys, 3 gaps; 3 frames each but the cuts' own
    for value in values:
        interval = m.topology_interval(value)
        key = interval or ("at", value)
        kept = cuts.get(m, key)
        fresh = interval_cuts.time_cut(m, value)[1]  # what playback's first visit would make
        assert kept is not None and kept.value == fresh.value
        np.testing.assert_array_equal(kept.vertices, fresh.vertices)
        np.testing.assert_array_equal(kept.corner_uv, fresh.corner_uv)
        if interval is not None and value != kept.value:
            frame = cuts.frame(m, key, value)
            np.testing.assert_array_equal(frame.positions, interval_cuts.interval_frame(fresh, value).positions)
    assert prefetch(m, values, cuts) == (0, 0)  # all kept already


def test_prefetch_keeps_to_half_the_budget_and_evicts_nothing():
    m = _stitched()
    one = interval_cuts.time_cut(m, 1.0)[1].nbytes()
    cuts = CutCache(budget=5 * one)
    cuts.put(m, "playback's", interval_cuts.time_cut(m, 3.0)[1])
    made, _ = prefetch(m, [float(f) for f in range(1, 14)], cuts)
    assert 0 < made < 7 and cuts.nbytes <= 2.5 * one
    assert cuts.get(m, "playback's") is not None


def test_the_tets_slices_are_not_made_ahead():
    cuts = CutCache()
    assert prefetch(_stitched(prisms=False), [1.0, 2.0, 3.0], cuts) == (0, 0) and len(cuts) == 0
