"""Laplacian deformation in Blender (chapter 4; §4.6.2's interface): an artist
puts vertices in an "anchor" and a "handle" vertex group, moves an Empty, and
runs Deform.

Target: a manifold object (its live slice) or a plain mesh object.

* Plain mesh: the vertex groups select anchors and handles among the mesh's
  vertices; the mesh's vertices move (one undo step).
* Manifold object: the groups (and, optionally, the selected faces) of the
  slice shown at the current frame select vertices of the animation manifold.
  A slice vertex lies on a manifold edge (a, b) (``vertex_edges``, a == b at a
  keyframe); the *Edge Endpoints* option says which of a, b it constrains:
  BOTH (default: the slice vertex then moves exactly with the constraint) or
  NEARER (the endpoint nearer by ``edge_parameter``, so a frame between two
  keyframes constrains only the nearer keyframe). With *Selected Faces as
  Handles*, a selected face of the slice selects the space-time simplex it
  was cut from (``face_simplex``): all its vertices become handles (slices
  are written with every face selected, which counts as no selection).
  A manifold vertex claimed as both anchor
  and handle (adjacent slice vertices of the two groups sharing an endpoint)
  is left free, and the report says how many.
  Slices are rewritten on every frame change, which drops their vertex
  groups: *Store Constraints* keeps the current frame's anchors and handles
  (as manifold vertex indices, in custom properties of the object) so that
  anchors painted on one frame and handles on another constrain the manifold
  together; Deform uses the stored ones plus the current slice's.
  Each Laplacian row ties a vertex to its neighbours (in time too), so one
  anchored keyframe does not keep the frames before it exactly: anchor a band
  of two consecutive keyframes (store them one after the other) and every
  frame before the later one stays as it was.
  The deformed manifold is written to a NEW cache file beside the old one
  (never overwritten: undo restores the previous ``cache_path`` and with it
  the previous manifold) and the object re-sliced.

The handle transform is the Empty's motion: its world matrix is recorded on
the target object the first time it is used (custom property), and each run
applies current · rest⁻¹ (in the object's local space; for a manifold lifted
to 5x5 with time left alone) and records the current matrix as the new rest,
so moving the Empty and running again continues from the result.

Live (optional): with *Live* on, a depsgraph_update_post handler re-solves
with the kept factorisation whenever the Empty moves and shows the result
(a plain mesh's vertices, a manifold's slice at the current frame);
a frame_change_post handler (after the live slicer) keeps a manifold's
preview on frame changes. Both handlers exist only while something is live
and go with unregister. Deform (the button reads "Apply Live") makes the
result permanent as above (without regularisation); turning Live off
discards it.

Every failure is reported and leaves the scene as it was.
"""

from __future__ import annotations

import os
import re
import uuid

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, PointerProperty, StringProperty
from bpy.types import Operator, PropertyGroup

from . import live, live_nodes
from ._lib import am
from .operators import OperatorError, _Progress

METHOD_ITEMS = (
    ("dual", "Dual", "Dual Laplacian (Au et al. 2006), restores features: best"),
    ("graph", "Graph", "Graph-Laplacian weights from the per-vertex QP of eq. 4.2"),
    ("uniform", "Uniform", "Equal weights (Taubin)"),
    ("cotangent", "Cotangent", "Cotangent weights (plain triangle meshes only)"),
)
BOUNDARY_ITEMS = (
    ("grow", "Grow", "Grow anchors/handles ring by ring when the dual method's ghosts leave too few constraints"),
    ("ghost_anchors", "Ghost Anchors", "Keep every boundary ghost in place (boundaries stay put)"),
    ("error", "Error", "Refuse, saying how many more constraints are needed"),
)
ENDPOINT_ITEMS = (
    ("BOTH", "Both", "A slice vertex constrains both ends of the manifold edge it lies on"),
    ("NEARER", "Nearer", "A slice vertex constrains the end of its manifold edge nearer in time"),
)

ANCHORS_KEY = "animanifold_deform_anchors"
HANDLES_KEY = "animanifold_deform_handles"
REST_KEY = "animanifold_deform_rest"
REST_EMPTY_KEY = "animanifold_deform_empty"


def _is_empty(_self, obj):
    return obj.type == "EMPTY"


def _live_update(self, context):
    _live_toggled(self, context)  # defined below, with the live mode


