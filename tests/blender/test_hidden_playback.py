"""Hidden live manifolds cost no slicing: the frame handlers skip what Blender does not
evaluate, and show it at the current frame once it is visible again (bpy 4.5)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import canonical, mesh_corners, shown  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture()
def live(demo, monkeypatch):
    """(manifold object, calls): every playback.update_object call's frame is counted."""
    from animanifold_blender import playback

    bpy.context.view_layer.objects.active = demo
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    man = bpy.data.objects[demo.name + "_manifold"]
    calls = []
    update_object = playback.update_object
    monkeypatch.setattr(playback, "update_object",
                        lambda obj, frame, **kw: (calls.append((obj.name, frame)), update_object(obj, frame, **kw)))
    return man, calls


def slices_between(calls, frames) -> list:
    calls.clear()
    for frame in frames:
        bpy.context.scene.frame_set(frame)
    return list(calls)


def assert_shows_frame(man, frame):
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    s = cache.slice(float(frame))
    expected = s.vertices[s.faces]
    np.testing.assert_allclose(canonical(mesh_corners(shown(man))), canonical(expected), atol=1e-5)


def hide_in_viewport(man):
    man.hide_set(True)


def disable_in_viewports(man):
    man.hide_viewport = True


def exclude_collection(man):
    collection = bpy.data.collections.new("Hidden")
    bpy.context.scene.collection.children.link(collection)
    collection.objects.link(man)
    bpy.context.scene.collection.objects.unlink(man)
    bpy.context.view_layer.layer_collection.children["Hidden"].exclude = True


def hide_layer_collection(man):
    exclude_collection(man)
    layer = bpy.context.view_layer.layer_collection.children["Hidden"]
    layer.exclude = False
    layer.hide_viewport = True


def reveal(man):
    man.hide_set(False)
    man.hide_viewport = False
    for layer in bpy.context.view_layer.layer_collection.children:
        layer.exclude = False
        layer.hide_viewport = False


@pytest.mark.parametrize("hide", [hide_in_viewport, disable_in_viewports, exclude_collection, hide_layer_collection])
def test_hidden_manifold_is_not_sliced_and_is_shown_when_visible_again(live, hide):
    man, calls = live
    bpy.context.scene.frame_set(10)
    hide(man)
    bpy.context.view_layer.update()
    assert slices_between(calls, range(11, 31)) == [], f"{hide.__name__}: a hidden manifold was sliced"
    reveal(man)
    calls.clear()
    bpy.context.view_layer.update()  # the depsgraph update Blender runs on unhiding
    assert calls == [(man.name, 30.0)], f"{hide.__name__}: not shown at the current frame when visible again"
    assert_shows_frame(man, 30)
    assert slices_between(calls, [31]) == [(man.name, 31.0)]


def test_renders_slice_what_renders_even_when_hidden_in_the_viewport(live):
    from animanifold_blender import visibility

    man, calls = live
    man.hide_set(True)
    assert slices_between(calls, [12]) == []
    visibility.set_rendering(True)
    try:
        assert set(slices_between(calls, [13])) == {(man.name, 13.0)}
        man.hide_render = True
        assert slices_between(calls, [14]) == []
    finally:
        visibility.set_rendering(False)


def test_a_still_render_shows_an_object_hidden_only_in_the_viewport(live):
    from animanifold_blender import handlers, visibility

    man, calls = live
    man.hide_set(True)
    assert slices_between(calls, [12, 22]) == []
    calls.clear()
    try:
        handlers.animanifold_render_init(bpy.context.scene)  # F12: no frame change comes
        assert calls == [(man.name, 22.0)]
        assert_shows_frame(man, 22)
    finally:
        handlers.animanifold_render_done()
    assert not visibility.rendering()
