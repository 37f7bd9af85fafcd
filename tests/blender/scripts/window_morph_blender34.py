"""Morph Selected as the interface runs it, in a real window (Debian's Blender 3.4 on a virtual
screen: Xvfb), not under -b: invoked from the 3D view it goes modal (the core in a worker thread),
the main thread's timers and the view's redraws go on while the job's stages advance, and it ends
with the object made; a second morph, held at its conforming stage, cancelled with Esc (a simulated key press) adds
nothing. Run:
    blender --factory-startup --enable-event-simulate --python window_morph_blender34.py -- ZIP [DIR]

Prints "WINDOW MORPH OK ..." as its last line and quits with status 0; on a failure it prints
"WINDOW MORPH FAILED: <why>" and quits with status 1.
"""
import os
import sys
import time

import addon_utils
import bpy

zip_path = sys.argv[sys.argv.index("--") + 1]
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # tests/, for helpers
from helpers import window_script  # noqa: E402
from helpers.blender_helpers import select_pair  # noqa: E402
from helpers.window_script import view3d  # noqa: E402
from helpers.held_morph import BEFORE_THE_HOLD, HELD_METHOD, HOLD  # noqa: E402
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)

from animanifold_blender import ops_morph  # noqa: E402  (the installed copy)

state = {"phase": "start", "began": time.perf_counter(), "redraws": 0, "stages": set()}
jobs = []  # every MorphJob the operator starts, to watch from here


class WatchedJob(ops_morph.MorphJob):
    def __init__(self, *args, **kwargs):
        if state.get("hold"):  # the core waits there (its test hold), whatever the machine's speed
            kwargs["test_hold"], kwargs["method"] = state["hold"], HELD_METHOD
        super().__init__(*args, **kwargs)
        jobs.append(self)


ops_morph.MorphJob = WatchedJob


def finish(ok: bool, message: str) -> None:
    window_script.finish("MORPH", ok, message)


def count_redraw(*_args):
    state["redraws"] += 1


def start_morph(source, target) -> None:
    """Morph Selected on the pair, invoked from the 3D view as a button or shortcut would."""
    select_pair(source, target)
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        result = bpy.ops.animanifold.morph_selected("INVOKE_DEFAULT")
    if result != {"RUNNING_MODAL"}:
        finish(False, f"invoked from the 3D view, Morph Selected returned {result}, not RUNNING_MODAL")


def step():
    scene = bpy.context.scene
    if window_script.stuck(state["began"]):
        finish(False, f"stuck in phase {state['phase']}")
    if state["phase"] == "start":
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o)
        scene.frame_start, scene.frame_end = 1, 24
        bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0)
        state["source"] = bpy.context.active_object.name
        bpy.ops.mesh.primitive_torus_add(major_segments=16, minor_segments=8, major_radius=0.8, minor_radius=0.3)
        state["target"] = bpy.context.active_object.name
        start_morph(bpy.data.objects[state["source"]], bpy.data.objects[state["target"]])
        state["phase"], state["t"] = "morphing", time.perf_counter()
        return 0.01
    if state["phase"] == "morphing":
        name = f"{state['source']}_to_{state['target']}"
        if name not in bpy.data.objects:
            if jobs and not jobs[-1].done:
                state["stages"].add(jobs[-1].stage)  # the timer (main thread) runs while the job does
                state["ticks"] = state.get("ticks", 0) + 1
            return 0.01
        morph = bpy.data.objects[name]
        if not morph.animanifold.is_manifold:
            finish(False, f"{name} is not a manifold object")
        from animanifold_blender import object_manifold

        validity = object_manifold.manifold_for(morph).validity
        if not validity["ends_reproduced"]:
            finish(False, f"ends not reproduced: {validity['source_distance']}, {validity['target_distance']}")
        scene.frame_set(12)
        if len(morph.data.polygons) == 0:
            finish(False, "the middle frame is empty")
        if len(jobs) != 1 or not jobs[0].done or jobs[0].cancelled:
            finish(False, f"the morph did not run as one modal job: {len(jobs)} jobs")
        state["first"] = f"{name} in {time.perf_counter() - state['t']:.2f} s"
        # a second pair, held 30 s at its conforming stage, cancelled with Esc right after it starts
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0, location=(4, 0, 0))
        big = bpy.context.active_object
        bpy.ops.mesh.primitive_torus_add(location=(4, 0, 0))
        ring = bpy.context.active_object
        state["before"] = set(bpy.data.objects.keys())
        state["hold"] = HOLD
        start_morph(big, ring)
        state["phase"], state["t"] = "cancelling", time.perf_counter()
        return 0.2
    if state["phase"] == "cancelling":
        window_script.press("ESC")
        state["phase"], state["esc"] = "cancelled", time.perf_counter()
        return 0.05
    if state["phase"] == "cancelled":
        job = jobs[-1]
        if not job.done:
            if window_script.stuck(state["esc"]):  # not cancelled, it would have ended after its hold
                finish(False, f"the job still runs {window_script.HANG_SECONDS:g} s after Esc")
            return 0.05
        if not job.cancelled:
            finish(False, f"Esc did not cancel the job (it ended at its {job.stage} stage)")
        if job.stage not in BEFORE_THE_HOLD:  # the held stage ended: the cancel waited for the hold
            finish(False, f"Esc took effect only after the held stage ended (at the {job.stage} stage)")
        time.sleep(0.3)  # the operator's next timer event ends it
        state["phase"] = "check"
        return 0.5
    if state["phase"] == "check":
        added = set(bpy.data.objects.keys()) - state["before"]
        if added:
            finish(False, f"the cancelled morph added {sorted(added)}")
        finish(True, f"{bpy.app.version_string}: {state['first']} (while it ran: {state.get('ticks', 0)} "
                     f"timer ticks, stages {sorted(state['stages'])}); Esc cancelled the second after {state['esc'] - state['t']:.2f} s "
                     f"in {time.perf_counter() - state['esc']:.2f} s, nothing added; {state['redraws']} redraws of "
                     "the 3D view in all")
    return 0.05


bpy.types.SpaceView3D.draw_handler_add(count_redraw, (), "WINDOW", "POST_PIXEL")
bpy.app.timers.register(window_script.ticking("MORPH", step), first_interval=0.5)
