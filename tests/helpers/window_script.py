"""What the real-window scripts (tests/blender/scripts/window_*_blender34.py) share: they run
in Debian's Blender with a window, act in its 3D view and quit Blender with their verdict, a
last line "WINDOW <NAME> OK ..." or "WINDOW <NAME> FAILED: <why>"."""

from __future__ import annotations

import os
import time
import traceback

import bpy


# A bound against a hang, not a speed bar: every phase of the scripts takes seconds, and one
# still waiting after this long is stuck. Below run_blender_in_window's 300 s, so that the
# script's verdict names the phase rather than the subprocess timing out.
HANG_SECONDS = 240.0


def stuck(since: float) -> bool:
    """Whether HANG_SECONDS have passed since `since`, a time.perf_counter() reading: the one
    wall-clock comparison the tests make (tests/test_fresh_machine.py)."""
    return time.perf_counter() - since > HANG_SECONDS


def finish(name: str, ok: bool, message: str) -> None:
    print((f"WINDOW {name} OK " if ok else f"WINDOW {name} FAILED: ") + message, flush=True)
    os._exit(0 if ok else 1)


def view3d():
    """(window, area, region) of the first window's 3D view."""
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            region = next(r for r in area.regions if r.type == "WINDOW")
            return window, area, region
    raise RuntimeError("no 3D view in the window")


def press(kind: str) -> None:
    """A simulated key press and release in the window (Blender runs with --enable-event-simulate)."""
    window, _area, _region = view3d()
    window.event_simulate(type=kind, value="PRESS")
    window.event_simulate(type=kind, value="RELEASE")


def ticking(name: str, step):
    """A timer function that runs `step` and fails the script with the traceback of what it raises."""
    def tick():
        try:
            return step()
        except Exception:
            finish(name, False, traceback.format_exc())

    return tick
