"""The "Tools" sub-panel: operators that make new geometry from a mesh object."""

from __future__ import annotations

from bpy.types import Panel


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


classes = (VIEW3D_PT_animanifold_tools,)
