"""Relink Cache: points a manifold object whose cache is missing or damaged at another
.amf file, checked by loading it first (the object is left as it was if it does not
load), instead of converting again into a second manifold object."""

from __future__ import annotations

import os

import bpy
from bpy.props import StringProperty
from bpy.types import Operator

from . import live
from ._lib import am
from .live_registry import registry
from .reporting import OperatorError, reporting


def _is_manifold(obj) -> bool:
    settings = getattr(obj, "animanifold", None)
    return obj is not None and settings is not None and settings.is_manifold and obj.library is None


class ANIMANIFOLD_OT_relink_cache(Operator):
    """Point the manifold object at another cache file (.amf), checked before it is used"""

    bl_idname = "animanifold.relink_cache"
    bl_label = "Relink Cache"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(name="Cache", subtype="FILE_PATH")
    filter_glob: StringProperty(default="*.amf", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        if not _is_manifold(context.active_object):
            cls.poll_message_set("Select a manifold object (made by Convert)")
            return False
        return True

    def invoke(self, context, _event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = context.active_object
        with reporting(self, f"Cannot relink the cache of '{obj.name}'"):
            path = os.path.normpath(bpy.path.abspath(self.filepath))
            if not self.filepath or not os.path.isfile(path):
                raise OperatorError(f"there is no cache file '{self.filepath}'")
            manifold = am.load(path)  # a damaged or foreign file raises here, before anything changes
            if obj.animanifold.mode == "LIVE" and manifold.dimension != 4:
                raise OperatorError(f"'{path}' holds a {manifold.dimension - 1}D manifold, not an animation")
            registry.remember(path, manifold)
            stored = bpy.path.relpath(path) if bpy.data.filepath else path
            old = obj.animanifold.cache_path
            obj.animanifold.cache_path = stored  # its update shows the object's frame from the new cache
            if not live.show_object(obj, live.scene_frame(context.scene), scene=context.scene):
                error = live.last_error(obj)
                obj.animanifold.cache_path = old
                raise OperatorError(error or "the new cache cannot be shown")
            self.report({"INFO"}, f"'{obj.name}' uses the cache {stored}")
            return {"FINISHED"}
        return {"CANCELLED"}


classes = (ANIMANIFOLD_OT_relink_cache,)
