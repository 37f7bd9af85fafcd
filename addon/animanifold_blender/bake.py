"""Baking a manifold object's frames into data that needs no add-on.

* a collection with one mesh object per frame, shown by a geometry-nodes
  modifier (Collection Info → Delete Geometry on the instances whose index is
  not frame − start → Realize Instances): plays and renders in any Blender
  3.4+ (and on a farm) without animanifold;
* an Alembic cache through Blender's own exporter, optionally read back by a
  Mesh Sequence Cache modifier (Blender's native varying-topology cache);
* an OBJ/PLY sequence (one file per frame).

Every frame is sliced as live playback slices it (object_manifold.shown_manifold
and object_manifold.frame_slice): the object's Smooth settings (manifold subdivision, frame
smoothing) are baked.

Nothing here deletes the user's data: a re-bake builds the new data first and
only then removes the previous bake's collection, objects, meshes and node group.
"""

from __future__ import annotations

import os

import bpy
import numpy as np

from . import alembic_parts, bake_switch, live_nodes, mesh_writer
from ._lib import am
from .object_manifold import frame_slice, frame_slices, shown_manifold
from .reporting import ReportedError

MODIFIER_NAME = "Animanifold Bake"
CACHE_MODIFIER_NAME = "Animanifold Alembic"
# The node-group bake's modifier, then the Alembic bake's (alembic_parts: the cache's empty input,
# the cache, the join).
BAKE_MODIFIERS = (MODIFIER_NAME, alembic_parts.INPUT_MODIFIER_NAME, CACHE_MODIFIER_NAME,
                  alembic_parts.PARTS_MODIFIER_NAME)


class BakeError(ReportedError):
    """A bake that cannot be made (the message says why)."""


def frame_object_name(obj_name: str, frame: int) -> str:
    return f"{obj_name}_f{frame:06d}" if frame >= 0 else f"{obj_name}_fm{-frame:06d}"


def build_frames(obj, frames: list[int], collection_name: str, progress=None) -> bpy.types.Collection:
    """One mesh object per frame (the slice at that frame), in frame order, in a new
    collection that is not linked to any scene (the node group instances it)."""
    return am.core_job.Steps(build_frames_steps(obj, frames, collection_name, progress)).run()


def build_frames_steps(obj, frames: list[int], collection_name: str, progress=None):
    """build_frames as am.core_job.Steps, pausing after each frame; stopped there (closed), it
    removes what it made."""
    manifold = shown_manifold(obj)  # subdivided as the object's Smooth settings say
    settings = obj.animanifold
    smoothed = settings.smooth_levels > 0
    materials = list(obj.data.materials)
    collection = bpy.data.collections.new(collection_name)
    mesh = None
    try:
        for i, (frame, s) in enumerate(zip(frames, frame_slices(obj, manifold, [float(f) for f in frames], "t"))):
            name = frame_object_name(obj.name, frame)
            mesh = bpy.data.meshes.new(name)
            for mat in materials:
                mesh.materials.append(mat)
            mesh_writer.write_mesh(
                mesh, s.vertices, s.faces, uv=s.vertex_attributes.get("uv"), uv_name=settings.uv_name or "UVMap",
                material_index=s.face_attributes.get("material_index"), smooth=s.face_attributes.get("smooth"),
                normals=am.display.frame_normals(s, smoothed), extra=s.vertex_attributes,
            )
            frame_obj = bpy.data.objects.new(name, mesh)
            collection.objects.link(frame_obj)
            mesh = None
            if progress is not None:
                progress(i + 1)
            yield am.core_job.Pause("building frames")
    except BaseException:
        if mesh is not None:  # made, not yet in an object
            bpy.data.meshes.remove(mesh)
        remove_collection(collection)
        raise
    return collection


def remove_collection(collection) -> None:
    """Removes a bake collection with its frame objects and their meshes."""
    objects = list(collection.objects)
    meshes = [o.data for o in objects if o.type == "MESH"]
    for o in objects:
        bpy.data.objects.remove(o)
    for me in meshes:
        if me.users == 0:
            bpy.data.meshes.remove(me)
    bpy.data.collections.remove(collection)


