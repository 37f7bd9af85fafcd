"""Which vertices Laplacian deformation holds (anchors) and moves (handles).

Plain mesh: the vertex groups select anchors and handles among the mesh's vertices.

Manifold object: the groups (and, optionally, the selected faces) of the slice shown at
the current frame select vertices of the animation manifold. A slice vertex lies on a
manifold edge (a, b) (``vertex_edges``, a == b at a keyframe); the *Edge Endpoints*
option says which of a, b it constrains: BOTH (the slice vertex then moves exactly with
the constraint) or NEARER (the endpoint nearer by ``edge_parameter``, so a frame between
two keyframes constrains only the nearer keyframe). With *Selected Faces as Handles*, a
selected face of the slice selects the space-time simplex it was cut from
(``face_simplex``): all its vertices become handles (slices are written with every face
selected, which counts as no selection). A manifold vertex claimed as both anchor and
handle is left free, and the report says how many.

Slices are rewritten on every frame change, which drops their vertex groups: *Store
Constraints* keeps the current frame's anchors and handles as manifold vertex indices
in custom properties of the object, so that constraints painted on several frames
deform the manifold together.
"""

from __future__ import annotations

import numpy as np

from .live import scene_frame
from .mesh_input import group_members, selected_faces
from .object_manifold import slice_for, smoothing
from .reporting import OperatorError

ANCHORS_KEY = "animanifold_deform_anchors"
HANDLES_KEY = "animanifold_deform_handles"


def stored(obj, key: str) -> np.ndarray:
    """The manifold vertex indices stored on `obj` under `key` (ANCHORS_KEY, HANDLES_KEY)."""
    value = obj.get(key)
    if value is None:
        return np.zeros(0, dtype=np.int64)
    return np.asarray(list(value), dtype=np.int64)


def store(obj, anchors: np.ndarray, handles: np.ndarray) -> None:
    obj[ANCHORS_KEY] = [int(x) for x in anchors]
    obj[HANDLES_KEY] = [int(x) for x in handles]


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
    if smoothing(obj):
        raise OperatorError(f"'{obj.name}' shows a smoothed manifold (Smooth panel): its mesh is not a slice of "
                            "the manifold that Deform moves; set Manifold Levels and Frame Levels to 0 to deform it")
    manifold, s = slice_for(obj, frame)
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
    """Unique anchors and handles; a vertex claimed by both is left free (and noted)."""
    anchors, handles = np.unique(anchors), np.unique(handles)
    both = np.intersect1d(anchors, handles)
    if len(both):
        notes.append(f"{len(both)} vertices claimed as both anchor and handle were left free")
        anchors, handles = np.setdiff1d(anchors, both), np.setdiff1d(handles, both)
    return anchors, handles


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
    frame = scene_frame(context.scene)
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
