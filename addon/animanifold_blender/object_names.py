"""Names for the objects the add-on makes."""

from __future__ import annotations

import bpy


def unique_object_name(base: str) -> str:
    """`base`, or `base.001`, `base.002`, ...: the first name no object or mesh has (the new
    object's cache file is named after it, so its mesh must get the same name)."""
    name, i = base, 0
    while name in bpy.data.objects or name in bpy.data.meshes:
        i += 1
        name = f"{base}.{i:03d}"
    return name
