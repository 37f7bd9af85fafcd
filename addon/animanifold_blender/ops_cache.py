"""Relink Cache: points a manifold object whose cache is missing or damaged at another
.amf file, checked by loading it first (the object is left as it was if it does not
load), instead of converting again into a second manifold object. Report Missing Caches
(File > External Data, beside Blender's Report Missing Files, which walks only data-block
paths and never sees a manifold's): a warning per manifold object whose cache is gone."""

from __future__ import annotations

import os

import bpy
from bpy.props import StringProperty
from bpy.types import Operator

from . import cache_paths, live
from ._lib import am
from .live_registry import registry
from .object_manifold import is_manifold_object
from .polls import active_object_in_any_mode_is
from .reporting import OperatorError, reporting


def _is_manifold(obj) -> bool:
    return is_manifold_object(obj) and obj.library is None


class ANIMANIFOLD_OT_relink_cache(Operator):
    """Point the manifold object at another cache file (.amf), checked before it is used"""

    bl_idname = "animanifold.relink_cache"
    bl_label = "Relink Cache"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(name="Cache", subtype="FILE_PATH")
    filter_glob: StringProperty(default="*.amf", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        return active_object_in_any_mode_is(cls, context, _is_manifold, "Select a manifold object (made by Convert)")

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


class ANIMANIFOLD_OT_report_missing_caches(Operator):
    """Report the manifold objects whose cache file is missing"""

    bl_idname = "animanifold.report_missing_caches"
    bl_label = "Report Missing Manifold Caches"

    def execute(self, context):
        missing = 0
        for obj in bpy.data.objects:
            if not _is_manifold(obj):
                continue
            try:
                path = cache_paths.cache_abspath(obj)
            except am.CacheError as e:
                self.report({"WARNING"}, str(e))
                missing += 1
                continue
            if not os.path.isfile(path):
                self.report({"WARNING"}, f"'{obj.name}': cache {obj.animanifold.cache_path} not found ({path})")
                missing += 1
        if not missing:
            self.report({"INFO"}, "No manifold cache is missing")
        return {"FINISHED"}


def draw_external_data_menu(self, _context):
    self.layout.operator(ANIMANIFOLD_OT_report_missing_caches.bl_idname)


def register_menu() -> None:
    unregister_menu()  # never twice (a register without its unregister)
    bpy.types.TOPBAR_MT_file_external_data.append(draw_external_data_menu)


def unregister_menu() -> None:
    if draw_external_data_menu in bpy.types.TOPBAR_MT_file_external_data._dyn_ui_initialize():
        bpy.types.TOPBAR_MT_file_external_data.remove(draw_external_data_menu)


classes = (ANIMANIFOLD_OT_relink_cache, ANIMANIFOLD_OT_report_missing_caches)
