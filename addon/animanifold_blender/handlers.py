"""Application handlers, all registered here, each naming its handler lists with @on and
registered in the order they are defined: live slicing on frame change (before and after the
frame is evaluated) of the objects Blender evaluates, and of hidden ones once shown again
(depsgraph update; renders slice what renders: render init/complete/cancel), caches copied
beside the .blend on save (cache_follow), interactive deformation (solving when its Empty
moves, and its preview shown over the frame the slicer wrote), re-attach after load, forget
what was written after undo/redo.

All are @persistent (through @on) so they stay registered across file loads, and are found by
name on register so reloading the add-on never doubles them.
"""

from __future__ import annotations

from typing import Callable

import bpy
from bpy.app.handlers import persistent

from . import cache_follow, interactive_deform, live, visibility
from .live_registry import registry

# (name of a bpy.app.handlers list, handler), in the order the handlers are defined below: they are
# appended in it, so handlers on the same list run in it.
_HANDLERS: list[tuple[str, Callable]] = []


def on(*list_names: str):
    """Makes the decorated function a handler on each of Blender's handler lists `list_names`,
    persistent so that it stays registered across file loads."""
    def add(fn):
        fn = persistent(fn)
        _HANDLERS.extend((name, fn) for name in list_names)
        return fn
    return add


@on("frame_change_pre")
def animanifold_frame_change_pre(scene, *_args):
    # Before the new frame is evaluated: a cut written here (playback entering a
    # topology interval or a keyframe) is evaluated once, in the same pass.
    live.update_scene(scene)


@on("frame_change_post")
def animanifold_frame_change_post(scene, depsgraph=None):
    # After evaluation: animated settings (a keyframed sweep value, say) have their
    # new values now; objects without animation were shown at this frame already.
    live.update_scene(scene, after_evaluation=True)


@on("frame_change_post")
def animanifold_interactive_deform_frame_post(scene, depsgraph=None):
    # After the slicer's post-frame handler (defined, so registered, later): an object being
    # deformed interactively shows its preview, not its cache's frame.
    interactive_deform.on_frame_change(scene)


@on("depsgraph_update_post")
def animanifold_interactive_deform_depsgraph_post(scene, depsgraph=None):
    interactive_deform.on_depsgraph_update(scene)


@on("depsgraph_update_post")
def animanifold_show_revealed(scene, depsgraph=None):
    # An object the frame handlers skipped as hidden is shown at the current frame
    # once Blender evaluates it again (unhidden, its collection included).
    live.show_revealed(scene)


@on("render_init")
def animanifold_render_init(scene=None, *_args):
    # While rendering, what renders is sliced, whatever the viewport hides; an object
    # skipped as hidden in the viewport is shown at the frame now (a still has no frame change).
    visibility.set_rendering(True)
    if scene is not None:
        live.show_revealed(scene)


@on("render_complete", "render_cancel")
def animanifold_render_done(*_args):
    visibility.set_rendering(False)


@on("save_pre")
def animanifold_save_pre(filepath=None, *_args):
    # Caches follow the .blend to its new folder (cache_follow); a failure is printed, the
    # save goes on (the panel then shows the missing cache).
    if isinstance(filepath, str) and filepath:
        for note in cache_follow.before_save(filepath):
            print(f"animanifold: {note}")


@on("save_post")
def animanifold_save_post(filepath=None, *_args):
    if isinstance(filepath, str) and filepath:
        cache_follow.after_save(filepath)


@on("load_post")
def animanifold_load_post(*_args):
    # A new file: forget caches and errors of the previous one, then show every
    # live manifold at its scene's current frame (its cache may have changed).
    registry.clear()
    visibility.set_rendering(False)
    for scene in bpy.data.scenes:
        live.update_scene(scene, force=True)


@on("undo_post", "redo_post")
def animanifold_undo_post(*_args):
    # Undo and redo restore meshes and modifiers together: what the add-on remembers
    # having written may be stale, so the next frame change writes in full.
    registry.forget_shown()


def _remove_by_name(handler_list, name):
    for h in list(handler_list):
        if getattr(h, "__name__", None) == name and getattr(h, "__module__", "").endswith("handlers"):
            handler_list.remove(h)


def register_handlers():
    for list_name, fn in _HANDLERS:
        _remove_by_name(getattr(bpy.app.handlers, list_name), fn.__name__)  # leftovers of an earlier load
    for list_name, fn in _HANDLERS:
        getattr(bpy.app.handlers, list_name).append(fn)


def unregister_handlers():
    for list_name, fn in _HANDLERS:
        _remove_by_name(getattr(bpy.app.handlers, list_name), fn.__name__)
    registry.clear()
    visibility.set_rendering(False)
