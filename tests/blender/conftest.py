"""Fixtures for the in-process Blender tests (bpy 4.5 from PyPI).

The add-on is imported from the dev tree (addon/ and python/ on sys.path) and
registered once per session; every test starts from empty factory settings.
Without bpy every test here is skipped (each module calls pytest.importorskip).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
for p in (str(ROOT / "addon"), str(ROOT / "python"), str(ROOT / "blender_scenes")):
    if p not in sys.path:
        sys.path.insert(0, p)

try:
    import bpy
except ImportError:  # the test modules skip with the reason
    bpy = None

BPY_REASON = "bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed"


@pytest.fixture(scope="session")
def addon():
    if bpy is None:
        pytest.skip(BPY_REASON)
    import animanifold_blender

    animanifold_blender.register()
    yield animanifold_blender
    animanifold_blender.unregister()


@pytest.fixture()
def empty_scene(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene


@pytest.fixture()
def demo(empty_scene):
    from build_demo_scene import build_demo_scene

    return build_demo_scene(segments=16, rings=8)
