"""Bake Frames: a manifold object's frames baked with bake's pieces in order (the node-group
bake, then optionally Alembic, a Mesh Sequence Cache and an OBJ/PLY sequence). Everything
that can fail on the settings is checked first; on a failure, or when Esc stops a bake run
from the interface between two frames or files (job_modal), the node-group bake is rolled back
and the files it wrote are removed.
"""

from __future__ import annotations

import math
import os

import bpy

from . import bake
from .cache_paths import is_blend_relative
from ._lib import am
from .object_manifold import manifold_for, shown_manifold_steps
from .progress import Progress
from .reporting import OperatorError


def _remove_new_files(paths: list[str], new_folder: str | None) -> None:
    """Removes the files a bake wrote that were not there before, and the folder it made (when
    `new_folder` is given and nothing else is in it)."""
    for path in paths:
        try:
            os.unlink(path)
        except OSError:
            pass
    if new_folder is not None:
        try:
            os.rmdir(new_folder)
        except OSError:  # not made after all, or holds something else
            pass


def bake_object(context, obj, **options) -> str:
    """Bakes `obj` (see bake_steps) here, blocking, with the progress bar; the report's text."""
    progress = Progress(context.window_manager, where="subdividing the manifold")
    try:
        return am.core_job.Steps(bake_steps(context, progress, obj, **options)).run(progress)
    finally:
        progress.end()


def bake_steps(context, progress, obj, use_scene_range: bool, start: int, end: int, alembic_wanted: bool,
               use_cache: bool, export: str, directory: str):
    """Bakes `obj` (see the module) as am.core_job.Steps whose long call is the manifold's
    subdivision (when the object's Smooth settings ask for one not kept yet), made before
    anything changes, and which pause after each frame built, the Alembic export and each frame
    file written: a cancel at any of these leaves the scene and the files as they were. Its
    result is the report's text; `progress` (progress.Progress) shows how far it is: the
    subdivision fills the bar, then the frames fill it again."""
    scene = context.scene
    manifold_for(obj)  # validates the cache before anything changes
    manifold = yield from shown_manifold_steps(obj)  # and subdivides it (Smooth settings) before anything changes
    if use_scene_range:
        start, end = scene.frame_start, scene.frame_end
    t0, t1 = manifold.time_range
    first, last = max(start, math.ceil(t0 - 1e-9)), min(end, math.floor(t1 + 1e-9))
    if last < first:
        raise OperatorError(f"the frames {start}–{end} are outside the manifold's frames {t0:g}–{t1:g}: nothing to bake")
    frames = list(range(first, last + 1))

    alembic = alembic_wanted and bake.alembic_supported()
    directory = directory or "//animanifold_bake/"
    if use_cache and not alembic:
        raise OperatorError("a Mesh Sequence Cache needs the Alembic bake, which this Blender "
                            + ("does not support" if not bake.alembic_supported() else "was told to skip"))
    if (alembic or export != "NONE") and is_blend_relative(directory) and not bpy.data.filepath:
        raise OperatorError(f"the bake folder '{directory}' is relative to the .blend, which is not saved yet: "
                            "save the .blend or choose an absolute folder")
    folder = bpy.path.abspath(directory)
    chunk = "" if (first, last) == (scene.frame_start, scene.frame_end) else f"_{first:06d}-{last:06d}"
    stem = bpy.path.clean_name(obj.name)

    count = progress.counter(2 * len(frames) + 2)
    count(0)
    transaction = bake.NodeGroupBake(obj)
    new_files = []  # the files written that were not there before, removed on a failure or a cancel
    new_folder = not os.path.isdir(folder)
    try:
        yield from transaction.apply_steps(frames, count)
        notes = [f"{len(frames)} frames {first}–{last} (node group)"]
        if alembic:
            path = os.path.join(folder, f"{stem}{chunk}.abc")
            if not os.path.exists(path):
                new_files.append(path)
            parts = bake.export_alembic(context, obj, path, first, last)  # Blender's exporter: one call
            yield am.core_job.Pause("exporting Alembic")
            stored = bpy.path.relpath(path) if bpy.data.filepath and is_blend_relative(directory) else path
            notes.append(f"Alembic {stored}")
            if use_cache:
                bake.use_mesh_sequence_cache(obj, path, stored, transaction.new_cache_files, parts,
                                             transaction.new_ids)
                notes.append("shown by a Mesh Sequence Cache modifier")
        count(len(frames) + 1)
        if export != "NONE":
            files = yield from bake.export_sequence_steps(obj, frames, folder, export,
                                                          lambda i: count(len(frames) + 1 + i), mtl_suffix=chunk,
                                                          new_files=new_files)
            notes.append(f"{len(files)} {export} files in {folder}")
    except BaseException:  # a failure, or Esc between two steps (GeneratorExit): the scene as it was
        transaction.rollback()
        _remove_new_files(new_files, folder if new_folder else None)
        raise
    transaction.commit()
    notes[0] = f"{len(frames)} frames {first}–{last} in collection '{transaction.collection.name}' (node group)"
    if alembic_wanted and not bake.alembic_supported():
        notes.append("no Alembic: this Blender was built without it")
    return f"Baked '{obj.name}': " + "; ".join(notes)
