"""Operators: Convert (keyframed action → manifold object), Bake and Back to Live.

Their work is done by convert and bake_object, which check everything that can fail
before touching the scene and remove whatever they created on a failure; `reporting`
turns the failure into the operator's error report.

Invoked from the interface, Convert and Bake are modal (job_modal): their long core calls
(the stitches, the subdivision) run in a worker thread, Esc cancels, and the scene work
between them runs in the main thread. Executed (a script, `blender -b`, redo), they block.
"""

from __future__ import annotations

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy.types import Operator

from . import bake, preferences
from ._lib import am
from .bake_object import bake_object, bake_steps
from .adaptive_sampling import MAX_SAMPLES, TOLERANCE_PERCENT
from .convert import convert_object, convert_steps
from .job_modal import CoreJobModal
from .object_manifold import is_manifold_object, manifold_for
from .operator_defaults import option
from .polls import active_object_in_any_mode_is, active_object_is, in_object_mode
from .progress import Progress
from .properties import BLEND_RELATIVE, EXPORT_ITEMS, SAMPLING_ITEMS
from .reporting import reporting


class ANIMANIFOLD_OT_convert_action(CoreJobModal, Operator):
    """Turn the active object's keyframed animation into an animation manifold object"""

    bl_idname = "animanifold.convert_action"
    bl_label = "Convert to Manifold"
    bl_options = {"REGISTER", "UNDO"}
    _status_label = "Convert to Manifold"
    _job_name = "animanifold convert"

    sampling: EnumProperty(name="Sampling", items=SAMPLING_ITEMS, default="ADAPTIVE")
    step: IntProperty(name="N", default=5, min=1)
    tolerance: FloatProperty(name="Tolerance", default=TOLERANCE_PERCENT, min=1e-6, max=100.0, subtype="PERCENTAGE",
                             precision=3)
    max_samples: IntProperty(name="Sample Cap", default=MAX_SAMPLES, min=2)
    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=250)
    cache_directory: StringProperty(name="Cache Folder", subtype="DIR_PATH", options=BLEND_RELATIVE)

    @classmethod
    def poll(cls, context):
        if not in_object_mode(cls, context):
            return False
        obj = context.active_object
        if obj is None:
            cls.poll_message_set("Select the object to convert")
            return False
        if is_manifold_object(obj):
            cls.poll_message_set("The active object is a manifold already: select its source to convert again")
            return False
        return True

    def _arguments(self, context) -> tuple:
        """convert_object's arguments after `context`: the source, the range and the options."""
        scene = context.scene
        settings = scene.animanifold
        if option(self, settings, "use_scene_range"):
            start, end = scene.frame_start, scene.frame_end
        else:
            start, end = option(self, settings, "frame_start"), option(self, settings, "frame_end")
        return (context.active_object, start, end, option(self, settings, "sampling"), option(self, settings, "step"),
                option(self, settings, "cache_directory"), option(self, settings, "tolerance"),
                option(self, settings, "max_samples"))

    def execute(self, context):
        """Blocking: scripts, `blender -b`, and redo from the Adjust Last Operation panel."""
        preferences.apply_threads(context)
        with reporting(self, "Convert failed"):
            return self._finish(context, None, convert_object(context, *self._arguments(context)))
        return {"CANCELLED"}

    def _start(self, context) -> set:
        """The stitches run in a worker thread (job_modal), Esc cancels before the cache is
        written or the object made; the sampling and the object are made here."""
        with reporting(self, "Convert failed"):
            arguments = self._arguments(context)
            progress = Progress(context.window_manager)
            return self._start_steps(context, am.core_job.Steps(convert_steps(context, progress, *arguments)),
                                     arguments[0], progress)
        return {"CANCELLED"}

    def _finish(self, context, source, done):
        """Reports the Converted `done`."""
        for note in done.notes:
            self.report({"WARNING"}, note)
        fit = done.fidelity
        within = "" if fit is None else (f", largest deviation {fit.percent(fit.deviation):.3g} % of its size "
                                         f"at frame {fit.frame:g}")
        self.report({"INFO"}, f"'{done.obj.name}': {len(done.manifold.simplices)} tets from {done.samples} "
                              f"samples (frames {done.start}–{done.end}){within}, cache {done.stored}")
        return {"FINISHED"}

    def _cancelled_text(self, obj) -> str:
        return f"Convert of '{obj.name}' cancelled: nothing was added"

    def _failure_text(self, obj) -> str:
        return "Convert failed"


