"""Bake Frames from the interface: modal, the manifold's subdivision in a worker thread, then the
frames and files made a slice at a time; Esc cancels at any point and leaves nothing baked.

The operator's modal half runs on a stand-in (Blender operators cannot be made outside an
operator call, and modal() needs a window's events). The subdivision is held at one of its
steps until the test has pressed Esc, so the cancel lands inside it however fast the machine
is; the frames and files are made one per event (job_modal.MAIN_THREAD_SLICE set to 0), so Esc
lands between two of them. Nothing here waits on a clock."""

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


def test_a_bake_with_nothing_to_subdivide_makes_its_frames_and_files_between_events(smoothed):
    """The subdivision kept already: no long call to wait for, but the frames and files are still
    made a slice per event, so the bar moves and Esc can stop them; the end is the same bake."""
    man, folder = smoothed
    assert bpy.ops.animanifold.bake() == {"FINISHED"}  # computes and keeps the subdivision
    calls = []
    modal, op, started = _bake_stand_in(calls)
    assert started == {"RUNNING_MODAL"}, op.reports
    assert until_done(modal, calls) == {"FINISHED"}, op.reports
    assert op.reports[-1][1].startswith("Baked 'Blob_manifold': 3 frames 10–12"), op.reports
    assert man.animanifold.mode == "BAKED" and ("progress end",) in calls
    assert len(list(folder.iterdir())) == 4  # 3 frames and the .mtl


@pytest.fixture()
def one_step_per_event(smoothed, monkeypatch):
    """`smoothed` with its subdivision kept (baked once more, into another folder) and the bake's
    main-thread work made one frame or file per event; the bake's folder is new."""
    from animanifold_blender import job_modal

    man, folder = smoothed
    assert bpy.ops.animanifold.bake() == {"FINISHED"}
    for path in folder.iterdir():
        path.unlink()
    folder.rmdir()
    monkeypatch.setattr(job_modal, "MAIN_THREAD_SLICE", 0.0)
    return man, folder


def _esc_state(man) -> dict:
    """What an Esc during the bake must leave as it was: the scene and the previous bake, the
    object's mode (Blender's and the manifold's) and the cache files."""
    from animanifold_blender import live_nodes

    return {**_bake_state(man), "context mode": bpy.context.mode,
            "cache files": sorted(c.name for c in bpy.data.cache_files),
            "live modifier": live_nodes.released_inputs(man)}


def _bake_cancelled_by_esc(ready) -> list:
    """Bake started as invoke() starts it, given timer events until `ready()` (each event makes one
    frame or file), then Esc: it is cancelled with its warning, its bar and status line ended.
    The calls recorded."""
    calls = []
    modal, op, started = _bake_stand_in(calls)
    assert started == {"RUNNING_MODAL"}, op.reports
    for _ in range(100):
        if ready():
            break
        assert modal(ModalContext(calls), modal_event("TIMER")) == {"RUNNING_MODAL"}, op.reports
    else:
        pytest.fail("the bake never got to the point where Esc is pressed")
    assert modal(ModalContext(calls), modal_event("ESC", "PRESS")) == {"CANCELLED"}
    assert op.reports == [({"WARNING"}, "Bake of 'Blob_manifold' cancelled: nothing was baked")]
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls and ("status", None) in calls
    return calls


def _new_frames() -> list[str]:
    """The frame objects of the bake being built (its collection's name until the commit)."""
    collection = bpy.data.collections.get("Blob_manifold_bake.new")
    return [] if collection is None else sorted(o.name for o in collection.objects)


def test_esc_while_the_frames_are_built_removes_them_and_leaves_the_previous_bake(one_step_per_event):
    """Esc after two of the three frames are built (one per event, the first before the first
    event): they are removed, the previous bake, the object's modifiers and the scene are as they
    were, and no file is written."""
    man, folder = one_step_per_event
    before, seen = _esc_state(man), []
    _bake_cancelled_by_esc(lambda: seen.append(len(_new_frames())) or seen[-1] == 2)
    assert seen == [1, 2]
    assert _esc_state(man) == before and _new_frames() == [] and not folder.exists()


