"""Writing triangles into a Blender mesh in place (no new data blocks while scrubbing),
through numpy and foreach_set, with the shims the supported Blender versions need.

Blender 4.0+ keeps positions, corner vertices, material indices, sharp faces and UV
maps as generic attributes with raw (memcpy) foreach access, ~10x faster than the
MeshVertex/MeshLoop/MeshPolygon RNA paths, which convert item by item; older
versions take those RNA paths.
"""

from __future__ import annotations

import bpy
import numpy as np

from . import extra_layers
from ._lib import am

_NEEDS_LOOP_TOTAL = bpy.app.version < (3, 6, 0)
_NEEDS_AUTO_SMOOTH = bpy.app.version < (4, 1, 0)
_ATTRIBUTES = bpy.app.version >= (4, 0, 0)
# 4.5+ keeps "free" custom normals as a float vector attribute, exactly as given; before,
# they are encoded against the computed normals (an error up to ~1e-3).
_FREE_NORMALS = bpy.app.version >= (4, 5, 0)
FREE_NORMALS_NAME = "custom_normal"


def write_mesh(mesh, vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray | None = None,
               uv_name: str = "UVMap", material_index: np.ndarray | None = None,
               smooth: np.ndarray | None = None, normals: np.ndarray | None = None,
               edges: tuple | None = None, vectors: dict | None = None,
               corner_uv: np.ndarray | None = None, extra: dict | None = None, owner=None) -> bool:
    """Replaces the geometry of `mesh` by triangles (in place, no new data blocks).
    True when the mesh held these triangles already (holds_triangles) and `owner`, the
    object showing it, is given: then only its layers are written, its edges stay as
    they were, and the owner's vertex groups go as a new geometry would drop them.
    `normals` (P, 3): smooth normals set as custom normals (slices between
    keyframes have thin triangles that shade unevenly with computed normals).
    `edges`: (edge vertices (2E,), corner edges (3F,)) that Blender computed for
    these faces before (mesh_edges), set instead of computing them again.
    `vectors`: name -> (P, 3) float32 point attributes (float vectors) to add (4.0+).
    `corner_uv` (2 * 3F,) float32: the UV map per corner, instead of `uv` per vertex.
    `extra`: a slice's vertex attributes, whose extra_layers (other UV maps, colours) are written."""
    P, F = len(vertices), len(faces)
    corner_vertex = np.ascontiguousarray(faces, dtype=np.int32).reshape(-1)
    if owner is not None and not extra and holds_triangles(mesh, P, corner_vertex):
        if owner.vertex_groups:  # painted on the frame shown before (clear_geometry drops them too)
            owner.vertex_groups.clear()
        _rewrite_in_place(mesh, vertices, corner_vertex, uv, uv_name, material_index, smooth, normals, vectors,
                          corner_uv)
        return True
    mesh.clear_geometry()
    mesh.vertices.add(P)
    mesh.loops.add(3 * F)
    mesh.polygons.add(F)
    co = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1)
    # loop_start is unsigned in 4.0+: an unsigned array is copied raw, where a signed
    # one takes the per-item path.
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * F, 3, dtype=np.uint32 if _ATTRIBUTES else np.int32))
    if _ATTRIBUTES:
        attributes = mesh.attributes
        attributes["position"].data.foreach_set("vector", co)
        attributes[".corner_vert"].data.foreach_set("value", corner_vertex)
        if material_index is not None and F:
            attributes.new("material_index", "INT", "FACE").data.foreach_set(
                "value", np.ascontiguousarray(material_index, dtype=np.int32))
        if smooth is not None and F:
            attributes.new("sharp_face", "BOOLEAN", "FACE").data.foreach_set(
                "value", np.ascontiguousarray(smooth, dtype=np.int32) == 0)
        if uv is not None and corner_uv is None:
            corner_uv = am.interval_cuts.corner_values(uv, corner_vertex)
        if corner_uv is not None:
            attributes.new(uv_name or "UVMap", "FLOAT2", "CORNER").data.foreach_set("vector", corner_uv)
        for name, values in (vectors or {}).items():
            attributes.new(name, "FLOAT_VECTOR", "POINT").data.foreach_set(
                "vector", np.ascontiguousarray(values, dtype=np.float32).reshape(-1))
        if edges is not None and F:
            edge_verts, corner_edge = edges
            mesh.edges.add(len(edge_verts) // 2)
            attributes[".edge_verts"].data.foreach_set("value", edge_verts)
            attributes[".corner_edge"].data.foreach_set("value", corner_edge)
    else:
        mesh.vertices.foreach_set("co", co)
        mesh.loops.foreach_set("vertex_index", corner_vertex)
        if _NEEDS_LOOP_TOTAL:
            mesh.polygons.foreach_set("loop_total", np.full(F, 3, dtype=np.int32))
        if material_index is not None and F:
            mesh.polygons.foreach_set("material_index", np.ascontiguousarray(material_index, dtype=np.int32))
        if smooth is not None and F:
            mesh.polygons.foreach_set("use_smooth", np.ascontiguousarray(smooth, dtype=bool))
        if uv is not None:
            layer = mesh.uv_layers.new(name=uv_name or "UVMap")
            if layer is not None and F:
                corner = np.ascontiguousarray(uv, dtype=np.float32)[corner_vertex]
                layer.data.foreach_set("uv", corner.reshape(-1))
    if extra and F:
        extra_layers.write(mesh, extra, corner_vertex)
    # With edges given (4.0+), the mesh has them: only tag it.
    mesh.update(calc_edges=not (_ATTRIBUTES and edges is not None))
    if normals is not None and F:
        if _NEEDS_AUTO_SMOOTH:
            mesh.use_auto_smooth = True
        set_vertex_normals(mesh, normals)
    return False


def holds_triangles(mesh, vertex_count: int, corner_vertex: np.ndarray) -> bool:
    """Whether `mesh` already holds exactly these triangles over `vertex_count` vertices
    (a frame of an animation that keeps its faces: a prism frame, a key of it). Only
    where write_mesh can then leave the topology alone: 4.5+, whose custom normals are
    a plain attribute (before, they live in a layer only clear_geometry resets)."""
    F = len(corner_vertex) // 3
    if not (_FREE_NORMALS and F and len(mesh.vertices) == vertex_count and len(mesh.polygons) == F
            and len(mesh.loops) == 3 * F and ".corner_vert" in mesh.attributes.keys()):
        return False
    held = np.empty(3 * F, dtype=np.int32)
    mesh.attributes[".corner_vert"].data.foreach_get("value", held)
    return np.array_equal(held, corner_vertex)


def _rewrite_in_place(mesh, vertices, corner_vertex, uv, uv_name, material_index, smooth, normals, vectors,
                      corner_uv) -> None:
    """write_mesh on a mesh that holds its triangles (holds_triangles): every layer
    write_mesh sets is written into the mesh's own, the others it would not make are
    removed, and the faces, edges and Blender's caches of them stay (no edge hash, no
    topology rebuild: the cost of a new interval's first frame during playback)."""
    F = len(corner_vertex) // 3
    layers = {"position": ("FLOAT_VECTOR", "POINT", "vector", np.ascontiguousarray(vertices, dtype=np.float32))}
    if material_index is not None:
        layers["material_index"] = ("INT", "FACE", "value", np.ascontiguousarray(material_index, dtype=np.int32))
    if smooth is not None:
        layers["sharp_face"] = ("BOOLEAN", "FACE", "value", np.ascontiguousarray(smooth, dtype=np.int32) == 0)
    if uv is not None and corner_uv is None:
        corner_uv = am.interval_cuts.corner_values(uv, corner_vertex)
    if corner_uv is not None:
        layers[uv_name or "UVMap"] = ("FLOAT2", "CORNER", "vector", corner_uv)
    for name, values in (vectors or {}).items():
        layers[name] = ("FLOAT_VECTOR", "POINT", "vector", np.ascontiguousarray(values, dtype=np.float32))
    if normals is not None:
        layers[FREE_NORMALS_NAME] = None  # set_vertex_normals writes it
    attributes = mesh.attributes
    for name in [n for n in attributes.keys() if not n.startswith(".") and n not in layers]:
        attributes.remove(attributes[name])
    for name, layer in layers.items():
        if layer is None:
            continue
        data_type, domain, key, values = layer
        target = attributes.get(name)
        if target is not None and (target.data_type != data_type or target.domain != domain):
            attributes.remove(target)
            target = None
        if target is None:
            target = attributes.new(name, data_type, domain)
        target.data.foreach_set(key, values.reshape(-1))
    mesh.update()
    tag_positions_changed(mesh)
    if normals is not None and F:
        set_vertex_normals(mesh, normals)


def set_vertex_normals(mesh, normals: np.ndarray) -> None:
    """Custom normals per vertex (P, 3), unit length; the live modifier's are set the
    same way (Set Mesh Normal, free, on points), so live frames shade as baked ones."""
    values = np.ascontiguousarray(normals, dtype=np.float32)
    if not _FREE_NORMALS:
        mesh.normals_split_custom_set_from_vertices(values)
        return
    layer = mesh.attributes.get(FREE_NORMALS_NAME)
    if layer is None or layer.domain != "POINT" or layer.data_type != "FLOAT_VECTOR":
        if layer is not None:
            mesh.attributes.remove(layer)
        layer = mesh.attributes.new(FREE_NORMALS_NAME, "FLOAT_VECTOR", "POINT")
    layer.data.foreach_set("vector", values.reshape(-1))
    mesh.update()


def mesh_edges(mesh) -> tuple[np.ndarray, np.ndarray] | None:
    """The edges Blender computed for `mesh` (for write_mesh's `edges`); None before 4.0."""
    if not _ATTRIBUTES:
        return None
    edge_verts = np.empty(2 * len(mesh.edges), dtype=np.int32)
    corner_edge = np.empty(len(mesh.loops), dtype=np.int32)
    if len(edge_verts):
        mesh.attributes[".edge_verts"].data.foreach_get("value", edge_verts)
    if len(corner_edge):
        mesh.attributes[".corner_edge"].data.foreach_get("value", corner_edge)
    return edge_verts, corner_edge


def write_positions(mesh, vertices: np.ndarray, corner_vertex: np.ndarray, uv: np.ndarray | None = None,
                    uv_name: str = "UVMap", normals: np.ndarray | None = None, extra: dict | None = None) -> None:
    """Moves the vertices of a mesh that write_mesh filled (same vertices and
    faces): positions, the UV maps, colours (`extra`: see write_mesh) and custom normals only."""
    co = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1)
    if _ATTRIBUTES:
        mesh.attributes["position"].data.foreach_set("vector", co)
    else:
        mesh.vertices.foreach_set("co", co)
    if uv is not None and len(corner_vertex):
        corner = am.interval_cuts.corner_values(uv, corner_vertex)
        if _ATTRIBUTES and uv_name in mesh.attributes:
            mesh.attributes[uv_name].data.foreach_set("vector", corner)
        elif uv_name in mesh.uv_layers:
            mesh.uv_layers[uv_name].data.foreach_set("uv", corner)
    if extra and len(corner_vertex):
        extra_layers.write(mesh, extra, corner_vertex, create=False)
    mesh.update()
    tag_positions_changed(mesh)  # bounds too
    if normals is not None and len(corner_vertex):
        set_vertex_normals(mesh, normals)