class AnimanifoldDeformSettings(PropertyGroup):
    """Per object: the Deform panel's values, used as the operator's defaults."""

    anchor_group: StringProperty(name="Anchors", default="anchor",
                                 description="Vertex group of the vertices that stay (empty: none)")
    handle_group: StringProperty(name="Handles", default="handle",
                                 description="Vertex group of the vertices the Empty moves (empty: none)")
    empty: PointerProperty(name="Empty", type=bpy.types.Object, poll=_is_empty,
                           description="The Empty whose motion moves the handles")
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default="dual")
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default="grow")
    restore: BoolProperty(name="Restore", default=True, description="Dual method: restore features after the solve")
    regularise: BoolProperty(name="Regularise", default=False,
                             description="Manifold objects: split edges the deformation stretched (§4.5.1)")
    time_weight: FloatProperty(name="Time Weight", default=1.0, min=0.0, soft_max=10.0,
                               description="Regularise: length one frame counts for when measuring edges")
    endpoints: EnumProperty(name="Edge Endpoints", items=ENDPOINT_ITEMS, default="BOTH")
    use_selected_faces: BoolProperty(name="Selected Faces as Handles", default=False,
                                     description="Manifold objects: a selected slice face makes the space-time "
                                                 "simplex it was cut from a handle (a slice is written with every "
                                                 "face selected: that counts as no selection)")
    live: BoolProperty(name="Live", default=False, update=_live_update,
                       description="Re-solve whenever the Empty moves (kept factorisation); Deform applies it")


def _option(op, settings, name):
    if op.properties.is_property_set(name):
        return getattr(op, name)
    return getattr(settings, name)


# -- reading the target ------------------------------------------------------------

def group_members(obj, name: str) -> np.ndarray | None:
    """(N,) bool: vertices of `obj` in vertex group `name` with a weight > 0;
    None when the object has no such group. (Blender exposes no array access
    to deform weights, so this walks the vertices' group lists once.)"""
    group = obj.vertex_groups.get(name)
    if group is None:
        return None
    index = group.index
    mesh = obj.data
    members = [v.index for v in mesh.vertices for g in v.groups if g.group == index and g.weight > 0.0]
    out = np.zeros(len(mesh.vertices), dtype=bool)
    out[np.asarray(members, dtype=np.int64)] = True
    return out


