"""Convert: a keyframed mesh object becomes a manifold object (its cache written,
a new object made beside it and shown live). Everything that can fail is checked
before the scene changes; on a failure whatever was created is removed again.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import bpy
import numpy as np
from mathutils import Matrix

from . import live_nodes, messages, sampling
from ._lib import am
from .cache_paths import convert_cache_path
from .live import scene_frame
from .live_registry import registry
from .object_names import unique_object_name
from .playback import update_object
from .progress import Progress
from .reporting import OperatorError


@dataclass
class Converted:
    obj: object  # the new manifold object
    manifold: object
    samples: int
    start: int
    end: int
    stored: str  # the cache path stored on the object
    note: str | None  # a warning for the report (a cache in a temporary folder)


def convert_object(context, obj, start: int, end: int, mode: str, step: int, directory: str) -> Converted:
    """Samples `obj` over frames start..end (`mode` KEYFRAMES or EVERY_N with `step`), saves
    the manifold to a cache (in `directory`, else beside the .blend) and makes the object."""
    if obj.type != "MESH":
        raise OperatorError(f"'{obj.name}' is {messages.object_type(obj)}, not a mesh: only mesh objects can be converted")
    if getattr(obj, "animanifold", None) is not None and obj.animanifold.is_manifold:
        raise OperatorError(f"'{obj.name}' is already a manifold object")
    if end <= start:
        raise OperatorError(f"the frame range {start}–{end} is empty: the end frame must be after the start")
    frames = sampling.sample_frames(obj, start, end, mode, step)

    name = unique_object_name(f"{obj.name}_manifold")  # its cache file is named after it
    stored, absolute, note = convert_cache_path(directory, name)

    progress = Progress(context, len(frames) + 2)
    try:
        keys = sampling.sample_object(context, obj, frames, progress)
        manifold = _stitch(keys)
        manifold.metadata.update({
            "source_object": obj.name,
            "frame_range": [float(start), float(end)],
            "sampling": mode if mode == "KEYFRAMES" else f"EVERY_{step}",
            "uv_map": keys.uv_name,
            "object_motion_baked": bool(keys.moves),
            "blender": bpy.app.version_string,
        })
        progress(len(frames) + 1)
        existed = os.path.exists(absolute)
        am.save(manifold, absolute)
        try:
            new = _create_object(context, obj, name, stored, absolute, manifold, keys, start, end)
        except BaseException:
            if not existed:
                try:
                    os.unlink(absolute)
                except OSError:
                    pass
            registry.forget(absolute)
            raise
        progress(len(frames) + 2)
    finally:
        progress.end()
    return Converted(new, manifold, len(frames), start, end, stored, note)


def _stitch(keys):
    vertex_attributes = {"source_vertex": keys.source_vertex.astype(np.float64)}
    if keys.smooth.all():  # smooth-shaded: carry the source's vertex normals
        vertex_attributes["normal"] = keys.normals
    if keys.uv is not None:
        vertex_attributes["uv"] = keys.uv
    return am.stitch(
        keys.positions, keys.faces, keys.times, vertex_attributes=vertex_attributes,
        face_attributes={"material_index": keys.material_index, "smooth": keys.smooth},
    )


def _create_object(context, obj, name, stored, absolute, manifold, keys, start, end):
    mesh = new = None
    try:
        mesh = bpy.data.meshes.new(name)
        for slot in obj.material_slots:
            mesh.materials.append(slot.material)
        new = bpy.data.objects.new(name, mesh)
        new.matrix_world = Matrix(keys.matrix_world.tolist())  # the source's world matrix at the first sample
        collections = list(obj.users_collection) or [context.scene.collection]
        for coll in collections:
            coll.objects.link(new)
        settings = new.animanifold
        settings.uv_name = keys.uv_name or "UVMap"
        settings.frame_start = float(start)
        settings.frame_end = float(end)
        settings.source = obj
        lo, hi = manifold.bounding_box
        size = float(np.linalg.norm((hi - lo)[:3])) or 1.0
        settings.time_scale = 2.0 * size / max(float(end - start), 1.0)
        settings.sweep_value = float((lo[0] + hi[0]) / 2)
        settings.cache_path = stored
        settings.is_manifold = True
        registry.remember(absolute, manifold)
        update_object(new, scene_frame(context.scene))
    except BaseException:
        if new is not None:
            bpy.data.objects.remove(new)
        if mesh is not None:
            bpy.data.meshes.remove(mesh)
        live_nodes.remove_unused_group()  # made for the new object's first frame
        raise
    # Rendering an animation from the UI runs frame_change_post while the render
    # thread reads meshes: Blender's "Lock Interface" makes the live update safe.
    context.scene.render.use_lock_interface = True
    # Done: hide the source (never modify or delete it) and select the result.
    obj.hide_render = True
    if obj.name in context.view_layer.objects:
        obj.hide_set(True)
        obj.select_set(False)
    if new.name in context.view_layer.objects:
        new.select_set(True)
        context.view_layer.objects.active = new
    return new
