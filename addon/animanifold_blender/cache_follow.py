"""Caches follow the .blend when it is saved somewhere else (save_pre/save_post handlers).

A cache path stored relative to the .blend ('//name.amf') names another file once the
.blend is saved into another folder; a cache of an unsaved file sits in the temporary
folder (cache_paths). Before the file is written, each such cache is copied to where its
stored path will point (beside the new .blend, under a free name if another file is
there), and the stored path set to it, so the saved file and the session both find it.
Copied, not moved: undo may bring back the old path, and the old .blend still uses it.
Absolute paths the user chose are left alone. A "Save Copy" (the session stays on the
old file) gets its old paths back after the save. Blender before 4.x's save handlers get
no file path (3.4 passes None): there caches do not follow, and Relink Cache repairs.

Blender's own path tools (File > External Data: Make Paths Relative/Absolute, Report
Missing Files) walk only data-block file paths (images, libraries, caches of the
modifiers they know); a manifold's path is an add-on property they never see. The panel
shows a missing cache as the object's error, Report Missing Manifold Caches (beside
Blender's in that menu) lists them, and Relink Cache points one at a file.
"""

from __future__ import annotations

import contextlib
import filecmp
import os
import shutil
import tempfile

import bpy

from . import cache_paths
from ._lib import am

# Object name -> its stored path before a save changed it (restored after a Save Copy).
_before: dict[str, str] = {}
# Inside caches_stay_in_place(): saves copy no cache.
_staying = False


def _temporary_folder() -> str:
    return os.path.normpath(os.path.join(tempfile.gettempdir(), "animanifold"))


def _manifold_objects():
    for obj in bpy.data.objects:
        settings = getattr(obj, "animanifold", None)
        if settings is not None and settings.is_manifold and obj.library is None and settings.cache_path:
            yield obj


def _free_path(path: str, source: str) -> str:
    """`path`, or beside it a name no other file has (a file there that is not a copy of `source`)."""
    stem, ext = os.path.splitext(path)
    candidate, n = path, 1
    while os.path.exists(candidate) and not filecmp.cmp(candidate, source, shallow=False):
        candidate, n = f"{stem}.{n}{ext}", n + 1
    return candidate


def _target(obj, blend: str) -> str | None:
    """Where the cache of `obj` goes when the file is saved as `blend`; None: it stays."""
    stored = obj.animanifold.cache_path
    old = cache_paths.cache_abspath(obj)
    folder = os.path.dirname(blend)
    if cache_paths.is_blend_relative(stored):
        new = os.path.normpath(os.path.join(folder, stored[2:]))
    elif os.path.dirname(old) == _temporary_folder():
        blend_stem = bpy.path.clean_name(os.path.splitext(os.path.basename(blend))[0])
        new = os.path.join(folder, f"{blend_stem}.{bpy.path.clean_name(obj.name)}.amf")
    else:
        return None
    return None if new == old else _free_path(new, old)


def _stored(path: str, blend: str) -> str:
    try:
        return "//" + os.path.relpath(path, os.path.dirname(blend))
    except ValueError:  # another drive (Windows): no relative path
        return path


def before_save(blend: str) -> list[str]:
    """Copies the caches the save at `blend` would lose and points their objects at the
    copies; returns a note per cache that could not be copied (missing, unreadable)."""
    _before.clear()
    notes = []
    if _staying:
        return notes
    for obj in _manifold_objects():
        try:
            target = _target(obj, blend)
        except am.CacheError:
            continue
        if target is None:
            continue
        source = cache_paths.cache_abspath(obj)
        try:
            if not os.path.exists(target):
                os.makedirs(os.path.dirname(target), exist_ok=True)
                shutil.copy2(source, target)
        except OSError as e:
            notes.append(f"the cache of '{obj.name}' was not copied beside {blend}: {e}")
            continue
        _before[obj.name] = obj.animanifold.cache_path
        # Relative to the file being written; set without the update (which would load
        # it relative to the file still open).
        obj.animanifold["cache_path"] = _stored(target, blend)
    return notes


def after_save(blend: str) -> None:
    """After a Save Copy the session stays on its file: its objects get their old paths back."""
    if os.path.normpath(bpy.data.filepath) != os.path.normpath(blend):
        for name, stored in _before.items():
            obj = bpy.data.objects.get(name)
            if obj is not None:
                obj.animanifold["cache_path"] = stored
    _before.clear()


@contextlib.contextmanager
def caches_stay_in_place():
    """Saves of copies that share the caches where they are (a render farm's chunk .blends,
    written side by side by concurrent tasks into one output folder): no cache is copied,
    and the copies name each cache by its absolute path, so they still find it."""
    global _staying
    stored = {}
    for obj in _manifold_objects():
        with contextlib.suppress(am.CacheError):
            absolute = cache_paths.cache_abspath(obj)
            stored[obj.name] = obj.animanifold.cache_path
            obj.animanifold["cache_path"] = absolute  # set without the update: the file is the same
    _staying = True
    try:
        yield
    finally:
        _staying = False
        for name, path in stored.items():
            obj = bpy.data.objects.get(name)
            if obj is not None:
                obj.animanifold["cache_path"] = path