def test_esc_while_the_files_are_written_removes_them_and_the_new_bake(one_step_per_event):
    """Esc after the frames are built and the first frame file is written: the files and the
    folder made for them are removed, and so is the new bake; everything is as it was."""
    man, folder = one_step_per_event
    before = _esc_state(man)
    _bake_cancelled_by_esc(lambda: folder.is_dir() and len(list(folder.glob("*.obj"))) == 1)
    assert _esc_state(man) == before and _new_frames() == [] and not folder.exists()


def test_esc_on_a_live_object_leaves_it_playing_live(demo, tmp_path, monkeypatch):
    """A first bake of a live object, cancelled after its first file: the live modifier, which the
    bake had released when it put its own in place, plays the manifold again as before."""
    from animanifold_blender import job_modal, live_nodes

    settings = bpy.context.scene.animanifold
    settings.cache_directory = str(tmp_path)
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    settings.bake_alembic, settings.bake_export = False, "OBJ"
    settings.bake_use_scene_range, settings.bake_start, settings.bake_end = False, 10, 12
    folder = tmp_path / "objs"
    settings.bake_directory = str(folder)
    monkeypatch.setattr(job_modal, "MAIN_THREAD_SLICE", 0.0)
    bpy.context.scene.frame_set(11)
    before = {**scene_state(), "mode": man.animanifold.mode, "live modifier": live_nodes.released_inputs(man),
              "modifiers": [(m.name, m.show_viewport, m.show_render) for m in man.modifiers]}
    assert man.animanifold.mode == "LIVE" and before["live modifier"]["Active"], before
    _bake_cancelled_by_esc(lambda: folder.is_dir() and len(list(folder.glob("*.obj"))) == 1)
    after = {**scene_state(), "mode": man.animanifold.mode, "live modifier": live_nodes.released_inputs(man),
             "modifiers": [(m.name, m.show_viewport, m.show_render) for m in man.modifiers]}
    assert after == before and _new_frames() == [] and not folder.exists()


def test_a_rolled_back_bake_gives_the_live_modifier_its_inputs_back_at_once(demo, tmp_path):
    """The bake releases the live modifier when it puts its own in place; its rollback sets the
    object's mode back to LIVE, which drives the modifier again at once, not at the next frame."""
    from animanifold_blender import live_nodes
    from animanifold_blender.bake import NodeGroupBake

    bpy.context.scene.animanifold.cache_directory = str(tmp_path)
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    bpy.context.scene.frame_set(11)
    before = live_nodes.released_inputs(man)
    assert before["Active"], before
    bake = NodeGroupBake(man)
    bake.apply([10, 11, 12])
    assert not live_nodes.released_inputs(man)["Active"]
    bake.rollback()
    assert live_nodes.released_inputs(man) == before and man.animanifold.mode == "LIVE"


@pytest.mark.skipif(not bpy.app.alembic.supported, reason="this bpy has no Alembic")
def test_esc_after_the_alembic_export_removes_the_archive_and_its_cache(one_step_per_event):
    """Blender's Alembic exporter is one call: Esc pressed meanwhile is answered right after it,
    before the Mesh Sequence Cache is made; the archive goes with the rest of the bake."""
    man, folder = one_step_per_event
    settings = bpy.context.scene.animanifold
    settings.bake_alembic, settings.bake_use_mesh_cache, settings.bake_export = True, True, "NONE"
    before = _esc_state(man)
    _bake_cancelled_by_esc(lambda: folder.is_dir() and len(list(folder.glob("*.abc"))) == 1)
    assert _esc_state(man) == before and _new_frames() == [] and not folder.exists()


def test_invoked_without_a_window_bake_runs_at_once(smoothed):
    """Invoked where there is no window to run a modal operator in (bpy, `blender -b`), Bake blocks
    like execute() instead of waiting for events that never come."""
    man, folder = smoothed
    assert bpy.ops.animanifold.bake("INVOKE_DEFAULT") == {"FINISHED"}
    assert man.animanifold.mode == "BAKED" and len(list(folder.iterdir())) == 4  # 3 frames and the .mtl
