"""The add-on's preferences (preferences.py): the thread count reaches the core (0 follows
Blender's own Threads setting) when it changes and before long work, and the Frame Cache
Budget is what playback's cache keeps within."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from animanifold import interval_cuts  # noqa: E402
from animanifold_blender import preferences  # noqa: E402
from animanifold_blender._lib import am  # noqa: E402
from animanifold_blender.live_registry import registry  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture()
def prefs(empty_scene):
    """The add-on's preferences, as when Blender enabled it (the session's add-on was
    registered by hand, which gives it no entry in Preferences > Add-ons)."""
    before = am.threads()
    entry = bpy.context.preferences.addons.new()
    entry.module = preferences.PACKAGE
    yield entry.preferences
    bpy.context.preferences.addons.remove(entry)
    am.set_threads(before)


def test_the_preferences_are_this_add_ons():
    assert preferences.AnimanifoldPreferences.bl_idname == preferences.PACKAGE == "animanifold_blender"


def test_setting_the_threads_preference_sets_the_cores_count(prefs):
    prefs.threads = 1
    assert am.threads() == 1
    prefs.threads = 3
    assert am.threads() == 3


def test_zero_threads_follow_blenders_own_setting_at_use(prefs, empty_scene):
    render = empty_scene.render
    render.threads_mode = "FIXED"
    render.threads = 3
    prefs.threads = 0
    assert am.threads() == 3
    render.threads = 1
    assert preferences.apply_threads(bpy.context) == 1 and am.threads() == 1


def test_without_preferences_the_count_is_blenders(empty_scene):
    empty_scene.render.threads_mode = "FIXED"
    empty_scene.render.threads = 1
    before = am.threads()
    try:
        assert preferences.addon_preferences() is None
        assert preferences.apply_threads(bpy.context) == 1
    finally:
        am.set_threads(before)


def test_convert_applies_the_threads_preference_before_it_runs(prefs, demo, tmp_path):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "threads.blend"))
    prefs.threads = 2
    am.set_threads(1)  # as if a script changed it since
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    assert am.threads() == 2


def big_cut(corners: int) -> interval_cuts.Cut:
    faces = np.zeros((corners // 3, 3), np.int32)
    zeros = np.zeros((corners, 3), np.float32)
    return interval_cuts.Cut(0.5, faces, None, None, zeros, np.zeros(2 * corners, np.float32), rate=zeros.copy(),
                             uv=zeros.copy(), uv_rate=zeros.copy())


class Manifold:  # a loaded manifold as the cache sees it: keyed by identity, weakly referenced
    pass


def test_the_frame_cache_keeps_within_the_budget_preference(prefs):
    assert prefs.frame_cache_budget == preferences.DEFAULT_BUDGET_MB == 256
    registry.clear()
    assert registry.cuts.budget == registry.cuts.frame_budget == 256 * 2**20
    cut = big_cut(600_000)
    assert 16 * 2**20 < cut.nbytes() < 256 * 2**20
    manifold = Manifold()
    registry.cuts.put(manifold, "a", cut)
    assert registry.cuts.get(manifold, "a") is cut
    prefs.frame_cache_budget = 16
    assert registry.cuts.budget == registry.cuts.frame_budget == 16 * 2**20
    registry.cuts.put(manifold, "b", cut)  # more than the budget now: not kept
    assert registry.cuts.get(manifold, "b") is None
    registry.clear()
