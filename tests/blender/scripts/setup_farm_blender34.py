"""Prepares a farm test under a Blender binary (Debian's 3.4): installs the add-on zip as a
legacy add-on, enables it in the (test's own) user preferences and saves them, so later
`blender -b scene.blend --python-expr "from animanifold_blender import farm; ..."` runs find it,
then saves the converted demo scene as OUT_DIR/farm.blend. Run:
    blender -b --factory-startup --python-exit-code 1 --python setup_farm_blender34.py -- ZIP SCENES_DIR OUT_DIR
"""
import os
import sys

import addon_utils
import bpy

zip_path, scenes_dir, out_dir = sys.argv[sys.argv.index("--") + 1:][:3]
sys.path.insert(0, scenes_dir)
from build_demo_scene import build_demo_scene  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)
bpy.ops.wm.save_userpref()
build_demo_scene(segments=16, rings=8)
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "farm.blend"))
assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
bpy.ops.wm.save_mainfile()
print("FARM SETUP OK", bpy.app.version_string)