def selected_faces(mesh) -> np.ndarray:
    flags = np.zeros(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("select", flags)
    return np.flatnonzero(flags)


def mesh_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (N, 3) local, triangles (T, 3))."""
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    mesh.calc_loop_triangles()
    tri = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tri)
    return co.reshape(-1, 3).astype(np.float64), tri.reshape(-1, 3)


def stored(obj, key: str) -> np.ndarray:
    value = obj.get(key)
    if value is None:
        return np.zeros(0, dtype=np.int64)
    return np.asarray(list(value), dtype=np.int64)


def _is_manifold(obj) -> bool:
    settings = getattr(obj, "animanifold", None)
    return settings is not None and settings.is_manifold


def _group(obj, name: str, what: str, has_stored: bool) -> np.ndarray | None:
    """Members of group `name` (None: no group name given, or a missing/empty group
    made up for by stored constraints); raises when the group is missing or empty."""
    if not name:
        return None
    members = group_members(obj, name)
    if members is None:
        if has_stored:
            return None
        raise OperatorError(f"'{obj.name}' has no vertex group '{name}' for the {what}: add it, or change the "
                            f"{what} group name")
    if not members.any() and not has_stored:
        raise OperatorError(f"the vertex group '{name}' of '{obj.name}' ({what}) has no vertices")
    return members


def slice_constraints(obj, frame: float, anchor_group: str, handle_group: str, endpoints: str,
                      use_faces: bool, stored_anchors: bool = False, stored_handles: bool = False,
                      notes: list[str] | None = None):
    """Manifold vertices selected by the current slice of a manifold object:
    (anchors, handles, manifold, slice) — index arrays, unsorted unique.
    Every slice is written with all its faces selected, so a selection of
    every face is taken as no selection (and noted)."""
    if obj.animanifold.axis != "t":
        raise OperatorError(f"'{obj.name}' shows a sweep view along {obj.animanifold.axis}: switch its axis to t "
                            "to deform it")
    if live.smoothing(obj):
        raise OperatorError(f"'{obj.name}' shows a smoothed manifold (Smooth panel): its mesh is not a slice of "
                            "the manifold that Deform moves; set Manifold Levels and Frame Levels to 0 to deform it")
    manifold, s = live.slice_for(obj, frame)
    if s.vertex_edges is None:
        raise OperatorError(f"the frame of '{obj.name}' at {frame:g} is cut by the holes its morph's inputs share "
                            "(its points are not on manifold edges): deform it at the first or last frame")
    mesh = obj.data
    if len(mesh.vertices) != len(s.vertices) or len(mesh.polygons) != len(s.faces):
        raise OperatorError(
            f"the mesh of '{obj.name}' ({len(mesh.vertices)} vertices, {len(mesh.polygons)} faces) is not its slice "
            f"at frame {frame:g} ({len(s.vertices)}, {len(s.faces)}): was it edited? Change frame to re-slice it")
    edges = np.asarray(s.vertex_edges, dtype=np.int64)
    parameter = np.asarray(s.edge_parameter, dtype=np.float64)

    def to_manifold(mask):
        if mask is None or not mask.any():
            return np.zeros(0, dtype=np.int64)
        e = edges[mask]
        if endpoints == "NEARER":
            return np.unique(np.where(parameter[mask] <= 0.5, e[:, 0], e[:, 1]))
        return np.unique(e.reshape(-1))

    anchors = to_manifold(_group(obj, anchor_group, "anchors", stored_anchors))
    handles = to_manifold(_group(obj, handle_group, "handles", stored_handles))
    if use_faces:
        faces = selected_faces(mesh)
        if len(faces) == len(mesh.polygons):
            if notes is not None and len(faces):
                notes.append("every slice face is selected (as a fresh slice is): face selection ignored")
        elif len(faces):
            simplices = np.asarray(manifold.simplices)[np.asarray(s.face_simplex, dtype=np.int64)[faces]]
            handles = np.union1d(handles, simplices.reshape(-1))
    return anchors, handles, manifold, s


def resolve(anchors: np.ndarray, handles: np.ndarray, notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    anchors, handles = np.unique(anchors), np.unique(handles)
    both = np.intersect1d(anchors, handles)
    if len(both):
        notes.append(f"{len(both)} vertices claimed as both anchor and handle were left free")
        anchors, handles = np.setdiff1d(anchors, both), np.setdiff1d(handles, both)
    return anchors, handles


# -- the Empty ----------------------------------------------------------------------

def _matrix(value) -> np.ndarray:
    return np.array([list(row) for row in value], dtype=np.float64)


def empty_for(op, obj, settings):
    name = op.empty if op.properties.is_property_set("empty") else ""
    empty = bpy.data.objects.get(name) if name else settings.empty
    if name and empty is None:
        raise OperatorError(f"there is no object '{name}' to drive the handles")
    if empty is None:
        raise OperatorError(f"choose an Empty to drive the handles of '{obj.name}'")
    if empty.type != "EMPTY":
        raise OperatorError(f"'{empty.name}' is a {empty.type.lower()}, not an Empty")
    return empty


def recorded_rest(obj, empty) -> np.ndarray | None:
    rest = obj.get(REST_KEY)
    if rest is None or obj.get(REST_EMPTY_KEY) != empty.name:
        return None
    return np.asarray(list(rest), dtype=np.float64).reshape(4, 4)


def record_rest(obj, empty) -> None:
    obj[REST_KEY] = [float(x) for x in _matrix(empty.matrix_world).reshape(-1)]
    obj[REST_EMPTY_KEY] = empty.name


def local_transform(obj, empty, rest: np.ndarray, dimension: int) -> np.ndarray:
    """current · rest⁻¹ of the Empty, in `obj`'s local space; (D+1)x(D+1), time kept for D = 4."""
    O = _matrix(obj.matrix_world)
    world = _matrix(empty.matrix_world) @ np.linalg.inv(rest)
    M = np.linalg.inv(O) @ world @ O
    if dimension == 3:
        return M
    T = np.eye(5)
    T[:3, :3] = M[:3, :3]
    T[:3, 4] = M[:3, 3]
    return T


# -- cache files --------------------------------------------------------------------

_SUFFIX = re.compile(r"\.deform-[0-9a-f]{8}$")


