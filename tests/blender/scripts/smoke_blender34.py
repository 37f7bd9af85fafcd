"""Smoke test under a Blender binary (Debian's 3.4): installs the zip, converts
the demo scene, bakes it with the node group, and checks frames without the
add-on's handler. Run:
    blender -b --factory-startup --python-exit-code 1 --python smoke_blender34.py -- ZIP SCENES_DIR OUT_DIR
"""
import os
import sys

import addon_utils
import bpy
import numpy as np

zip_path, scenes_dir, out_dir = sys.argv[sys.argv.index("--") + 1:][:3]
sys.path.insert(0, scenes_dir)
from build_demo_scene import KEYFRAMES, build_demo_scene  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)  # (this would unload add-ons enabled before it)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)
assert hasattr(bpy.ops.animanifold, "convert_action") and bpy.ops.animanifold.convert_action.poll is not None
import animanifold_blender  # noqa: E402  (the installed copy)
assert "animanifold_blender" in animanifold_blender._lib.am.__name__, animanifold_blender._lib.am.__name__

obj = build_demo_scene(segments=16, rings=8)
name = obj.name
blend = os.path.join(out_dir, "smoke.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
man = bpy.data.objects[name + "_manifold"]
assert man.animanifold.cache_path.startswith("//"), man.animanifold.cache_path
assert obj.hide_get() and obj.hide_render
scene = bpy.context.scene
meshes = len(bpy.data.meshes)
live = {}
for f in (1, 7, 12, 30, 48):
    scene.frame_set(f)
    co = np.empty(3 * len(man.data.vertices), np.float32)
    man.data.vertices.foreach_get("co", co)
    live[f] = co
assert len(bpy.data.meshes) == meshes, "scrubbing created meshes"
assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
assert man.animanifold.mode == "BAKED" and man.modifiers.get("Animanifold Bake") is not None
bpy.ops.wm.save_as_mainfile(filepath=blend)

# Without the add-on: its handlers gone, the node group alone shows each frame.
addon_utils.disable("animanifold_blender", default_set=True)
assert not any("animanifold" in getattr(h, "__name__", "") for h in bpy.app.handlers.frame_change_post)
bpy.ops.wm.open_mainfile(filepath=blend)
man = bpy.data.objects[name + "_manifold"]
for f, expected in live.items():
    bpy.context.scene.frame_set(f)
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = np.empty(3 * len(ev.vertices), np.float32)
    ev.vertices.foreach_get("co", co)
    assert co.shape == expected.shape and np.allclose(co, expected, atol=1e-6), f"frame {f}: baked mesh differs"
print("SMOKE OK", bpy.app.version_string)
