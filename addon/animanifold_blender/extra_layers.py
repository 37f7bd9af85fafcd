"""The source's UV maps beyond the active one, and its colour attributes, carried through
a manifold as vertex attributes.

The active UV map travels as the vertex attribute "uv" (its name kept in the object's
settings). Every other UV map travels as "uv:<map name>", every colour attribute as
"color:<name>" (point domain) or "corner_color:<name>" (face-corner domain), byte or float
colour alike (read as linear floats, written back as float colours: in-between frames
blend them). Sampling reads them per corner, so the seam split covers every map; a slice
vertex then carries one value of each, written back per corner (UV maps, corner colours)
or per point.
"""

from __future__ import annotations

import numpy as np

UV_PREFIX = "uv:"
POINT_COLOR_PREFIX = "color:"
CORNER_COLOR_PREFIX = "corner_color:"
_PREFIXES = (UV_PREFIX, POINT_COLOR_PREFIX, CORNER_COLOR_PREFIX)


def read_corner_layers(mesh, loop_vertex: np.ndarray) -> dict[str, np.ndarray]:
    """name -> (L, c) float32 per corner: the UV maps other than the active one, and the
    colour attributes (point-domain colours spread to their corners)."""
    layers: dict[str, np.ndarray] = {}
    L = len(loop_vertex)
    active = mesh.uv_layers.active
    for layer in mesh.uv_layers:
        if active is not None and layer.name == active.name:
            continue
        values = np.empty(2 * L, dtype=np.float32)
        layer.data.foreach_get("uv", values)
        layers[UV_PREFIX + layer.name] = values.reshape(L, 2) + np.float32(0.0)  # -0.0 -> 0.0
    for attribute in mesh.color_attributes:
        if attribute.domain not in ("POINT", "CORNER"):
            continue
        values = np.empty(4 * len(attribute.data), dtype=np.float32)
        attribute.data.foreach_get("color", values)
        values = values.reshape(-1, 4) + np.float32(0.0)
        if attribute.domain == "POINT":
            layers[POINT_COLOR_PREFIX + attribute.name] = values[loop_vertex]
        else:
            layers[CORNER_COLOR_PREFIX + attribute.name] = values
    return layers


def carried(vertex_attributes) -> list[str]:
    """The names of the extra layers among a manifold's (or a slice's) vertex attributes."""
    return sorted(name for name in vertex_attributes.keys() if name.startswith(_PREFIXES))


def _corner_values(values: np.ndarray, corner_vertex: np.ndarray, width: int) -> np.ndarray:
    table = np.ascontiguousarray(np.asarray(values)[:, :width], dtype=np.float32)
    return np.ascontiguousarray(table[corner_vertex]).reshape(-1)


def _target(mesh, name: str, create: bool):
    """The mesh layer a carried attribute is written to, and how (foreach key, width, domain)."""
    if name.startswith(UV_PREFIX):
        map_name = name[len(UV_PREFIX):]
        layer = mesh.uv_layers.get(map_name)
        if layer is None and create:
            # uv_layers.new makes a real UV map in every supported Blender (in 3.4 a
            # FLOAT2 corner attribute is not one).
            layer = mesh.uv_layers.new(name=map_name, do_init=False)
        return layer, "uv", 2, "CORNER"
    domain = "POINT" if name.startswith(POINT_COLOR_PREFIX) else "CORNER"
    attr_name = name.split(":", 1)[1]
    layer = mesh.attributes.get(attr_name)
    if layer is not None and (layer.domain != domain or layer.data_type != "FLOAT_COLOR"):
        if not create:
            return None, "color", 4, domain
        mesh.attributes.remove(layer)
        layer = None
    if layer is None and create:
        layer = mesh.attributes.new(attr_name, "FLOAT_COLOR", domain)
    return layer, "color", 4, domain


def write(mesh, vertex_attributes, corner_vertex: np.ndarray, create: bool = True) -> None:
    """Writes every carried layer of a slice (per-vertex values) into `mesh`, whose corners
    are `corner_vertex` (3F,). `create`: make the layers (a mesh write_mesh just filled),
    else only update the ones there (a mesh moved in place)."""
    corner_vertex = np.ascontiguousarray(corner_vertex, dtype=np.int32).reshape(-1)
    for name in carried(vertex_attributes):
        layer, key, width, domain = _target(mesh, name, create)
        if layer is None:
            continue
        values = np.asarray(vertex_attributes[name])
        if domain == "POINT":
            data = np.ascontiguousarray(values[:, :width], dtype=np.float32).reshape(-1)
        else:
            data = _corner_values(values, corner_vertex, width)
        if len(data) == width * len(layer.data):
            layer.data.foreach_set(key, data)


def metadata(vertex_attributes) -> dict:
    """What the cache's metadata says of the carried layers: UV map and colour names."""
    names = carried(vertex_attributes)
    return {
        "uv_maps": [n[len(UV_PREFIX):] for n in names if n.startswith(UV_PREFIX)],
        "color_attributes": [n.split(":", 1)[1] for n in names if not n.startswith(UV_PREFIX)],
    }
