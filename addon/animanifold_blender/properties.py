"""Settings: per object (a manifold object's cache and slicing; Laplacian deformation's
groups, Empty and options) and per scene (sampling and bake options), shown by the
panels and used as the operators' defaults."""

from __future__ import annotations

import math
import traceback

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

from . import interactive_deform, live
from ._lib import am
from .adaptive_sampling import MAX_SAMPLES, TOLERANCE_PERCENT
from .enum_items import enum_items
from .object_manifold import prune_subdivided

# Blender 4.5+ warns on '//' paths in add-on path properties unless they say they take them.
BLEND_RELATIVE = {"PATH_SUPPORTS_BLEND_RELATIVE"} if bpy.app.version >= (4, 5, 0) else set()

AXIS_ITEMS = (
    ("t", "t", "Time: the frame at the scene's current frame (the animation)"),
    ("x", "x", "Sweep view: the slice at x = value, time laid out along x"),
    ("y", "y", "Sweep view: the slice at y = value, time laid out along y"),
    ("z", "z", "Sweep view: the slice at z = value, time laid out along z"),
)

SAMPLING_ITEMS = (
    ("ADAPTIVE", "Within Tolerance",
     "Keyframes, plus samples added until every frame and half frame is within the tolerance of the source"),
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
        live.show_object(obj, live.scene_frame(context.scene))  # a failure goes to the panel


def _resmooth(self, context):
    """A Smooth setting changed: free the subdivisions no object uses any more (and
    forget failed ones, so they are tried again), then re-slice."""
    try:
        prune_subdivided()
    except Exception as e:  # called from a property's update: must not raise into Blender
        traceback.print_exc()
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
        options=BLEND_RELATIVE,
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
        name="Smooth Normals", default=True, update=_reslice,
        description="Live frames get the keyframes' smooth normals carried along the manifold, as baked frames "
                    "do (off: Blender's own normals, flat along thin faces and creased at UV seams)")
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
    # Measured by Convert's Within Tolerance sampling (-1: not measured).
    max_deviation: FloatProperty(name="Deviation", default=-1.0, options={"HIDDEN"}, subtype="DISTANCE",
                                 description="Largest distance of a frame from the source's evaluated mesh")
    deviation_frame: FloatProperty(name="Deviation Frame", default=0.0, options={"HIDDEN"})
    source_size: FloatProperty(name="Source Size", default=0.0, options={"HIDDEN"}, subtype="DISTANCE",
                               description="Bounding-box diagonal of the source the deviation is measured against")


class AnimanifoldSceneSettings(PropertyGroup):
    sampling: EnumProperty(name="Sampling", items=SAMPLING_ITEMS, default="ADAPTIVE")
    step: IntProperty(name="N", default=5, min=1, description="Sample every N frames")
    tolerance: FloatProperty(
        name="Tolerance", default=TOLERANCE_PERCENT, min=1e-6, max=100.0, subtype="PERCENTAGE", precision=3,
        description="Within Tolerance: the largest distance of a frame from the source's evaluated mesh, in % of "
                    "the object's bounding-box diagonal")
    max_samples: IntProperty(name="Sample Cap", default=MAX_SAMPLES, min=2,
                             description="Within Tolerance: at most this many samples (the report warns when the "
                                         "tolerance is not reached within them)")
    use_scene_range: BoolProperty(name="Scene Range", default=True, description="Use the scene's frame range")
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=250)
    cache_directory: StringProperty(
        name="Cache Folder",
        description="Folder for manifold caches; empty: beside the .blend (a temporary folder for an unsaved file)",
        subtype="DIR_PATH",
        options=BLEND_RELATIVE,
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
                                   options=BLEND_RELATIVE,
                                   description="Folder for Alembic and OBJ/PLY files ('//' is beside the .blend)")


