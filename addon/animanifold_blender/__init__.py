"""Animanifold for Blender: keyframed actions become animation manifolds
(tetrahedra in x, y, z, t); frames come back sliced live on frame change and
baked into data that plays and renders without the add-on.

Modules by role (as Blender's own io_scene_gltf2 and bl_operators):

* registration: this file; preferences (threads, frame cache budget); properties (every setting); handlers (every
  application handler, in order); ui, ui_tools (panels);
* operators, thin (properties, poll, execute/invoke): operators (Convert, Bake,
  Back to Live), ops_morph (Morph Selected), ops_skeleton and ops_deform; from the
  interface all but Back to Live are modal (job_modal: the core in a worker thread,
  am.CoreJob or am.core_job.Steps, Esc cancels; progress maps its steps onto the bar); `reporting` turns their
  failures into reports, `polls` holds their shared poll checks;
* what they run: convert, bake_object and bake, morph_object, deform_apply with
  deform_constraints, deform_handle and interactive_deform;
* render farms: farm (a chunk's bake and the assembly, called from Blender's command
  line), farm_files (atomic writes, chunk manifests), module_alias (`animanifold_blender`
  importable when Blender loads the add-on as an extension under bl_ext.*);
* live playback: live (a scene's frame), playback (the strategies), object_manifold
  (the manifold an object shows), live_registry (all state kept between frames),
  live_nodes (the geometry-nodes modifier); the bpy-free parts are the package's
  (am.interval_cuts, am.cut_cache, am.cut_prefetch, am.subdivision_cache);
* Blender data in and out: sampling, mesh_input, mesh_writer, cache_paths,
  object_names; the `animanifold` package through _lib.
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

from . import module_alias  # noqa: E402

module_alias.install(__name__)  # `import animanifold_blender` also when Blender named us bl_ext.<repo>.…

from . import (handlers, operators, ops_cache, ops_deform, ops_morph, ops_skeleton, preferences, properties,  # noqa: E402
               ui, ui_tools)

# Parent panels before their sub-panels.
classes = (preferences.classes + properties.classes + operators.classes + ops_cache.classes + ops_skeleton.classes + ops_deform.classes
           + ops_morph.classes
           + ui.classes
           + ui_tools.classes)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    properties.register_properties()
    preferences.register_preferences()
    handlers.register_handlers()
    ops_cache.register_menu()


def unregister():
    ops_cache.unregister_menu()
    handlers.unregister_handlers()
    properties.unregister_properties()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
