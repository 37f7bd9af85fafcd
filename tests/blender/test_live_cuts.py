"""The kept cuts and frames of live playback (live_cuts): a frame's arrays, budgets and
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


def frame(value: float, corners: int = 6) -> live_cuts.Frame:
    return live_cuts.Frame(value, np.zeros(3 * corners, np.float32), np.zeros(2 * corners, np.float32))


def test_a_frame_moves_each_vertex_and_uv_along_its_rate():
    c = cut()
    c.vertices[:] = np.arange(18).reshape(6, 3) / 8.0
    c.rate[:] = np.arange(18).reshape(6, 3) / -32.0
    c.uv[:, :2] = np.arange(12).reshape(6, 2) / 16.0
    c.uv_rate[:, :2] = np.arange(12).reshape(6, 2) / -64.0
    c.faces = np.array([[5, 0, 3], [1, 4, 2]], np.int32)
    f = live_cuts.interval_frame(c, 8.0)
    assert f.value == 8.0 and f.positions.dtype == f.corner_uv.dtype == np.float32
    np.testing.assert_allclose(f.positions.reshape(-1, 3), c.vertices + 3.0 * c.rate, atol=1e-7)
    np.testing.assert_allclose(f.corner_uv.reshape(-1, 2), (c.uv[:, :2] + 3.0 * c.uv_rate[:, :2])[c.faces.reshape(-1)],
                               atol=1e-7)
    assert f.nbytes() == live_cuts.frame_nbytes(c) == 4 * (18 + 12)
    own = live_cuts.interval_frame(c, c.value)  # the cut's own arrays, not copies
    assert np.shares_memory(own.positions, c.vertices) and own.corner_uv is c.corner_uv
    c.uv_rate = None  # no UVs: positions only
    assert live_cuts.interval_frame(c, 8.0).corner_uv is None and live_cuts.frame_nbytes(c) == 4 * 18


def test_frames_are_kept_within_their_budget_and_nothing_is_evicted_for_them():
    m = Manifold()
    size = frame(0.0).nbytes()
    cache = live_cuts.CutCache(frame_budget=2 * size)
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
    cache = live_cuts.CutCache(budget=one.nbytes() + 1, frame_budget=10 * frame(0.0).nbytes())
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


def test_keys_sharing_unchangeable_faces_and_uvs_share_their_corner_uvs():
    import dataclasses

    from animanifold.slices import Slice

    faces = np.array([[0, 1, 2], [2, 1, 3]], np.int32)
    faces.flags.writeable = False
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    uv.flags.writeable = False
    key = Slice(axis=3, value=1.0, vertices=np.zeros((4, 3)), faces=faces, normals=None,
                vertex_attributes={"uv": uv})
    one, two = live_cuts.vertex_time_cut(key), live_cuts.vertex_time_cut(dataclasses.replace(key, value=2.0))
    assert one.faces is faces and two.faces is faces  # kept, not copied
    assert two.corner_uv is one.corner_uv
    np.testing.assert_array_equal(one.corner_uv.reshape(-1, 2), uv[faces.reshape(-1)])
    moving = uv + 0.5  # a writeable array may change: its corners are gathered again
    three = live_cuts.vertex_time_cut(dataclasses.replace(key, vertex_attributes={"uv": moving}))
    np.testing.assert_array_equal(three.corner_uv.reshape(-1, 2), moving[faces.reshape(-1)])
    writeable = np.array(faces)
    assert live_cuts.vertex_time_cut(dataclasses.replace(key, faces=writeable)).faces is not writeable


def _stitched(prisms: bool = True):
    import animanifold as am
    from animanifold import procedural

    v, f = procedural.icosphere(2)
    frames = [v * (1.0 + 0.1 * i) for i in range(4)]
    m = am.stitch(frames, f, [1.0, 5.0, 9.0, 13.0], vertex_attributes={"uv": v[:, :2]})
    return m if prisms else am.AnimationManifold(m.core_complex, m.metadata)


def test_prefetch_makes_every_cut_and_integer_frame_of_the_range_as_playback_would():
    from animanifold_blender import live_prefetch

    m, cuts = _stitched(), live_cuts.CutCache()
    values = [float(f) for f in range(1, 14)]
    assert live_prefetch.prefetch(m, values, cuts) == (4 + 3, 3 * 3 - 3)  # 4 keys, 3 gaps; 3 frames each but the cuts' own
    for value in values:
        interval = m.topology_interval(value)
        key = interval or ("at", value)
        kept = cuts.get(m, key)
        fresh = live_cuts.time_cut(m, value)[1]  # what playback's first visit would make
        assert kept is not None and kept.value == fresh.value
        np.testing.assert_array_equal(kept.vertices, fresh.vertices)
        np.testing.assert_array_equal(kept.corner_uv, fresh.corner_uv)
        if interval is not None and value != kept.value:
            frame = cuts.frame(m, key, value)
            np.testing.assert_array_equal(frame.positions, live_cuts.interval_frame(fresh, value).positions)
    assert live_prefetch.prefetch(m, values, cuts) == (0, 0)  # all kept already


def test_prefetch_keeps_to_half_the_budget_and_evicts_nothing():
    from animanifold_blender import live_prefetch

    m = _stitched()
    one = live_cuts.time_cut(m, 1.0)[1].nbytes()
    cuts = live_cuts.CutCache(budget=5 * one)
    cuts.put(m, "playback's", live_cuts.time_cut(m, 3.0)[1])
    made, _ = live_prefetch.prefetch(m, [float(f) for f in range(1, 14)], cuts)
    assert 0 < made < 7 and cuts.nbytes <= 2.5 * one
    assert cuts.get(m, "playback's") is not None


def test_the_tets_slices_are_not_made_ahead():
    from animanifold_blender import live_prefetch

    cuts = live_cuts.CutCache()
    assert live_prefetch.prefetch(_stitched(prisms=False), [1.0, 2.0, 3.0], cuts) == (0, 0) and len(cuts) == 0
