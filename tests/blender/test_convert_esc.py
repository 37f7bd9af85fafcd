"""Convert from the interface: modal, its stitches in a worker thread, Esc cancels.

The operator's modal half runs on a stand-in (Blender operators cannot be made outside an
operator call, and modal() needs a window's events). The stitch is held at one of its steps
until the test has pressed Esc, so the cancel lands inside the stitch however fast the machine
is; nothing here waits on a clock."""

from __future__ import annotations

import os
import threading
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from helpers.blender_helpers import (BLENDER, NO_BLENDER_BINARY, NO_XVFB, XVFB, ModalContext, modal_event,  # noqa: E402
                                     modal_stand_in, run_blender_in_window, scene_state, until_done)

pytestmark = pytest.mark.blender


def _convert_stand_in(calls, sampling):
    """(modal, op, result of _start): Convert started as invoke() starts it, on a stand-in whose
    properties are the panel's (none set on the operator), with `sampling`."""
    from animanifold_blender import operators

    bpy.context.scene.animanifold.sampling = sampling
    modal, op = modal_stand_in(operators.ANIMANIFOLD_OT_convert_action, calls,
                               properties=SimpleNamespace(is_property_set=lambda name: False))
    return modal, op, op._start(ModalContext(calls))


def _held_stitches(monkeypatch, hold_at: int):
    """Stitch number `hold_at` (1 = the first) waits at its first step until `esc` is set, after
    `reached`; the others run as they are. (reached, esc, count of stitches begun)."""
    from animanifold_blender import sampling

    real, reached, esc, begun = sampling.stitch_keyframes, threading.Event(), threading.Event(), []

    def stitch(keys, progress=None, interrupted=None):
        begun.append(True)
        if len(begun) != hold_at:
            return real(keys, progress, interrupted)

        def step(name, fraction):
            if not reached.is_set():
                reached.set()
                esc.wait(30.0)
            return progress(name, fraction)

        return real(keys, step, interrupted)

    monkeypatch.setattr(sampling, "stitch_keyframes", stitch)
    return reached, esc, begun


def _esc(modal, calls, reached, esc):
    """Timer ticks (the steps run on between stitches) until the held stitch is reached, then Esc;
    what the operator ends with."""
    for _ in range(2400):  # a bound against a hang, not a wait on the clock
        if reached.wait(0.05):
            break
        assert modal(ModalContext(calls), modal_event("TIMER")) == {"RUNNING_MODAL"}
    assert reached.is_set()  # the worker is inside the held stitch
    assert modal(ModalContext(calls), modal_event("ESC", "PRESS")) == {"RUNNING_MODAL"}
    esc.set()
    return until_done(modal, calls)


@pytest.mark.parametrize("sampling, hold_at", [("KEYFRAMES", 1), ("ADAPTIVE", 1), ("ADAPTIVE", 2)])
def test_esc_during_a_stitch_cancels_convert_and_leaves_the_scene_as_it_was(demo, tmp_path, monkeypatch,
                                                                           sampling, hold_at):
    """Esc in the first stitch, or (adaptive sampling) in the second, after a round of sampling
    in the main thread: the operator cancels with a warning, adds no object, writes no cache
    and leaves the frame, selection and visibility as they were."""
    scene = bpy.context.scene
    scene.animanifold.cache_directory = str(tmp_path)
    scene.frame_set(7)
    before = scene_state()
    reached, esc, begun = _held_stitches(monkeypatch, hold_at)
    calls = []
    modal, op, started = _convert_stand_in(calls, sampling)
    assert started == {"RUNNING_MODAL"}, op.reports
    assert any(c[0] == "status" and "Esc to cancel" in c[1] for c in calls), calls
    assert modal(ModalContext(calls), modal_event("MIDDLEMOUSE", "PRESS")) == {"PASS_THROUGH"}
    assert modal(ModalContext(calls), modal_event("X", "PRESS")) == {"RUNNING_MODAL"}  # no delete while it runs
    assert _esc(modal, calls, reached, esc) == {"CANCELLED"}
    assert len(begun) == hold_at
    assert [text for kind, text in op.reports] == ["Convert of 'Blob' cancelled: nothing was added"]
    assert op.reports[0][0] == {"WARNING"}
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls and ("status", None) in calls
    assert scene_state() == before
    assert os.listdir(tmp_path) == []


