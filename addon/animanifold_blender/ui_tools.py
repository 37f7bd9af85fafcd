"""The "Tools" sub-panel: operators that make new geometry from a mesh object,
and Laplacian deformation of a mesh or manifold object."""

from __future__ import annotations

from bpy.types import Panel

from .deform_constraints import ANCHORS_KEY, HANDLES_KEY, stored
from .interactive_deform import session
from .ui import SidebarPanel, split_layout


class VIEW3D_PT_animanifold_tools(SidebarPanel, Panel):
    bl_label = "Tools"
    bl_idname = "VIEW3D_PT_animanifold_tools"
    bl_parent_id = "VIEW3D_PT_animanifold"

    def draw(self, context):
        layout = split_layout(self.layout)
        col = layout.column(align=True)
        col.label(text="Skeleton", icon="OUTLINER_DATA_ARMATURE")
        row = col.row(align=True)
        row.operator("animanifold.skeleton", text="Internal").side = "INTERNAL"
        row.operator("animanifold.skeleton", text="External").side = "EXTERNAL"
        col = layout.column(align=True)
        # The order is in the operator's tooltip: source selected first, target active.
        col.label(text="Morph", icon="MOD_SIMPLEDEFORM")
        col.operator("animanifold.morph_selected", text="Morph Selected", icon="FORWARD")

        obj = context.active_object
        if obj is None or obj.type != "MESH" or not hasattr(obj, "animanifold_deform"):
            return
        settings = obj.animanifold_deform
        manifold = obj.animanifold.is_manifold
        box = layout.box()
        box.label(text="Deform", icon="MOD_LATTICE")
        col = box.column()
        col.prop_search(settings, "anchor_group", obj, "vertex_groups", text="Anchors")
        col.prop_search(settings, "handle_group", obj, "vertex_groups", text="Handles")
        col.prop(settings, "empty", text="Empty")
        col.prop(settings, "method", text="Method")
        col.prop(settings, "boundary", text="Boundary")
        col.prop(settings, "restore", text="Restore")
        if manifold:
            col.prop(settings, "regularise", text="Regularise")
            if settings.regularise:
                col.prop(settings, "time_weight", text="Time Weight")
            col.prop(settings, "endpoints", text="Endpoints")
            col.prop(settings, "use_selected_faces", text="Face Handles")
            anchors = len(stored(obj, ANCHORS_KEY))
            handles = len(stored(obj, HANDLES_KEY))
            row = box.row(align=True)
            row.operator("animanifold.deform_store", text="Store", icon="PINNED")
            row.operator("animanifold.deform_clear", text="", icon="X")
            if anchors or handles:
                box.label(text=f"{anchors} anchors, {handles} handles")
        running = session(obj) is not None
        row = box.row(align=True)
        row.prop(settings, "interactive", text="Live Deform", toggle=True, icon="HAND" if not running else "PAUSE")
        row.operator("animanifold.deform", text="Apply" if running else "Deform", icon="MOD_SIMPLEDEFORM")
        if settings.interactive and not running:
            box.label(text="Not running: toggle it again", icon="ERROR")


classes = (VIEW3D_PT_animanifold_tools,)