def _new_socket(group, name, in_out):
    if hasattr(group, "interface"):  # 4.0+
        group.interface.new_socket(name, in_out=in_out, socket_type="NodeSocketGeometry")
    elif in_out == "INPUT":
        group.inputs.new("NodeSocketGeometry", name)
    else:
        group.outputs.new("NodeSocketGeometry", name)


def _math(nodes, operation, location):
    node = nodes.new("ShaderNodeMath")
    node.operation = operation
    node.location = location
    return node


def build_node_group(name: str, collection, first_frame: int, count: int) -> bpy.types.NodeTree:
    """Geometry nodes showing the instance of `collection` for the scene frame:
    child i is shown at frame first_frame + i (floor of the frame, so subframes
    hold the frame); before and after the baked range the first and last frame hold.
    Before Blender 3.5 the frame object's mesh is picked by bake_switch instead (Realize
    Instances there turns UV maps into plain attributes)."""
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    _new_socket(group, "Geometry", "INPUT")
    _new_socket(group, "Geometry", "OUTPUT")
    nodes, links = group.nodes, group.links
    group_in = nodes.new("NodeGroupInput")
    group_in.location = (-900, 200)
    group_out = nodes.new("NodeGroupOutput")
    group_out.location = (500, 0)

    info = nodes.new("GeometryNodeCollectionInfo")
    info.location = (-500, 150)
    info.transform_space = "ORIGINAL"
    info.inputs["Collection"].default_value = collection
    info.inputs["Separate Children"].default_value = True
    info.inputs["Reset Children"].default_value = True

    time = nodes.new("GeometryNodeInputSceneTime")
    time.location = (-900, -150)
    offset = _math(nodes, "SUBTRACT", (-700, -150))
    offset.inputs[1].default_value = float(first_frame)
    links.new(time.outputs["Frame"], offset.inputs[0])
    floor = _math(nodes, "FLOOR", (-550, -150))
    links.new(offset.outputs[0], floor.inputs[0])
    low = _math(nodes, "MAXIMUM", (-450, -150))
    links.new(floor.outputs[0], low.inputs[0])
    low.inputs[1].default_value = 0.0
    held = _math(nodes, "MINIMUM", (-350, -150))
    links.new(low.outputs[0], held.inputs[0])
    held.inputs[1].default_value = float(count - 1)
    if bake_switch.NEEDS_SWITCH:
        # The order Collection Info gives the modern path: its children by name.
        objects = sorted(collection.objects, key=lambda o: o.name)
        bake_switch.link_frames(group, held.outputs[0], objects, group_out.inputs[0])
        nodes.remove(info)
        return group
    index = nodes.new("GeometryNodeInputIndex")
    index.location = (-500, -300)
    diff = _math(nodes, "SUBTRACT", (-300, -200))
    links.new(index.outputs[0], diff.inputs[0])
    links.new(held.outputs[0], diff.inputs[1])
    absolute = _math(nodes, "ABSOLUTE", (-150, -200))
    links.new(diff.outputs[0], absolute.inputs[0])
    other = _math(nodes, "GREATER_THAN", (0, -200))
    links.new(absolute.outputs[0], other.inputs[0])
    other.inputs[1].default_value = 0.5

    delete = nodes.new("GeometryNodeDeleteGeometry")
    delete.location = (100, 100)
    delete.domain = "INSTANCE"
    links.new(info.outputs[0], delete.inputs["Geometry"])
    links.new(other.outputs[0], delete.inputs["Selection"])
    realize = nodes.new("GeometryNodeRealizeInstances")
    realize.location = (300, 100)
    links.new(delete.outputs[0], realize.inputs[0])
    links.new(realize.outputs[0], group_out.inputs[0])
    return group


