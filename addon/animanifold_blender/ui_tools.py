"""The "Tools" sub-panel: operators that make new geometry from a mesh object,
and Laplacian deformation of a mesh or manifold object."""

from __future__ import annotations

from bpy.types import Panel

from .deform_constraints import ANCHORS_KEY, HANDLES_KEY, stored
from .interactive_deform import session


class VIEW3D_PT_animanifold_tools(Panel):
    bl_label = "Tools"
    bl_idname = "VIEW3D_PT_animanifold_tools"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Animanifold"
    bl_parent_id = "VIEW3D_PT_animanifold"

    def draw(self, context):
        layout = self.layout
        col = layout.column(align=True)
        col.label(text="Voronoi Skeleton", icon="OUTLINER_DATA_ARMATURE")
        col.operator("animanifold.skeleton", text="Internal Skeleton").side = "INTERNAL"
        col.operator("animanifold.skeleton", text="External Skeleton").side = "EXTERNAL"
        col = layout.column(align=True)
        col.label(text="Morph (select source, then target)", icon="MOD_SIMPLEDEFORM")
        col.operator("animanifold.morph_selected", icon="FORWARD")

        obj = context.active_object
        if obj is None or obj.type != "MESH" or not hasattr(obj, "animanifold_deform"):
            return
        settings = obj.animanifold_deform
        manifold = obj.animanifold.is_manifold
        box = layout.box()
        box.label(text="Laplacian Deform", icon="MOD_LATTICE")
        box.prop_search(settings, "anchor_group", obj, "vertex_groups")
        box.prop_search(settings, "handle_group", obj, "vertex_groups")
        box.prop(settings, "empty")
        row = box.row(align=True)
        row.prop(settings, "method", text="")
        row.prop(settings, "boundary", text="")
        row = box.row(align=True)
        row.prop(settings, "restore")
        if manifold:
            row.prop(settings, "regularise")
            if settings.regularise:
                box.prop(settings, "time_weight")
            box.prop(settings, "endpoints")
            box.prop(settings, "use_selected_faces")
            anchors = len(stored(obj, ANCHORS_KEY))
            handles = len(stored(obj, HANDLES_KEY))
            row = box.row(align=True)
            row.operator("animanifold.deform_store", icon="PINNED")
            row.operator("animanifold.deform_clear", text="", icon="X")
            if anchors or handles:
                box.label(text=f"Stored: {anchors} anchors, {handles} handles")
        running = session(obj) is not None
        row = box.row(align=True)
        row.prop(settings, "interactive", toggle=True, icon="PLAY" if not running else "PAUSE")
        row.operator("animanifold.deform", text="Apply" if running else "Deform", icon="MOD_SIMPLEDEFORM")
        if settings.interactive and not running:
            box.label(text="Interactive is not running: toggle it off and on", icon="ERROR")


classes = (VIEW3D_PT_animanifold_tools,)