METHOD_ITEMS = enum_items(am._core.LaplacianMethod, {
    "dual": ("Dual", "Dual Laplacian (Au et al. 2006), restores features: best"),
    "graph": ("Graph", "Graph-Laplacian weights from the per-vertex QP of eq. 4.2"),
    "uniform": ("Uniform", "Equal weights (Taubin)"),
    "cotangent": ("Cotangent", "Cotangent weights (plain triangle meshes only)"),
})
BOUNDARY_ITEMS = enum_items(am._core.BoundaryRule, {
    "grow": ("Grow", "Grow anchors/handles ring by ring when the dual method's ghosts leave too few constraints"),
    "ghost_anchors": ("Ghost Anchors", "Keep every boundary ghost in place (boundaries stay put)"),
    "error": ("Error", "Refuse, saying how many more constraints are needed"),
})
ENDPOINT_ITEMS = (
    ("BOTH", "Both", "A slice vertex constrains both ends of the manifold edge it lies on"),
    ("NEARER", "Nearer", "A slice vertex constrains the end of its manifold edge nearer in time"),
)


def _is_empty(_self, obj):
    return obj.type == "EMPTY"


def _interactive_toggled(self, context):
    interactive_deform.toggled(self, context)


def _conventional_group(obj, name: str) -> str:
    groups = getattr(obj, "vertex_groups", None)
    return name if groups is not None and groups.get(name) is not None else ""


class AnimanifoldDeformSettings(PropertyGroup):
    """Per object: the Deform panel's values, used as the operator's defaults."""

    # Empty by default, so the panel does not show a group the mesh lacks (drawn red, as
    # an error, before anything is done); the conventional names are used when present.
    anchor_group: StringProperty(name="Anchors", default="",
                                 description="Vertex group of the vertices that stay (empty: the group "
                                             "'anchor' if the mesh has one, else none)")
    handle_group: StringProperty(name="Handles", default="",
                                 description="Vertex group of the vertices the Empty moves (empty: the group "
                                             "'handle' if the mesh has one, else none)")
    @property
    def anchor_group_used(self) -> str:
        """The anchor group Deform uses: the one chosen, else 'anchor' if the object has it."""
        return self.anchor_group or _conventional_group(self.id_data, "anchor")

    @property
    def handle_group_used(self) -> str:
        """The handle group Deform uses: the one chosen, else 'handle' if the object has it."""
        return self.handle_group or _conventional_group(self.id_data, "handle")

    empty: PointerProperty(name="Empty", type=bpy.types.Object, poll=_is_empty,
                           description="The Empty whose motion moves the handles")
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default=METHOD_ITEMS[0][0])
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default=BOUNDARY_ITEMS[0][0])
    restore: BoolProperty(name="Restore", default=True, description="Dual method: restore features after the solve")
    regularise: BoolProperty(name="Regularise", default=False,
                             description="Manifold objects: split edges the deformation stretched (§4.5.1)")
    time_weight: FloatProperty(name="Time Weight", default=1.0, min=0.0, soft_max=10.0,
                               description="Regularise: length one frame counts for when measuring edges")
    endpoints: EnumProperty(name="Edge Endpoints", items=ENDPOINT_ITEMS, default="BOTH")
    use_selected_faces: BoolProperty(name="Selected Faces as Handles", default=False,
                                     description="Manifold objects: a selected slice face makes the space-time "
                                                 "simplex it was cut from a handle (a slice is written with every "
                                                 "face selected: that counts as no selection)")
    # Read from no other stored name: a session never outlives the Blender session that started it.
    interactive: BoolProperty(name="Interactive", default=False, update=_interactive_toggled,
                              description="Re-solve whenever the Empty moves (kept factorisation); Deform applies it")


classes = (AnimanifoldObjectSettings, AnimanifoldSceneSettings, AnimanifoldDeformSettings)


def register_properties():
    bpy.types.Object.animanifold = PointerProperty(type=AnimanifoldObjectSettings)
    bpy.types.Scene.animanifold = PointerProperty(type=AnimanifoldSceneSettings)
    bpy.types.Object.animanifold_deform = PointerProperty(type=AnimanifoldDeformSettings)


def unregister_properties():
    interactive_deform.clear()
    for owner, name in ((bpy.types.Object, "animanifold_deform"), (bpy.types.Scene, "animanifold"),
                        (bpy.types.Object, "animanifold")):
        if hasattr(owner, name):
            delattr(owner, name)
