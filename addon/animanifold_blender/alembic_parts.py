"""Alembic bakes whose materials and colours stay right when the topology changes.

Blender's Alembic exporter writes an object's face sets (its materials) at the first frame
only, and carries colours only as byte colours on face corners (8 bits, clamped to 0..1).
Our frames change topology, so:

* **one archive object per material.** At export, one temporary part object per used
  material slot shows the baked object's faces of that slot (Object Info → Delete Geometry →
  Set Material). A part has one material, so the face set written at its first frame stays
  right at every frame: faces the set does not list keep material 0, the only one. A plain
  Alembic import (or another application) gets one object per material, each rendering
  right.
* **colours as pairs of UV maps.** Every colour attribute also travels as two float UV maps,
  `<name>_rg` and `<name>_ba` (UV maps are written and read back per frame at full float
  precision), besides the byte colour `<name>` an import without the add-on shows.
* **the .blend joins them back.** With a Mesh Sequence Cache the manifold object reads the
  first part (on an empty mesh, INPUT_MODIFIER_NAME: a frame whose topology differs from the
  mesh below the cache is built on that mesh's attribute layout, so the object's own custom
  normals and colours would come back at their defaults: zero normals render black); a geometry-nodes modifier (PARTS_MODIFIER_NAME) joins the other parts (helper
  objects outside the scene, each reading its part through its own Mesh Sequence Cache),
  sets each part's material and rebuilds every colour attribute, exactly, in its domain.
  It is plain Blender data: the .blend plays and renders without the add-on.
"""

from __future__ import annotations

import bpy
import numpy as np

from . import extra_layers

PARTS_MODIFIER_NAME = "Animanifold Alembic Parts"
INPUT_MODIFIER_NAME = "Animanifold Alembic Input"
RG, BA = "_rg", "_ba"
# Blender's Alembic reader reads at most 8 UV maps per object (MAX_MTFACE); colours beyond
# those travel as byte colours only.
MAX_UV_MAPS = 8




def archive_name(name: str) -> str:
    """A name as Blender's Alembic exporter writes it (spaces, dots and colons become _)."""
    return name.replace(" ", "_").replace(".", "_").replace(":", "_")


def colour_layers(manifold) -> list[tuple[str, str]]:
    """(name, domain) of the colour attributes a manifold carries, as frames show them."""
    out = []
    for name in extra_layers.carried(manifold.vertex_attributes):
        if name.startswith(extra_layers.POINT_COLOR_PREFIX):
            out.append((name[len(extra_layers.POINT_COLOR_PREFIX):], "POINT"))
        elif name.startswith(extra_layers.CORNER_COLOR_PREFIX):
            out.append((name[len(extra_layers.CORNER_COLOR_PREFIX):], "CORNER"))
    return out


