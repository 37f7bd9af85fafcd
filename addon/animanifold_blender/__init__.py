"""Animanifold for Blender: keyframed actions become animation manifolds
(tetrahedra in x, y, z, t); frames come back sliced live on frame change and
baked into data that plays and renders without the add-on.

Modules: properties (settings), sampling (evaluated mesh → keyframes),
live (slices → meshes), live_nodes (the geometry-nodes modifier that plays a
topology interval), live_cuts (cuts kept between frames), handlers (frame
change, load, undo), bake, operators, ui;
ops_skeleton and ui_tools for the Voronoi skeleton; ops_deform for Laplacian
deformation (anchor/handle vertex groups and an Empty, also in ui_tools);
ops_morph for Morph Selected, which runs the core in morph_job's worker thread
when invoked from the interface (Esc cancels).
"""

bl_info = {
    "name": "Animanifold",
    "author": "animanifold developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > Animanifold",
    "description": "Keyframed actions as animation manifolds: sliced live or baked to a cache",
    "category": "Animation",
}

import bpy  # noqa: E402

from . import handlers, operators, ops_deform, ops_morph, ops_skeleton, properties, ui, ui_tools  # noqa: E402

# Parent panels before their sub-panels.
classes = (properties.classes + operators.classes + ops_skeleton.classes + ops_deform.classes + ops_morph.classes
           + ui.classes
           + ui_tools.classes)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    properties.register_properties()
    ops_deform.register_properties()
    handlers.register_handlers()


def unregister():
    handlers.unregister_handlers()
    ops_deform.unregister_properties()
    properties.unregister_properties()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
