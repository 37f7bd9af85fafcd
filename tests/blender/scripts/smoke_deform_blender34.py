"""Smoke test of animanifold.deform under a Blender binary (Debian's 3.4): installs
the zip, converts the demo scene into a stitched manifold, anchors keyframes 12 and
24 (stored), puts the top of keyframe 36 in the "handle" group, moves an Empty and
deforms; checks the new cache, the untouched early frames and the moved handles;
then deforms a plain mesh. Run:
    blender -b --factory-startup --python-exit-code 1 --python smoke_deform_blender34.py -- ZIP SCENES_DIR OUT_DIR
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
assert hasattr(bpy.ops.animanifold, "deform")
import animanifold_blender  # noqa: E402  (the installed copy)

am = animanifold_blender._lib.am
assert "animanifold_blender" in am.__name__, am.__name__


def vertices(mesh):
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def group(obj, name, indices):
    g = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
    g.add([int(i) for i in indices], 1.0, "REPLACE")


def activate(obj):
    for other in bpy.context.selected_objects:
        other.select_set(False)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)


build_demo_scene(segments=16, rings=8)
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "deform_smoke.blend"))
assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}  # keyframes 12 and 24 are anchored below
man = bpy.data.objects["Blob_manifold"]
activate(man)
scene = bpy.context.scene
old_path = man.animanifold.cache_path
old = am.load(bpy.path.abspath(old_path))

for frame in (12, 24):  # a band of two anchored keyframes bounds the frames before 24
    scene.frame_set(frame)
    group(man, "anchor", range(len(man.data.vertices)))
    assert bpy.ops.animanifold.deform_store() == {"FINISHED"}
scene.frame_set(36)
v = vertices(man.data)
top = np.flatnonzero(v[:, 2] > np.quantile(v[:, 2], 0.8))
group(man, "handle", top)
empty = bpy.data.objects.new("Grab", None)
scene.collection.objects.link(empty)
empty.location = (0.0, 0.0, 2.0)
bpy.context.view_layer.update()
assert bpy.ops.animanifold.deform(empty="Grab") == {"FINISHED"}  # records where the Empty is
empty.location.x += 0.6
bpy.context.view_layer.update()
assert bpy.ops.animanifold.deform(empty="Grab") == {"FINISHED"}
new_path = man.animanifold.cache_path
assert new_path != old_path and os.path.isfile(bpy.path.abspath(new_path)), new_path
assert os.path.isfile(bpy.path.abspath(old_path))
new = am.load(bpy.path.abspath(new_path))
assert new.check().is_oriented_manifold
early = old.points[:, 3] <= 24.0 + 1e-9
err = np.abs(new.points[early] - old.points[early]).max()
assert err < 1e-3, f"frames up to 24 moved by {err}"
h = np.unique(np.asarray(old.slice(36.0).vertex_edges)[top].reshape(-1))
assert np.allclose(new.points[h], old.points[h] + [0.6, 0, 0, 0], atol=1e-6)
late = np.abs(new.points[~early] - old.points[~early]).max()
assert late > 0.1, late
scene.frame_set(40)
assert len(man.data.polygons) > 0

# A plain mesh: anchors stay, handles follow the Empty.
bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, location=(4.0, 0.0, 0.0))
sphere = bpy.context.active_object
v0 = vertices(sphere.data)
anchors, handles = np.flatnonzero(v0[:, 2] < -0.5), np.flatnonzero(v0[:, 2] > 0.6)
group(sphere, "anchor", anchors)
group(sphere, "handle", handles)
assert bpy.ops.animanifold.deform(empty="Grab", method="graph") == {"FINISHED"}  # records
empty.location.z += 1.0
bpy.context.view_layer.update()
assert bpy.ops.animanifold.deform(empty="Grab", method="graph") == {"FINISHED"}
v1 = vertices(sphere.data)
assert np.allclose(v1[anchors], v0[anchors], atol=1e-6) and np.allclose(v1[handles], v0[handles] + [0, 0, 1], atol=1e-6)

addon_utils.disable("animanifold_blender", default_set=True)
print("DEFORM SMOKE OK", bpy.app.version_string, f"early error {err:.2e}, late motion {late:.3f}")
