"""The sidebar panel (3D View › Sidebar › Animanifold)."""

from __future__ import annotations

from bpy.types import Panel

from . import bake, live
from ._lib import am
from .object_manifold import is_manifold_object, loaded_manifold


class SidebarPanel:
    """Mixed into each of the add-on's panels: its tab in the 3D View's sidebar."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Animanifold"


def split_layout(layout):
    """`layout` with labels left and fields right (as Blender's own panels): no label is cut at
    the default sidebar width; a label longer than LABEL_CHARS would be."""
    layout.use_property_split = True
    layout.use_property_decorate = False
    return layout


class VIEW3D_PT_animanifold(SidebarPanel, Panel):
    bl_label = "Animanifold"
    bl_idname = "VIEW3D_PT_animanifold"

    def draw(self, context):
        layout = split_layout(self.layout)
        scene_settings = context.scene.animanifold
        obj = context.active_object
        _draw_convert(layout.box(), scene_settings)
        if obj is not None and obj.animanifold.is_manifold:
            _draw_manifold(layout.box(), obj)
        _draw_bake(layout.box(), scene_settings)


# The longest label the panels draw: at the default sidebar width a split layout's
# label column holds about this many characters.
LABEL_CHARS = 12


def _draw_convert(box, scene_settings) -> None:
    box.label(text="Convert", icon="ACTION")
    col = box.column()
    col.prop(scene_settings, "sampling")
    if scene_settings.sampling == "EVERY_N":
        col.prop(scene_settings, "step", text="Every")
    elif scene_settings.sampling == "ADAPTIVE":
        col.prop(scene_settings, "tolerance")
    col.prop(scene_settings, "use_scene_range", text="Scene Range")
    if not scene_settings.use_scene_range:
        sub = col.column(align=True)
        sub.prop(scene_settings, "frame_start", text="Start")
        sub.prop(scene_settings, "frame_end", text="End")
    col.prop(scene_settings, "cache_directory", text="Cache")
    box.operator("animanifold.convert_action", text="Convert", icon="ACTION")


def _draw_manifold(box, obj) -> None:
    settings = obj.animanifold
    box.label(text=obj.name, icon="MESH_ICOSPHERE")
    col = box.column()
    col.prop(settings, "cache_path", text="Cache")
    if settings.source is not None:
        col.prop(settings, "source", text="Source")
    if settings.max_deviation >= 0 and settings.source_size > 0:
        # two lines: one would be cut at the default sidebar width
        col.label(text=f"Deviation: {100 * settings.max_deviation / settings.source_size:.3g} %")
        col.label(text=f"Worst Frame: {settings.deviation_frame:g}")
    error = live.last_error(obj)
    if error:
        box.label(text=error, icon="ERROR")
        box.operator("animanifold.relink_cache", text="Relink Cache", icon="FILE_REFRESH")
    if settings.mode == "LIVE":
        row = col.row()
        row.prop(settings, "axis", text="Slice Axis", expand=True)
        if settings.axis == "t":
            col.prop(settings, "live_normals", text="Normals")
        else:
            col.prop(settings, "sweep_value", text="Value")
            col.prop(settings, "time_scale", text="Time Scale")
    else:
        box.label(text="Baked: plays without the add-on", icon="CHECKMARK")
        box.operator("animanifold.make_live", icon="FILE_REFRESH")


def _draw_bake(box, scene_settings) -> None:
    box.label(text="Bake", icon="RENDER_ANIMATION")
    col = box.column()
    col.prop(scene_settings, "bake_use_scene_range", text="Scene Range")
    if not scene_settings.bake_use_scene_range:
        sub = col.column(align=True)
        sub.prop(scene_settings, "bake_start", text="Start")
        sub.prop(scene_settings, "bake_end", text="End")
    row = col.row()
    row.enabled = bake.alembic_supported()
    row.prop(scene_settings, "bake_alembic", text="Alembic")
    row = col.row()
    row.enabled = bake.alembic_supported() and scene_settings.bake_alembic
    row.prop(scene_settings, "bake_use_mesh_cache", text="Mesh Cache")
    col.prop(scene_settings, "bake_export", text="Sequence")
    col.prop(scene_settings, "bake_directory", text="Folder")
    box.operator("animanifold.bake", text="Bake", icon="EXPORT")


class VIEW3D_PT_animanifold_smooth(SidebarPanel, Panel):
    """Smoothing of a manifold object: subdivision of its manifold (shape and motion)
    and OpenSubdiv refinement of its frames; live playback and Bake both use them."""

    bl_label = "Smooth"
    bl_idname = "VIEW3D_PT_animanifold_smooth"
    bl_parent_id = "VIEW3D_PT_animanifold"

    @classmethod
    def poll(cls, context):
        return is_manifold_object(context.active_object)

    def draw(self, context):
        layout = split_layout(self.layout)
        obj = context.active_object
        settings = obj.animanifold

        col = _levels_column(layout, settings, "Manifold", "MOD_SUBSURF", "subdivision_levels",
                             "keep_keyframe_times", "Keep Keys")
        manifold = loaded_manifold(obj)  # never loads or subdivides while drawing
        if manifold is not None:
            tets = am.subdivided_simplex_count(manifold, settings.subdivision_levels)
            kind = "tets" if manifold.dimension == 4 else "triangles"
            if tets >= LARGE_TETS:
                col.label(text=f"{tets:,} {kind}: slow slicing, much memory", icon="ERROR")
            elif settings.subdivision_levels > 0:
                col.label(text=f"{tets:,} {kind}", icon="INFO")

        col = _levels_column(layout, settings, "Frames", "SURFACE_NSURFACE", "smooth_levels", "crease_angle", "Crease")
        if settings.mode == "LIVE" and obj.type == "MESH" and obj.data is not None and settings.smooth_levels > 0:
            faces = len(obj.data.polygons)
            col.label(text=f"{faces:,} faces this frame", icon="ERROR" if faces >= LARGE_FACES else "INFO")
        if settings.mode == "BAKED":
            layout.label(text="The bake keeps the settings it was made with: bake again", icon="INFO")


def _levels_column(layout, settings, title: str, icon: str, levels: str, option: str, option_text: str):
    """A column headed `title` with the `levels` setting, and `option`, which only matters
    once there is a level (greyed out at 0); returns the column."""
    col = layout.column()
    col.label(text=title, icon=icon)
    col.prop(settings, levels, text="Levels")
    row = col.row()
    row.enabled = getattr(settings, levels) > 0
    row.prop(settings, option, text=option_text)
    return col


# The panel warns from this many shown tets on (slower slicing, more memory).
LARGE_TETS = 2_000_000

# Frames with this many faces after smoothing play slowly: the panel warns.
LARGE_FACES = 1_000_000

classes = (VIEW3D_PT_animanifold, VIEW3D_PT_animanifold_smooth)
