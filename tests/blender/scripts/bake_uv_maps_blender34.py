"""Under a Blender binary older than 3.5 (Debian's 3.4): the node-group bake's evaluated
mesh has real UV maps (every one of the source's), equal to the live frame's, in this
process and in the saved file opened without the add-on. Prints "UVMAPS OK <version>".
Run:
    blender -b --factory-startup --python-exit-code 1 --python bake_uv_maps_blender34.py -- ZIP SCENES_DIR OUT_DIR
"""
import os
import sys

import addon_utils
import bpy
import numpy as np

zip_path, scenes_dir, out_dir = sys.argv[sys.argv.index("--") + 1:][:3]
sys.path.insert(0, scenes_dir)
from build_demo_scene import build_demo_scene  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)

MAPS = ("UVMap", "Detail")
FRAMES = (1, 7, 12, 30, 48)
obj = build_demo_scene(segments=16, rings=8)
detail = obj.data.uv_layers.new(name="Detail")
L = len(obj.data.loops)
detail.data.foreach_set("uv", np.column_stack([np.linspace(0, 1, L), np.linspace(1, 0, L)]).astype(np.float32).ravel())
obj.data.uv_layers.active = obj.data.uv_layers["UVMap"]
blend = os.path.join(out_dir, "uvmaps.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
NAME = obj.name + "_manifold"
man = bpy.data.objects[NAME]


def uv_maps(mesh):
    maps = {}
    for layer in mesh.uv_layers:
        values = np.empty(2 * len(mesh.loops), np.float32)
        layer.data.foreach_get("uv", values)
        maps[layer.name] = values
    return maps


def shown():
    return uv_maps(man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data)


live = {}
for f in FRAMES:
    bpy.context.scene.frame_set(f)
    live[f] = shown()
    assert set(MAPS) <= set(live[f]), f"live frame {f}: UV maps {sorted(live[f])}"


def check(where):
    for f, expected in live.items():
        bpy.context.scene.frame_set(f)
        got = shown()
        for name in MAPS:
            assert name in got, f"{where}, frame {f}: no UV map {name!r} (UV maps {sorted(got)})"
            assert got[name].shape == expected[name].shape and np.allclose(got[name], expected[name], atol=1e-6), \
                f"{where}, frame {f}: UV map {name!r} differs from the live frame's"
        assert np.ptp(got["UVMap"]) > 0.5, f"{where}, frame {f}: a degenerate UV map"


assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
check("baked")
bpy.ops.wm.save_as_mainfile(filepath=blend)
addon_utils.disable("animanifold_blender", default_set=True)
bpy.ops.wm.open_mainfile(filepath=blend)
man = bpy.data.objects[NAME]
check("reopened without the add-on")
print("UVMAPS OK", bpy.app.version_string)
