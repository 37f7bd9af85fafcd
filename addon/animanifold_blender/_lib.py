"""Finds the `animanifold` package: bundled inside the add-on (the zip made by
scripts/package_addon.py) or importable from sys.path (dev tree, pip install)."""

from __future__ import annotations

import importlib
import importlib.util


def _load():
    bundled = f"{__package__}.animanifold"
    if importlib.util.find_spec(bundled) is not None:
        return importlib.import_module(bundled)
    try:
        return importlib.import_module("animanifold")
    except ImportError as e:
        raise ImportError(
            "animanifold: the compiled 'animanifold' package was found neither inside the add-on "
            f"nor on sys.path ({e}). Install the add-on from dist/animanifold_blender.zip "
            "(scripts/package_addon.py) or put the project's python/ folder on sys.path."
        ) from e


am = _load()
