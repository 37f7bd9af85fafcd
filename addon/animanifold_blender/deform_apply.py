"""Laplacian deformation of an object, made permanent (chapter 4; §4.6.2's interface).

A plain mesh's vertices move (one undo step). A manifold object's deformed manifold is
written to a NEW cache file beside the old one (never overwritten: undo restores the
previous ``cache_path`` and with it the previous manifold) and the object re-sliced.
Each Laplacian row ties a vertex to its neighbours (in time too), so one anchored
keyframe does not keep the frames before it exactly: anchor a band of two consecutive
keyframes (store them one after the other) and every frame before the later one stays
as it was. Everything that can fail on the user's input is checked before anything
changes; a failure leaves the scene as it was.
"""

from __future__ import annotations

import os

import bpy
import numpy as np

from . import cache_paths, interactive_deform
from ._lib import am
from .deform_constraints import is_manifold_object, manifold_constraints, mesh_constraints
from .deform_handle import local_transform, record_rest, recorded_rest
from .live import is_live, scene_frame
from .live_registry import registry
from .mesh_input import mesh_arrays
from .mesh_writer import write_points
from .playback import update_object
from .progress import Progress
from .reporting import OperatorError


def check_target(obj, regularise: bool) -> None:
    """Refuses a plain mesh that Regularise or shape keys make undeformable."""
    if is_manifold_object(obj):
        return
    if regularise:
        raise OperatorError("Regularise splits edges, which would rebuild the mesh: it applies to manifold "
                            "objects only; turn it off to deform a plain mesh")
    if obj.data.shape_keys is not None:
        raise OperatorError(f"'{obj.name}' has shape keys: deforming its vertices would be hidden by them")


def deform_object(context, obj, opt: dict, empty, report) -> set:
    """Deforms `obj` by the motion of `empty` since its recorded rest with the options `opt`
    (the operator's properties); reports on `report` (Operator.report); the operator's result."""
    notes: list[str] = []
    if is_manifold_object(obj):
        anchors, handles, manifold = manifold_constraints(context, obj, opt, notes)
        dimension = manifold.dimension
    else:
        anchors, handles = mesh_constraints(obj, opt, notes)
        manifold, dimension = None, 3
    rest = recorded_rest(obj, empty)
    if rest is None:
        record_rest(obj, empty)
        report({"INFO"}, f"Recorded where '{empty.name}' is: move it and run Deform again to move the "
                         f"handles of '{obj.name}'")
        return {"FINISHED"}
    T = local_transform(obj, empty, rest, dimension)
    if np.allclose(T, np.eye(len(T)), atol=1e-9):
        report({"INFO"}, f"'{empty.name}' has not moved since the last deformation of '{obj.name}': nothing to do")
        return {"CANCELLED"}
    progress = Progress(context, 4)
    try:
        progress(1)
        if manifold is not None:
            where = _deform_manifold(context, obj, manifold, anchors, handles, T, opt, notes, progress)
        else:
            points, triangles = mesh_arrays(obj.data)
            moved = am.laplacian_deform(points, triangles, anchors, handles, T,
                                        options=_laplacian_options(opt))
            progress(3)
            write_points(obj.data, moved)
            where = ""
        progress(4)
    finally:
        progress.end()
    record_rest(obj, empty)
    report({"INFO"}, f"Deformed '{obj.name}' ({opt['method']}): {len(anchors)} anchors, {len(handles)} "
                     f"handles moved by '{empty.name}'{where}" + ("; " + "; ".join(notes) if notes else ""))
    return {"FINISHED"}


def _laplacian_options(opt) -> "am.LaplacianOptions":
    """The solve the operator's method, boundary rule and restore switch ask for."""
    return am.LaplacianOptions(method=opt["method"], boundary=opt["boundary"], restore=bool(opt["restore"]))


def _deform_manifold(context, obj, manifold, anchors, handles, T, opt, notes, progress) -> str:
    """Deforms a manifold object's manifold into a new cache; the report's words on where it went."""
    regularise = None
    if opt["regularise"]:
        regularise = am.RegulariseOptions(axis_weights=(1.0, 1.0, 1.0, float(opt["time_weight"])))
    moved = am.deform(manifold, anchors, handles, T, options=am.DeformOptions(_laplacian_options(opt), regularise))
    progress(3)
    summary = moved.metadata.get("regularisation") if opt["regularise"] else None
    if summary is not None:
        notes.append(f"regularised: {summary['added_vertices']} vertices added in "
                     f"{summary['iterations']} rounds"
                     + ("" if summary["converged"] else " (stopped at the iteration cap)"))
    where = f"; cache {write_manifold(context, obj, moved)}"
    if obj.animanifold.mode == "BAKED":
        notes.append("the object shows its bake, which still has the old frames: bake again")
    return where


def apply_interactive(context, obj, state) -> None:
    """Makes an interactive deformation's result permanent (interactive_deform)."""
    points = state.current
    if points is None:
        raise OperatorError(f"'{state.empty_name}' has not moved since Interactive started: nothing to apply")
    if state.manifold is None:
        write_points(obj.data, points)
    else:
        moved = am.AnimationManifold.from_arrays(points, state.manifold.simplices,
                                                 dict(state.manifold.vertex_attributes),
                                                 dict(state.manifold.simplex_attributes), state.manifold.metadata)
        write_manifold(context, obj, moved)
    empty = bpy.data.objects.get(state.empty_name)
    interactive_deform.stop(obj, restore_view=False)
    obj.animanifold_deform["interactive"] = False
    if empty is not None:
        record_rest(obj, empty)


def write_manifold(context, obj, manifold) -> str:
    """Saves `manifold` to a new cache file beside the object's, points the object at it
    and re-slices; on any failure the file is removed and the object left as it was."""
    stored_path, absolute = cache_paths.deformed_cache_path(obj)
    old = obj.animanifold.cache_path
    am.save(manifold, absolute)
    try:
        registry.remember(absolute, manifold)
        obj.animanifold.cache_path = stored_path
        if is_live(obj):
            update_object(obj, scene_frame(context.scene))
    except BaseException:
        if obj.animanifold.cache_path != old:
            obj.animanifold.cache_path = old
        registry.forget(absolute)
        try:
            os.unlink(absolute)
        except OSError:
            pass
        raise
    return stored_path
