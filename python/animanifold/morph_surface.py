"""The inputs' UV maps and material indices on a morph's frames.

A morph (animanifold.morph) builds the shape; this module gives its frames the inputs' look.
Every simplex of the manifold is given to one input and one face of it, and its corners take
that input's UV map there:

* Which input. A simplex with a facet on an end (three corners at t0, or at t1) belongs to that
  end's input: the end frames are the inputs, so they keep the inputs' own UVs and materials.
  Any other simplex belongs to the input its corners lie closer to, in a measure that moves with
  time: a corner at the fraction s of the range leans to the source when s times its distance to
  the source is less than (1 - s) times its distance to the target (summed over the corners; a
  tie goes to the target in the second half of the range). Early frames take the source's look
  everywhere but where they already touch the target, late frames the target's, and in between
  each part takes the look of the surface it is passing through.
* Which face. A simplex lying on its input with a facet takes the face under that facet's
  centre (at the ends, the very face the frame shows); any other the face closest to its corner
  nearest the input. Its material index is that face's.
* UVs. Every simplex reads the UV map in its own face's chart: the UV at its corner's position
  carried onto the face's plane (the face's linear UV map, continued past its edges). Around a
  vertex, simplices whose charts agree there (to _SAME_UV of the map's extent) share one copy of
  it; where they disagree (a seam of the input, or the look passing from source to target) the
  vertex is split, one copy per chart, as Convert splits keyframe vertices at UV seams. A copy
  takes the UV of the vertex's closest point on the input, read in the face holding that point
  whose UVs agree best with its chart (on an edge or a corner, each side of a seam offers its
  own) when that agrees with the chart, and otherwise the UV of its closest point in the
  nearest of its simplices' own faces. A vertex on an input so has exactly the input's UV there,
  on the right side of every seam: the ends are exact.

UVs are per face corner (Blender's UV maps), so an input's seams are kept exactly. Frames that
a hole space cuts (the seed's methods between the ends) are welded for the cut and take their
attributes back from the raw frame (hole_cut.py); the field method cuts none.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from . import _core
from .barycentric import closest_in_triangles, plane_barycentric
from .manifold import AnimationManifold
from ._core import InputError

# Corners within this share of the size of an input lie on it (the ends are exact to 1e-9).
_ON_SURFACE = 1e-9
# Two simplices' UVs at a vertex within this share of the UV map's extent are one chart there.
_SAME_UV = 1e-2
# Off the input, charts continued from different faces drift apart (the surface bends away from
# their planes): there they are one chart when they agree to this share of the vertex's distance
# from the input, in UV units (the map's extent over the input's). A seam's jump is most of the
# map's extent; this drift is a small share of the distance.
_SAME_UV_OFF_SURFACE = 0.5
# Blender's limit on material slots.
_MATERIAL_LIMIT = 32767


@dataclass(frozen=True)
class SurfaceAttributes:
    """What a morph input shows besides its shape: a UV map, per face corner, (l, 3, 2) in the order
    of its faces (a face's corners as its row lists them), and a material index per face, (l,)."""

    uv: np.ndarray | None = None
    material_index: np.ndarray | None = None


@dataclass
class _Input:
    """One input's mesh and attributes, and the closest point on it of every manifold vertex."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None
    material_index: np.ndarray | None
    distance: np.ndarray = None  # (n,) from every manifold vertex
    face: np.ndarray = None  # (n,) the face of its closest point
    barycentric: np.ndarray = None  # (n, 3) its closest point there


def carry_surface_attributes(manifold: AnimationManifold, source: tuple[np.ndarray, np.ndarray],
                             target: tuple[np.ndarray, np.ndarray], source_attributes: SurfaceAttributes | None,
                             target_attributes: SurfaceAttributes | None) -> AnimationManifold:
    """`manifold` (a morph of `source` into `target`, 3D) with the inputs' UV map as the vertex
    attribute "uv" and their material indices as the simplex attribute "material_index" (see the
    module doc). Material indices are taken as given: a caller that shows both inputs' materials
    numbers the target's after the source's. Returns a new manifold (its vertices split at seams);
    its metadata["validity"]["surface_attributes"] says what was carried and how many vertices the
    seams added. Raises ValueError naming the input and face for attributes that do not fit."""
    start = time.perf_counter()
    if manifold.dimension != 4:
        raise InputError("UV maps and materials are carried onto 3D morphs (triangle meshes) only")
    inputs = [_checked_input(name, mesh, attributes) for name, mesh, attributes in
              (("source", source, source_attributes), ("target", target, target_attributes))]
    points, simplices = manifold.points, manifold.simplices
    t0, t1 = manifold.time_range
    for i in inputs:
        i.distance, i.face, i.barycentric = _core.closest_points(np.ascontiguousarray(points[:, :3]), i.vertices,
                                                                 i.faces)
        i.face = i.face.astype(np.int64)
    size = max(float(np.linalg.norm(np.ptp(i.vertices, axis=0))) for i in inputs)
    to_target = _simplex_inputs(points[:, 3], simplices, inputs, t0, t1)
    face = _simplex_faces(points, simplices, inputs, to_target, (t0, t1), _ON_SURFACE * size)
    vertex_attributes = {k: np.asarray(v) for k, v in manifold.vertex_attributes.items()}
    simplex_attributes = {k: np.asarray(v) for k, v in manifold.simplex_attributes.items()}
    carries_uv = any(i.uv is not None for i in inputs)
    copies = np.arange(len(points))
    if carries_uv:
        simplices, copies, uv = _split_and_map_uv(points, simplices, inputs, to_target, face)
        vertex_attributes = {k: v[copies] for k, v in vertex_attributes.items()}
        vertex_attributes["uv"] = uv
    if any(i.material_index is not None for i in inputs):
        material = np.zeros(len(simplices), dtype=np.int32)
        for k, i in enumerate(inputs):
            mine = to_target == bool(k)
            if i.material_index is not None:
                material[mine] = i.material_index[face[mine]]
        simplex_attributes["material_index"] = material
    metadata = dict(manifold.metadata)
    report = dict(metadata.get("validity") or {})
    report["surface_attributes"] = {"uv": carries_uv, "materials": "material_index" in simplex_attributes,
                                    "seam_vertices": int(len(copies) - np.unique(manifold.simplices).size),
                                    "target_simplices": int(to_target.sum())}
    report["stage_seconds"] = list(report.get("stage_seconds", [])) + [["surface attributes",
                                                                        time.perf_counter() - start]]
    metadata["validity"] = report
    return AnimationManifold.from_arrays(points[copies], simplices, vertex_attributes, simplex_attributes, metadata,
                                         manifold.hole_space)


def check_surface_attributes(name: str, mesh: tuple[np.ndarray, np.ndarray],
                             attributes: SurfaceAttributes | None) -> None:
    """Raises ValueError naming the input (`name`) and face when `attributes` do not fit `mesh`."""
    _checked_input(name, mesh, attributes)


def _checked_input(name: str, mesh: tuple[np.ndarray, np.ndarray], attributes: SurfaceAttributes | None) -> _Input:
    vertices = np.ascontiguousarray(mesh[0], dtype=np.float64)
    faces = np.ascontiguousarray(mesh[1], dtype=np.int32)
    attributes = attributes or SurfaceAttributes()
    uv = material = None
    if attributes.uv is not None:
        uv = np.asarray(attributes.uv, dtype=np.float64)
        if uv.shape != (len(faces), 3, 2):
            raise InputError(f"the {name}'s UV map must be (faces, 3, 2) = ({len(faces)}, 3, 2), got {uv.shape}")
        bad = ~np.isfinite(uv).all(axis=(1, 2))
        if bad.any():
            raise InputError(f"the {name}'s UV map holds NaN or infinity at face {int(np.argmax(bad))}")
    if attributes.material_index is not None:
        given = np.asarray(attributes.material_index)
        if given.shape != (len(faces),):
            raise InputError(f"the {name}'s material indices must be (faces,) = ({len(faces)},), got {given.shape}")
        if given.size and not np.issubdtype(given.dtype, np.integer):
            raise InputError(f"the {name}'s material indices must be integers, got {given.dtype}")
        bad = (given < 0) | (given > _MATERIAL_LIMIT)
        if bad.any():
            f = int(np.argmax(bad))
            raise InputError(f"the {name}'s face {f} has material index {int(given[f])}, outside 0..{_MATERIAL_LIMIT}")
        material = given.astype(np.int32)
    return _Input(name, vertices, faces, uv, material)


def _simplex_inputs(times: np.ndarray, simplices: np.ndarray, inputs: list[_Input], t0: float,
                    t1: float) -> np.ndarray:
    """Whether each simplex belongs to the target (see the module doc)."""
    source, target = inputs
    # Each term is the vertex's, so it is computed once per vertex and gathered per simplex.
    tau = np.clip((times - t0) / (t1 - t0), 0.0, 1.0) if t1 > t0 else np.zeros(times.shape)
    closer = (tau * source.distance - (1 - tau) * target.distance)[simplices].sum(axis=1)
    to_target = (closer > 0) | ((closer == 0) & (tau[simplices].mean(axis=1) >= 0.5))
    tolerance = 1e-12 * max(abs(t1 - t0), 1.0)
    to_target[(np.abs(times - t0) <= tolerance)[simplices].sum(axis=1) >= 3] = False
    to_target[(np.abs(times - t1) <= tolerance)[simplices].sum(axis=1) >= 3] = True
    return to_target


def _simplex_faces(points: np.ndarray, simplices: np.ndarray, inputs: list[_Input], to_target: np.ndarray,
                   ends: tuple[float, float], on_surface: float) -> np.ndarray:
    """The face of its input each simplex takes its look from (see the module doc): under the centre
    of its facet on its input's end, else under the centre of its corners on the input when three or
    more are, else the face closest to its corner nearest the input."""
    face = np.empty(len(simplices), dtype=np.int64)
    tolerance = 1e-12 * max(abs(ends[1] - ends[0]), 1.0)
    for k, i in enumerate(inputs):
        mine = np.flatnonzero(to_target == bool(k))
        corners = simplices[mine]
        distance = i.distance[corners]
        face[mine] = i.face[corners[np.arange(len(mine)), np.argmin(distance, axis=1)]]
        on = distance <= on_surface
        at_end = (np.abs(points[:, 3] - ends[k]) <= tolerance)[corners]  # per vertex, then per corner
        on = np.where((at_end.sum(axis=1) >= 3)[:, None], at_end, on)
        lying = np.flatnonzero(on.sum(axis=1) >= 3)
        if len(lying):
            weight = on[lying][:, :, None]
            centres = (points[corners[lying], :3] * weight).sum(axis=1) / weight.sum(axis=1)
            face[mine[lying]] = _core.closest_points(np.ascontiguousarray(centres), i.vertices, i.faces)[1]
    return face


def _split_and_map_uv(points: np.ndarray, simplices: np.ndarray, inputs: list[_Input], to_target: np.ndarray,
                      face: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices split per chart of their simplices, and each copy's UV (see the module doc):
    (simplices over the copies, the vertex each copy is of, (copies, 2) UVs)."""
    # The distinct (vertex, face) pairs the corners use; the target's faces numbered after the source's.
    source_faces = len(inputs[0].faces)
    global_face = (face + np.where(to_target, source_faces, 0)).astype(np.int32)
    vertex, global_face, corner_pair = _core.vertex_face_pairs(simplices, global_face, len(points))
    vertex, global_face = vertex.astype(np.int64), global_face.astype(np.int64)
    of_target = global_face >= source_faces
    own_face = global_face - np.where(of_target, source_faces, 0)
    chart_uv, inside_uv, distance = (np.zeros((len(vertex), 2)), np.zeros((len(vertex), 2)),
                                     np.zeros(len(vertex)))
    same, tolerance = np.zeros(2), np.zeros(len(vertex))
    for k, i in enumerate(inputs):
        mine = np.flatnonzero(of_target == bool(k))
        if i.uv is None or not len(mine):
            continue
        uv_extent = float(np.linalg.norm(np.ptp(i.uv.reshape(-1, 2), axis=0)))
        same[k] = _SAME_UV * uv_extent
        per_length = uv_extent / max(float(np.linalg.norm(np.ptp(i.vertices, axis=0))), 1e-300)
        tolerance[mine] = same[k] + _SAME_UV_OFF_SURFACE * per_length * i.distance[vertex[mine]]
        corners, uvs = i.vertices[i.faces[own_face[mine]]], i.uv[own_face[mine]]
        p = points[vertex[mine], :3]
        chart_uv[mine] = np.einsum("ij,ijk->ik", plane_barycentric(p[:, None], corners)[:, 0], uvs)
        inside, distance[mine] = closest_in_triangles(p, corners)
        inside_uv[mine] = np.einsum("ij,ijk->ik", inside, uvs)
    chart = _charts(vertex, of_target, chart_uv, tolerance)
    # One copy per (vertex, chart): the copy's UV where the vertex's closest point agrees with it.
    copy_of_pair = chart
    uv = np.zeros((int(chart.max()) + 1 if len(chart) else 0, 2))
    first = np.unique(chart, return_index=True)[1]
    copy_vertex, copy_target = vertex[first], of_target[first]
    for k, i in enumerate(inputs):
        mine = np.flatnonzero(copy_target == bool(k))
        if i.uv is None or not len(mine):
            continue
        v = copy_vertex[mine]
        row, candidate = _uv_candidates(i, v)
        off_chart = np.abs(candidate - chart_uv[first[mine]][row]).max(axis=1)
        order = np.lexsort((off_chart, row))
        best = order[np.r_[True, row[order][1:] != row[order][:-1]]]  # per copy, in the order of `mine`
        agrees = off_chart[best] <= tolerance[first[mine]]
        uv[mine[agrees]] = candidate[best][agrees]
        uv[mine[~agrees]] = _nearest_own_uv(copy_of_pair, distance, inside_uv, mine[~agrees])
    simplices = copy_of_pair[corner_pair].reshape(simplices.shape).astype(np.int32)
    return simplices, copy_vertex, uv


def _uv_candidates(i: _Input, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The UVs of the closest points of the vertices `v` in every face of input `i` that holds the
    point: its face when inside one, both faces of an edge, every face around a corner (one UV per
    side of a seam there). Returns (the row of `v` each candidate is for, ascending; (c, 2) UVs)."""
    barycentric, face = i.barycentric[v], i.face[v]
    corners = i.faces[face]
    at_corner = barycentric.max(axis=1) >= 1 - 1e-12
    on_edge = ~at_corner & (barycentric.min(axis=1) <= 1e-12)
    rows, uvs = [], []
    inside = np.flatnonzero(~at_corner & ~on_edge)
    rows.append(inside)
    uvs.append(np.einsum("ij,ijk->ik", barycentric[inside], i.uv[face[inside]]))
    # Around a corner: every face corner that is the input vertex, from the vertex -> corners table.
    r = np.flatnonzero(at_corner)
    c = corners[r, np.argmax(barycentric[r], axis=1)]
    flat = i.faces.reshape(-1)
    by_vertex = np.argsort(flat, kind="stable")
    count = np.bincount(flat, minlength=len(i.vertices))
    start = np.cumsum(count) - count
    each = count[c]
    offset = np.arange(int(each.sum())) - np.repeat(np.cumsum(each) - each, each)
    entry = by_vertex[np.repeat(start[c], each) + offset]
    rows.append(np.repeat(r, each))
    uvs.append(i.uv[entry // 3, entry % 3])
    # On an edge: its two faces, each with its own UVs at the edge's ends.
    r = np.flatnonzero(on_edge)
    zero = np.argmin(barycentric[r], axis=1)
    a_slot, b_slot = (zero + 1) % 3, (zero + 2) % 3
    a, b = corners[r, a_slot], corners[r, b_slot]
    wa, wb = barycentric[r, a_slot], barycentric[r, b_slot]
    for neighbour in (face[r], _face_across(i.faces, face[r], a, b)):
        slot_a = np.argmax(i.faces[neighbour] == a[:, None], axis=1)
        slot_b = np.argmax(i.faces[neighbour] == b[:, None], axis=1)
        rows.append(r)
        uvs.append(wa[:, None] * i.uv[neighbour, slot_a] + wb[:, None] * i.uv[neighbour, slot_b])
    row, uv = np.concatenate(rows), np.concatenate(uvs)
    order = np.argsort(row, kind="stable")
    return row[order], uv[order]


def _face_across(faces: np.ndarray, face: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The other face of each edge (a, b) of `face` (a closed manifold mesh has exactly two)."""
    corner = np.arange(3)
    lo = np.minimum(faces[:, corner], faces[:, (corner + 1) % 3]).reshape(-1).astype(np.int64)
    hi = np.maximum(faces[:, corner], faces[:, (corner + 1) % 3]).reshape(-1).astype(np.int64)
    key = lo * (int(faces.max()) + 1) + hi
    order = np.argsort(key, kind="stable")
    wanted = np.minimum(a, b).astype(np.int64) * (int(faces.max()) + 1) + np.maximum(a, b)
    first = np.searchsorted(key[order], wanted)
    owners = np.stack([order[first] // 3, order[np.minimum(first + 1, len(order) - 1)] // 3], axis=1)
    return np.where(owners[:, 0] == face, owners[:, 1], owners[:, 0])


def _charts(vertex: np.ndarray, of_target: np.ndarray, chart_uv: np.ndarray, tolerance: np.ndarray) -> np.ndarray:
    """Numbers the (vertex, face) pairs so that pairs of one vertex and one input whose chart UVs
    agree (to `tolerance`, per pair) share a number: neighbours in the order of u, then of v, are
    joined where both coordinates agree (_core.chart_labels). The numbers run over 0..charts-1, in
    vertex order."""
    return _core.chart_labels(vertex * 2 + of_target, np.ascontiguousarray(chart_uv), tolerance).astype(np.int64)


def _nearest_own_uv(copy_of_pair: np.ndarray, distance: np.ndarray, inside_uv: np.ndarray,
                    copies: np.ndarray) -> np.ndarray:
    """For `copies` (ascending): the UV of the vertex's closest point in the nearest of the faces its
    pairs (its simplices' own faces) hold."""
    if not len(copies):
        return np.zeros((0, 2))
    wanted = np.zeros(int(copy_of_pair.max()) + 1, dtype=bool)
    wanted[copies] = True
    pairs = np.flatnonzero(wanted[copy_of_pair])
    order = pairs[np.lexsort((distance[pairs], copy_of_pair[pairs]))]
    nearest = order[np.r_[True, copy_of_pair[order][1:] != copy_of_pair[order][:-1]]]
    return inside_uv[nearest]
