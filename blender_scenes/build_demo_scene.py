"""Builds the demo scene procedurally: a UV sphere with a shape-key animation
(several keyframes: squash, stretch, twist) and a two-material look, a camera and
a light; with morph=True (the script's default) also the pair the main job morphs
(a UV sphere and a torus beside it, Morph Selected's source and target). Works
with bpy 4.5 (python3) and under `blender -b` (3.4+).

    python3 blender_scenes/build_demo_scene.py [out.blend]
    blender -b --factory-startup --python blender_scenes/build_demo_scene.py -- [out.blend]
"""

from __future__ import annotations

import math
import sys

import bpy
import numpy as np

DEMO_NAME = "Blob"
FRAME_START, FRAME_END = 1, 48
MORPH_SOURCE, MORPH_TARGET = "MorphSphere", "MorphTorus"
MORPH_LOCATION = (3.1, 0.0, 1.0)
# Morph pair resolution: UV sphere (segments, rings), torus (major, minor segments).
# The main job's morph and bake take about a second at this size (measured).
MORPH_SPHERE = (32, 16)
MORPH_TORUS = (24, 12)
KEYFRAMES = {  # frame: (squash, stretch, twist) shape key values
    1: (0.0, 0.0, 0.0),
    12: (1.0, 0.0, 0.0),
    24: (0.0, 1.0, 0.3),
    36: (0.0, 0.2, 1.0),
    48: (0.0, 0.0, 0.0),
}


def _material(name, color):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    if bsdf is not None:
        bsdf.inputs["Base Color"].default_value = color
        bsdf.inputs["Roughness"].default_value = 0.4
    mat.diffuse_color = color
    return mat


def build_morph_pair(sphere=MORPH_SPHERE, torus=MORPH_TORUS, location=MORPH_LOCATION):
    """Adds the morph's source and target: a UV sphere of radius 1 and a torus that fits
    inside it (major radius 0.75, minor 0.25), both closed Blender primitives (quads;
    Morph Selected triangulates them), turned by their object transforms to show the
    torus's hole to the camera (the morph aligns inputs by their transforms); returns
    (sphere, torus)."""
    material = _material("MorphSkin", (0.2, 0.6, 0.3, 1.0))
    turn = (math.radians(65), 0.0, math.radians(20))
    bpy.ops.mesh.primitive_uv_sphere_add(segments=sphere[0], ring_count=sphere[1], radius=1.0,
                                         location=location, rotation=turn)
    source = bpy.context.active_object
    bpy.ops.mesh.primitive_torus_add(major_segments=torus[0], minor_segments=torus[1], major_radius=0.75,
                                     minor_radius=0.25, location=location, rotation=turn)
    target = bpy.context.active_object
    for obj, name in ((source, MORPH_SOURCE), (target, MORPH_TARGET)):
        obj.name = name
        obj.data.name = name
        obj.data.materials.append(material)
    return source, target


def build_demo_scene(segments: int = 24, rings: int = 12, name: str = DEMO_NAME, morph: bool = False) -> bpy.types.Object:
    """Adds the animated object to the current scene (and a camera and light when
    the scene has none); returns the object, selected and active. segments/rings set
    its density; morph adds the morph pair beside it (build_morph_pair) and frames
    the camera on both."""
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAME_START, FRAME_END
    scene.frame_set(FRAME_START)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=1.0, location=(0, 0, 1))
    obj = bpy.context.active_object
    obj.name = name
    obj.data.name = name
    bpy.ops.object.shade_smooth()

    # Two materials: bottom half and top half (material_index per face, numpy).
    obj.data.materials.append(_material(f"{name}Skin", (0.8, 0.25, 0.1, 1.0)))
    obj.data.materials.append(_material(f"{name}Cap", (0.1, 0.35, 0.8, 1.0)))
    polys = obj.data.polygons
    centers = np.empty(3 * len(polys), dtype=np.float32)
    polys.foreach_get("center", centers)
    polys.foreach_set("material_index", (centers[2::3] > 0.3).astype(np.int32))

    # Shape keys, computed with numpy from the basis.
    basis = obj.shape_key_add(name="Basis", from_mix=False)
    co = np.empty(3 * len(obj.data.vertices), dtype=np.float32)
    basis.data.foreach_get("co", co)
    p = co.reshape(-1, 3).astype(np.float64)
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    shapes = {
        "Squash": np.column_stack([x * 1.35, y * 1.35, z * 0.55 - 0.35]),
        "Stretch": np.column_stack([x * 0.7, y * 0.7, z * 1.6 + 0.45]),
    }
    angle = (z + 1.0) * 0.9
    shapes["Twist"] = np.column_stack([x * np.cos(angle) - y * np.sin(angle) * 1.2,
                                       x * np.sin(angle) + y * np.cos(angle) * 1.2, z])
    for key_name, target in shapes.items():
        key = obj.shape_key_add(name=key_name, from_mix=False)
        key.data.foreach_set("co", target.astype(np.float32).reshape(-1))
    blocks = obj.data.shape_keys.key_blocks
    for frame, values in KEYFRAMES.items():
        for key_name, value in zip(shapes, values):
            blocks[key_name].value = value
            blocks[key_name].keyframe_insert("value", frame=frame)
    obj.data.shape_keys.animation_data.action.name = f"{name}Action"

    if scene.world is None:
        scene.world = bpy.data.worlds.new("DemoWorld")
        scene.world.color = (0.55, 0.6, 0.65)
        scene.world.use_nodes = True
        background = scene.world.node_tree.nodes.get("Background")
        if background is not None:
            background.inputs["Color"].default_value = (0.55, 0.6, 0.65, 1.0)
            background.inputs["Strength"].default_value = 0.6
    if morph:
        build_morph_pair()
    if not any(o.type == "CAMERA" for o in scene.objects):
        if morph:  # both objects: from further back, centred between them
            bpy.ops.object.camera_add(location=(MORPH_LOCATION[0] / 2, -10.0, 2.4), rotation=(math.radians(84), 0.0, 0.0))
        else:
            bpy.ops.object.camera_add(location=(0.0, -7.5, 2.6), rotation=(math.radians(82), 0.0, 0.0))
        scene.camera = bpy.context.active_object
    if not any(o.type == "LIGHT" for o in scene.objects):
        bpy.ops.object.light_add(type="SUN", location=(3, -3, 6), rotation=(math.radians(40), math.radians(20), 0))
        bpy.context.active_object.data.energy = 4.0
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return obj


if __name__ == "__main__":
    if "--" in sys.argv:
        argv = sys.argv[sys.argv.index("--") + 1:]
    else:  # python3 script.py [out.blend]; under blender without "--": no arguments
        argv = sys.argv[1:] if sys.argv and sys.argv[0].endswith(".py") else []
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_demo_scene(morph=True)
    if argv:
        bpy.ops.wm.save_as_mainfile(filepath=argv[0])
        print(f"demo scene saved to {argv[0]}")
