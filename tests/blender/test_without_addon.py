"""A live, unbaked file opened without the add-on never shows a wrong pose silently: at a
scene frame its saved mesh is not right for, the live modifier shows the text "animanifold
add-on required" in its place; the object carries a note saying why (bpy 4.5, the file
opened in a fresh process that never imports the add-on)."""

from __future__ import annotations

import json

import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import run_fresh_blender  # noqa: E402

pytestmark = pytest.mark.blender

PROBE = r"""
import json, sys
import bpy
blend, name, frames = sys.argv[1], sys.argv[2], [float(f) for f in sys.argv[3].split(",")]
assert "animanifold_blender" not in sys.modules
bpy.ops.wm.open_mainfile(filepath=blend)
obj = bpy.data.objects[name]
out = {"note": obj.get("animanifold_note")}
for f in frames:
    bpy.context.scene.frame_set(int(f), subframe=f - int(f))
    me = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    out[str(f)] = {"warning": "animanifold_add_on_required" in me.attributes, "vertices": len(me.vertices)}
bpy.ops.wm.read_factory_settings(use_empty=True)
print("PROBE" + json.dumps(out))
"""


def probe(blend, name, frames):
    out = run_fresh_blender(PROBE, str(blend), name, ",".join(map(str, frames)))
    line = [ln for ln in out.splitlines() if ln.startswith("PROBE")][-1]
    return json.loads(line[5:])


def saved_live(demo, tmp_path, frame, **settings):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "live.blend"))
    # keyframes only: the demo's keys are far apart, so frame 17 lies inside a topology interval
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    for key, value in settings.items():
        setattr(man.animanifold, key, value)
    bpy.context.scene.frame_set(frame)
    bpy.ops.wm.save_mainfile()
    return man


def test_a_driven_interval_plays_within_it_and_warns_outside(demo, tmp_path):
    man = saved_live(demo, tmp_path, 17)  # inside a topology interval: the live modifier moves the mesh
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    lo, hi = cache.topology_interval(17.0, "t")
    inside, outside = (lo + hi) / 2, hi + 10
    result = probe(tmp_path / "live.blend", man.name, [inside, outside, lo - 10])
    assert "add-on" in result["note"]
    assert not result[str(float(inside))]["warning"]
    assert result[str(float(inside))]["vertices"] == len(cache.slice(inside).vertices)
    assert result[str(float(outside))]["warning"] and result[str(float(lo - 10))]["warning"]
    assert result[str(float(outside))]["vertices"] > 0  # the text's


def test_a_handler_written_frame_warns_at_other_frames(demo, tmp_path):
    man = saved_live(demo, tmp_path, 20, smooth_levels=1)  # frames refined by OpenSubdiv: written by the handler
    result = probe(tmp_path / "live.blend", man.name, [20.0, 20.5, 30.0])
    assert not result["20.0"]["warning"] and not result["20.5"]["warning"]  # within a frame: motion blur's reach
    assert result["30.0"]["warning"]


def test_the_warning_is_not_shown_with_the_addon(demo, tmp_path):
    man = saved_live(demo, tmp_path, 20, smooth_levels=1)
    for frame in (30, 5, 45):
        bpy.context.scene.frame_set(frame)
        me = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        assert "animanifold_add_on_required" not in me.attributes, f"frame {frame}"
