"""Bake Frames from the interface: modal, the manifold's subdivision in a worker thread, Esc
cancels before anything is baked.

The operator's modal half runs on a stand-in (Blender operators cannot be made outside an
operator call, and modal() needs a window's events). The subdivision is held at one of its
steps until the test has pressed Esc, so the cancel lands inside it however fast the machine
is; nothing here waits on a clock."""

from __future__ import annotations

import threading
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from helpers.blender_helpers import (ModalContext, mesh_corners, modal_event, modal_stand_in, scene_state,  # noqa: E402
                                     until_done)

pytestmark = pytest.mark.blender


@pytest.fixture()
def smoothed(demo, tmp_path):
    """The demo converted, baked once (node group), then given a Manifold Level whose subdivision is
    not kept, so that the next bake computes it; the panel's bake settings write OBJ files."""
    from animanifold_blender.live_registry import registry

    settings = bpy.context.scene.animanifold
    settings.cache_directory = str(tmp_path)
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    assert bpy.ops.animanifold.bake(alembic=False, export="NONE", use_scene_range=False, frame_start=10,
                                    frame_end=12) == {"FINISHED"}
    man.animanifold.subdivision_levels = 1  # computed by the property update, without a bar
    registry.subdivisions.clear()  # so that the bake computes it
    settings.bake_alembic, settings.bake_export = False, "OBJ"
    settings.bake_use_scene_range, settings.bake_start, settings.bake_end = False, 10, 12
    settings.bake_directory = str(tmp_path / "objs")
    return man, tmp_path / "objs"


def _bake_stand_in(calls):
    """(modal, op, result of _start): Bake started as invoke() starts it, on a stand-in whose
    properties are the panel's (none set on the operator)."""
    from animanifold_blender import operators

    modal, op = modal_stand_in(operators.ANIMANIFOLD_OT_bake, calls,
                               properties=SimpleNamespace(is_property_set=lambda name: False))
    return modal, op, op._start(ModalContext(calls))


def _bake_state(man) -> dict:
    return {**scene_state(), "mode": man.animanifold.mode, "bake_collection": man.animanifold.bake_collection.name,
            "frames": sorted(o.name for o in man.animanifold.bake_collection.objects),
            "modifiers shown": [(m.name, m.show_viewport, m.show_render) for m in man.modifiers]}


def test_esc_during_the_subdivision_cancels_the_bake_and_leaves_the_previous_bake(smoothed, monkeypatch):
    """Esc while the subdivision runs: the operator cancels with a warning; the previous bake, the
    object's modifiers and the scene are as they were, no file is written and the cancelled
    subdivision is not kept (nor remembered as failed)."""
    from animanifold_blender import cache_paths
    from animanifold_blender.live_registry import registry

    man, folder = smoothed
    before = _bake_state(man)
    real, reached, esc = registry.subdivisions.subdivided, threading.Event(), threading.Event()

    def held(*args, progress=None, interrupted=None):
        def step(name, fraction):
            if not reached.is_set():  # the core's first step waits until the test has pressed Esc
                reached.set()
                esc.wait(30.0)
            return progress(name, fraction)

        return real(*args, progress=step, interrupted=interrupted)

    monkeypatch.setattr(registry.subdivisions, "subdivided", held)
    calls = []
    modal, op, started = _bake_stand_in(calls)
    assert started == {"RUNNING_MODAL"}, op.reports
    assert any(c[0] == "status" and "Esc to cancel" in c[1] for c in calls), calls
    assert modal(ModalContext(calls), modal_event("MIDDLEMOUSE", "PRESS")) == {"PASS_THROUGH"}
    assert reached.wait(60.0)
    assert modal(ModalContext(calls), modal_event("ESC", "PRESS")) == {"RUNNING_MODAL"}
    esc.set()
    assert until_done(modal, calls) == {"CANCELLED"}
    assert op.reports == [({"WARNING"}, "Bake of 'Blob_manifold' cancelled: nothing was baked")]
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls and ("status", None) in calls
    assert _bake_state(man) == before
    assert not folder.exists()
    path = cache_paths.cache_abspath(man)
    assert registry.subdivisions.kept(path) == []
    assert registry.subdivisions.kept_manifold(path, registry.loaded(path), 1, man.animanifold.keep_keyframe_times) \
        is None  # not remembered as failed: the next bake computes it


def test_the_modal_bake_makes_what_the_blocking_one_makes(smoothed):
    """Not cancelled, the modal Bake subdivides in its worker thread and builds the same frames as
    execute() from the same settings, and writes the same files."""
    from animanifold_blender.live_registry import registry

    man, folder = smoothed

    def baked():
        """The frames' names (a rebake's new frame objects are made beside the old: Blender numbers
        them) and meshes, and the files written."""
        frames = sorted(man.animanifold.bake_collection.objects, key=lambda o: o.name)
        return ([(o.name.split(".")[0], mesh_corners(o.data)) for o in frames],
                sorted(p.name for p in folder.iterdir()))

    assert bpy.ops.animanifold.bake() == {"FINISHED"}
    blocking = baked()
    registry.subdivisions.clear()
    calls = []
    modal, op, started = _bake_stand_in(calls)
    assert started == {"RUNNING_MODAL"}, op.reports
    assert until_done(modal, calls) == {"FINISHED"}, op.reports
    assert op.reports[-1][1].startswith("Baked 'Blob_manifold': 3 frames 10–12"), op.reports
    modal_frames, modal_files = baked()
    assert modal_files == blocking[1] and [n for n, _ in modal_frames] == [n for n, _ in blocking[0]]
    for (_, a), (_, b) in zip(modal_frames, blocking[0]):
        np.testing.assert_array_equal(a, b)
    assert man.animanifold.mode == "BAKED" and ("progress end",) in calls


def test_a_bake_with_nothing_to_subdivide_ends_at_once(smoothed):
    """The subdivision kept already: there is no long call to wait for, so the bake is made at
    once, without going modal."""
    man, folder = smoothed
    assert bpy.ops.animanifold.bake() == {"FINISHED"}  # computes and keeps the subdivision
    calls = []
    modal, op, started = _bake_stand_in(calls)
    assert started == {"FINISHED"}, op.reports
    assert not any(c[0] == "timer added" for c in calls) and ("progress end",) in calls
    assert man.animanifold.mode == "BAKED"


def test_invoked_without_a_window_bake_runs_at_once(smoothed):
    """Invoked where there is no window to run a modal operator in (bpy, `blender -b`), Bake blocks
    like execute() instead of waiting for events that never come."""
    man, folder = smoothed
    assert bpy.ops.animanifold.bake("INVOKE_DEFAULT") == {"FINISHED"}
    assert man.animanifold.mode == "BAKED" and len(list(folder.iterdir())) == 4  # 3 frames and the .mtl
