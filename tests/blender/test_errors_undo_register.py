"""Failures leave the scene unchanged; undo; register/unregister cycles."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from helpers.blender_helpers import run_then_undo, scene_state  # noqa: E402

pytestmark = pytest.mark.blender


def fails(match, **kwargs):
    before = scene_state()
    with pytest.raises(RuntimeError, match=match):
        bpy.ops.animanifold.convert_action(**kwargs)
    assert scene_state() == before, "a failed Convert changed the scene"


def test_not_a_mesh(empty_scene):
    bpy.ops.object.camera_add()
    fails(r"'Camera' is a camera, not a mesh")
    bpy.ops.object.empty_add()
    fails(r"'Empty' is an empty, not a mesh")
    bpy.ops.object.armature_add()
    fails(r"'Armature' is an armature, not a mesh")


def test_no_animation(empty_scene):
    bpy.ops.mesh.primitive_cube_add()
    fails(r"'Cube' has no animation: no object, shape-key or armature action and no driver", sampling="KEYFRAMES")
    empty_scene.frame_end = 20  # the default samples by measuring every frame: it finds nothing moving
    fails(r"'Cube' does not move in frames 1–20: no animation in the range")
    empty_scene.frame_end = 250
    fails(r"'Cube' does not move in frames 1–250: no animation in the range", sampling="EVERY_N", step=50)


def test_animation_outside_the_range(empty_scene):
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    for frame, z in ((300, 0.0), (320, 1.0)):
        cube.location.z = z
        cube.keyframe_insert("location", frame=frame)
    empty_scene.frame_set(1)
    fails(r"does not move in frames 1–250: no animation in the range")


def test_empty_range(demo):
    scene = bpy.context.scene
    scene.frame_end = scene.frame_start
    fails(r"frame range 1–1 is empty")
    fails(r"frame range 20–10 is empty", use_scene_range=False, frame_start=20, frame_end=10)


def test_topology_change_names_the_frame(demo):
    # A Decimate modifier whose ratio is keyframed: connectivity changes mid-range.
    mod = demo.modifiers.new("Decimate", "DECIMATE")
    for frame, ratio in ((1, 1.0), (10, 1.0), (20, 0.4)):
        mod.ratio = ratio
        demo.keyframe_insert('modifiers["Decimate"].ratio', frame=frame)
    bpy.context.scene.frame_set(1)
    before = scene_state()
    with pytest.raises(RuntimeError, match=r"topology of 'Blob' changes at frame 12 "):
        bpy.ops.animanifold.convert_action(sampling="KEYFRAMES")  # the first sample after frame 10
    assert scene_state() == before
    # The default measures every frame and half frame: it names the first that changes.
    with pytest.raises(RuntimeError, match=r"topology of 'Blob' changes at frame 10\.5 "):
        bpy.ops.animanifold.convert_action()
    assert scene_state() == before


def test_topology_change_with_the_same_counts_says_what_changed(empty_scene):
    # A Triangulate modifier whose quad method is keyframed: the same vertices and faces,
    # other diagonals.
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    mod = cube.modifiers.new("Triangulate", "TRIANGULATE")
    for frame, method in ((1, "FIXED"), (10, "FIXED_ALTERNATE")):
        mod.quad_method = method
        cube.keyframe_insert('modifiers["Triangulate"].quad_method', frame=frame)
    with pytest.raises(RuntimeError, match=r"changes at frame 10 \(8 vertices, 12 faces as at frame 1, but face \d+ "
                                           r"joins vertices \([\d, ]+\) instead of \([\d, ]+\) there\)"):
        bpy.ops.animanifold.convert_action()


def test_unsaved_file_with_relative_cache_folder(demo):
    fails(r"relative to the \.blend, which is not saved yet", cache_directory="//caches/")


def test_poll_needs_an_active_object(empty_scene):
    assert not bpy.ops.animanifold.convert_action.poll()
    assert not bpy.ops.animanifold.bake.poll()  # no manifold object


def test_undo_after_convert_restores_the_scene(demo):
    run_then_undo(bpy.ops.animanifold.convert_action, "Convert to Manifold", made="Blob_manifold", hidden="Blob")
    # Undo reloads data blocks: the handler holds no stale references.
    for frame in (5, 12, 30):
        bpy.context.scene.frame_set(frame)
    bpy.ops.ed.redo()
    man = bpy.data.objects["Blob_manifold"]
    bpy.context.scene.frame_set(12)
    assert len(man.data.polygons) > 0 and bpy.data.objects["Blob"].hide_get()


_LISTS = ("frame_change_pre", "frame_change_post", "depsgraph_update_post", "load_post", "undo_post", "redo_post",
          "render_init", "render_complete", "render_cancel", "save_pre", "save_post")
# Playback (2), shown again (1), rendering (3), interactive deformation (2), save (2), load, undo, redo:
# handlers._HANDLERS.
HANDLERS = 13


def _handler_count():
    names = [getattr(h, "__name__", "") for lst in _LISTS for h in getattr(bpy.app.handlers, lst)]
    return sum(n.startswith("animanifold_") for n in names)


def test_register_unregister_register(addon):
    assert _handler_count() == HANDLERS
    addon.unregister()
    try:
        assert _handler_count() == 0
        assert not hasattr(bpy.types.Object, "animanifold") and not hasattr(bpy.types.Scene, "animanifold")
        assert not hasattr(bpy.types, "ANIMANIFOLD_OT_convert_action")
        assert not hasattr(bpy.types, "VIEW3D_PT_animanifold")
        with pytest.raises((AttributeError, RuntimeError)):
            bpy.ops.animanifold.convert_action()
    finally:
        addon.register()
    addon.unregister()
    addon.register()
    assert _handler_count() == HANDLERS
    assert hasattr(bpy.types, "ANIMANIFOLD_OT_convert_action") and hasattr(bpy.types.Object, "animanifold")
    # A stale copy of the handler (an earlier load of the module) is replaced, not doubled.
    addon.handlers.register_handlers()
    assert _handler_count() == HANDLERS
    # The add-on still works after the cycles.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    from build_demo_scene import build_demo_scene

    build_demo_scene(segments=8, rings=4)
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    counts = np.array([len(bpy.data.meshes)])
    bpy.context.scene.frame_set(20)
    assert len(bpy.data.meshes) == counts[0]


def test_bake_in_unsaved_file_needs_a_path(demo):
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}  # cache in the temp folder
    before = scene_state()
    with pytest.raises(RuntimeError, match=r"bake folder '//animanifold_bake/' is relative to the \.blend, which is not saved"):
        bpy.ops.animanifold.bake(alembic=False, export="OBJ")
    assert scene_state() == before
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}  # the node group needs no path


class _FakeLayout:
    """Records what a panel draws; checks every property and operator exists."""

    def __init__(self, log):
        self.log = log
        self.enabled = True

    def box(self):
        return self

    def row(self, **_kw):
        return self

    def column(self, **_kw):
        return self

    def prop_search(self, data, name, *_args, **kw):
        self.prop(data, name, **kw)

    def label(self, text="", **_kw):
        self.log.append(("label", text))

    def prop(self, data, name, **_kw):
        assert name in data.bl_rna.properties, f"panel draws a missing property {name!r}"
        self.log.append(("prop", name))

    def operator(self, idname, **_kw):
        module, name = idname.split(".")
        assert hasattr(getattr(bpy.ops, module), name) and getattr(getattr(bpy.ops, module), name).idname()
        self.log.append(("operator", idname))
        return None


def test_panel_draws_for_plain_live_and_baked_objects(demo, addon):
    from types import SimpleNamespace

    def draw():
        log = []
        addon.ui.VIEW3D_PT_animanifold.draw(SimpleNamespace(layout=_FakeLayout(log)), bpy.context)
        return log

    assert ("operator", "animanifold.convert_action") in draw()
    assert ("prop", "tolerance") in draw()  # the default sampling's setting
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    log = draw()
    assert ("prop", "axis") in log and ("operator", "animanifold.bake") in log
    settings = bpy.context.active_object.animanifold
    percent = 100 * settings.max_deviation / settings.source_size
    assert 0 < percent <= 0.2 and ("label", f"Deviation: {percent:.3g} %") in log
    assert ("label", f"Worst Frame: {settings.deviation_frame:g}") in log
    bpy.context.active_object.animanifold.axis = "x"
    assert ("prop", "sweep_value") in draw()
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    assert ("operator", "animanifold.make_live") in draw()