def new_cache_path(obj) -> tuple[str, str]:
    """(stored, absolute): a fresh file beside the object's cache."""
    old_stored = obj.animanifold.cache_path
    old = live.cache_abspath(obj)
    folder = os.path.dirname(old)
    stem = _SUFFIX.sub("", os.path.splitext(os.path.basename(old))[0])
    while True:
        absolute = os.path.join(folder, f"{stem}.deform-{uuid.uuid4().hex[:8]}.amf")
        if not os.path.exists(absolute):
            break
    stored = bpy.path.relpath(absolute) if old_stored.startswith("//") and bpy.data.filepath else absolute
    return stored, absolute


# -- the operators ------------------------------------------------------------------

def _laplacian_options(opt) -> "am.LaplacianOptions":
    """The solve the operator's method, boundary rule and restore switch ask for."""
    return am.LaplacianOptions(method=opt["method"], boundary=opt["boundary"], restore=bool(opt["restore"]))


class ANIMANIFOLD_OT_deform(Operator):
    """Laplacian deformation: anchors stay, handles follow the Empty's motion since its last use
    (a manifold object through space and time, or a plain mesh)"""

    bl_idname = "animanifold.deform"
    bl_label = "Laplacian Deform"
    bl_options = {"REGISTER", "UNDO"}

    anchor_group: StringProperty(name="Anchors", default="anchor")
    handle_group: StringProperty(name="Handles", default="handle")
    empty: StringProperty(name="Empty", description="Name of the Empty (default: the panel's)")
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default="dual")
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default="grow")
    restore: BoolProperty(name="Restore", default=True)
    regularise: BoolProperty(name="Regularise", default=False)
    time_weight: FloatProperty(name="Time Weight", default=1.0, min=0.0)
    endpoints: EnumProperty(name="Edge Endpoints", items=ENDPOINT_ITEMS, default="BOTH")
    use_selected_faces: BoolProperty(name="Selected Faces as Handles", default=False)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        if obj is None or obj.type != "MESH" or obj.library is not None:
            cls.poll_message_set("Select a mesh or manifold object")
            return False
        return True

    def execute(self, context):
        obj = context.active_object
        try:
            return self._execute(context, obj)
        except (OperatorError, am.CacheError) as e:
            self.report({"ERROR"}, str(e))
        except (ValueError, RuntimeError, OSError) as e:  # the Deformer names what is wrong
            self.report({"ERROR"}, f"Deform of '{obj.name}' failed: {e}")
        except Exception as e:  # a bug: still report it, nothing was changed
            self.report({"ERROR"}, f"Deform of '{obj.name}' failed unexpectedly: {type(e).__name__}: {e}")
        return {"CANCELLED"}

    def _execute(self, context, obj):
        settings = obj.animanifold_deform
        opt = {name: _option(self, settings, name) for name in (
            "anchor_group", "handle_group", "method", "boundary", "restore", "regularise", "time_weight",
            "endpoints", "use_selected_faces")}
        empty = empty_for(self, obj, settings)
        manifold_object = _is_manifold(obj)
        if not manifold_object and opt["regularise"]:
            raise OperatorError("Regularise splits edges, which would rebuild the mesh: it applies to manifold "
                                "objects only; turn it off to deform a plain mesh")
        if not manifold_object and obj.data.shape_keys is not None:
            raise OperatorError(f"'{obj.name}' has shape keys: deforming its vertices would be hidden by them")
        state = LIVE.get(obj.name_full)
        if state is not None:
            return self._apply_live(context, obj, state)

        notes: list[str] = []
        # Everything that can fail on the user's input is checked before anything changes.
        if manifold_object:
            anchors, handles, manifold = manifold_constraints(context, obj, opt, notes)
            dimension = manifold.dimension
        else:
            anchors, handles = mesh_constraints(obj, opt, notes)
            manifold, dimension = None, 3
        rest = recorded_rest(obj, empty)
        if rest is None:
            record_rest(obj, empty)
            self.report({"INFO"}, f"Recorded where '{empty.name}' is: move it and run Deform again to move the "
                                  f"handles of '{obj.name}'")
            return {"FINISHED"}
        T = local_transform(obj, empty, rest, dimension)
        if np.allclose(T, np.eye(len(T)), atol=1e-9):
            self.report({"INFO"}, f"'{empty.name}' has not moved since the last deformation of '{obj.name}': "
                                  "nothing to do")
            return {"CANCELLED"}

        progress = _Progress(context, 4)
        try:
            progress(1)
            if manifold is not None:
                regularise = None
                if opt["regularise"]:
                    regularise = am.RegulariseOptions(axis_weights=(1.0, 1.0, 1.0, float(opt["time_weight"])))
                moved = am.deform(manifold, anchors, handles, T,
                                  options=am.DeformOptions(_laplacian_options(opt), regularise))
                progress(3)
                summary = moved.metadata.get("regularisation") if opt["regularise"] else None
                if summary is not None:
                    notes.append(f"regularised: {summary['added_vertices']} vertices added in "
                                 f"{summary['iterations']} rounds"
                                 + ("" if summary["converged"] else " (stopped at the iteration cap)"))
                where = f"; cache {write_manifold(context, obj, moved)}"
                if obj.animanifold.mode == "BAKED":
                    notes.append("the object shows its bake, which still has the old frames: bake again")
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
        self.report({"INFO"}, f"Deformed '{obj.name}' ({opt['method']}): {len(anchors)} anchors, {len(handles)} "
                              f"handles moved by '{empty.name}'{where}" + ("; " + "; ".join(notes) if notes else ""))
        return {"FINISHED"}

    def _apply_live(self, context, obj, state):
        """Live mode: Deform makes the live result permanent."""
        points = state.current
        if points is None:
            raise OperatorError(f"'{state.empty_name}' has not moved since Live started: nothing to apply")
        if state.manifold is None:
            write_points(obj.data, points)
        else:
            moved = am.AnimationManifold.from_arrays(points, state.manifold.simplices,
                                                     dict(state.manifold.vertex_attributes),
                                                     dict(state.manifold.simplex_attributes), state.manifold.metadata)
            write_manifold(context, obj, moved)
        empty = bpy.data.objects.get(state.empty_name)
        stop_live(obj, restore_view=False)
        obj.animanifold_deform["live"] = False
        if empty is not None:
            record_rest(obj, empty)
        self.report({"INFO"}, f"Applied the live deformation of '{obj.name}'")
        return {"FINISHED"}


