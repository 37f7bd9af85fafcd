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
from dataclasses import dataclass, field

import bpy
import numpy as np

from . import cache_paths, interactive_deform
from ._lib import am
from .deform_constraints import manifold_constraints, mesh_constraints
from .deform_handle import local_transform, record_rest, recorded_rest
from .live import is_live, scene_frame
from .live_registry import registry
from .mesh_input import mesh_arrays
from .mesh_writer import write_points
from .object_manifold import is_manifold_object
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


@dataclass
class DeformPlan:
    """What a Deform computes, read from the scene beforehand: `compute` touches no Blender
    data, so it may run in a worker thread (am.CoreJob) while the interface keeps drawing."""

    obj_name: str
    empty_name: str
    opt: dict
    anchors: np.ndarray
    handles: np.ndarray
    transform: np.ndarray
    manifold: object = None  # the object's AnimationManifold; None for a plain mesh
    points: np.ndarray | None = None  # a plain mesh's vertices and triangles
    triangles: np.ndarray | None = None
    notes: list = field(default_factory=list)

    def compute(self, progress=None, interrupted=None):
        """The deformed manifold, or a plain mesh's moved (N, 3) vertices."""
        laplacian = _laplacian_options(self.opt)
        if self.manifold is None:
            return am.laplacian_deform(self.points, self.triangles, self.anchors, self.handles, self.transform,
                                       options=laplacian, progress=progress, interrupted=interrupted)
        regularise = None
        if self.opt["regularise"]:
            regularise = am.RegulariseOptions(axis_weights=(1.0, 1.0, 1.0, float(self.opt["time_weight"])))
        return am.deform(self.manifold, self.anchors, self.handles, self.transform,
                         options=am.DeformOptions(laplacian, regularise), progress=progress, interrupted=interrupted)


def plan_deform(context, obj, opt: dict, empty, report) -> tuple[DeformPlan | None, set]:
    """What deforming `obj` by the motion of `empty` since its recorded rest with the options `opt`
    (the operator's properties) computes; (None, the operator's result) when there is nothing to
    compute: the rest is recorded first, or the Empty has not moved (reported on `report`)."""
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
        return None, {"FINISHED"}
    T = local_transform(obj, empty, rest, dimension)
    if np.allclose(T, np.eye(len(T)), atol=1e-9):
        report({"INFO"}, f"'{empty.name}' has not moved since the last deformation of '{obj.name}': nothing to do")
        return None, {"CANCELLED"}
    points, triangles = (None, None) if manifold is not None else mesh_arrays(obj.data)
    return DeformPlan(obj.name, empty.name, opt, anchors, handles, T, manifold, points, triangles, notes), set()


def deform_object(context, obj, opt: dict, empty, report) -> set:
    """Deforms `obj` by the motion of `empty` (plan_deform), blocking, with the core's steps on
    the progress bar; reports on `report` (Operator.report); the operator's result."""
    plan, result = plan_deform(context, obj, opt, empty, report)
    if plan is None:
        return result
    progress = Progress(context.window_manager, 5.0, 90.0, where="reading the constraints")
    try:
        progress.at(5.0, "before the core's first step")
        deformed = plan.compute(progress=progress)
        progress.at(90.0, "writing the result")
        return finish_deform(context, obj, plan, deformed, report)
    finally:
        progress.end()


def finish_deform(context, obj, plan: DeformPlan, deformed, report) -> set:
    """Writes what `plan.compute` returned into `obj` (its mesh, or a new cache), records the
    Empty's new rest and reports; the operator's result."""
    notes = list(plan.notes)
    if plan.manifold is not None:
        where = _write_deformed_manifold(context, obj, deformed, plan.opt, notes)
    else:
        write_points(obj.data, deformed)
        where = ""
    empty = bpy.data.objects.get(plan.empty_name)
    if empty is not None:
        record_rest(obj, empty)
    report({"INFO"}, f"Deformed '{obj.name}' ({plan.opt['method']}): {len(plan.anchors)} anchors, "
                     f"{len(plan.handles)} handles moved by '{plan.empty_name}'{where}"
           + ("; " + "; ".join(notes) if notes else ""))
    return {"FINISHED"}


def _laplacian_options(opt) -> "am.LaplacianOptions":
    """The solve the operator's method, boundary rule and restore switch ask for."""
    return am.LaplacianOptions(method=opt["method"], boundary=opt["boundary"], restore=bool(opt["restore"]))


def _write_deformed_manifold(context, obj, moved, opt, notes) -> str:
    """Saves a manifold object's deformed manifold into a new cache; the report's words on where it went."""
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