class NodeGroupBake:
    """A node-group bake as a transaction: :meth:`apply` builds the frames and
    puts the new modifier in place of the old one; :meth:`commit` then deletes
    the previous bake, :meth:`rollback` restores it exactly (object mode,
    modifiers, collection, node group) and removes everything new."""

    def __init__(self, obj):
        self.obj = obj
        settings = obj.animanifold
        self.old_mode = settings.mode
        self.old_collection = settings.bake_collection
        self.old_modifiers = [(m.name, m.type, getattr(m, "node_group", None), getattr(m, "cache_file", None),
                               getattr(m, "object_path", None), m.show_viewport, m.show_render)
                              for m in obj.modifiers if m.name in BAKE_MODIFIERS]
        self.old_order = [m.name for m in obj.modifiers]
        self.collection = None
        self.group = None
        self.new_cache_files = []
        self.new_ids = []  # the Alembic parts' helper objects, meshes and node group
        self.replaced = False  # whether apply got to replace the old bake's modifiers

    def apply(self, frames: list[int], progress=None, collection=None):
        """`collection`: frame objects made elsewhere (a farm's chunks), one per frame in order."""
        am.core_job.Steps(self.apply_steps(frames, progress, collection)).run()

    def apply_steps(self, frames: list[int], progress=None, collection=None):
        """apply as am.core_job.Steps, pausing after each frame it builds (see rollback)."""
        obj = self.obj
        base = f"{obj.name}_bake"
        self.collection = collection or (yield from build_frames_steps(obj, frames, base + ".new", progress))
        self.group = build_node_group(base + ".new", self.collection, frames[0], len(frames))
        self.replaced = True
        for name in BAKE_MODIFIERS:
            mod = obj.modifiers.get(name)
            if mod is not None:
                obj.modifiers.remove(mod)
        modifier = obj.modifiers.new(MODIFIER_NAME, "NODES")
        modifier.node_group = self.group
        # The bake shows the frames: the live modifier below it passes its mesh through
        # instead of moving it every frame for nothing (Back to Live turns it on again).
        live_nodes.release(obj)
        obj.animanifold.bake_collection = self.collection
        obj.animanifold.mode = "BAKED"

    def commit(self):
        obj = self.obj
        base = f"{obj.name}_bake"
        for _, _, group, cache, _, _, _ in self.old_modifiers:
            if group is not None and group.users == 0:
                alembic_parts.remove_ids([group] + alembic_parts.helpers_of(group))
            if cache is not None and cache.users == 0:
                bpy.data.batch_remove([cache])
        if self.old_collection is not None and self.old_collection != self.collection:
            remove_collection(self.old_collection)
        self.collection.name = base
        self.group.name = base

    def rollback(self):
        obj = self.obj
        if self.replaced:  # else apply stopped before it touched the object (building the frames)
            for name in BAKE_MODIFIERS:
                mod = obj.modifiers.get(name)
                if mod is not None:
                    obj.modifiers.remove(mod)
        alembic_parts.remove_ids(self.new_ids)
        for cache in self.new_cache_files:
            if cache.users == 0:
                bpy.data.batch_remove([cache])
        if self.group is not None:
            bpy.data.node_groups.remove(self.group)
        if self.collection is not None:
            remove_collection(self.collection)
        if self.replaced:
            self._restore_old_modifiers()
        obj.animanifold.bake_collection = self.old_collection
        obj.animanifold.mode = self.old_mode

    def _restore_old_modifiers(self):
        """The old bake's modifiers again, in the old order."""
        obj = self.obj
        for name, kind, group, cache, path, show_viewport, show_render in self.old_modifiers:
            mod = obj.modifiers.new(name, kind)
            if kind == "NODES":
                mod.node_group = group
            else:
                mod.cache_file = cache
                mod.object_path = path
            mod.show_viewport, mod.show_render = show_viewport, show_render
        for index, name in enumerate(n for n in self.old_order if n in obj.modifiers):
            current = [m.name for m in obj.modifiers].index(name)
            if current != index:
                obj.modifiers.move(current, index)


# -- Alembic ----------------------------------------------------------------------