def mesh_constraints(obj, opt, notes):
    """(anchors, handles) vertex indices of a plain mesh, from its vertex groups."""
    anchors = _group(obj, opt["anchor_group"], "anchors", False)
    handles = _group(obj, opt["handle_group"], "handles", False)
    anchors = np.zeros(0, np.int64) if anchors is None else np.flatnonzero(anchors)
    handles = np.zeros(0, np.int64) if handles is None else np.flatnonzero(handles)
    anchors, handles = resolve(anchors, handles, notes)
    if not len(handles):
        raise OperatorError(f"'{obj.name}' has no handle vertices: put some in the vertex group "
                            f"'{opt['handle_group'] or 'handle'}'")
    return anchors, handles


def manifold_constraints(context, obj, opt, notes):
    """(anchors, handles, manifold) of a manifold object: stored constraints plus the current slice's."""
    stored_a, stored_h = stored(obj, ANCHORS_KEY), stored(obj, HANDLES_KEY)
    frame = live.scene_frame(context.scene)
    anchors, handles, manifold, _ = slice_constraints(
        obj, frame, opt["anchor_group"], opt["handle_group"], opt["endpoints"], opt["use_selected_faces"],
        stored_anchors=len(stored_a) > 0, stored_handles=len(stored_h) > 0, notes=notes)
    n = len(manifold.points)
    for values in (stored_a, stored_h):
        if len(values) and (values.min() < 0 or values.max() >= n):
            raise OperatorError(f"the stored constraints of '{obj.name}' name vertex {int(values.max())} but its "
                                f"manifold has {n} vertices: clear them and store them again")
    if len(stored_a) or len(stored_h):
        notes.append(f"with {len(stored_a)} stored anchors and {len(stored_h)} stored handles")
    anchors, handles = resolve(np.concatenate([anchors, stored_a]), np.concatenate([handles, stored_h]), notes)
    if not len(handles):
        raise OperatorError(f"no handles for '{obj.name}': put slice vertices in the vertex group "
                            f"'{opt['handle_group'] or 'handle'}', select slice faces, or store handles from "
                            "another frame")
    return anchors, handles, manifold


def write_points(mesh, points: np.ndarray) -> None:
    mesh.vertices.foreach_set("co", np.ascontiguousarray(points, dtype=np.float32).reshape(-1))
    mesh.update()


