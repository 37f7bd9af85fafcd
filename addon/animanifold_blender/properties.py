"""Settings: per object (a manifold object's cache and slicing) and per scene
(sampling and bake options used by the panel and as operator defaults)."""

from __future__ import annotations

import math

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)
from bpy.types import PropertyGroup

from . import live

# Blender 4.5+ warns on '//' paths in add-on path properties unless they say they take them.
_BLEND_RELATIVE = {"PATH_SUPPORTS_BLEND_RELATIVE"} if bpy.app.version >= (4, 5, 0) else set()

AXIS_ITEMS = (
    ("t", "t", "Time: the frame at the scene's current frame (the animation)"),
    ("x", "x", "Sweep view: the slice at x = value, time laid out along x"),
    ("y", "y", "Sweep view: the slice at y = value, time laid out along y"),
    ("z", "z", "Sweep view: the slice at z = value, time laid out along z"),
)

SAMPLING_ITEMS = (
    ("KEYFRAMES", "Keyframes", "Sample at the keyframes of every action driving the object (shape keys, object, armature)"),
    ("EVERY_N", "Every N Frames", "Sample every N frames (procedural animation, smoother in-betweens)"),
)

EXPORT_ITEMS = (
    ("NONE", "None", "No file sequence"),
    ("OBJ", "OBJ", "One .obj file per frame"),
    ("PLY", "PLY", "One .ply file per frame"),
)


def _reslice(self, context):
    obj = self.id_data
    if isinstance(obj, bpy.types.Object) and live.is_live(obj) and context is not None and context.scene is not None:
        try:
            live.update_object(obj, live.scene_frame(context.scene))
            live._ERRORS.pop(obj.name_full, None)
        except Exception as e:  # shown in the panel; never raise from an update callback
            live._ERRORS[obj.name_full] = f"{type(e).__name__}: {e}"


def _resmooth(self, context):
    """A Smooth setting changed: free the subdivisions no object uses any more (and
    forget failed ones, so they are tried again), then re-slice."""
    try:
        live.prune_subdivided()
    except Exception as e:  # never raise from an update callback
        print(f"animanifold: cannot prune subdivided manifolds: {type(e).__name__}: {e}")
    _reslice(self, context)


class AnimanifoldObjectSettings(PropertyGroup):
    is_manifold: BoolProperty(name="Is Manifold", default=False, options={"HIDDEN"})
    mode: EnumProperty(
        name="Mode",
        items=(
            ("LIVE", "Live", "Sliced by the add-on on every frame change"),
            ("BAKED", "Baked", "Shown by the bake (node group or mesh sequence cache); the add-on leaves it alone"),
        ),
        default="LIVE",
        update=_reslice,
    )
    cache_path: StringProperty(
        name="Cache",
        description="Manifold cache file (.amf); '//' is relative to the .blend",
        subtype="FILE_PATH",
        options=_BLEND_RELATIVE,
        update=_reslice,
    )
    source: PointerProperty(name="Source", type=bpy.types.Object, description="The object this manifold was made from")
    axis: EnumProperty(name="Axis", items=AXIS_ITEMS, default="t", update=_reslice,
                       description="Slicing axis: t shows the animation, x/y/z a sweep through time")
    sweep_value: FloatProperty(name="Value", default=0.0, update=_reslice, subtype="DISTANCE",
                               description="Where the sweep view cuts along its axis (object space)")
    time_scale: FloatProperty(name="Time Scale", default=0.05, min=1e-6, soft_max=10.0, update=_reslice,
                              description="Length per frame along the sliced axis in sweep views")
    live_normals: BoolProperty(
        name="Smooth Normals", default=False, update=_reslice,
        description="Live slices get the keyframes' smooth normals as custom normals (nicer shading between "
                    "keyframes, slower playback); baked frames always have them")
    subdivision_levels: IntProperty(
        name="Manifold Levels", default=0, min=0, max=2, update=_resmooth,
        description="Tetrahedral subdivision of the animation manifold (Schaefer et al. 2004): smooths the shape "
                    "and the motion between keyframes together; each level has 8x the tets (computed once, kept "
                    "in memory)")
    keep_keyframe_times: BoolProperty(
        name="Keep Keyframe Times", default=True, update=_resmooth,
        description="Keyframes stay at their times, so the subdivided animation passes through them; off: "
                    "only the first and last frame stay at their times, the motion gets smoother")
    smooth_levels: IntProperty(
        name="Frame Levels", default=0, min=0, max=3, update=_resmooth,
        description="Loop subdivision of every frame to its limit surface (OpenSubdiv): each level has 4x the "
                    "faces; frames are refined anew on every frame change")
    crease_angle: FloatProperty(
        name="Crease Angle", default=math.radians(30.0), min=math.radians(1.0), max=math.pi, subtype="ANGLE",
        update=_resmooth,
        description="Edges of a frame whose faces meet at more than this angle stay sharp when it is smoothed "
                    "(180°: none)")
    uv_name: StringProperty(name="UV Map", default="UVMap", options={"HIDDEN"})
    frame_start: FloatProperty(name="Start", options={"HIDDEN"})
    frame_end: FloatProperty(name="End", options={"HIDDEN"})
    bake_collection: PointerProperty(name="Bake Collection", type=bpy.types.Collection)


class AnimanifoldSceneSettings(PropertyGroup):
    sampling: EnumProperty(name="Sampling", items=SAMPLING_ITEMS, default="KEYFRAMES")
    step: IntProperty(name="N", default=5, min=1, description="Sample every N frames")
    use_scene_range: BoolProperty(name="Scene Range", default=True, description="Use the scene's frame range")
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=250)
    cache_directory: StringProperty(
        name="Cache Folder",
        description="Folder for manifold caches; empty: beside the .blend (a temporary folder for an unsaved file)",
        subtype="DIR_PATH",
        options=_BLEND_RELATIVE,
    )
    bake_use_scene_range: BoolProperty(name="Scene Range", default=True,
                                       description="Bake the scene's frame range (clipped to the manifold)")
    bake_start: IntProperty(name="Start", default=1, description="First frame to bake (a farm bakes chunks)")
    bake_end: IntProperty(name="End", default=250, description="Last frame to bake")
    bake_alembic: BoolProperty(name="Alembic", default=True,
                               description="Also write an Alembic cache with Blender's exporter (where supported)")
    bake_use_mesh_cache: BoolProperty(name="Use Mesh Sequence Cache", default=False,
                                      description="Show the Alembic cache through a Mesh Sequence Cache modifier")
    bake_export: EnumProperty(name="Sequence", items=EXPORT_ITEMS, default="NONE")
    bake_directory: StringProperty(name="Folder", default="//animanifold_bake/", subtype="DIR_PATH",
                                   options=_BLEND_RELATIVE,
                                   description="Folder for Alembic and OBJ/PLY files ('//' is beside the .blend)")


classes = (AnimanifoldObjectSettings, AnimanifoldSceneSettings)


def register_properties():
    bpy.types.Object.animanifold = PointerProperty(type=AnimanifoldObjectSettings)
    bpy.types.Scene.animanifold = PointerProperty(type=AnimanifoldSceneSettings)


def unregister_properties():
    for owner in (bpy.types.Scene, bpy.types.Object):
        if hasattr(owner, "animanifold"):
            del owner.animanifold
