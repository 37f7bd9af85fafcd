"""The kept cuts and per-frame UV maps of live playback (live_cuts.CutCache): budgets and
what goes with what. No scene needed (the add-on package imports bpy)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from animanifold_blender import live_cuts  # noqa: E402

pytestmark = pytest.mark.blender


class Manifold:  # stands for a loaded manifold: the cache keys by identity and holds weak references
    pass


def cut(corners: int = 6) -> live_cuts.Cut:
    faces = np.arange(corners, dtype=np.int32).reshape(-1, 3)
    uv = np.zeros((corners, 3), np.float32)
    return live_cuts.Cut(5.0, faces, None, None, np.zeros((corners, 3), np.float32),
                         np.zeros(2 * corners, np.float32), rate=np.zeros((corners, 3), np.float32),
                         uv=uv, uv_rate=np.ones((corners, 3), np.float32))


def test_frame_uv_moves_each_vertex_along_its_rate_per_corner():
    c = cut()
    c.uv[:, :2] = np.arange(12).reshape(6, 2) / 16.0
    c.uv_rate[:, :2] = np.arange(12).reshape(6, 2) / -64.0
    c.faces = np.array([[5, 0, 3], [1, 4, 2]], np.int32)
    got = live_cuts.frame_uv(c, 8.0)
    expected = (c.uv[:, :2] + 3.0 * c.uv_rate[:, :2])[c.faces.reshape(-1)]
    assert got.dtype == np.float32 and got.shape == (12,)
    np.testing.assert_allclose(got.reshape(-1, 2), expected, atol=1e-7)


def test_frames_are_kept_within_their_budget_and_nothing_is_evicted_for_them():
    m = Manifold()
    uv = np.zeros(12, np.float32)  # 48 bytes
    cache = live_cuts.CutCache(frame_budget=2 * uv.nbytes)
    cache.put(m, "a", cut())
    assert cache.keep_frame_uv(m, "a", 6.0, uv) and cache.keep_frame_uv(m, "a", 7.0, uv.copy())
    assert not cache.frame_room(m, "a", uv.nbytes)
    assert not cache.keep_frame_uv(m, "a", 8.0, uv.copy())  # full: 6 and 7 stay
    assert cache.frame_uv(m, "a", 6.0) is uv and cache.frame_uv(m, "a", 7.0) is not None
    assert cache.frame_uv(m, "a", 8.0) is None
    assert cache.frame_nbytes == 2 * uv.nbytes
    assert not cache.keep_frame_uv(m, "b", 6.0, uv)  # no cut "b" kept: nothing to keep it with


def test_frames_go_with_their_cut():
    m = Manifold()
    uv = np.zeros(12, np.float32)
    one = cut()
    cache = live_cuts.CutCache(budget=one.nbytes() + 1, frame_budget=10 * uv.nbytes)
    cache.put(m, "a", one)
    assert cache.keep_frame_uv(m, "a", 6.0, uv)
    cache.put(m, "b", cut())  # over the cut budget: "a" is evicted, its frames with it
    assert cache.get(m, "a") is None and cache.frame_uv(m, "a", 6.0) is None
    assert cache.frame_nbytes == 0
    assert cache.keep_frame_uv(m, "b", 6.0, uv)
    cache.put(m, "b", cut())  # a new cut for the key: the old one's frames are not its frames
    assert cache.frame_uv(m, "b", 6.0) is None and cache.frame_nbytes == 0
    cache.keep_frame_uv(m, "b", 6.0, uv)
    cache.clear()
    assert cache.frame_nbytes == 0 and len(cache) == 0