class ANIMANIFOLD_OT_bake(CoreJobModal, Operator):
    """Bake the active manifold object's frames: a frames collection shown by a node group
    (plays and renders without the add-on), optionally Alembic and an OBJ/PLY sequence"""

    bl_idname = "animanifold.bake"
    bl_label = "Bake Frames"
    bl_options = {"REGISTER", "UNDO"}
    _status_label = "Bake Frames"
    _job_name = "animanifold bake"

    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1, description="First frame (a farm bakes chunks)")
    frame_end: IntProperty(name="End", default=250)
    alembic: BoolProperty(name="Alembic", default=True)
    use_mesh_cache: BoolProperty(name="Use Mesh Sequence Cache", default=False)
    export: EnumProperty(name="Sequence", items=EXPORT_ITEMS, default="NONE")
    directory: StringProperty(name="Folder", subtype="DIR_PATH", options=BLEND_RELATIVE)

    @classmethod
    def poll(cls, context):
        return active_object_is(cls, context, is_manifold_object, "Select a manifold object (made by Convert)")

    def _options(self, context) -> dict:
        """bake_object's options."""
        settings = context.scene.animanifold
        return dict(use_scene_range=option(self, settings, "use_scene_range", "bake_use_scene_range"),
                    start=option(self, settings, "frame_start", "bake_start"),
                    end=option(self, settings, "frame_end", "bake_end"),
                    alembic_wanted=option(self, settings, "alembic", "bake_alembic"),
                    use_cache=option(self, settings, "use_mesh_cache", "bake_use_mesh_cache"),
                    export=option(self, settings, "export", "bake_export"),
                    directory=option(self, settings, "directory", "bake_directory"))

    def execute(self, context):
        """Blocking: scripts, `blender -b`, and redo from the Adjust Last Operation panel."""
        preferences.apply_threads(context)
        with reporting(self, "Bake failed"):
            return self._finish(context, None, bake_object(context, context.active_object, **self._options(context)))
        return {"CANCELLED"}

    def _start(self, context) -> set:
        """The subdivision runs in a worker thread (job_modal), then the frames and files are
        made here a slice at a time; Esc cancels at any point and leaves nothing baked."""
        obj = context.active_object
        with reporting(self, "Bake failed"):
            progress = Progress(context.window_manager, where="subdividing the manifold")
            steps = am.core_job.Steps(bake_steps(context, progress, obj, **self._options(context)))
            return self._start_steps(context, steps, obj, progress)
        return {"CANCELLED"}

    def _finish(self, context, source, report):
        self.report({"INFO"}, report)
        return {"FINISHED"}

    def _cancelled_text(self, obj) -> str:
        return f"Bake of '{obj.name}' cancelled: nothing was baked"

    def _failure_text(self, obj) -> str:
        return "Bake failed"


class ANIMANIFOLD_OT_make_live(Operator):
    """Slice the manifold object live again (turn off its bake modifiers)"""

    bl_idname = "animanifold.make_live"
    bl_label = "Back to Live"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_object_in_any_mode_is(cls, context, _is_baked, "Select a baked manifold object")

    def execute(self, context):
        obj = context.active_object
        with reporting(self, f"Cannot slice '{obj.name}' live"):
            manifold_for(obj)  # the cache must be there before the bake is switched off
            for name in (bake.MODIFIER_NAME, bake.CACHE_MODIFIER_NAME):
                mod = obj.modifiers.get(name)
                if mod is not None:
                    mod.show_viewport = False
                    mod.show_render = False
            obj.animanifold.mode = "LIVE"
            return {"FINISHED"}
        return {"CANCELLED"}


def _is_baked(obj) -> bool:
    return is_manifold_object(obj) and obj.animanifold.mode == "BAKED"


classes = (ANIMANIFOLD_OT_convert_action, ANIMANIFOLD_OT_bake, ANIMANIFOLD_OT_make_live)
