"""Operators: Convert (keyframed action → manifold object), Bake and Back to Live.

Their work is done by convert and bake_object, which check everything that can fail
before touching the scene and remove whatever they created on a failure; `reporting`
turns the failure into the operator's error report.
"""

from __future__ import annotations

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy.types import Operator

from . import bake, preferences
from .bake_object import bake_object
from .adaptive_sampling import MAX_SAMPLES, TOLERANCE_PERCENT
from .convert import convert_object
from .object_manifold import is_manifold_object, manifold_for
from .operator_defaults import option
from .polls import active_object_is, in_object_mode
from .properties import BLEND_RELATIVE, EXPORT_ITEMS, SAMPLING_ITEMS
from .reporting import reporting


class ANIMANIFOLD_OT_convert_action(Operator):
    """Turn the active object's keyframed animation into an animation manifold object"""

    bl_idname = "animanifold.convert_action"
    bl_label = "Convert to Manifold"
    bl_options = {"REGISTER", "UNDO"}

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

    def execute(self, context):
        preferences.apply_threads(context)
        with reporting(self, "Convert failed"):
            scene = context.scene
            settings = scene.animanifold
            if option(self, settings, "use_scene_range"):
                start, end = scene.frame_start, scene.frame_end
            else:
                start, end = option(self, settings, "frame_start"), option(self, settings, "frame_end")
            done = convert_object(context, context.active_object, start, end, option(self, settings, "sampling"),
                                  option(self, settings, "step"), option(self, settings, "cache_directory"),
                                  option(self, settings, "tolerance"), option(self, settings, "max_samples"))
            for note in done.notes:
                self.report({"WARNING"}, note)
            fit = done.fidelity
            within = "" if fit is None else (f", largest deviation {fit.percent(fit.deviation):.3g} % of its size "
                                             f"at frame {fit.frame:g}")
            self.report({"INFO"}, f"'{done.obj.name}': {len(done.manifold.simplices)} tets from {done.samples} "
                                  f"samples (frames {done.start}–{done.end}){within}, cache {done.stored}")
            return {"FINISHED"}
        return {"CANCELLED"}


class ANIMANIFOLD_OT_bake(Operator):
    """Bake the active manifold object's frames: a frames collection shown by a node group
    (plays and renders without the add-on), optionally Alembic and an OBJ/PLY sequence"""

    bl_idname = "animanifold.bake"
    bl_label = "Bake Frames"
    bl_options = {"REGISTER", "UNDO"}

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

    def execute(self, context):
        preferences.apply_threads(context)
        with reporting(self, "Bake failed"):
            settings = context.scene.animanifold
            report = bake_object(
                context, context.active_object,
                use_scene_range=option(self, settings, "use_scene_range", "bake_use_scene_range"),
                start=option(self, settings, "frame_start", "bake_start"),
                end=option(self, settings, "frame_end", "bake_end"),
                alembic_wanted=option(self, settings, "alembic", "bake_alembic"),
                use_cache=option(self, settings, "use_mesh_cache", "bake_use_mesh_cache"),
                export=option(self, settings, "export", "bake_export"),
                directory=option(self, settings, "directory", "bake_directory"))
            self.report({"INFO"}, report)
            return {"FINISHED"}
        return {"CANCELLED"}


class ANIMANIFOLD_OT_make_live(Operator):
    """Slice the manifold object live again (turn off its bake modifiers)"""

    bl_idname = "animanifold.make_live"
    bl_label = "Back to Live"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return is_manifold_object(obj) and obj.animanifold.mode == "BAKED"

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


classes = (ANIMANIFOLD_OT_convert_action, ANIMANIFOLD_OT_bake, ANIMANIFOLD_OT_make_live)