def alembic_supported() -> bool:
    return bool(getattr(bpy.app, "alembic", None) and bpy.app.alembic.supported)


def export_alembic(context, obj, filepath: str, frame_start: int, frame_end: int) -> list[tuple[str, object]]:
    """Exports the (baked, evaluated) object over the range with Blender's exporter, as one
    archive object per material with its colours as UV map pairs (alembic_parts). Returns the
    parts as (archive object name, material), in the order use_mesh_sequence_cache takes.
    Selection and active object are restored; the parts made for the export are removed."""
    if not alembic_supported():
        raise BakeError("this Blender was built without Alembic support")
    view_layer = context.view_layer
    selected = [o for o in view_layer.objects if o.select_get()]
    active = view_layer.objects.active
    staging = bpy.data.collections.new(f"{obj.name}_alembic_export")
    made = [staging]
    try:
        context.scene.collection.children.link(staging)
        made += alembic_parts.make_export_parts(obj, shown_manifold(obj), staging)
        parts = alembic_parts.part_objects(made)
        for o in selected:
            o.select_set(False)
        for part in parts:
            part.select_set(True)
        view_layer.objects.active = parts[0]
        os.makedirs(os.path.dirname(filepath), exist_ok=True)
        result = bpy.ops.wm.alembic_export(
            filepath=filepath, start=frame_start, end=frame_end, selected=True, uvs=True, normals=True,
            face_sets=True, vcolors=True, as_background_job=False, evaluation_mode="RENDER",
            export_custom_properties=False,
        )
        described = [(part.name, part.data.materials[0] if len(part.data.materials) == 1 else None)
                     for part in parts]
    finally:
        alembic_parts.remove_ids(made)
        for o in selected:
            o.select_set(True)
        view_layer.objects.active = active
    if "FINISHED" not in result or not os.path.isfile(filepath):
        raise BakeError(f"Blender's Alembic exporter did not write {filepath}")
    return described


def _archive_path(paths: list[str], name: str) -> str | None:
    """The mesh path of object `name` among an archive's paths (the exporter writes
    /<object>/<mesh>, with the object's name cleaned)."""
    for p in paths:
        if p.count("/") >= 2 and p.split("/")[1] in (name, bpy.path.clean_name(name)):
            return p
    return None


def use_mesh_sequence_cache(obj, filepath: str, stored_path: str, created: list,
                            parts: list[tuple[str, object]], made: list) -> None:
    """Shows the Alembic file through a Mesh Sequence Cache modifier reading the first of
    `parts` (export_alembic's), then alembic_parts' join of the others and of the colours; the
    node-group bake modifier stays on the object, disabled, to switch back. `stored_path` is the
    path kept in the .blend (relative where possible); new cache files go to `created`, the
    join's helper objects and node group to `made`."""
    existing = set(bpy.data.cache_files)
    result = bpy.ops.cachefile.open(filepath=filepath)
    new = [c for c in bpy.data.cache_files if c not in existing]
    created.extend(new)
    if "FINISHED" not in result or not new:
        raise BakeError(f"cannot open the Alembic cache {filepath}")
    cache = new[0]
    cache.filepath = stored_path
    for name in BAKE_MODIFIERS[1:]:
        old = obj.modifiers.get(name)
        if old is not None:
            obj.modifiers.remove(old)
    alembic_parts.empty_input(obj, made)
    modifier = obj.modifiers.new(CACHE_MODIFIER_NAME, "MESH_SEQUENCE_CACHE")
    modifier.cache_file = cache
    # The archive's object paths are read when the modifier is first evaluated.
    bpy.context.evaluated_depsgraph_get().update()
    paths = [p.path for p in cache.object_paths]
    found = [(_archive_path(paths, name), material) for name, material in parts]
    missing = [name for (path, _), (name, _) in zip(found, parts) if path is None]
    if missing or not found:
        raise BakeError(f"the Alembic cache {filepath} holds no mesh of '{obj.name}' "
                        f"(looked for {missing or [obj.name]}; paths: {paths})")
    modifier.object_path = found[0][0]
    alembic_parts.join_parts(obj, cache, found, alembic_parts.exact_colours(shown_manifold(obj)), made)
    nodes_modifier = obj.modifiers.get(MODIFIER_NAME)
    if nodes_modifier is not None:
        nodes_modifier.show_viewport = False
        nodes_modifier.show_render = False


