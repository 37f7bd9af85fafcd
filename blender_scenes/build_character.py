"""Builds a procedural skinned character with a walk cycle, for playback benchmarks: a stick
skeleton (hips, spine, neck, head, arms, legs) thickened by a Skin modifier and smoothed by
a Subdivision Surface modifier into one closed mesh (about 60k triangles at the default
level), bound to an armature whose bones follow the same skeleton (envelope weights, so the
binding is the same on every machine), and a walk cycle keyed on the bones over frames 1-48
(two steps). Works with bpy 4.5 (python3) and under `blender -b` (3.4+).

    python3 blender_scenes/build_character.py [out.blend]
"""

from __future__ import annotations

import math
import sys

import bpy

CHARACTER_NAME = "Walker"
FRAME_START, FRAME_END = 1, 48
STEP_FRAMES = 24  # one stride: left leg forward, then right

# Skeleton joints (x, y, z) and the radius the skin gives each; bones join them.
JOINTS = {
    "hips": ((0.0, 0.0, 1.0), 0.16), "chest": ((0.0, 0.0, 1.45), 0.18), "neck": ((0.0, 0.0, 1.62), 0.06),
    "head": ((0.0, 0.0, 1.85), 0.12),
    "shoulder.L": ((0.2, 0.0, 1.5), 0.07), "elbow.L": ((0.45, 0.0, 1.5), 0.05), "hand.L": ((0.7, 0.0, 1.5), 0.04),
    "shoulder.R": ((-0.2, 0.0, 1.5), 0.07), "elbow.R": ((-0.45, 0.0, 1.5), 0.05), "hand.R": ((-0.7, 0.0, 1.5), 0.04),
    "hip.L": ((0.1, 0.0, 0.95), 0.09), "knee.L": ((0.1, 0.0, 0.5), 0.07), "foot.L": ((0.1, 0.0, 0.08), 0.06),
    "hip.R": ((-0.1, 0.0, 0.95), 0.09), "knee.R": ((-0.1, 0.0, 0.5), 0.07), "foot.R": ((-0.1, 0.0, 0.08), 0.06),
}
# (bone name, head joint, tail joint, parent bone)
BONES = [
    ("spine", "hips", "chest", None), ("neck", "chest", "neck", "spine"), ("head", "neck", "head", "neck"),
    ("clavicle.L", "chest", "shoulder.L", "spine"), ("upper_arm.L", "shoulder.L", "elbow.L", "clavicle.L"),
    ("forearm.L", "elbow.L", "hand.L", "upper_arm.L"),
    ("clavicle.R", "chest", "shoulder.R", "spine"), ("upper_arm.R", "shoulder.R", "elbow.R", "clavicle.R"),
    ("forearm.R", "elbow.R", "hand.R", "upper_arm.R"),
    ("pelvis.L", "hips", "hip.L", "spine"), ("thigh.L", "hip.L", "knee.L", "pelvis.L"),
    ("shin.L", "knee.L", "foot.L", "thigh.L"),
    ("pelvis.R", "hips", "hip.R", "spine"), ("thigh.R", "hip.R", "knee.R", "pelvis.R"),
    ("shin.R", "knee.R", "foot.R", "thigh.R"),
]


def _skin_mesh(subdivision_levels: int) -> bpy.types.Object:
    """The skeleton as vertices and edges, a Skin modifier and a Subdivision Surface modifier,
    applied: one closed mesh."""
    names = list(JOINTS)
    mesh = bpy.data.meshes.new(CHARACTER_NAME)
    edges = [(names.index(head), names.index(tail)) for _, head, tail, _ in BONES]
    mesh.from_pydata([JOINTS[n][0] for n in names], edges, [])
    obj = bpy.data.objects.new(CHARACTER_NAME, mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.modifier_add(type="SKIN")  # the operator, unlike modifiers.new, adds the skin radii layer
    for vertex, name in zip(mesh.skin_vertices[0].data, names):
        vertex.radius = (JOINTS[name][1], JOINTS[name][1])
    mesh.skin_vertices[0].data[names.index("hips")].use_root = True
    subsurf = obj.modifiers.new("Subdivision", "SUBSURF")
    subsurf.levels = subsurf.render_levels = subdivision_levels
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph))
    obj.modifiers.clear()
    obj.data = evaluated
    bpy.data.meshes.remove(mesh)
    evaluated.name = CHARACTER_NAME
    return obj


def _armature() -> bpy.types.Object:
    data = bpy.data.armatures.new(CHARACTER_NAME + "Rig")
    rig = bpy.data.objects.new(data.name, data)
    bpy.context.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    for name, head, tail, parent in BONES:
        bone = data.edit_bones.new(name)
        bone.head, bone.tail = JOINTS[head][0], JOINTS[tail][0]
        bone.head_radius = bone.tail_radius = 0.5 * max(JOINTS[head][1], JOINTS[tail][1])
        bone.envelope_distance = 1.5 * max(JOINTS[head][1], JOINTS[tail][1])
        if parent is not None:
            bone.parent = data.edit_bones[parent]
            bone.use_connect = False
    bpy.ops.object.mode_set(mode="OBJECT")
    return rig


def _walk_cycle(rig: bpy.types.Object) -> None:
    """Legs and arms swing in opposition, knees bend on the swing, the spine sways: a key
    every quarter stride, interpolated by Blender's default Bézier easing."""
    for bone in rig.pose.bones:
        bone.rotation_mode = "XYZ"
    for frame in range(FRAME_START, FRAME_END + 1, STEP_FRAMES // 4):
        phase = 2 * math.pi * (frame - FRAME_START) / STEP_FRAMES
        swing = math.sin(phase)
        angles = {
            "thigh.L": (0.5 * swing, 0, 0), "thigh.R": (-0.5 * swing, 0, 0),
            "shin.L": (-0.6 * max(0.0, -swing), 0, 0), "shin.R": (-0.6 * max(0.0, swing), 0, 0),
            "upper_arm.L": (0, 0.4 * swing, 0), "upper_arm.R": (0, 0.4 * swing, 0),
            "forearm.L": (0, 0.3, 0), "forearm.R": (0, -0.3, 0),
            "spine": (0.05, 0, 0.12 * swing), "head": (0, 0, -0.1 * swing),
        }
        for name, rotation in angles.items():
            bone = rig.pose.bones[name]
            bone.rotation_euler = rotation
            bone.keyframe_insert("rotation_euler", frame=frame)


def build_character(subdivision_levels: int = 3) -> bpy.types.Object:
    """Adds the character and its rig to the current scene (frames 1-48, the walk cycle on the
    rig); returns the character mesh object (an Armature modifier deforms it)."""
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAME_START, FRAME_END
    body = _skin_mesh(subdivision_levels)
    rig = _armature()
    body.parent = rig
    modifier = body.modifiers.new("Armature", "ARMATURE")
    modifier.object = rig
    modifier.use_vertex_groups = False
    modifier.use_bone_envelopes = True
    _walk_cycle(rig)
    bpy.context.view_layer.objects.active = body
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == body)
    scene.frame_set(FRAME_START)
    return body


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    body = build_character()
    body.data.calc_loop_triangles()
    print(f"{body.name}: {len(body.data.vertices)} vertices, {len(body.data.loop_triangles)} triangles")
    if argv:
        bpy.ops.wm.save_as_mainfile(filepath=argv[0])
