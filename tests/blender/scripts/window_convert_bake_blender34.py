"""Convert and Bake Frames as the interface runs them, in a real window (Debian's Blender 3.4 on a
virtual screen: Xvfb), not under -b: invoked from the 3D view they go modal (the stitch, the
subdivision in a worker thread). Each is first run with its long call held until the operator
asks it to stop and cancelled with Esc (a simulated key press): the scene and the folders are as
they were. Run again, Convert makes the manifold object and Bake its frames; Undo (ed.undo in the
window) takes back the bake, then the object, one step each. Run:
    blender --factory-startup --enable-event-simulate --python window_convert_bake_blender34.py -- ZIP DIR

Prints "WINDOW CONVERT OK ..." as its last line and quits with status 0; on a failure it prints
"WINDOW CONVERT FAILED: <why>" and quits with status 1.
"""
import os
import sys
import time

import addon_utils
import bpy

zip_path, folder = sys.argv[sys.argv.index("--") + 1], sys.argv[sys.argv.index("--") + 2]
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # tests/, for helpers
from helpers import window_script  # noqa: E402
from helpers.window_script import press, view3d  # noqa: E402
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("animanifold_blender", default_set=True, handle_error=None)

from animanifold_blender import sampling  # noqa: E402  (the installed copy)
from animanifold_blender.live_registry import registry  # noqa: E402

state = {"phase": "start", "began": time.perf_counter(), "hold": True, "held": [], "ended": 0}
caches, bakes = os.path.join(folder, "caches"), os.path.join(folder, "bakes")


def held(call):
    """`call` (a long call taking progress and interrupted), held at its first step while
    state["hold"] until the operator's job asks it to stop (Esc): the cancel lands inside it
    whatever the machine's speed."""
    def wrapper(*args, progress=None, interrupted=None):
        if not state["hold"] or interrupted is None:  # run again, or playback's (no job, no Esc)
            return call(*args, progress=progress, interrupted=interrupted)
        state["held"].append(call.__name__)

        def step(name, fraction):
            waited = time.perf_counter()
            while not interrupted() and not window_script.stuck(waited):
                time.sleep(0.01)
            return progress(name, fraction)

        try:
            return call(*args, progress=step, interrupted=interrupted)
        finally:
            state["ended"] += 1

    wrapper.__name__ = call.__name__
    return wrapper


sampling.stitch_keyframes = held(sampling.stitch_keyframes)
registry.subdivisions.subdivided = held(registry.subdivisions.subdivided)


def finish(ok: bool, message: str) -> None:
    window_script.finish("CONVERT", ok, message)


def snapshot() -> dict:
    vl = bpy.context.view_layer
    return {"objects": sorted(bpy.data.objects.keys()), "meshes": sorted(bpy.data.meshes.keys()),
            "collections": sorted(bpy.data.collections.keys()), "groups": sorted(bpy.data.node_groups.keys()),
            "hidden": sorted(o.name for o in vl.objects if o.hide_get()),
            "selected": sorted(o.name for o in vl.objects if o.select_get()),
            "active": vl.objects.active.name if vl.objects.active else None,
            "modifiers": {o.name: [m.name for m in o.modifiers] for o in bpy.data.objects},
            "modes": {o.name: o.animanifold.mode for o in bpy.data.objects},
            "frame": bpy.context.scene.frame_current, "caches": sorted(os.listdir(caches)),
            "bakes": sorted(os.listdir(bakes)) if os.path.isdir(bakes) else []}


def invoke(operator, **options) -> None:
    """`operator` invoked from the 3D view, as its button would be: it must go modal."""
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        result = operator("INVOKE_DEFAULT", **options)
    if result != {"RUNNING_MODAL"}:
        finish(False, f"invoked from the 3D view, {operator.idname()} returned {result}, not RUNNING_MODAL")


def convert():
    invoke(bpy.ops.animanifold.convert_action, sampling="KEYFRAMES", cache_directory=caches)


def bake():
    invoke(bpy.ops.animanifold.bake, alembic=bpy.app.alembic.supported, export="OBJ", directory=bakes)


def undo():
    # Ctrl+Z runs ed.undo in the window (simulated key presses do not reach the undo keymap)
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo()


def start():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    os.makedirs(caches, exist_ok=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 20
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2)
    ball = bpy.context.active_object
    state["source"], state["made"] = ball.name, f"{ball.name}_manifold"
    for frame, x in ((1, 0.0), (10, 2.0), (20, 1.0)):
        ball.location.x = x
        ball.keyframe_insert("location", frame=frame)
    scene.frame_set(5)
    bpy.ops.ed.undo_push(message="the keyframed ball")
    return cancel_then(convert, "converting")


def cancel_then(run, after: str):
    """Starts `run` held, for phase `esc`; `after` is the phase once its cancel is checked."""
    state["before"], state["after"], state["hold"], state["phase"] = snapshot(), after, True, "esc"
    run()
    state["run"] = run
    return 0.2


def esc():
    if len(state["held"]) == state["ended"]:
        return 0.05  # the worker has not reached the held call yet
    press("ESC")
    state["phase"], state["esc"] = "cancelled", time.perf_counter()
    return 0.3


def cancelled():
    if len(state["held"]) != state["ended"]:
        if window_script.stuck(state["esc"]):
            finish(False, f"the held {state['held'][-1]} did not stop after Esc")
        return 0.1
    state["phase"] = "check"
    return 0.5  # the operator's next timer event ends it


def check():
    if snapshot() != state["before"]:
        finish(False, f"after Esc in {state['held'][-1]} the scene is {snapshot()}, not {state['before']}")
    state["hold"], state["phase"] = False, state["after"]
    state["run"]()
    return 0.1


def converting():
    if state["made"] not in bpy.data.objects:
        return 0.1
    made = bpy.data.objects[state["made"]]
    if not made.animanifold.is_manifold or not os.listdir(caches):
        finish(False, "the second Convert made no manifold object or no cache")
    made.animanifold.subdivision_levels = 1  # computed by the property update
    registry.subdivisions.clear()  # so that the bake computes it
    bpy.ops.ed.undo_push(message="one manifold level")
    return cancel_then(bake, "baking")


def baking():
    made = bpy.data.objects[state["made"]]
    collection = made.animanifold.bake_collection
    # The object is BAKED once its frames are built; the bake has ended (committed) once its
    # collection has its own name (".new" while the files are still written).
    if made.animanifold.mode != "BAKED" or collection is None or collection.name.endswith(".new"):
        return 0.1
    if not os.listdir(bakes):
        finish(False, "the second Bake wrote no files")
    undo()
    made = bpy.data.objects.get(state["made"])
    if made is None or made.animanifold.mode != "LIVE":
        finish(False, "Undo did not take back the modal Bake alone")
    undo()  # the manifold level
    undo()
    if state["made"] in bpy.data.objects:
        finish(False, "Undo did not remove the object of the modal Convert")
    if state["source"] not in bpy.data.objects:  # undone past its own step
        finish(False, "Undo removed the keyframed source too: the modal Convert pushed no undo step")
    finish(True, f"{bpy.app.version_string}: Esc cancelled Convert and Bake inside their long calls "
                 f"({state['held']}), nothing added or written; run again they made the object and its "
                 "frames; Undo took each back")


PHASES = {f.__name__: f for f in (start, esc, cancelled, check, converting, baking)}


def step():
    if window_script.stuck(state["began"]):
        finish(False, f"stuck in phase {state['phase']}")
    return PHASES[state["phase"]]()


bpy.app.timers.register(window_script.ticking("CONVERT", step), first_interval=0.5)