def write_frame(mesh, uv_name: str, frame: am.interval_cuts.Frame) -> bool:
    """Copies a frame's positions and UV map into a mesh holding its cut (one raw copy
    each, after Blender unshares each buffer from the evaluated mesh). False, and
    nothing written, if the mesh's sizes or UV map do not match (Blender 4.0+)."""
    # The UV map through uv_layers: mesh.attributes[name] looks the layer up for
    # writing, which after each evaluation costs about a hundred times uv_layers'
    # lookup and a good part of a frame's copy.
    layer = mesh.uv_layers.get(uv_name) if frame.corner_uv is not None else None
    if (3 * len(mesh.vertices) != len(frame.positions)
            or (frame.corner_uv is not None and (layer is None or 2 * len(mesh.loops) != len(frame.corner_uv)))):
        return False
    # Through the position attribute: mesh.vertices.foreach_set("co") is no raw copy
    # (it sets the vertices one by one through RNA).
    mesh.attributes["position"].data.foreach_set("vector", frame.positions)
    if layer is not None:
        layer.uv.foreach_set("vector", frame.corner_uv)
    tag_positions_changed(mesh)
    return True


def tag_positions_changed(mesh) -> None:
    """After foreach_set of a mesh's positions: its normals, bounds and BVH are stale
    and the depsgraph must copy it again. mesh.update() marks only the normals (in 4.5
    the evaluated object keeps its old bounding box); setting one vertex's
    co through RNA runs Blender's positions-changed tag and tags the depsgraph."""
    if len(mesh.vertices):
        vertex = mesh.vertices[0]
        vertex.co = vertex.co
    mesh.update_tag()


def write_points(mesh, points: np.ndarray) -> None:
    """Moves the vertices of `mesh` to `points` (N, 3), its faces kept."""
    mesh.vertices.foreach_set("co", np.ascontiguousarray(points, dtype=np.float32).reshape(-1))
    mesh.update()
