"""Smoke test of Morph Selected under a Blender binary (Debian's 3.4): installs the
zip; morphs a UV sphere into a torus (different genus) and a UV sphere into a
turned, mirrored cube (same genus), each moved by its object transform; checks
that the frames at the range ends are the inputs (every frame vertex on the
input's surface and every input vertex in the frame, within 1e-6 of the
bounding-box diagonal; equal area and volume); bakes the torus morph and checks
the baked frames without the add-on. Run:
    blender -b --factory-startup --python-exit-code 1 --python smoke_morph_blender34.py -- ZIP SCENES_DIR OUT_DIR

The last line is "MORPH SMOKE OK <version> method=<method> torus_end=<exact|off:...>":
with the strip method (§8.5) the torus's end is reported, not asserted (stripping
alone cannot reproduce a change of genus); with any other method it is asserted.
"""
import os
import sys

import addon_utils
import bpy
import numpy as np

zip_path, scenes_dir, out_dir = sys.argv[sys.argv.index("--") + 1:][:3]
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # tests/, for helpers
from helpers.blender_helpers import select_pair as select  # noqa: E402
from helpers.morph_scenes import (add_sphere_and_torus, add_sphere_and_turned_mirrored_cube,  # noqa: E402
                                  assert_morph_shows, compare_with, evaluated)
from helpers.surface_checks import frame_matches  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)
assert hasattr(bpy.ops.animanifold, "morph_selected")
import animanifold_blender  # noqa: E402  (the installed copy)
from animanifold_blender import object_manifold, ops_morph  # noqa: E402

assert "animanifold_blender" in animanifold_blender._lib.am.__name__, animanifold_blender._lib.am.__name__

scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 24
blend = os.path.join(out_dir, "morph_smoke.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)  # the caches go beside it

# Same genus: both ends exact with any method.
ball, box = add_sphere_and_turned_mirrored_cube(x=5.0)
ball.name, box.name = "Ball", "Box"  # so that the next pair keeps the names "Sphere" and "Torus"
select(ball, box)
assert bpy.ops.animanifold.morph_selected() == {"FINISHED"}
cube_morph = bpy.context.active_object
assert_morph_shows(cube_morph, ball, 1)
assert_morph_shows(cube_morph, box, 24)

# Different genus: a UV sphere into a torus.
sphere, torus = add_sphere_and_torus()
select(sphere, torus)
assert bpy.ops.animanifold.morph_selected() == {"FINISHED"}
morph = bpy.context.active_object
name = morph.name
assert name == "Sphere_to_Torus" and morph.animanifold.is_manifold, name
assert morph.animanifold.cache_path.startswith("//"), morph.animanifold.cache_path
assert sphere.hide_get() and torus.hide_get() and sphere.hide_render and torus.hide_render
manifold = object_manifold.manifold_for(morph)
method = manifold.metadata["morph"]["method"]
assert method == ops_morph.BEST_METHOD, (method, ops_morph.BEST_METHOD)
assert manifold.time_range == (1.0, 24.0), manifold.time_range
assert manifold.validity["inverted_simplices"] == 0, manifold.validity

scene.frame_set(1)
report = compare_with(morph, sphere)
assert frame_matches(report), ("sphere → torus, frame 1", report)
scene.frame_set(24)
report = compare_with(morph, torus)
if frame_matches(report):
    torus_end = "exact"
else:
    assert method == "strip", ("sphere → torus, frame 24", method, report)
    torus_end = "off:" + ",".join(f"{k}:{v:.2g}" for k, v in report.items())

live_frames = {}
for f in (1, 9, 17, 24):
    scene.frame_set(f)
    live_frames[f] = evaluated(morph)[0]
assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
assert morph.animanifold.mode == "BAKED"
bpy.ops.wm.save_as_mainfile(filepath=blend)

# Without the add-on: the node group alone shows each frame.
addon_utils.disable("animanifold_blender", default_set=True)
bpy.ops.wm.open_mainfile(filepath=blend)
morph = bpy.data.objects[name]
for f, expected in live_frames.items():
    bpy.context.scene.frame_set(f)
    got = evaluated(morph)[0]
    assert got.shape == expected.shape and np.allclose(got, expected, atol=1e-6), f"frame {f}: baked mesh differs"
print("MORPH SMOKE OK", bpy.app.version_string, f"method={method}", f"torus_end={torus_end}")
