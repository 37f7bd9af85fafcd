"""Helpers shared by the Blender tests (import after pytest.importorskip("bpy"))."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import bpy
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "blender_scenes"
DATA = ROOT.parent / "shared" / "data"

# -- helpers ---------------------------------------------------------------------

def eval_corners(obj, frame=None) -> np.ndarray:
    """(T, 3, 3) loop-triangle corner positions of the evaluated mesh, local space."""
    if frame is not None:
        bpy.context.scene.frame_set(frame)
    ob_eval = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ob_eval.to_mesh()
    try:
        return mesh_corners(mesh)
    finally:
        ob_eval.to_mesh_clear()


def select_pair(source, target) -> None:
    """Only `source` and `target` selected, `target` active (Morph Selected's inputs)."""
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    source.select_set(True)
    target.select_set(True)
    bpy.context.view_layer.objects.active = target


def shown(obj):
    """The mesh `obj` shows (and renders, exports) at the current frame: its evaluated
    mesh. A live manifold object's own mesh holds its topology interval's middle frame;
    its "Animanifold Live" modifier moves the vertices to the frame."""
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


def mesh_corners(mesh) -> np.ndarray:
    mesh.calc_loop_triangles()
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    tv = np.empty(3 * len(mesh.loop_triangles), np.int32)
    mesh.loop_triangles.foreach_get("vertices", tv)
    return co.reshape(-1, 3).astype(np.float64)[tv.reshape(-1, 3)]


def triangle_looks(mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per loop triangle: corner positions (T, 3, 3) in local space, active-map UVs (T, 3, 2) and
    material index (T,)."""
    mesh.calc_loop_triangles()
    T = len(mesh.loop_triangles)
    loops = np.empty(3 * T, np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    material_index = np.empty(T, np.int32)
    mesh.loop_triangles.foreach_get("material_index", material_index)
    uv = np.empty(2 * len(mesh.loops), np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    return mesh_corners(mesh), uv.reshape(-1, 2)[loops.reshape(-1, 3)].astype(np.float64), material_index


def mesh_vertices(mesh) -> np.ndarray:
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def canonical(corners: np.ndarray, decimals: int | None = None) -> np.ndarray:
    """Triangles (T, 3, 3) as a sorted (T, 9) table, each triangle rotated (keeping its
    orientation) to start at its lexicographically smallest corner."""
    c = np.asarray(corners, dtype=np.float64)
    if decimals is not None:
        c = np.round(c, decimals)
    T = len(c)
    keys = c.reshape(T * 3, 3)
    order = np.lexsort(keys.T[::-1]).argsort().reshape(T, 3)  # rank of each corner
    start = order.argmin(axis=1)
    idx = (start[:, None] + np.arange(3)[None, :]) % 3
    rotated = np.take_along_axis(c, idx[:, :, None], axis=1).reshape(T, 9)
    return rotated[np.lexsort(rotated.T[::-1])]


def scene_state() -> dict:
    """What a failed operator must leave unchanged."""
    scene = bpy.context.scene
    vl = bpy.context.view_layer
    return {
        "objects": sorted(o.name for o in bpy.data.objects),
        "meshes": sorted(m.name for m in bpy.data.meshes),
        "collections": sorted(c.name for c in bpy.data.collections),
        "node_groups": sorted(g.name for g in bpy.data.node_groups),
        "hidden": sorted(o.name for o in vl.objects if o.hide_get()),
        "hide_render": sorted(o.name for o in bpy.data.objects if o.hide_render),
        "selected": sorted(o.name for o in vl.objects if o.select_get()),
        "active": vl.objects.active.name if vl.objects.active else None,
        "frame": (scene.frame_current, scene.frame_subframe),
        "modifiers": {o.name: [m.name for m in o.modifiers] for o in bpy.data.objects},
    }


def run_then_undo(operator, step: str, made: str, hidden: str) -> None:
    """Runs `operator` as the interface does, checks that it made the object `made` and hid
    `hidden`, then undoes it: `made` is gone and the scene is as before. Redo is the caller's."""
    before = scene_state()
    bpy.ops.ed.undo_push(message=f"before {step}")
    assert operator() == {"FINISHED"}
    # Operators called from Python in background mode push no undo step of their own;
    # push the one the UI pushes when the operator (bl_options UNDO) finishes.
    bpy.ops.ed.undo_push(message=step)
    assert made in bpy.data.objects and bpy.data.objects[hidden].hide_get()
    bpy.ops.ed.undo()
    assert made not in bpy.data.objects
    assert scene_state() == before


def run_fresh_blender(script: str, *args: str, timeout: int = 240) -> str:
    """Runs `script` in a fresh python3 process with bpy, WITHOUT the add-on or the
    animanifold package on sys.path; returns its stdout."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)}
    # bpy can hang at interpreter exit after reading Alembic (its delayed file-close thread):
    # a script that got to its end leaves at once, its output flushed; a failure raised before.
    script += "\nimport os as _os, sys as _sys\n_sys.stdout.flush(); _sys.stderr.flush(); _os._exit(0)\n"
    proc = subprocess.run([sys.executable, "-c", script, *args], capture_output=True, text=True, env=env,
                          timeout=timeout, cwd="/")
    if proc.returncode != 0:
        raise AssertionError(f"fresh Blender process failed ({proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc.stdout


# -- Debian's blender 3.4 binary -----------------------------------------------------

BLENDER = shutil.which("blender") or "/usr/bin/blender"
NO_BLENDER_BINARY = "Debian's blender binary (/usr/bin/blender) is not installed"


def _packed_addon_and_env(tmp_path: Path) -> tuple[Path, dict]:
    """The add-on zip (scripts/package_addon.py) and an environment for Debian's Blender that
    keeps its user folders in tmp_path and its embedded Python away from ours."""
    zip_path = tmp_path / "animanifold_blender.zip"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "package_addon.py"), "--output", str(zip_path)],
                   check=True, capture_output=True, text=True)
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"), BLENDER_USER_CONFIG=str(tmp_path / "config"))
    env.pop("PYTHONPATH", None)
    # Blender's embedded Python derives its prefix from the python3 on PATH: keep a
    # pyenv (or venv) interpreter that runs pytest from hiding Debian's dist-packages.
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                  if ".pyenv" not in p and "/venv" not in p and "/.venv" not in p)
    for key in [k for k in env if k.startswith("PYENV") or k == "VIRTUAL_ENV"]:
        env.pop(key)
    return zip_path, env


def run_blender_binary_smoke(tmp_path: Path, script: str) -> subprocess.CompletedProcess:
    """Packs the add-on zip and runs tests/blender/scripts/<script> under Debian's
    `blender -b --factory-startup --python-exit-code 1` with arguments
    (zip, blender_scenes/, tmp_path); returns the finished process."""
    zip_path, env = _packed_addon_and_env(tmp_path)
    return subprocess.run(
        [BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
         str(ROOT / "tests" / "blender" / "scripts" / script), "--", str(zip_path), str(SCENES), str(tmp_path)],
        capture_output=True, text=True, env=env, timeout=300,
    )


XVFB = shutil.which("Xvfb")
NO_XVFB = "Xvfb (Debian's xvfb, a virtual screen) is not installed"


def run_blender_in_window(tmp_path: Path, script: str) -> subprocess.CompletedProcess:
    """Runs tests/blender/scripts/<script> in Debian's Blender with a real window, on a virtual
    screen of its own (Xvfb on a free display), with simulated events enabled; arguments (zip,
    tmp_path). The script quits Blender itself (os._exit) with its verdict."""
    zip_path, env = _packed_addon_and_env(tmp_path)
    read, write = os.pipe()
    screen = subprocess.Popen([XVFB, "-displayfd", str(write), "-screen", "0", "1280x800x24", "-nolisten", "tcp"],
                              pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    try:
        with os.fdopen(read) as display:
            number = display.readline().strip()
        if not number:
            raise RuntimeError("Xvfb did not start")
        env["DISPLAY"] = f":{number}"
        return subprocess.run(
            [BLENDER, "--factory-startup", "--enable-event-simulate", "--python",
             str(ROOT / "tests" / "blender" / "scripts" / script), "--", str(zip_path), str(tmp_path)],
            capture_output=True, text=True, env=env, timeout=300,
        )
    finally:
        screen.terminate()
        screen.wait(timeout=10)


class RecordingProgressBar:
    """A window manager's progress bar that records its calls: ("begin", lo, hi),
    ("update", value), ("end",); `values` are the updates in order."""

    def __init__(self):
        self.calls = []

    def progress_begin(self, lo, hi):
        self.calls.append(("begin", lo, hi))

    def progress_update(self, value):
        self.calls.append(("update", value))

    def progress_end(self):
        self.calls.append(("end",))

    @property
    def values(self) -> list:
        return [c[1] for c in self.calls if c[0] == "update"]

    def assert_filled_once_in_order(self) -> None:
        """Begun at 0..100, ended, and updated with non-decreasing values inside it."""
        assert self.calls[0] == ("begin", 0, 100) and self.calls[-1] == ("end",)
        assert self.values == sorted(self.values) and 0 <= self.values[0] and self.values[-1] <= 100


def modal_stand_in(cls, calls=None, **state):
    """(modal, op): a modal operator's state (what invoke() leaves on it, given as `state`)
    on a stand-in with `cls`'s methods bound to it, since Blender operators cannot be made
    outside an operator call and modal() needs a window's events. `op.reports` records
    what the operator reports; the operator's bar (`_progress`, begun by invoke()) records
    into `calls`."""
    op = SimpleNamespace(_timer="the timer", reports=[], **state)
    op.report = lambda kind, text: op.reports.append((set(kind), text))
    for name in ("_tick", "_job_done", "_finish", "_stop_waiting", "cancel", "_cancelled_text", "_failure_text",
                 "_next_job", "_job_for", "_job_progress", "_start_job", "_start_steps", "_start", "_arguments",
                 "_options"):
        if hasattr(cls, name):
            setattr(op, name, functools.partial(getattr(cls, name), op))
    for name in ("_steps", "_status_label", "_job_name"):
        if name not in state and hasattr(cls, name):
            setattr(op, name, getattr(cls, name))
    if "_progress" not in state and hasattr(cls, "_job_progress"):
        op._progress = op._job_progress(ModalWindowManager(calls if calls is not None else []))
    return functools.partial(cls.modal, op), op


class ModalWindowManager:
    """What a modal operator asks of the window manager once its job runs, recorded in
    `calls` (bpy has no window to give one)."""

    def __init__(self, calls):
        self.calls = calls

    def progress_begin(self, lo, hi):
        pass  # begun by invoke(), before the stand-in's state is what the test looks at

    def event_timer_add(self, step, window=None):
        self.calls.append(("timer added", step))
        return "the timer"

    def modal_handler_add(self, operator):
        self.calls.append(("modal handler added",))

    def event_timer_remove(self, timer):
        self.calls.append(("timer removed", timer))

    def progress_update(self, value):
        self.calls.append(("progress", value))

    def progress_end(self):
        self.calls.append(("progress end",))


def record_core_progress(module, monkeypatch) -> tuple[list, list]:
    """(steps, ended): `module`'s Progress replaced by one that records each (step,
    fraction) the core reports and each end() of the bar."""
    steps, ended = [], []

    class Recording(module.Progress):
        def __call__(self, step, fraction):
            steps.append((step, fraction))
            return super().__call__(step, fraction)

        def end(self):
            ended.append(True)
            super().end()

    monkeypatch.setattr(module, "Progress", Recording)
    return steps, ended


class ModalContext:
    """bpy.context for a modal stand-in: its window manager and the workspace's status line
    recorded in `calls`, everything else Blender's."""

    def __init__(self, calls):
        self.window_manager = ModalWindowManager(calls)
        self.workspace = SimpleNamespace(status_text_set=lambda text: calls.append(("status", text)))

    def __getattr__(self, name):
        return getattr(bpy.context, name)


def modal_event(kind: str, value: str = "NOTHING") -> SimpleNamespace:
    """An event as modal() reads it: its type and value."""
    return SimpleNamespace(type=kind, value=value)


def until_done(modal, calls, ticks: int = 2400):
    """Sends `modal` timer events, 0.05 s apart, until it returns something other than
    RUNNING_MODAL, and returns that (None after `ticks` events: a bound against a hang, not an
    assertion on time)."""
    for _ in range(ticks):
        result = modal(ModalContext(calls), modal_event("TIMER"))
        if result != {"RUNNING_MODAL"}:
            return result
        time.sleep(0.05)
    return None
