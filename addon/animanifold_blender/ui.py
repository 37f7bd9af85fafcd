"""The sidebar panel (3D View › Sidebar › Animanifold)."""

from __future__ import annotations

from bpy.types import Panel

from . import bake, live, subdivision_cache
from ._lib import am
from .object_manifold import loaded_manifold


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
        elif scene_settings.sampling == "ADAPTIVE":
            box.prop(scene_settings, "tolerance")
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
        if settings.max_deviation >= 0 and settings.source_size > 0:
            box.label(text=f"Deviation: {100 * settings.max_deviation / settings.source_size:.3g} % "
                           f"(frame {settings.deviation_frame:g})")
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


class VIEW3D_PT_animanifold_smooth(Panel):
    """Smoothing of a manifold object: subdivision of its manifold (shape and motion)
    and OpenSubdiv refinement of its frames; live playback and Bake both use them."""

    bl_label = "Smooth"
    bl_idname = "VIEW3D_PT_animanifold_smooth"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Animanifold"
    bl_parent_id = "VIEW3D_PT_animanifold"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and getattr(obj, "animanifold", None) is not None and obj.animanifold.is_manifold

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        settings = obj.animanifold

        col = layout.column()
        col.label(text="Manifold (shape and motion)", icon="MOD_SUBSURF")
        col.prop(settings, "subdivision_levels")
        row = col.row()
        row.enabled = settings.subdivision_levels > 0
        row.prop(settings, "keep_keyframe_times")
        manifold = loaded_manifold(obj)  # never loads or subdivides while drawing
        if manifold is not None:
            tets = am.subdivided_simplex_count(manifold, settings.subdivision_levels)
            kind = "tets" if manifold.dimension == 4 else "triangles"
            if tets >= subdivision_cache.LARGE_TETS:
                col.label(text=f"{tets:,} {kind}: slow slicing, much memory", icon="ERROR")
            elif settings.subdivision_levels > 0:
                col.label(text=f"{tets:,} {kind}", icon="INFO")

        col = layout.column()
        col.label(text="Frames (OpenSubdiv)", icon="SURFACE_NSURFACE")
        col.prop(settings, "smooth_levels")
        row = col.row()
        row.enabled = settings.smooth_levels > 0
        row.prop(settings, "crease_angle")
        if settings.mode == "LIVE" and obj.type == "MESH" and obj.data is not None and settings.smooth_levels > 0:
            faces = len(obj.data.polygons)
            col.label(text=f"{faces:,} faces this frame", icon="ERROR" if faces >= LARGE_FACES else "INFO")
        if settings.mode == "BAKED":
            layout.label(text="The bake keeps the settings it was made with: bake again", icon="INFO")


# Frames with this many faces after smoothing play slowly: the panel warns.
LARGE_FACES = 1_000_000

classes = (VIEW3D_PT_animanifold, VIEW3D_PT_animanifold_smooth)
