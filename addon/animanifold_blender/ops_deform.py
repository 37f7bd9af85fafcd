"""Operators of Laplacian deformation (chapter 4; §4.6.2's interface): an artist puts
vertices in an "anchor" and a "handle" vertex group, moves an Empty, and runs Deform.
What is constrained: deform_constraints; the Empty's motion: deform_handle; the
deformation made permanent: deform_apply; Interactive mode: interactive_deform.
"""

from __future__ import annotations

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty
from bpy.types import Operator

from . import preferences
from ._lib import am
from .deform_apply import apply_interactive, check_target, deform_object, finish_deform, plan_deform
from .deform_constraints import ANCHORS_KEY, HANDLES_KEY, resolve, slice_constraints, store, stored
from .deform_handle import REST_EMPTY_KEY, REST_KEY, empty_for
from .interactive_deform import session
from .job_modal import CoreJobModal
from .live import scene_frame
from .object_manifold import is_manifold_object
from .operator_defaults import option
from .polls import active_object_in_any_mode_is, active_object_is
from .properties import BOUNDARY_ITEMS, ENDPOINT_ITEMS, METHOD_ITEMS
from .reporting import OperatorError, reporting

_OPTIONS = ("anchor_group", "handle_group", "method", "boundary", "restore", "regularise", "time_weight",
            "endpoints", "use_selected_faces")
# The group names the panel's settings resolve (AnimanifoldDeformSettings.*_used).
_SETTING = {"anchor_group": "anchor_group_used", "handle_group": "handle_group_used"}


class ANIMANIFOLD_OT_deform(CoreJobModal, Operator):
    """Laplacian deformation: anchors stay, handles follow the Empty's motion since its last use
    (a manifold object through space and time, or a plain mesh)"""

    bl_idname = "animanifold.deform"
    bl_label = "Laplacian Deform"
    bl_options = {"REGISTER", "UNDO"}

    anchor_group: StringProperty(name="Anchors", default="anchor")
    handle_group: StringProperty(name="Handles", default="handle")
    empty: StringProperty(name="Empty", description="Name of the Empty (default: the panel's)")
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default=METHOD_ITEMS[0][0])
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default=BOUNDARY_ITEMS[0][0])
    restore: BoolProperty(name="Restore", default=True)
    regularise: BoolProperty(name="Regularise", default=False)
    time_weight: FloatProperty(name="Time Weight", default=1.0, min=0.0)
    endpoints: EnumProperty(name="Edge Endpoints", items=ENDPOINT_ITEMS, default="BOTH")
    use_selected_faces: BoolProperty(name="Selected Faces as Handles", default=False)

    @classmethod
    def poll(cls, context):
        return active_object_is(cls, context, lambda obj: obj.type == "MESH" and obj.library is None,
                                "Select a mesh or manifold object")

    def _inputs(self, context, obj):
        """(options, Empty) of a Deform of `obj`, checked; raises OperatorError."""
        settings = obj.animanifold_deform
        opt = {name: option(self, settings, name, _SETTING.get(name)) for name in _OPTIONS}
        empty = empty_for(obj, self.empty if self.properties.is_property_set("empty") else "", settings)
        check_target(obj, opt["regularise"])
        return opt, empty

    def execute(self, context):
        """Blocking: scripts, `blender -b`, redo, and applying an interactive deformation."""
        preferences.apply_threads(context)
        obj = context.active_object
        with reporting(self, self._failure_text(obj)):
            opt, empty = self._inputs(context, obj)
            state = session(obj)
            if state is not None:
                apply_interactive(context, obj, state)
                self.report({"INFO"}, f"Applied the interactive deformation of '{obj.name}'")
                return {"FINISHED"}
            return deform_object(context, obj, opt, empty, self.report)
        return {"CANCELLED"}

    def invoke(self, context, event):
        """From the interface: the solve runs in a worker thread (am.CoreJob, job_modal), the
        progress bar follows its steps, Esc cancels and leaves the object as it was."""
        preferences.apply_threads(context)
        obj = context.active_object
        if bpy.app.background or context.window is None or session(obj) is not None:
            return self.execute(context)
        with reporting(self, self._failure_text(obj)):
            opt, empty = self._inputs(context, obj)
            self._plan, result = plan_deform(context, obj, opt, empty, self.report)
            if self._plan is None:
                return result
            return self._start_job(context, am.CoreJob(self._plan.compute, name="animanifold deform"), obj)
        return {"CANCELLED"}

    def _finish(self, context, obj, deformed):
        return finish_deform(context, obj, self._plan, deformed, self.report)

    def _cancelled_text(self, obj) -> str:
        return f"Deform of '{obj.name}' cancelled: it is as it was"

    def _failure_text(self, obj) -> str:
        return f"Deform of '{obj.name}' failed"


class ANIMANIFOLD_OT_deform_store(Operator):
    """Keep the anchors and handles selected on this frame's slice (vertex groups, selected faces),
    so that constraints painted on several frames deform the manifold together"""

    bl_idname = "animanifold.deform_store"
    bl_label = "Store Constraints"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_object_is(cls, context, lambda obj: is_manifold_object(obj) and obj.library is None,
                                "Select a manifold object (made by Convert)")

    def execute(self, context):
        obj = context.active_object
        s = obj.animanifold_deform
        with reporting(self, f"Cannot store constraints of '{obj.name}'"):
            notes: list[str] = []
            anchors, handles, _, _ = slice_constraints(obj, scene_frame(context.scene), s.anchor_group_used,
                                                       s.handle_group_used, s.endpoints, s.use_selected_faces,
                                                       stored_anchors=True, stored_handles=True, notes=notes)
            if not len(anchors) and not len(handles):
                raise OperatorError(f"the slice of '{obj.name}' has nothing in the vertex groups "
                                    f"'{s.anchor_group_used}' / '{s.handle_group_used}' and no selected faces: nothing stored")
            a, h = resolve(np.concatenate([stored(obj, ANCHORS_KEY), anchors]),
                           np.concatenate([stored(obj, HANDLES_KEY), handles]), notes)
            store(obj, a, h)
            self.report({"INFO"}, f"'{obj.name}' stores {len(a)} anchors and {len(h)} handles"
                                  + ("; " + "; ".join(notes) if notes else ""))
            return {"FINISHED"}
        return {"CANCELLED"}


class ANIMANIFOLD_OT_deform_clear(Operator):
    """Forget the stored anchors and handles and the Empty's recorded rest"""

    bl_idname = "animanifold.deform_clear"
    bl_label = "Clear Constraints"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_object_in_any_mode_is(cls, context, lambda obj: bool(_stored_keys(obj)),
                                            "The active object stores no anchors, handles or rest")

    def execute(self, context):
        obj = context.active_object
        for key in _stored_keys(obj):
            del obj[key]
        return {"FINISHED"}


def _stored_keys(obj) -> list[str]:
    """The custom properties in which `obj` (None included) keeps its constraints and the Empty's rest."""
    if obj is None:
        return []
    return [key for key in (ANCHORS_KEY, HANDLES_KEY, REST_KEY, REST_EMPTY_KEY) if key in obj]


classes = (ANIMANIFOLD_OT_deform, ANIMANIFOLD_OT_deform_store, ANIMANIFOLD_OT_deform_clear)
