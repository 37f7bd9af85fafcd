"""animanifold.skeleton adds the Voronoi skeleton of a mesh object (chapter 7)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from helpers.blender_helpers import (ModalContext, RecordingProgressBar, modal_event, modal_stand_in, scene_state,  # noqa: E402
                                     until_done)

pytestmark = pytest.mark.blender


def world_vertices(obj) -> np.ndarray:
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    m = np.array(obj.matrix_world)
    v = co.reshape(-1, 3).astype(np.float64)
    return v @ m[:3, :3].T + m[:3, 3]


def test_torus_internal_skeleton_lies_near_its_core_circle(empty_scene):
    bpy.ops.mesh.primitive_torus_add(major_radius=1.0, minor_radius=0.3, major_segments=32, minor_segments=12,
                                     location=(0.5, 0.0, 0.2))
    torus = bpy.context.active_object
    assert bpy.ops.animanifold.skeleton(side="INTERNAL") == {"FINISHED"}
    skeleton = bpy.context.active_object
    assert skeleton is not torus and skeleton.name == "Torus_skeleton"
    v = world_vertices(skeleton) - [0.5, 0.0, 0.2]
    # every skeleton vertex is inside the tube: within the minor radius of the core circle
    distance_to_core = np.hypot(np.hypot(v[:, 0], v[:, 1]) - 1.0, v[:, 2])
    assert len(v) > 0 and distance_to_core.max() < 0.3
    side = np.empty(len(skeleton.data.polygons), np.int32)
    skeleton.data.attributes["side"].data.foreach_get("value", side)
    assert (side == 0).all()
    assert len(torus.data.vertices) == 32 * 12, "the source mesh was changed"


def test_external_skeleton_fills_the_hole(empty_scene):
    bpy.ops.mesh.primitive_torus_add(major_radius=1.0, minor_radius=0.3)
    assert bpy.ops.animanifold.skeleton(side="EXTERNAL") == {"FINISHED"}
    v = world_vertices(bpy.context.active_object)
    assert (np.hypot(v[:, 0], v[:, 1]) < 1.0 + 0.3 + 1e-6).all(), "the external skeleton stays in the convex hull"
    assert (np.hypot(v[:, 0], v[:, 1]) < 0.7 + 1e-6).any(), "some of it spans the hole"


def test_open_mesh_is_refused_and_nothing_is_added(empty_scene):
    bpy.ops.mesh.primitive_grid_add()
    before = scene_state()
    with pytest.raises(RuntimeError, match=r"No skeleton for 'Grid': .*open|boundary"):
        bpy.ops.animanifold.skeleton()
    assert scene_state() == before


def test_convex_shape_has_no_external_skeleton(empty_scene):
    bpy.ops.mesh.primitive_ico_sphere_add()
    before = scene_state()
    assert bpy.ops.animanifold.skeleton(side="EXTERNAL") == {"CANCELLED"}
    assert scene_state() == before


def test_poll_needs_a_mesh(empty_scene):
    bpy.ops.object.empty_add()
    assert not bpy.ops.animanifold.skeleton.poll()


def test_the_cores_steps_drive_the_progress_bar(empty_scene, monkeypatch):
    from animanifold_blender import ops_skeleton

    bar = RecordingProgressBar()

    steps = []

    class Recording(ops_skeleton.Progress):
        def __init__(self, wm, *args, **kwargs):
            super().__init__(bar, *args, **kwargs)

        def __call__(self, step, fraction):
            steps.append(step)
            return super().__call__(step, fraction)

    monkeypatch.setattr(ops_skeleton, "Progress", Recording)
    bpy.ops.mesh.primitive_torus_add(major_radius=1.0, minor_radius=0.3)
    assert bpy.ops.animanifold.skeleton(side="INTERNAL") == {"FINISHED"}
    bar.assert_filled_once_in_order()
    assert steps[:3] == ["checks", "separability", "voronoi"] and "bisectors" in steps



def test_the_modal_skeleton_passes_the_view_on_cancels_on_esc_and_builds_in_the_main_thread(empty_scene):
    """modal() while the job runs (a stand-in operator: Blender operators cannot be made outside
    an operator call, and modal() needs a window's events): timer ticks move the bar, view events
    pass, everything else waits; Esc stops the core at its next step and nothing is added; a
    finished job's object is made by modal() in the main thread, as execute() makes it."""
    import threading

    from animanifold_blender import ops_skeleton
    from animanifold_blender._lib import am
    from animanifold_blender.mesh_input import closed_triangle_mesh

    calls = []

    event = modal_event

    def operator(job, source):
        return modal_stand_in(ops_skeleton.ANIMANIFOLD_OT_skeleton, calls, _job=job, _source=source, side="INTERNAL",
                              max_iterations=4, wrap="BOX")

    bpy.ops.mesh.primitive_torus_add(major_radius=1.0, minor_radius=0.3)
    torus = bpy.context.active_object
    vertices, faces = closed_triangle_mesh(bpy.context, torus)
    objects = len(bpy.data.objects)

    reached, esc = threading.Event(), threading.Event()

    def held_at_separability(v, f, progress, interrupted, **options):
        def step(name, fraction):
            if name == "separability":  # the core waits here until the test has pressed Esc
                reached.set()
                esc.wait(30.0)
            return progress(name, fraction)

        return am.voronoi_skeleton(v, f, progress=step, interrupted=interrupted, **options)

    modal, op = operator(am.CoreJob(held_at_separability, vertices, faces, side="internal", warn=False), torus)
    assert modal(ModalContext(calls), event("TIMER")) == {"RUNNING_MODAL"} and calls[0][0] == "progress"
    assert modal(ModalContext(calls), event("MIDDLEMOUSE", "PRESS")) == {"PASS_THROUGH"}
    assert modal(ModalContext(calls), event("X", "PRESS")) == {"RUNNING_MODAL"}  # no delete while it runs
    assert reached.wait(30.0)  # Esc before the core reached "separability" would stop it at "checks"
    assert modal(ModalContext(calls), event("ESC", "PRESS")) == {"RUNNING_MODAL"}
    esc.set()
    assert until_done(modal, calls) == {"CANCELLED"}
    assert op._job.cancelled and op._job.stage == "separability"
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls
    assert any("cancelled" in text for _, text in op.reports) and len(bpy.data.objects) == objects

    modal, op = operator(am.CoreJob(am.voronoi_skeleton, vertices, faces, side="internal", warn=False), torus)
    assert until_done(modal, calls) == {"FINISHED"}, op.reports
    assert bpy.context.active_object.name == "Torus_skeleton" and len(bpy.data.objects) == objects + 1
