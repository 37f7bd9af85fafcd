"""Which live manifold objects Blender evaluates, so that the frame handlers slice only
those: an object hidden in the viewport, disabled in viewports, in an excluded or hidden
collection, or in no view layer of the scene costs nothing per frame, and is shown at
the current frame when it becomes visible again (handlers: depsgraph update).

While a render runs (render_init .. render_complete/render_cancel) what counts is what
renders: objects not disabled in renders, in a view layer that renders, in a collection
it does not exclude; the viewport's hiding does not apply.
"""

from __future__ import annotations

import bpy

_rendering = False


def set_rendering(value: bool) -> None:
    global _rendering
    _rendering = value


def rendering() -> bool:
    return _rendering


def _context_view_layer(scene):
    """The view layer the viewport shows of `scene`, or None when the context's scene is another."""
    context_scene = getattr(bpy.context, "scene", None)
    view_layer = getattr(bpy.context, "view_layer", None)
    if context_scene is not None and view_layer is not None and context_scene == scene:
        return view_layer
    return None


def _renders(obj, scene) -> bool:
    if obj.hide_render:
        return False
    return any(vl.use and vl.objects.get(obj.name) == obj for vl in scene.view_layers)


def _visible_in_viewport(obj, scene) -> bool:
    view_layer = _context_view_layer(scene)
    layers = (view_layer,) if view_layer is not None else tuple(scene.view_layers)
    # visible_get: hidden (H), disabled in viewports, excluded or hidden collections,
    # and not in the view layer at all all read False.
    return any(obj.visible_get(view_layer=vl) for vl in layers)


def is_evaluated(obj, scene) -> bool:
    """Whether Blender shows (or, during a render, renders) `obj` in `scene`."""
    return _renders(obj, scene) if _rendering else _visible_in_viewport(obj, scene)