def write_manifold(context, obj, manifold) -> str:
    """Saves `manifold` to a new cache file beside the object's, points the object at it
    and re-slices; on any failure the file is removed and the object left as it was."""
    stored_path, absolute = new_cache_path(obj)
    old = obj.animanifold.cache_path
    am.save(manifold, absolute)
    try:
        live.remember(absolute, manifold)
        obj.animanifold.cache_path = stored_path
        if live.is_live(obj):
            live.update_object(obj, live.scene_frame(context.scene))
    except BaseException:
        if obj.animanifold.cache_path != old:
            obj.animanifold.cache_path = old
        live.forget(absolute)
        try:
            os.unlink(absolute)
        except OSError:
            pass
        raise
    return stored_path


class ANIMANIFOLD_OT_deform_store(Operator):
    """Keep the anchors and handles selected on this frame's slice (vertex groups, selected faces),
    so that constraints painted on several frames deform the manifold together"""

    bl_idname = "animanifold.deform_store"
    bl_label = "Store Constraints"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        if obj is None or not _is_manifold(obj) or obj.library is not None:
            cls.poll_message_set("Select a manifold object (made by Convert)")
            return False
        return True

    def execute(self, context):
        obj = context.active_object
        s = obj.animanifold_deform
        try:
            notes: list[str] = []
            anchors, handles, _, _ = slice_constraints(obj, live.scene_frame(context.scene), s.anchor_group,
                                                       s.handle_group, s.endpoints, s.use_selected_faces,
                                                       stored_anchors=True, stored_handles=True, notes=notes)
        except (OperatorError, am.CacheError, ValueError, RuntimeError, OSError) as e:
            self.report({"ERROR"}, f"Cannot store constraints of '{obj.name}': {e}")
            return {"CANCELLED"}
        if not len(anchors) and not len(handles):
            self.report({"ERROR"}, f"the slice of '{obj.name}' has nothing in the vertex groups "
                                   f"'{s.anchor_group}' / '{s.handle_group}' and no selected faces: nothing stored")
            return {"CANCELLED"}
        a, h = resolve(np.concatenate([stored(obj, ANCHORS_KEY), anchors]),
                       np.concatenate([stored(obj, HANDLES_KEY), handles]), notes)
        obj[ANCHORS_KEY] = [int(x) for x in a]
        obj[HANDLES_KEY] = [int(x) for x in h]
        self.report({"INFO"}, f"'{obj.name}' stores {len(a)} anchors and {len(h)} handles"
                              + ("; " + "; ".join(notes) if notes else ""))
        return {"FINISHED"}


class ANIMANIFOLD_OT_deform_clear(Operator):
    """Forget the stored anchors and handles and the Empty's recorded rest"""

    bl_idname = "animanifold.deform_clear"
    bl_label = "Clear Constraints"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and any(k in obj for k in (ANCHORS_KEY, HANDLES_KEY, REST_KEY, REST_EMPTY_KEY))

    def execute(self, context):
        obj = context.active_object
        for key in (ANCHORS_KEY, HANDLES_KEY, REST_KEY, REST_EMPTY_KEY):
            if key in obj:
                del obj[key]
        return {"FINISHED"}


# -- live mode ----------------------------------------------------------------------

