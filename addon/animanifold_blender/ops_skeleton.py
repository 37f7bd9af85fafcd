"""Operator: the Voronoi skeleton of a mesh object as a new object (chapter 7).

The internal skeleton approximates the medial axis (for inspection); the
external one fills concavities and holes within the convex hull (the guide
the morph pushes into time). The source object is never changed; on any
failure nothing is added and the reason is reported. From the interface the
skeleton is computed in a worker thread (am.CoreJob) and Esc cancels it.
"""

from __future__ import annotations

import bpy
import numpy as np
from bpy.props import EnumProperty, IntProperty
from bpy.types import Operator

from . import preferences
from ._lib import am
from .enum_items import enum_items
from .mesh_input import closed_triangle_mesh
from .mesh_writer import write_mesh
from .polls import active_object_is
from .job_modal import CoreJobModal
from .progress import Progress
from .reporting import reporting

SIDE_ITEMS = enum_items(am._core.SkeletonSide, {
    "internal": ("Internal", "The medial skeleton inside the shape"),
    "external": ("External", "The skeleton of the concavities and holes, inside the convex hull"),
    "both": ("Both", "Internal and external (a face attribute 'side' tells them apart: 0 internal, 1 external)"),
}, upper=True)
WRAP_ITEMS = enum_items(am._core.WrapShape, {
    "box": ("Box", "Bound every Voronoi cell with points on a box around the mesh"),
    "sphere": ("Sphere", "Bound every Voronoi cell with points on a sphere around the mesh"),
    "none": ("None", "No wrap (cells of hull vertices stay unbounded)"),
}, upper=True)


class ANIMANIFOLD_OT_skeleton(CoreJobModal, Operator):
    """Add the Voronoi skeleton of the active mesh object as a new object"""

    bl_idname = "animanifold.skeleton"
    bl_label = "Add Voronoi Skeleton"
    bl_options = {"REGISTER", "UNDO"}

    side: EnumProperty(name="Side", items=SIDE_ITEMS, default="INTERNAL")
    max_iterations: IntProperty(name="Max Iterations", default=4, min=0, max=32,
                                description="Cap on the rounds that make the mesh Voronoi separable (§7.6)")
    wrap: EnumProperty(name="Wrap", items=WRAP_ITEMS, default="BOX")

    @classmethod
    def poll(cls, context):
        return active_object_is(cls, context, lambda obj: obj.type == "MESH", "Select a mesh object")

    def _options(self) -> dict:
        return dict(side=self.side.lower(), max_iterations=self.max_iterations, wrap=self.wrap.lower(), warn=False)

    def execute(self, context):
        """Blocking: scripts, `blender -b`, and redo from the Adjust Last Operation panel."""
        preferences.apply_threads(context)
        obj = context.active_object
        progress = Progress(context.window_manager, 10.0, 90.0, where="reading the mesh")
        with reporting(self, f"No skeleton for '{obj.name}'"):
            try:
                vertices, faces = closed_triangle_mesh(context, obj)
                progress.at(10.0, "before the core's first step")
                sk = am.voronoi_skeleton(vertices, faces, progress=progress, **self._options())
                progress.at(90.0, "making the skeleton object")
            finally:
                progress.end()
            return self._finish(context, obj, sk)
        return {"CANCELLED"}

    def _start(self, context) -> set:
        """From the interface (CoreJobModal.invoke): the skeleton is computed in a worker thread
        (am.CoreJob), the progress bar follows its steps, Esc cancels; the view can be turned
        meanwhile."""
        obj = context.active_object
        with reporting(self, f"No skeleton for '{obj.name}'"):
            vertices, faces = closed_triangle_mesh(context, obj)
            job = am.CoreJob(am.voronoi_skeleton, vertices, faces, name="animanifold skeleton", **self._options())
            return self._start_job(context, job, obj)
        return {"CANCELLED"}

    def _cancelled_text(self, obj) -> str:
        return f"Skeleton of '{obj.name}' cancelled: nothing was added"

    def _failure_text(self, obj) -> str:
        return f"No skeleton for '{obj.name}'"

    def _finish(self, context, obj, sk):
        """Adds the skeleton's object and reports what was made."""
        if len(sk.faces) == 0:
            self.report({"WARNING"}, f"'{obj.name}' has no {self.side.lower()} skeleton (a convex shape has no "
                                     "external one); nothing added")
            return {"CANCELLED"}
        add_skeleton_object(context, obj, sk)
        warning = am.skeleton.separability_warning(sk, self.max_iterations)
        if warning:
            self.report({"WARNING"}, warning)
        self.report({"INFO"}, f"'{obj.name}_skeleton': {len(sk.faces)} faces from {len(sk.refined_vertices)} mesh "
                              f"vertices ({'separable' if sk.separable else 'not separable'} after "
                              f"{sk.iterations} rounds)")
        return {"FINISHED"}


def add_skeleton_object(context, obj, sk):
    """A new object beside `obj` showing skeleton `sk` (its face attribute 'side': 0 internal,
    1 external), selected and active."""
    name = f"{obj.name}_skeleton"
    mesh = bpy.data.meshes.new(name)
    write_mesh(mesh, sk.vertices, sk.faces)
    side = mesh.attributes.new("side", "INT", "FACE")
    side.data.foreach_set("value", (np.asarray(sk.side) == "external").astype(np.int32))
    skeleton = bpy.data.objects.new(name, mesh)
    skeleton.matrix_world = obj.matrix_world
    collection = obj.users_collection[0] if obj.users_collection else context.scene.collection
    collection.objects.link(skeleton)
    for other in context.selected_objects:
        other.select_set(False)
    skeleton.select_set(True)
    context.view_layer.objects.active = skeleton
    return skeleton

classes = (ANIMANIFOLD_OT_skeleton,)
