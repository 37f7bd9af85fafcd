"""The sidebar panel (3D View › Sidebar › Animanifold)."""

from __future__ import annotations

from bpy.types import Panel

from . import bake, live


class VIEW3D_PT_animanifold(Panel):
    bl_label = "Animanifold"
    bl_idname = "VIEW3D_PT_animanifold"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Animanifold"

    def draw(self, context):
        layout = self.layout
        scene_settings = context.scene.animanifold
        obj = context.active_object

        box = layout.box()
        box.label(text="Convert", icon="MOD_MESHDEFORM")
        box.prop(scene_settings, "sampling")
        if scene_settings.sampling == "EVERY_N":
            box.prop(scene_settings, "step")
        box.prop(scene_settings, "use_scene_range")
        if not scene_settings.use_scene_range:
            row = box.row(align=True)
            row.prop(scene_settings, "frame_start")
            row.prop(scene_settings, "frame_end")
        box.prop(scene_settings, "cache_directory")
        box.operator("animanifold.convert_action", icon="PLAY")

        if obj is None or not obj.animanifold.is_manifold:
            return
        settings = obj.animanifold

        box = layout.box()
        box.label(text=f"Manifold: {obj.name}", icon="MESH_ICOSPHERE")
        box.prop(settings, "cache_path")
        if settings.source is not None:
            box.label(text=f"Source: {settings.source.name}")
        error = live.last_error(obj)
        if error:
            box.label(text=error, icon="ERROR")
        if settings.mode == "LIVE":
            row = box.row()
            row.prop(settings, "axis", expand=True)
            if settings.axis == "t":
                box.prop(settings, "live_normals")
            else:
                box.prop(settings, "sweep_value")
                box.prop(settings, "time_scale")
        else:
            box.label(text="Baked: shown without the add-on", icon="CHECKMARK")
            box.operator("animanifold.make_live", icon="FILE_REFRESH")

        box = layout.box()
        box.label(text="Bake", icon="RENDER_ANIMATION")
        box.prop(scene_settings, "bake_use_scene_range")
        if not scene_settings.bake_use_scene_range:
            row = box.row(align=True)
            row.prop(scene_settings, "bake_start")
            row.prop(scene_settings, "bake_end")
        row = box.row()
        row.enabled = bake.alembic_supported()
        row.prop(scene_settings, "bake_alembic")
        sub = box.row()
        sub.enabled = bake.alembic_supported() and scene_settings.bake_alembic
        sub.prop(scene_settings, "bake_use_mesh_cache")
        box.prop(scene_settings, "bake_export")
        box.prop(scene_settings, "bake_directory")
        box.operator("animanifold.bake", icon="EXPORT")


classes = (VIEW3D_PT_animanifold,)