class LiveState:
    """What a live deformation keeps: the factorisation (Deformer), the rest of the
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


LIVE: dict[str, LiveState] = {}


def start_live(context, obj) -> None:
    settings = obj.animanifold_deform
    empty = settings.empty
    if empty is None:
        raise OperatorError(f"choose an Empty to drive the handles of '{obj.name}'")
    notes: list[str] = []
    opt = {name: getattr(settings, name) for name in (
        "anchor_group", "handle_group", "method", "boundary", "restore", "endpoints", "use_selected_faces")}
    rest = _matrix(empty.matrix_world)
    if _is_manifold(obj):
        anchors, handles, manifold = manifold_constraints(context, obj, opt, notes)
        points, simplices = np.array(manifold.points), np.array(manifold.simplices)
    else:
        if obj.data.shape_keys is not None:
            raise OperatorError(f"'{obj.name}' has shape keys: deforming its vertices would be hidden by them")
        anchors, handles = mesh_constraints(obj, opt, notes)
        manifold = None
        points, simplices = mesh_arrays(obj.data)
    deformer = am.Deformer(points, simplices, anchors, handles, opt["method"], opt["boundary"])
    LIVE[obj.name_full] = LiveState(obj, deformer, empty.name, rest, points, manifold, points.shape[1],
                                    opt["restore"] and opt["method"] == "dual")
    _ensure_handler()


def stop_live(obj, restore_view: bool = True) -> None:
    state = LIVE.pop(obj.name_full, None)
    if state is not None and restore_view and state.current is not None:
        try:  # show the undeformed object again
            if state.manifold is None:
                write_points(obj.data, state.start)
            elif live.is_live(obj):
                live.update_object(obj, live.scene_frame(bpy.context.scene))
        except Exception as e:  # never raise from an update callback
            print(f"animanifold: cannot restore '{obj.name}' after live deform: {type(e).__name__}: {e}")
    if not LIVE:
        _remove_handler()


def _live_toggled(settings, context):
    obj = settings.id_data
    if not isinstance(obj, bpy.types.Object):
        return
    if settings.live and obj.name_full not in LIVE:
        try:
            start_live(context, obj)
        except Exception as e:  # an update callback must not raise: show it and switch off
            message = str(e) if isinstance(e, OperatorError) else f"{type(e).__name__}: {e}"
            live._ERRORS[obj.name_full] = f"Live deform: {message}"
            print(f"animanifold: live deform of '{obj.name}' cannot start: {message}")
            settings["live"] = False  # without re-entering this callback
    elif not settings.live and obj.name_full in LIVE:
        stop_live(obj)


def live_step(obj, state: LiveState, scene) -> bool:
    """Re-solves when the Empty moved; returns whether anything was shown."""
    empty = bpy.data.objects.get(state.empty_name)
    if empty is None:
        return False
    E = _matrix(empty.matrix_world)
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


def show_preview(obj, state: LiveState, scene) -> None:
    """The live result of a manifold object at the scene's frame."""
    t0, t1 = state.preview.time_range
    s = state.preview.slice(min(max(live.scene_frame(scene), t0), t1), "t")
    live.write_mesh(obj.data, s.vertices, s.faces)
    live_nodes.release(obj)  # the mesh holds the preview as it is


def _live_states():
    """(object, state) of every running live deformation; drops the stale ones
    (object deleted, Live switched off, another file's object of that name)."""
    for name, state in list(LIVE.items()):
        obj = bpy.data.objects.get(name)
        if (obj is None or getattr(obj, "session_uid", None) != state.uid
                or not getattr(obj, "animanifold_deform", None) or not obj.animanifold_deform.live):
            LIVE.pop(name, None)
            continue
        yield obj, state


def _guarded(obj, state, step) -> None:
    try:
        step()
        state.error = None
    except Exception as e:  # a failed solve must not break the depsgraph or playback
        message = f"{type(e).__name__}: {e}"
        if state.error != message:
            print(f"animanifold: live deform of '{obj.name}': {message}")
        state.error = message


@bpy.app.handlers.persistent
def animanifold_deform_depsgraph_post(scene, depsgraph=None):
    for obj, state in _live_states():
        _guarded(obj, state, lambda: live_step(obj, state, scene))


@bpy.app.handlers.persistent
def animanifold_deform_frame_post(scene, depsgraph=None):
    # Runs after the live slicer (registered later): a manifold object keeps showing its live result.
    for obj, state in _live_states():
        if state.manifold is not None and state.preview is not None:
            _guarded(obj, state, lambda: show_preview(obj, state, scene))


_LIVE_HANDLERS = (
    (bpy.app.handlers.depsgraph_update_post, animanifold_deform_depsgraph_post),
    (bpy.app.handlers.frame_change_post, animanifold_deform_frame_post),
)


def _ensure_handler():
    for handlers, fn in _LIVE_HANDLERS:
        if not any(getattr(h, "__name__", "") == fn.__name__ for h in handlers):
            handlers.append(fn)


def _remove_handler():
    """Removes the live handlers (never from inside one: Blender is iterating the list)."""
    for handlers, fn in _LIVE_HANDLERS:
        for h in list(handlers):
            if getattr(h, "__name__", "") == fn.__name__:
                handlers.remove(h)


# -- registration -------------------------------------------------------------------

classes = (AnimanifoldDeformSettings, ANIMANIFOLD_OT_deform, ANIMANIFOLD_OT_deform_store, ANIMANIFOLD_OT_deform_clear)


def register_properties():
    bpy.types.Object.animanifold_deform = PointerProperty(type=AnimanifoldDeformSettings)


def unregister_properties():
    LIVE.clear()
    _remove_handler()
    if hasattr(bpy.types.Object, "animanifold_deform"):
        del bpy.types.Object.animanifold_deform