# -- file sequences -----------------------------------------------------------------

SEQUENCE_EXTENSIONS = {"OBJ": ".obj", "PLY": ".ply"}


def frame_file_name(obj, frame: int, fmt: str) -> str:
    return f"{bpy.path.clean_name(obj.name)}_{frame:06d}{SEQUENCE_EXTENSIONS[fmt]}"


def material_table(obj) -> tuple[list[str], list[tuple[float, float, float]]]:
    """The object's material slots as (names, diffuse colours); empty slots get a placeholder name."""
    mats = list(obj.data.materials) if obj.type == "MESH" else []
    names = [m.name if m is not None else f"material_{i}" for i, m in enumerate(mats)]
    colours = [tuple(m.diffuse_color[:3]) if m is not None else (0.8, 0.8, 0.8) for m in mats]
    return names, colours


def mtl_file_name(obj, suffix: str = "") -> str:
    return f"{bpy.path.clean_name(obj.name)}{suffix}.mtl"


def frame_file_bytes(obj, manifold, frame: int, fmt: str, mtl_name: str | None) -> bytes:
    """A frame's OBJ/PLY text: the slice as the object shows it (smoothing included; object
    space) with its UV map, normals (custom normals when smooth-shaded, else flat) and materials."""
    s = frame_slice(obj, manifold, float(frame), "t")
    names, _ = material_table(obj)
    args = (np.ascontiguousarray(s.vertices), np.ascontiguousarray(s.faces), s.vertex_attributes.get("uv"),
            am.display.frame_normals(s, obj.animanifold.smooth_levels > 0), s.face_attributes.get("material_index"),
            names)
    if fmt == "OBJ":
        return am.mesh_export.obj_bytes(*args, mtl_name=mtl_name)
    return am.mesh_export.ply_bytes(*args)


def _write_file(path: str, data: bytes) -> None:
    with open(path, "wb") as f:
        f.write(data)


def export_sequence(obj, frames: list[int], directory: str, fmt: str, progress=None, write=_write_file,
                    mtl_suffix: str = "") -> list[str]:
    """One file per frame (frame_file_bytes) and, for OBJ with materials, one .mtl
    (<object><mtl_suffix>.mtl). `write(path, bytes)` writes each file (atomically on a farm)."""
    return am.core_job.Steps(export_sequence_steps(obj, frames, directory, fmt, progress, write, mtl_suffix)).run()


def export_sequence_steps(obj, frames: list[int], directory: str, fmt: str, progress=None, write=_write_file,
                          mtl_suffix: str = "", new_files: list[str] | None = None):
    """export_sequence as am.core_job.Steps, pausing after each frame's file. Each file it writes
    that was not there before goes to `new_files` as it is written, so that a caller's rollback
    can remove them, however far it got."""
    manifold = shown_manifold(obj)
    os.makedirs(directory, exist_ok=True)
    names, colours = material_table(obj)
    mtl_name = mtl_file_name(obj, mtl_suffix) if fmt == "OBJ" and names else None
    written = []

    def write_new(path: str, data: bytes) -> None:
        if new_files is not None and not os.path.exists(path):
            new_files.append(path)
        write(path, data)
        written.append(path)

    if mtl_name:
        write_new(os.path.join(directory, mtl_name), am.mesh_export.mtl_bytes(names, colours))
    for i, frame in enumerate(frames):
        write_new(os.path.join(directory, frame_file_name(obj, frame, fmt)),
                  frame_file_bytes(obj, manifold, frame, fmt, mtl_name))
        if progress is not None:
            progress(i + 1)
        yield am.core_job.Pause("writing the frame files")
    return written
