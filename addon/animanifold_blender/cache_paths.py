"""Where manifold caches live: the path an object stores (relative to the .blend where it
can be, '//...') and the absolute path it names. Convert and Morph Selected put a new
cache beside the .blend (or in a chosen folder, or a temporary one for an unsaved file, copied
beside the .blend when it is saved: cache_follow);
Deform writes a new file beside the object's cache, so that undo, which restores the
object's old cache path, restores the old manifold too."""

from __future__ import annotations

import os
import re
import tempfile
import uuid

import bpy

from ._lib import am
from .reporting import OperatorError


def is_blend_relative(path: str) -> bool:
    return path.startswith("//")


def cache_abspath(obj) -> str:
    """The absolute path of the cache file of manifold object `obj`."""
    path = obj.animanifold.cache_path
    if not path:
        raise am.CacheError(f"'{obj.name}' has no manifold cache path")
    return os.path.normpath(bpy.path.abspath(path, library=obj.library))


def _temporary(stem: str, what: str) -> tuple[str, str, str]:
    folder = os.path.join(tempfile.gettempdir(), "animanifold")
    absolute = os.path.join(folder, f"{stem}.{uuid.uuid4().hex[:8]}.amf")
    note = (f"The .blend is not saved: the {what} cache is in the temporary folder {folder} until the .blend "
            "is saved, when it is copied beside it")
    return absolute, absolute, note


def _beside_blend(stem: str) -> tuple[str, str, None]:
    blend_stem = bpy.path.clean_name(os.path.splitext(os.path.basename(bpy.data.filepath))[0])
    filename = f"{blend_stem}.{stem}.amf"
    return "//" + filename, os.path.join(os.path.dirname(bpy.data.filepath), filename), None


def convert_cache_path(directory: str, name: str) -> tuple[str, str, str | None]:
    """(path stored on the object, absolute path, note for the report) of the cache of a
    converted object named `name`: in `directory` if given, else beside the .blend, else
    in a temporary folder."""
    stem = bpy.path.clean_name(name)
    saved = bool(bpy.data.filepath)
    if directory:
        if is_blend_relative(directory) and not saved:
            raise OperatorError(
                f"the cache folder '{directory}' is relative to the .blend, which is not saved yet: "
                "save the .blend or choose an absolute folder"
            )
        absolute = os.path.join(bpy.path.abspath(directory), stem + ".amf")
        return (bpy.path.relpath(absolute) if saved else absolute), absolute, None
    return _beside_blend(stem) if saved else _temporary(stem, "manifold")


def morph_cache_path(name: str) -> tuple[str, str, str | None]:
    """(path stored on the object, absolute path, note): beside the .blend, or a temporary folder."""
    stem = bpy.path.clean_name(name)
    return _beside_blend(stem) if bpy.data.filepath else _temporary(stem, "morph")


_DEFORM_SUFFIX = re.compile(r"\.deform-[0-9a-f]{8}$")


def deformed_cache_path(obj) -> tuple[str, str]:
    """(stored, absolute): a fresh file beside the object's cache."""
    old_stored = obj.animanifold.cache_path
    old = cache_abspath(obj)
    folder = os.path.dirname(old)
    stem = _DEFORM_SUFFIX.sub("", os.path.splitext(os.path.basename(old))[0])
    while True:
        absolute = os.path.join(folder, f"{stem}.deform-{uuid.uuid4().hex[:8]}.amf")
        if not os.path.exists(absolute):
            break
    stored = bpy.path.relpath(absolute) if is_blend_relative(old_stored) and bpy.data.filepath else absolute
    return stored, absolute
