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

from . import adaptive_sampling, extra_layers, live_nodes, messages, sampling
from ._lib import am
from .cache_paths import convert_cache_path
from .live import scene_frame
from .live_registry import registry
from .object_manifold import is_manifold_object
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
    notes: list  # warnings for the report (a cache in a temporary folder, a tolerance not reached, ...)
    fidelity: object = None  # adaptive_sampling.Fidelity: the largest deviation reached (mode ADAPTIVE)


def convert_object(context, obj, start: int, end: int, mode: str, step: int, directory: str,
                   tolerance: float = adaptive_sampling.TOLERANCE_PERCENT,
                   max_samples: int = adaptive_sampling.MAX_SAMPLES) -> Converted:
    """Converts `obj` (see convert_steps) here, blocking, with the progress bar."""
    progress = Progress(context.window_manager)
    try:
        return am.core_job.Steps(convert_steps(context, progress, obj, start, end, mode, step, directory,
                                               tolerance, max_samples)).run(progress)
    finally:
        progress.end()


def convert_steps(context, progress, obj, start: int, end: int, mode: str, step: int, directory: str,
                  tolerance: float = adaptive_sampling.TOLERANCE_PERCENT,
                  max_samples: int = adaptive_sampling.MAX_SAMPLES):
    """Samples `obj` over frames start..end (`mode` ADAPTIVE: keyframes plus samples until
    every frame and half frame is within `tolerance` % of the object's size, at most
    `max_samples`; KEYFRAMES; or EVERY_N with `step`), saves the manifold to a cache (in
    `directory`, else beside the .blend) and makes the object: am.core_job.Steps whose long
    calls are the stitches, so a cancel comes before anything is written or made. Its
    result is the Converted; `progress` (progress.Progress) shows how far it is."""
    if obj.type != "MESH":
        raise OperatorError(f"'{obj.name}' is {messages.object_type(obj)}, not a mesh: only mesh objects can be converted")
    if is_manifold_object(obj):
        raise OperatorError(f"'{obj.name}' is already a manifold object")
    if end <= start:
        raise OperatorError(f"the frame range {start}–{end} is empty: the end frame must be after the start")
    frames, notes = sampling.sample_frames(obj, start, end, mode, step)

    name = unique_object_name(f"{obj.name}_manifold")  # its cache file is named after it
    stored, absolute, note = convert_cache_path(directory, name)
    notes = ([note] if note else []) + notes

    fidelity = None
    if mode == "ADAPTIVE":
        units = 2 * len(adaptive_sampling.candidate_frames(start, end, frames)) + 2
        keys, manifold, fidelity = yield from adaptive_sampling.adaptive_steps(
            context, obj, start, end, frames, tolerance, max_samples, progress)
        if not fidelity.reached:
            notes.append(fidelity.warning(obj.name))
    else:
        units = len(frames) + 2
        keys = sampling.sample_object(context, obj, frames, progress.counter(units))
        progress.span(100.0 * len(frames) / units, 100.0 * (len(frames) + 1) / units)
        manifold = yield am.core_job.CoreCall(sampling.stitch_keyframes, (keys,))
    manifold.metadata.update(_metadata(obj, start, end, mode, step, keys, fidelity))
    progress.at(100.0 * (units - 1) / units)
    existed = os.path.exists(absolute)
    am.save(manifold, absolute)
    try:
        new = _create_object(context, obj, name, stored, absolute, manifold, keys, start, end, fidelity)
    except BaseException:
        if not existed:
            try:
                os.unlink(absolute)
            except OSError:
                pass
        registry.forget(absolute)
        raise
    progress.at(100.0)
    return Converted(new, manifold, len(keys.times), start, end, stored, notes, fidelity)


def _metadata(obj, start, end, mode, step, keys, fidelity) -> dict:
    data = {
        "source_object": obj.name,
        "frame_range": [float(start), float(end)],
        "sampling": f"EVERY_{step}" if mode == "EVERY_N" else mode,
        "uv_map": keys.uv_name,
        **extra_layers.metadata(keys.extra),
        "object_motion_baked": bool(keys.moves),
        "blender": bpy.app.version_string,
    }
    if fidelity is not None:
        data.update({"tolerance": fidelity.tolerance, "max_deviation": fidelity.deviation,
                     "max_deviation_frame": fidelity.frame, "source_size": fidelity.size})
    return data


def _create_object(context, obj, name, stored, absolute, manifold, keys, start, end, fidelity):
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
        if fidelity is not None:
            settings.max_deviation = fidelity.deviation
            settings.deviation_frame = fidelity.frame
            settings.source_size = fidelity.size
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