def exact_colours(manifold) -> list[tuple[str, str]]:
    """The colour layers that fit beside the UV maps within the reader's UV map limit."""
    uv_maps = 1 + sum(name.startswith(extra_layers.UV_PREFIX) for name in manifold.vertex_attributes.keys())
    room = max(0, (MAX_UV_MAPS - uv_maps) // 2)
    return colour_layers(manifold)[:room]


def used_slots(obj) -> list[int]:
    """The material slots the baked frames (the frame objects of the bake collection) use,
    indices past the last slot counted as the last (as Blender draws them)."""
    count = len(obj.data.materials)
    if count <= 1:
        return [0] if count else []
    collection = obj.animanifold.bake_collection
    if collection is None:
        return list(range(count))
    used = set()
    for frame_obj in collection.objects:
        me = frame_obj.data
        index = np.zeros(len(me.polygons), np.int32)
        if len(index):
            me.polygons.foreach_get("material_index", index)
        used.update(np.unique(np.clip(index, 0, count - 1)).tolist())
    return sorted(used)


# -- node building --------------------------------------------------------------------

def _new_group(name: str):
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    for in_out in ("INPUT", "OUTPUT"):
        if hasattr(group, "interface"):  # 4.0+
            group.interface.new_socket("Geometry", in_out=in_out, socket_type="NodeSocketGeometry")
        elif in_out == "INPUT":
            group.inputs.new("NodeSocketGeometry", "Geometry")
        else:
            group.outputs.new("NodeSocketGeometry", "Geometry")
    return group


class _Chain:
    """Geometry nodes strung one after the other from the group input to its output."""

    def __init__(self, group):
        self.group, self.nodes, self.links = group, group.nodes, group.links
        self.x = 0
        self.socket = self.add("NodeGroupInput").outputs[0]

    def add(self, kind: str, **settings):
        node = self.nodes.new(kind)
        node.location = (self.x, 0)
        self.x += 200
        for key, value in settings.items():
            setattr(node, key, value)
        return node

    def then(self, node, inputs: dict | None = None):
        """Feeds the chain's geometry into `node` (its first input) and continues from its output."""
        self.links.new(self.socket, node.inputs[0])
        for key, value in (inputs or {}).items():
            if isinstance(value, bpy.types.NodeSocket):
                self.links.new(value, node.inputs[key])
            else:
                node.inputs[key].default_value = value
        self.socket = node.outputs[0]
        return node

    def store(self, name: str, data_type: str, domain: str, value) -> None:
        self.then(self.add("GeometryNodeStoreNamedAttribute", data_type=data_type, domain=domain),
                  {"Name": name, "Value": value})

    def object_geometry(self, obj):
        info = self.add("GeometryNodeObjectInfo", transform_space="ORIGINAL")
        info.inputs["Object"].default_value = obj
        return info.outputs["Geometry"]

    def finish(self) -> None:
        self.links.new(self.socket, self.add("NodeGroupOutput").inputs[0])


def _only_slot(chain: _Chain, slot: int, count: int) -> None:
    """Deletes the faces of every other slot (indices past the last count as the last)."""
    index = chain.add("GeometryNodeInputMaterialIndex")
    clamp = chain.add("ShaderNodeMath", operation="MINIMUM")
    chain.links.new(index.outputs[0], clamp.inputs[0])
    clamp.inputs[1].default_value = float(count - 1)
    diff = chain.add("ShaderNodeMath", operation="SUBTRACT")
    chain.links.new(clamp.outputs[0], diff.inputs[0])
    diff.inputs[1].default_value = float(slot)
    absolute = chain.add("ShaderNodeMath", operation="ABSOLUTE")
    chain.links.new(diff.outputs[0], absolute.inputs[0])
    other = chain.add("ShaderNodeMath", operation="GREATER_THAN")
    chain.links.new(absolute.outputs[0], other.inputs[0])
    other.inputs[1].default_value = 0.5
    chain.then(chain.add("GeometryNodeDeleteGeometry", domain="FACE"), {"Selection": other.outputs[0]})


def _encode_colours(chain: _Chain, colours) -> None:
    """Each colour as two float UV maps (<name>_rg, <name>_ba), then as a byte corner colour."""
    for name, _ in colours:
        read = chain.add("GeometryNodeInputNamedAttribute", data_type="FLOAT_COLOR")
        read.inputs["Name"].default_value = name
        split = chain.add("FunctionNodeSeparateColor")
        chain.links.new(read.outputs["Attribute"], split.inputs[0])
        for suffix, (a, b) in ((RG, ("Red", "Green")), (BA, ("Blue", "Alpha"))):
            pair = chain.add("ShaderNodeCombineXYZ")
            chain.links.new(split.outputs[a], pair.inputs["X"])
            chain.links.new(split.outputs[b], pair.inputs["Y"])
            chain.store(name + suffix, "FLOAT2", "CORNER", pair.outputs[0])
        chain.store(name, "BYTE_COLOR", "CORNER", read.outputs["Attribute"])


def _decode_colours(chain: _Chain, colours) -> None:
    """Each colour rebuilt from its two UV maps, as a float colour in its own domain."""
    for name, domain in colours:
        halves = []
        for suffix in (RG, BA):
            read = chain.add("GeometryNodeInputNamedAttribute", data_type="FLOAT_VECTOR")
            read.inputs["Name"].default_value = archive_name(name) + suffix
            xyz = chain.add("ShaderNodeSeparateXYZ")
            chain.links.new(read.outputs["Attribute"], xyz.inputs[0])
            halves.append(xyz)
        colour = chain.add("FunctionNodeCombineColor")
        for socket, (half, axis) in zip(("Red", "Green", "Blue", "Alpha"),
                                        ((0, "X"), (0, "Y"), (1, "X"), (1, "Y"))):
            chain.links.new(halves[half].outputs[axis], colour.inputs[socket])
        # Where a frame's topology differs from the object's own mesh, the Mesh Sequence Cache
        # builds the frame on that mesh's attribute layout: a colour of the object's own
        # (e.g. a point colour) comes back at its default (white) beside the archive's byte
        # colour of the same name. Both go before the float colour is written.
        for _ in range(2):
            chain.then(chain.add("GeometryNodeRemoveAttribute"), {"Name": name})
        chain.store(name, "FLOAT_COLOR", domain, colour.outputs[0])
        written = archive_name(name)
        stale = [written + RG, written + BA]
        if written != name:  # else the float colour has replaced the archive's byte colour
            stale.append(written)
        for stale_name in stale:
            chain.then(chain.add("GeometryNodeRemoveAttribute"), {"Name": stale_name})


def _set_material(chain: _Chain, material) -> None:
    if material is not None:
        chain.then(chain.add("GeometryNodeSetMaterial"), {"Material": material})


# -- export ---------------------------------------------------------------------------

def make_export_parts(obj, manifold, collection) -> list:
    """One object per used material slot (or one for every face when there is one slot or
    none), its mesh holding that slot's material, in `collection`, each showing its faces of `obj` and carrying the colours (see the
    module); returns the ID blocks made (objects, meshes, node groups) for remove_ids."""
    slots = used_slots(obj)
    count = len(obj.data.materials)
    # With more than one slot every part holds one material, even when only one is used: a
    # Mesh Sequence Cache numbers the face sets it reads from 0, whatever the object's slots.
    split = count > 1
    colours = exact_colours(manifold)
    made = []
    for slot in (slots if split else [-1]):
        material = obj.data.materials[slot] if slot >= 0 else None
        suffix = (material.name if material is not None else f"slot{slot}") if split else "all"
        name = f"{obj.name}_{suffix}"
        mesh = bpy.data.meshes.new(name)
        made.append(mesh)
        part = bpy.data.objects.new(name, mesh)
        made.append(part)
        group = _new_group(f"{name}_alembic")
        made.append(group)
        chain = _Chain(group)
        chain.socket = chain.object_geometry(obj)
        if split:
            _only_slot(chain, slot, count)
            _set_material(chain, material)
        for m in ([material] if split else obj.data.materials):
            mesh.materials.append(m)
        _encode_colours(chain, colours)
        chain.finish()
        part.modifiers.new("Animanifold Alembic Part", "NODES").node_group = group
        part.matrix_world = obj.matrix_world.copy()
        collection.objects.link(part)
    return made


def part_objects(made) -> list:
    return [i for i in made if isinstance(i, bpy.types.Object)]


def remove_ids(ids) -> None:
    """Removes ID blocks made here that still exist (their users go with them)."""
    alive = []
    for id_block in ids:
        try:
            id_block.name
        except ReferenceError:  # removed already
            continue
        alive.append(id_block)
    if alive:
        bpy.data.batch_remove(alive)


# -- the .blend side --------------------------------------------------------------------

def _part_geometry(chain: _Chain, obj, material):
    """The geometry of a helper object, with its part's material set."""
    socket = chain.object_geometry(obj)
    if material is None:
        return socket
    node = chain.add("GeometryNodeSetMaterial")
    chain.links.new(socket, node.inputs["Geometry"])
    node.inputs["Material"].default_value = material
    return node.outputs[0]


def empty_input(obj, made: list):
    """The modifier (INPUT_MODIFIER_NAME) that gives the cache below it an empty mesh to read
    into, at the end of the stack (move it above the cache). Its node group goes to `made`."""
    group = _new_group(f"{obj.name}_alembic_input")
    made.append(group)
    group.nodes.new("NodeGroupInput")
    group.nodes.new("NodeGroupOutput")  # nothing linked: no geometry
    modifier = obj.modifiers.new(INPUT_MODIFIER_NAME, "NODES")
    modifier.node_group = group
    return modifier


def join_parts(obj, cache, parts: list[tuple[str, object]], colours, made: list):
    """The modifier (PARTS_MODIFIER_NAME) that follows the Mesh Sequence Cache reading the
    first part of `parts` ((archive path, material)) on `obj`: it joins the other parts, each
    read by a helper object outside the scene, sets every part's material and rebuilds the
    colours `colours` ((name, domain)). New ID blocks go to `made`."""
    group = _new_group(f"{obj.name}_alembic_parts")
    made.append(group)
    chain = _Chain(group)
    _set_material(chain, parts[0][1])
    if len(parts) > 1:
        join = chain.add("GeometryNodeJoinGeometry")
        chain.links.new(chain.socket, join.inputs[0])
        for path, material in parts[1:]:
            mesh = bpy.data.meshes.new(f"{obj.name}_alembic_part")
            helper = bpy.data.objects.new(mesh.name, mesh)
            made.extend([helper, mesh])
            reader = helper.modifiers.new("Mesh Sequence Cache", "MESH_SEQUENCE_CACHE")
            reader.cache_file = cache
            reader.object_path = path
            chain.links.new(_part_geometry(chain, helper, material), join.inputs[0])
        chain.socket = join.outputs[0]
    _decode_colours(chain, colours)
    chain.finish()
    modifier = obj.modifiers.new(PARTS_MODIFIER_NAME, "NODES")
    modifier.node_group = group
    return modifier


def helpers_of(group) -> list:
    """The helper objects (and their meshes) a parts node group reads, for removal with it."""
    found = []
    for node in group.nodes:
        if node.bl_idname == "GeometryNodeObjectInfo":
            helper = node.inputs["Object"].default_value
            if helper is not None and any(m.type == "MESH_SEQUENCE_CACHE" for m in helper.modifiers):
                found += [helper, helper.data]
    return found
