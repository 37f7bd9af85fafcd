"""Interactive Laplacian deformation: with *Interactive* on, the object's constraints are
factorised once (am.Deformer) and every move of the Empty is solved again from that
factorisation and shown: a plain mesh's vertices, or a manifold's slice at the current
frame (the preview, kept on frame changes). Deform (the button reads "Apply") makes the
result permanent (deform_apply); turning Interactive off discards it.

The sessions live here, one per object; handlers.py runs `on_depsgraph_update` and
`on_frame_change` (after the live slicer, so the preview replaces the cache's frame).
Both are cheap when no session runs.
"""

from __future__ import annotations

import traceback

import bpy
import numpy as np

from . import live_nodes
from ._lib import am
from .deform_constraints import manifold_constraints, mesh_constraints
from .deform_handle import local_transform, matrix
from .live import is_live, scene_frame
from .live_registry import registry
from .mesh_input import mesh_arrays
from .mesh_writer import write_mesh, write_points
from .object_manifold import is_manifold_object
from .playback import update_object
from .progress import Progress
from .reporting import OperatorError, ReportedError


class InteractiveState:
    """What an interactive deformation keeps: the factorisation (Deformer), the rest of the
    Empty, the points it started from, the manifold (None for a plain mesh)."""

    def __init__(self, obj, deformer, empty_name, rest, start, manifold, dimension, restore):
        self.uid = getattr(obj, "session_uid", None)  # a different file's object of the same name is not ours
        self.deformer = deformer
        self.empty_name = empty_name
        self.rest = rest
        self.start = start
        self.manifold = manifold
        self.dimension = dimension
        self.restore = restore
        self.last = None  # the Empty's last matrix solved for
        self.current = None  # the latest solution, None before the Empty moves
        self.preview = None  # a manifold's latest solution as a manifold (for slicing)
        self.error = None


_SESSIONS: dict[str, InteractiveState] = {}


def session(obj) -> InteractiveState | None:
    """The running interactive deformation of `obj`, if any."""
    return _SESSIONS.get(obj.name_full)


def any_running() -> bool:
    return bool(_SESSIONS)


def start(context, obj) -> None:
    settings = obj.animanifold_deform
    empty = settings.empty
    if empty is None:
        raise OperatorError(f"choose an Empty to drive the handles of '{obj.name}'")
    notes: list[str] = []
    opt = {name: getattr(settings, name) for name in ("method", "boundary", "restore", "endpoints", "use_selected_faces")}
    opt["anchor_group"], opt["handle_group"] = settings.anchor_group_used, settings.handle_group_used
    rest = matrix(empty.matrix_world)
    if is_manifold_object(obj):
        anchors, handles, manifold = manifold_constraints(context, obj, opt, notes)
        points, simplices = np.array(manifold.points), np.array(manifold.simplices)
    else:
        if obj.data.shape_keys is not None:
            raise OperatorError(f"'{obj.name}' has shape keys: deforming its vertices would be hidden by them")
        anchors, handles = mesh_constraints(obj, opt, notes)
        manifold = None
        points, simplices = mesh_arrays(obj.data)
    progress = Progress(context.window_manager, where="factorising")  # the factorisation is what takes time
    try:
        deformer = am.Deformer(points, simplices, anchors, handles, opt["method"], opt["boundary"], progress=progress)
    finally:
        progress.end()
    _SESSIONS[obj.name_full] = InteractiveState(obj, deformer, empty.name, rest, points, manifold, points.shape[1],
                                                opt["restore"] and opt["method"] == "dual")


def stop(obj, restore_view: bool = True) -> None:
    state = _SESSIONS.pop(obj.name_full, None)
    if state is not None and restore_view and state.current is not None:
        try:  # show the undeformed object again
            if state.manifold is None:
                write_points(obj.data, state.start)
            elif is_live(obj):
                update_object(obj, scene_frame(bpy.context.scene))
        except Exception as e:  # called from a property's update: must not raise into Blender
            traceback.print_exc()
            print(f"animanifold: cannot restore '{obj.name}' after interactive deform: {type(e).__name__}: {e}")


def clear() -> None:
    _SESSIONS.clear()


def toggled(settings, context) -> None:
    """The *Interactive* property changed: start or stop the object's session. A session that
    cannot start switches the property off and says why in the panel."""
    obj = settings.id_data
    if not isinstance(obj, bpy.types.Object):
        return
    if settings.interactive and obj.name_full not in _SESSIONS:
        try:
            start(context, obj)
        except Exception as e:  # called from a property's update: must not raise into Blender
            if not isinstance(e, ReportedError):
                traceback.print_exc()
            message = str(e) if isinstance(e, ReportedError) else f"{type(e).__name__}: {e}"
            registry.set_error(obj, f"Interactive deform: {message}")
            print(f"animanifold: interactive deform of '{obj.name}' cannot start: {message}")
            settings["interactive"] = False  # without re-entering this callback
    elif not settings.interactive and obj.name_full in _SESSIONS:
        stop(obj)


def step(obj, state: InteractiveState, scene) -> bool:
    """Re-solves when the Empty moved; returns whether anything was shown."""
    empty = bpy.data.objects.get(state.empty_name)
    if empty is None:
        return False
    E = matrix(empty.matrix_world)
    if state.last is not None and np.array_equal(E, state.last):
        return False
    state.last = E
    T = local_transform(obj, empty, state.rest, state.dimension)
    points = state.deformer.deform(T)
    if state.restore:
        points = state.deformer.restore(10, 1e-4)
    state.current = np.array(points)
    if state.manifold is None:
        write_points(obj.data, state.current)
    else:
        state.preview = am.AnimationManifold.from_arrays(state.current, state.manifold.simplices)
        show_preview(obj, state, scene)
    return True


def show_preview(obj, state: InteractiveState, scene) -> None:
    """The interactive result of a manifold object at the scene's frame."""
    t0, t1 = state.preview.time_range
    s = state.preview.slice(min(max(scene_frame(scene), t0), t1), "t")
    write_mesh(obj.data, s.vertices, s.faces)
    live_nodes.release(obj)  # the mesh holds the preview as it is


def _running():
    """(object, state) of every running session; drops the stale ones (object deleted,
    Interactive switched off, another file's object of that name)."""
    for name, state in list(_SESSIONS.items()):
        obj = bpy.data.objects.get(name)
        if (obj is None or getattr(obj, "session_uid", None) != state.uid
                or not getattr(obj, "animanifold_deform", None) or not obj.animanifold_deform.interactive):
            _SESSIONS.pop(name, None)
            continue
        yield obj, state


def _guarded(obj, state, action) -> None:
    try:
        action()
        state.error = None
    except Exception as e:  # runs in a handler: a failed solve must not break the depsgraph or playback
        message = f"{type(e).__name__}: {e}"
        if state.error != message:
            traceback.print_exc()
            print(f"animanifold: interactive deform of '{obj.name}': {message}")
        state.error = message


def on_depsgraph_update(scene) -> None:
    """Solves again for every session whose Empty moved."""
    for obj, state in _running():
        _guarded(obj, state, lambda: step(obj, state, scene))


def on_frame_change(scene) -> None:
    """A manifold object keeps showing its interactive result on the new frame."""
    for obj, state in _running():
        if state.manifold is not None and state.preview is not None:
            _guarded(obj, state, lambda: show_preview(obj, state, scene))