def test_blender_ending_the_modal_convert_stops_the_stitch_and_adds_nothing(demo, tmp_path, monkeypatch):
    """File > Open (or the window closing) ends the modal operator itself: the job is told to stop,
    the steps are dropped, nothing is added."""
    bpy.context.scene.animanifold.cache_directory = str(tmp_path)
    before = scene_state()
    reached, esc, _ = _held_stitches(monkeypatch, 1)
    calls = []
    modal, op, started = _convert_stand_in(calls, "KEYFRAMES")
    assert started == {"RUNNING_MODAL"} and reached.wait(60.0)
    op.cancel(ModalContext(calls))
    esc.set()
    assert op._job.wait(60.0) and op._job.cancelled
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls
    assert scene_state() == before and os.listdir(tmp_path) == []


@pytest.mark.parametrize("sampling", ["KEYFRAMES", "ADAPTIVE"])
def test_the_modal_convert_makes_what_the_blocking_one_makes(demo, tmp_path, sampling):
    """Not cancelled, the modal Convert ends with the object execute() makes from the same
    source: the same samples, tets and points, the source hidden, the object active."""
    from animanifold_blender.object_manifold import manifold_for

    scene = bpy.context.scene
    scene.animanifold.cache_directory = str(tmp_path)
    source = bpy.data.objects["Blob"]
    assert bpy.ops.animanifold.convert_action(sampling=sampling) == {"FINISHED"}
    blocking = bpy.data.objects["Blob_manifold"]
    source.hide_set(False)
    source.hide_render = False
    bpy.context.view_layer.objects.active = source
    calls = []
    modal, op, started = _convert_stand_in(calls, sampling)
    assert started == {"RUNNING_MODAL"}, op.reports
    assert until_done(modal, calls) == {"FINISHED"}, op.reports
    made = bpy.context.active_object
    assert made.name == "Blob_manifold.001" and made.animanifold.is_manifold
    assert source.hide_get() and source.hide_render
    a, b = manifold_for(blocking), manifold_for(made)
    np.testing.assert_array_equal(a.simplices, b.simplices)
    np.testing.assert_array_equal(a.points, b.points)
    assert a.metadata == b.metadata
    assert any(text.startswith("'Blob_manifold.001': ") for _, text in op.reports), op.reports
    assert ("progress end",) in calls and ("status", None) in calls


def test_invoked_without_a_window_convert_runs_at_once(demo, tmp_path):
    """Invoked where there is no window to run a modal operator in (bpy, `blender -b`), Convert
    blocks like execute() instead of waiting for events that never come."""
    bpy.context.scene.animanifold.cache_directory = str(tmp_path)
    assert bpy.ops.animanifold.convert_action("INVOKE_DEFAULT", sampling="KEYFRAMES") == {"FINISHED"}
    assert bpy.context.active_object.name == "Blob_manifold"


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
@pytest.mark.skipif(XVFB is None, reason=NO_XVFB)
def test_convert_and_bake_in_a_real_window_go_modal_esc_cancels_them_and_undo_takes_them_back(tmp_path):
    """Debian's Blender 3.4 with a window on a virtual screen (tests/blender/scripts/
    window_convert_bake_blender34.py): invoked from the 3D view, Convert and Bake return
    RUNNING_MODAL; a simulated Esc while their long call (the stitch, the subdivision) is held
    until the operator asks it to stop leaves the scene and the folders as they were; run again
    they make the object and its frames, and Undo takes back each in one step."""
    proc = run_blender_in_window(tmp_path, "window_convert_bake_blender34.py")
    lines = proc.stdout.strip().splitlines()
    assert proc.returncode == 0 and lines and lines[-1].startswith("WINDOW CONVERT OK"), \
        (proc.returncode, proc.stdout[-3000:], proc.stderr[-3000:])
    assert "['stitch_keyframes', 'subdivided']" in lines[-1], lines[-1]
