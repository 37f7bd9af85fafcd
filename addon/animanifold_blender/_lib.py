"""The `animanifold` package the add-on is built on: bundled inside the add-on (the zip
made by scripts/package_addon.py puts it at `<add-on>/animanifold/`) or importable from
sys.path (the dev tree, a pip install). Every add-on module imports it from here."""

from __future__ import annotations

try:
    from . import animanifold as am
except ImportError:
    try:
        import animanifold as am
    except ImportError as e:
        raise ImportError(
            "animanifold: the compiled 'animanifold' package was found neither inside the add-on "
            f"nor on sys.path ({e}). Install the add-on from dist/animanifold_blender.zip "
            "(scripts/package_addon.py) or put the project's python/ folder on sys.path."
        ) from e

__all__ = ["am"]
