"""Reading mesh objects: the evaluated mesh as closed triangles (the input of a morph or a
skeleton) with, for the morph, its look (UV map per corner, material per triangle) and where
it sits in the world; and a mesh as it is, with its vertex groups and selected faces (the
input of Laplacian deformation)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import sampling
from ._lib import am


def closed_triangle_mesh(context, obj) -> tuple[np.ndarray, np.ndarray]:
    """The evaluated mesh of `obj` as (vertices (k, 3), triangles (l, 3)) in local space, unused vertices dropped."""
    vertices, faces, _ = _evaluated_triangles(context, obj)
    return vertices, faces


def _evaluated_triangles(context, obj) -> tuple[np.ndarray, np.ndarray, sampling.MeshSample]:
    depsgraph = context.evaluated_depsgraph_get()
    ob_eval = obj.evaluated_get(depsgraph)
    mesh = ob_eval.to_mesh()
    try:
        sample = sampling.read_mesh(mesh, ob_eval.matrix_world, triangulate=True)
    finally:
        ob_eval.to_mesh_clear()
    if sample.tri_vertices is None or len(sample.tri_vertices) == 0:
        raise ValueError(f"'{obj.name}' has no faces")
    used, faces = np.unique(sample.tri_vertices, return_inverse=True)
    return sample.positions[used], faces.reshape(-1, 3).astype(np.int32), sample


def world_mesh(context, obj) -> tuple[np.ndarray, np.ndarray]:
    """The evaluated mesh of `obj` in world space (mirroring transforms turn its faces back outward)."""
    return morph_input(context, obj).mesh


@dataclass
class MorphInput:
    """A mesh object as a morph input: world-space mesh, its look, and its materials."""

    mesh: tuple[np.ndarray, np.ndarray]  # vertices (k, 3) world space, triangles (l, 3)
    uv: np.ndarray | None  # (l, 3, 2) the active UV map per triangle corner
    uv_name: str | None
    material_index: np.ndarray  # (l,) into `materials`
    materials: list  # the object's material slots' materials (None for an empty slot)


def morph_input(context, obj) -> MorphInput:
    vertices, faces, sample = _evaluated_triangles(context, obj)
    m = np.array(obj.matrix_world, dtype=np.float64)
    world = vertices @ m[:3, :3].T + m[:3, 3]
    corners = [0, 1, 2]
    if np.linalg.det(m[:3, :3]) < 0:  # a mirroring transform turns the faces inside out
        corners = [1, 0, 2]
    uv = None if sample.loop_uv is None else sample.loop_uv.astype(np.float64)[sample.tri_loops][:, corners]
    return MorphInput((world, np.ascontiguousarray(faces[:, corners], dtype=np.int32)), uv, sample.uv_name,
                      sample.material_index.astype(np.int32), [slot.material for slot in obj.material_slots])


def morph_looks(source: MorphInput, target: MorphInput) -> tuple[list, str | None, "am.SurfaceAttributes | None",
                                                                  "am.SurfaceAttributes | None"]:
    """The morph's material slots (the source's, then the target's that the source does not have),
    its UV map's name (the source's, else the target's) and the two inputs' SurfaceAttributes with
    material indices into those slots; (slots, None, None, None) when neither input has a UV map
    or a material."""
    if source.uv is None and target.uv is None and not source.materials and not target.materials:
        return [], None, None, None
    slots = list(source.materials) or [None]  # a source without materials keeps showing none
    remap = []
    for material in target.materials or [None]:
        if material not in slots:
            slots.append(material)
        remap.append(slots.index(material))
    remap = np.asarray(remap, dtype=np.int32)

    def in_slots(index: np.ndarray, count: int) -> np.ndarray:
        return np.clip(index, 0, max(count - 1, 0))  # Blender keeps indices past the last slot

    source_look = am.SurfaceAttributes(source.uv, in_slots(source.material_index, len(source.materials)))
    target_look = am.SurfaceAttributes(target.uv, remap[in_slots(target.material_index, len(remap))])
    return slots, source.uv_name or target.uv_name, source_look, target_look


def mesh_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (N, 3) local, triangles (T, 3)) of a mesh as it is (not evaluated)."""
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    mesh.calc_loop_triangles()
    tri = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tri)
    return co.reshape(-1, 3).astype(np.float64), tri.reshape(-1, 3)


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
    """Indices of the mesh's selected faces."""
    flags = np.zeros(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("select", flags)
    return np.flatnonzero(flags)
