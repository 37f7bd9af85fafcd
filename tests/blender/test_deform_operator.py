"""animanifold.deform (issue 5, §4.6.2): anchor/handle vertex groups and an Empty
deform a plain mesh, or a manifold object through space and time."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import (BLENDER, NO_BLENDER_BINARY, ModalContext, mesh_vertices, modal_event, modal_stand_in,  # noqa: E402
                                     record_core_progress, run_blender_binary_smoke, scene_state, shown, until_done)

pytestmark = pytest.mark.blender


def custom(obj) -> dict:
    return {k: (list(v) if hasattr(v, "__len__") and not isinstance(v, str) else v) for k, v in obj.items()
            if k.startswith("animanifold_deform")}


def state(obj) -> dict:
    """Scene state plus what the deform operator may touch on `obj`."""
    out = scene_state()
    out["vertices"] = mesh_vertices(obj.data).tolist()
    out["custom"] = custom(obj)
    if obj.animanifold.is_manifold:
        out["cache_path"] = obj.animanifold.cache_path
    return out


def add_group(obj, name, indices):
    group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
    group.add([int(i) for i in indices], 1.0, "REPLACE")
    return group


def add_empty(location=(0.0, 0.0, 0.0)):
    empty = bpy.data.objects.new("Handle Empty", None)
    bpy.context.scene.collection.objects.link(empty)
    empty.location = location
    bpy.context.view_layer.update()
    return empty


def activate(obj):
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)


def world(obj, local):
    m = np.array(obj.matrix_world)
    return local @ m[:3, :3].T + m[:3, 3]


@pytest.fixture()
def sphere(empty_scene):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0, location=(1.0, 2.0, 0.0))
    obj = bpy.context.active_object
    obj.scale = (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    v = mesh_vertices(obj.data)
    add_group(obj, "anchor", np.flatnonzero(v[:, 2] < -0.5))
    add_group(obj, "handle", np.flatnonzero(v[:, 2] > 0.7))
    empty = add_empty((1.0, 2.0, 2.0))
    obj.animanifold_deform.empty = empty
    activate(obj)
    return obj, empty


def test_plain_mesh_anchors_stay_and_handles_follow_the_empty(sphere):
    obj, empty = sphere
    v0 = mesh_vertices(obj.data)
    anchors, handles = np.flatnonzero(v0[:, 2] < -0.5), np.flatnonzero(v0[:, 2] > 0.7)
    # First use records where the Empty is and changes no vertex.
    assert bpy.ops.animanifold.deform() == {"FINISHED"}
    np.testing.assert_array_equal(mesh_vertices(obj.data), v0)
    assert obj["animanifold_deform_empty"] == empty.name
    # Not moved: nothing to do.
    assert bpy.ops.animanifold.deform() == {"CANCELLED"}

    empty.location.z += 1.0  # world units; the object is scaled by 2
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform(method="graph") == {"FINISHED"}
    v1 = mesh_vertices(obj.data)
    np.testing.assert_allclose(v1[anchors], v0[anchors], atol=1e-6)
    np.testing.assert_allclose(v1[handles], v0[handles] + [0, 0, 0.5], atol=1e-6)
    free = np.setdiff1d(np.arange(len(v0)), np.union1d(anchors, handles))
    dz = (v1 - v0)[free, 2]
    assert (dz > -1e-6).all() and (dz < 0.5 + 1e-6).all() and dz.max() > 0.2

    # A quarter turn of the Empty about its own z axis turns the handles about it (world space).
    before = world(obj, v1)
    empty.rotation_euler.z = math.pi / 2
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform(method="dual") == {"FINISHED"}
    after = world(obj, mesh_vertices(obj.data))
    c = np.array(empty.location)
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(after[handles], (before[handles] - c) @ R.T + c, atol=1e-5)
    np.testing.assert_allclose(after[anchors], before[anchors], atol=1e-5)


def test_plain_mesh_deform_is_undoable(sphere):
    obj, empty = sphere
    name = obj.name
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # records the rest
    v0 = mesh_vertices(obj.data)
    bpy.ops.ed.undo_push(message="before deform")
    empty.location.x += 0.7
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform() == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Laplacian Deform")
    assert not np.allclose(mesh_vertices(bpy.data.objects[name].data), v0)
    bpy.ops.ed.undo()
    np.testing.assert_array_equal(mesh_vertices(bpy.data.objects[name].data), v0)


def fails(obj, match, **kwargs):
    before = state(obj)
    with pytest.raises(RuntimeError, match=match):
        bpy.ops.animanifold.deform(**kwargs)
    assert state(obj) == before, "a failed Deform changed the scene"


def test_plain_mesh_failures_are_reported_and_change_nothing(sphere):
    obj, empty = sphere
    fails(obj, r"no vertex group 'pins' for the anchors", anchor_group="pins")
    fails(obj, r"no vertex group 'grab' for the handles", handle_group="grab")
    obj.vertex_groups.new(name="nothing")
    fails(obj, r"vertex group 'nothing' of 'Sphere' \(handles\) has no vertices", handle_group="nothing")
    fails(obj, r"has no handle vertices", handle_group="")
    fails(obj, r"Regularise .* manifold objects only", regularise=True)
    fails(obj, r"there is no object 'Nope'", empty="Nope")
    fails(obj, r"'Sphere' is a mesh, not an Empty", empty="Sphere")
    obj.animanifold_deform.empty = None
    fails(obj, r"choose an Empty")
    obj.animanifold_deform.empty = empty
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # records the rest
    empty.location.x += 1.0
    bpy.context.view_layer.update()
    # The anchors and handles touch nothing else on one side: a component without constraints.
    bpy.ops.mesh.primitive_plane_add(location=(5, 0, 0))
    plane = bpy.context.active_object
    plane.select_set(False)
    activate(obj)
    # A Deformer error keeps its message: 'error' boundary rule on an open mesh needing constraints.
    bpy.ops.object.select_all(action="DESELECT")
    activate(plane)
    add_group(plane, "handle", [0])
    plane.animanifold_deform.empty = empty
    plane["animanifold_deform_rest"] = [float(x) for x in np.eye(4).reshape(-1)]
    plane["animanifold_deform_empty"] = empty.name
    fails(plane, r"Deform of 'Plane' failed: .*constraint", anchor_group="", method="dual", boundary="error")
    plane.shape_key_add(name="Basis")
    fails(plane, r"'Plane' has shape keys")


def test_poll(empty_scene):
    assert not bpy.ops.animanifold.deform.poll()
    add_empty()
    activate(bpy.data.objects["Handle Empty"])
    assert not bpy.ops.animanifold.deform.poll()
    bpy.ops.mesh.primitive_cube_add()
    assert bpy.ops.animanifold.deform.poll()
    assert not bpy.ops.animanifold.deform_store.poll()  # not a manifold object


# -- manifold objects ------------------------------------------------------------------

@pytest.fixture()
def manifold_object(demo, tmp_path):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "deform.blend"))
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    activate(man)
    return man


def slice_at(manifold, frame):
    s = manifold.slice(float(frame))
    return np.asarray(s.vertices), np.asarray(s.faces)


def constrain_by_height(man, frame: int, handles_above: float, anchors_below: float = 0.3):
    """At `frame`, the slice's vertices above the `handles_above` quantile of height become
    the handle group and those below `anchors_below` the anchor group; a new Empty drives
    the handles. Returns the Empty."""
    bpy.context.scene.frame_set(frame)
    v = mesh_vertices(shown(man))
    add_group(man, "handle", np.flatnonzero(v[:, 2] > np.quantile(v[:, 2], handles_above)))
    add_group(man, "anchor", np.flatnonzero(v[:, 2] < np.quantile(v[:, 2], anchors_below)))
    empty = add_empty()
    man.animanifold_deform.empty = empty
    return empty


def canonical_slice(vertices, faces):
    """A frame's triangles as a table that does not depend on the order of the faces or on
    which corner each starts at, and moves little when the points do: each triangle's x, y
    and z sorted over its corners, then each column sorted over the triangles."""
    corners = np.sort(np.round(vertices[faces], 9), axis=1)  # (F, 3 corners, 3 coordinates)
    return np.sort(corners.reshape(len(faces), 9), axis=0)


@pytest.mark.parametrize("method,tolerance", [("graph", 1e-9), ("dual", 1e-3)])
def test_manifold_deform_keeps_frames_bounded_by_anchors_and_moves_the_handles(manifold_object, method, tolerance):
    man = manifold_object
    scene = bpy.context.scene
    old_path = man.animanifold.cache_path
    old = am.load(bpy.path.abspath(old_path))
    # Keyframes 12 and 24, stored one after the other, anchor a band of two keyframes: every
    # Laplacian row touching frames before 24 then only sees fixed or earlier vertices.
    total = 0
    for frame in (12, 24):
        scene.frame_set(frame)
        add_group(man, "anchor", range(len(man.data.vertices)))
        total += len(man.data.vertices)
        assert bpy.ops.animanifold.deform_store() == {"FINISHED"}
    assert len(man["animanifold_deform_anchors"]) == total
    # Frame 36 (a keyframe): the top of the blob is the handle (the groups of frame 24 are gone).
    scene.frame_set(36)
    assert man.vertex_groups.get("anchor") is None
    v36 = mesh_vertices(shown(man))
    top = np.flatnonzero(v36[:, 2] > np.quantile(v36[:, 2], 0.8))
    add_group(man, "handle", top)
    empty = add_empty((0.0, 0.0, 2.0))
    man.animanifold_deform.empty = empty
    assert bpy.ops.animanifold.deform(method=method) == {"FINISHED"}  # records the rest
    assert man.animanifold.cache_path == old_path
    empty.location.x += 0.6
    bpy.context.view_layer.update()
    bpy.ops.ed.undo_push(message="before deform")
    assert bpy.ops.animanifold.deform(method=method) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Laplacian Deform")

    new_path = man.animanifold.cache_path
    assert new_path != old_path and new_path.startswith("//") and ".deform-" in new_path
    assert os.path.isfile(bpy.path.abspath(new_path)) and os.path.isfile(bpy.path.abspath(old_path))
    new = am.load(bpy.path.abspath(new_path))
    np.testing.assert_array_equal(new.simplices, old.simplices)
    assert new.check().is_oriented_manifold
    # Frames up to the anchored keyframe are untouched: the manifold vertices there
    # (a stitched manifold's tets up to frame 24 use only those) and the slices.
    early = old.points[:, 3] <= 24.0 + 1e-9
    np.testing.assert_allclose(new.points[early], old.points[early], atol=tolerance)
    assert np.abs(new.points[~early] - old.points[~early]).max() > 0.1
    for frame in (1, 6, 12, 18, 24) if method == "graph" else (24,):
        (a, fa), (b, fb) = slice_at(old, frame), slice_at(new, frame)
        assert len(fa) == len(fb), frame
        np.testing.assert_allclose(canonical_slice(b, fb), canonical_slice(a, fa), atol=tolerance, err_msg=f"frame {frame}")
    # The handle vertices (keyframe 36 slice vertices are manifold vertices) moved with the Empty.
    s36 = old.slice(36.0)
    h = np.unique(np.asarray(s36.vertex_edges)[top].reshape(-1))
    np.testing.assert_allclose(new.points[h], old.points[h] + [0.6, 0, 0, 0], atol=1e-6)
    # The object shows the new manifold's frame.
    got = mesh_vertices(shown(man))
    np.testing.assert_allclose(np.sort(got, axis=0), np.sort(new.slice(36.0).vertices, axis=0), atol=1e-5)
    # Undo goes back to the previous cache (the file was never overwritten).
    bpy.ops.ed.undo()
    man = bpy.data.objects["Blob_manifold"]
    assert man.animanifold.cache_path == old_path
    scene = bpy.context.scene
    scene.frame_set(30)
    scene.frame_set(36)
    np.testing.assert_allclose(np.sort(mesh_vertices(shown(man)), axis=0), np.sort(s36.vertices, axis=0), atol=1e-5)


def test_selected_slice_faces_make_their_space_time_simplices_handles(manifold_object):
    man = manifold_object
    scene = bpy.context.scene
    scene.frame_set(30)  # between keyframes 24 and 36
    old = am.load(bpy.path.abspath(man.animanifold.cache_path))
    s = old.slice(30.0)
    centres = np.asarray(s.vertices)[np.asarray(s.faces)].mean(1)
    picked = np.flatnonzero(centres[:, 2] > np.quantile(centres[:, 2], 0.9))
    select = np.zeros(len(man.data.polygons), dtype=bool)
    select[picked] = True
    man.data.polygons.foreach_set("select", select)
    v = mesh_vertices(shown(man))
    add_group(man, "anchor", np.flatnonzero(v[:, 2] < np.quantile(v[:, 2], 0.3)))
    empty = add_empty()
    man.animanifold_deform.empty = empty
    options = {"handle_group": "", "method": "uniform", "use_selected_faces": True}
    assert bpy.ops.animanifold.deform(**options) == {"FINISHED"}
    empty.location.y += 0.4
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform(**options) == {"FINISHED"}
    new = am.load(bpy.path.abspath(man.animanifold.cache_path))
    h = np.unique(np.asarray(old.simplices)[np.asarray(s.face_simplex)[picked]].reshape(-1))
    assert len(h) >= 4
    np.testing.assert_allclose(new.points[h], old.points[h] + [0, 0.4, 0, 0], atol=1e-6)
    # The handles span the keyframes on both sides of frame 30.
    assert {24.0, 36.0} <= set(np.round(old.points[h, 3], 6).tolist())


def test_manifold_regularise_adds_vertices_and_stays_a_manifold(manifold_object):
    man = manifold_object
    empty = constrain_by_height(man, 48, handles_above=0.85)
    old = am.load(bpy.path.abspath(man.animanifold.cache_path))
    assert bpy.ops.animanifold.deform() == {"FINISHED"}
    empty.location.z += 2.0
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform(method="graph", regularise=True, time_weight=0.05) == {"FINISHED"}
    new = am.load(bpy.path.abspath(man.animanifold.cache_path))
    summary = new.metadata["regularisation"]
    assert summary["added_vertices"] > 0 and len(new.points) == len(old.points) + summary["added_vertices"]
    assert new.check().is_oriented_manifold
    # Converged: no edge is both longer than ε and stretched, so none is longer than ε or
    # than the longest edge of the input (edges long already are left alone).
    from animanifold.regularisation import edges_of, manhattan_lengths

    w = np.array([1.0, 1.0, 1.0, 0.05])
    longest = manhattan_lengths(old.points, edges_of(old.simplices, len(old.points)), w).max()
    assert summary["converged"] and summary["max_edge_length"] <= max(summary["epsilon"], longest) + 1e-9
    np.testing.assert_array_equal(new.vertex_attributes["source_vertex"][: len(old.points)],
                                  old.vertex_attributes["source_vertex"])
    assert len(man.data.polygons) > 0


def test_manifold_failures_change_nothing(manifold_object):
    man = manifold_object
    scene = bpy.context.scene
    scene.frame_set(36)
    empty = add_empty()
    man.animanifold_deform.empty = empty
    man.animanifold_deform.anchor_group, man.animanifold_deform.handle_group = "anchor", "handle"
    fails(man, r"no vertex group 'anchor' for the anchors")
    add_group(man, "anchor", [0, 1, 2])
    fails(man, r"no vertex group 'handle' for the handles")
    man.vertex_groups.new(name="handle")
    fails(man, r"vertex group 'handle' of 'Blob_manifold' \(handles\) has no vertices")
    add_group(man, "handle", [40, 41])
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # records the rest
    empty.location.x += 0.5
    bpy.context.view_layer.update()
    fails(man, r"Deform of 'Blob_manifold' failed: .*cotangent", method="cotangent")
    man.animanifold.axis = "x"
    fails(man, r"sweep view along x")
    man.animanifold.axis = "t"  # re-slices: the groups are gone
    assert man.vertex_groups.get("anchor") is None
    add_group(man, "anchor", [0, 1, 2])
    add_group(man, "handle", [40, 41])
    # A stored constraint naming a vertex the manifold lacks.
    man["animanifold_deform_anchors"] = [10**7]
    fails(man, r"stored constraints of 'Blob_manifold' name vertex 10000000")
    del man["animanifold_deform_anchors"]
    # The slice mesh edited away from its slice.
    man.data.vertices.add(1)
    fails(man, r"is not its slice at frame 36")


def test_interactive_deform_resolves_on_empty_moves_and_applies(sphere):
    from animanifold_blender import handlers, interactive_deform

    obj, empty = sphere
    v0 = mesh_vertices(obj.data)
    handles = np.flatnonzero(v0[:, 2] > 0.7)
    obj.animanifold_deform.method = "graph"
    obj.animanifold_deform.interactive = True
    assert interactive_deform.session(obj) is not None
    assert handlers.animanifold_interactive_deform_depsgraph_post in bpy.app.handlers.depsgraph_update_post
    empty.location.z += 1.0
    bpy.context.view_layer.update()  # runs depsgraph_update_post
    handlers.animanifold_interactive_deform_depsgraph_post(bpy.context.scene)  # idempotent if it already ran
    v1 = mesh_vertices(obj.data)
    np.testing.assert_allclose(v1[handles], v0[handles] + [0, 0, 0.5], atol=1e-6)
    # Turning Interactive off shows the mesh as it was.
    obj.animanifold_deform.interactive = False
    np.testing.assert_allclose(mesh_vertices(obj.data), v0, atol=1e-6)
    assert interactive_deform.session(obj) is None and not interactive_deform.any_running()
    # On again, move, and Deform applies the interactive result.
    obj.animanifold_deform.interactive = True
    empty.location.z += 1.0
    bpy.context.view_layer.update()
    handlers.animanifold_interactive_deform_depsgraph_post(bpy.context.scene)
    assert bpy.ops.animanifold.deform() == {"FINISHED"}
    assert not obj.animanifold_deform.interactive and interactive_deform.session(obj) is None
    np.testing.assert_allclose(mesh_vertices(obj.data)[handles], v0[handles] + [0, 0, 0.5], atol=1e-6)
    assert not interactive_deform.any_running()


def test_starting_interactive_deform_shows_the_factorisations_steps_on_the_progress_bar(sphere, monkeypatch):
    from animanifold_blender import interactive_deform

    steps, ended = record_core_progress(interactive_deform, monkeypatch)
    obj, _ = sphere
    obj.animanifold_deform.method = "graph"
    obj.animanifold_deform.interactive = True
    assert interactive_deform.session(obj) is not None
    assert [s for s, _ in steps] == ["checks", "laplacian", "factorising"] and ended == [True]
    assert [f for _, f in steps] == sorted(f for _, f in steps)
    obj.animanifold_deform.interactive = False


def test_deform_shows_the_cores_steps_on_the_progress_bar(sphere, monkeypatch):
    from animanifold_blender import deform_apply

    steps, ended = record_core_progress(deform_apply, monkeypatch)
    obj, empty = sphere
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # records the rest: nothing computed
    assert steps == [] and ended == []
    empty.location.z += 1.0
    bpy.context.view_layer.update()
    assert bpy.ops.animanifold.deform() == {"FINISHED"}
    names = [s for s, _ in steps]
    assert names[0] == "checks" and "factorising" in names and names[-1] == "done"
    assert names.index("factorising") < names.index("deforming") < names.index("restoring")  # a round each
    fractions = [f for _, f in steps]
    assert fractions == sorted(fractions) and 0.0 <= fractions[0] and fractions[-1] == 1.0 and ended == [True]



def test_the_modal_deform_cancels_on_esc_leaving_the_mesh_and_writes_in_the_main_thread(sphere):
    """modal() while the job runs (a stand-in operator: Blender operators cannot be made outside
    an operator call, and modal() needs a window's events): view events pass, everything else
    waits; Esc stops the core at its next step and the mesh and the Empty's rest are as they
    were; a finished job's result is written by modal() in the main thread, as execute() does."""
    import threading

    from animanifold_blender import deform_apply, ops_deform
    from animanifold_blender._lib import am as addon_am

    obj, empty = sphere
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # records the rest
    empty.location.z += 1.0
    bpy.context.view_layer.update()
    v0, rest0 = mesh_vertices(obj.data), custom(obj)
    opt = {"anchor_group": "anchor", "handle_group": "handle", "method": "dual", "boundary": "grow",
           "restore": True, "regularise": False, "time_weight": 1.0, "endpoints": "BOTH",
           "use_selected_faces": False}
    calls = []

    event = modal_event

    def operator(call):
        plan, result = deform_apply.plan_deform(bpy.context, obj, opt, empty, lambda *a: None)
        assert plan is not None, result
        return modal_stand_in(ops_deform.ANIMANIFOLD_OT_deform, calls, _job=addon_am.CoreJob(call, plan), _source=obj,
                              _plan=plan)

    reached, esc = threading.Event(), threading.Event()

    def held_at_deforming(plan, progress, interrupted):
        def step(name, fraction):
            if name == "deforming":  # past the factorisation: the solve waits here for Esc
                reached.set()
                esc.wait(30.0)
            return progress(name, fraction)

        return plan.compute(progress=step, interrupted=interrupted)

    modal, op = operator(held_at_deforming)
    assert modal(ModalContext(calls), event("TIMER")) == {"RUNNING_MODAL"}
    assert modal(ModalContext(calls), event("MIDDLEMOUSE", "PRESS")) == {"PASS_THROUGH"}
    assert modal(ModalContext(calls), event("X", "PRESS")) == {"RUNNING_MODAL"}
    assert reached.wait(30.0)
    assert modal(ModalContext(calls), event("ESC", "PRESS")) == {"RUNNING_MODAL"}
    esc.set()
    assert until_done(modal, calls) == {"CANCELLED"}
    assert op._job.cancelled and op._job.stage == "deforming"
    assert ("timer removed", "the timer") in calls and ("progress end",) in calls
    assert any("cancelled" in text for _, text in op.reports)
    np.testing.assert_array_equal(mesh_vertices(obj.data), v0)
    assert custom(obj) == rest0

    modal, op = operator(lambda plan, progress, interrupted: plan.compute(progress, interrupted))
    assert until_done(modal, calls) == {"FINISHED"}, op.reports
    handles = np.flatnonzero(v0[:, 2] > 0.7)
    np.testing.assert_allclose(mesh_vertices(obj.data)[handles], v0[handles] + [0, 0, 0.5], atol=1e-6)
    assert custom(obj) != rest0  # the Empty's new rest is recorded


def test_interactive_cannot_start_without_handles_and_says_why(sphere):
    from animanifold_blender import interactive_deform, live

    obj, _ = sphere
    obj.animanifold_deform.handle_group = "missing"
    obj.animanifold_deform.interactive = True
    assert not obj.animanifold_deform.interactive and interactive_deform.session(obj) is None
    assert "no vertex group 'missing'" in live.last_error(obj)


# -- Debian's blender 3.4 binary -----------------------------------------------------

@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
def test_smoke_blender_binary_deforms_a_stitched_manifold(tmp_path):
    proc = run_blender_binary_smoke(tmp_path, "smoke_deform_blender34.py")
    assert proc.returncode == 0 and "DEFORM SMOKE OK" in proc.stdout, proc.stdout[-4000:] + proc.stderr[-4000:]


def test_interactive_manifold_preview_follows_frames_and_unregister_removes_the_handlers(manifold_object, addon):
    from animanifold_blender import handlers, interactive_deform

    man = manifold_object
    scene = bpy.context.scene
    empty = constrain_by_height(man, 36, handles_above=0.8)
    man.animanifold_deform.method = "graph"
    man.animanifold_deform.interactive = True
    state = interactive_deform.session(man)
    empty.location.x += 0.5
    bpy.context.view_layer.update()
    handlers.animanifold_interactive_deform_depsgraph_post(scene)
    assert state.preview is not None
    for frame in (40, 36):
        scene.frame_set(frame)  # the slicer shows the cache, then the interactive handler the preview
        expected = state.preview.slice(float(frame)).vertices
        np.testing.assert_allclose(np.sort(mesh_vertices(shown(man)), axis=0), np.sort(expected, axis=0), atol=1e-5)
    old_path = man.animanifold.cache_path
    assert bpy.ops.animanifold.deform() == {"FINISHED"}  # applies the interactive result
    assert man.animanifold.cache_path != old_path and not man.animanifold_deform.interactive
    new = am.load(bpy.path.abspath(man.animanifold.cache_path))
    np.testing.assert_allclose(new.points, state.current, atol=1e-12)
    # Interactive again, then unregister: both interactive handlers are gone, nothing dangles; the
    # interactive handler runs after the slicer's on a frame change.
    add_group(man, "handle", [0])  # (applying re-sliced the object: its groups are gone)
    add_group(man, "anchor", [1])
    man.animanifold_deform.interactive = True
    names = lambda lst: [getattr(h, "__name__", "") for h in lst]  # noqa: E731
    post = names(bpy.app.handlers.frame_change_post)
    assert post.index("animanifold_interactive_deform_frame_post") > post.index("animanifold_frame_change_post")
    addon.unregister()
    try:
        assert not interactive_deform.any_running()
        assert "animanifold_interactive_deform_frame_post" not in names(bpy.app.handlers.frame_change_post)
        assert "animanifold_interactive_deform_depsgraph_post" not in names(bpy.app.handlers.depsgraph_update_post)
        assert not hasattr(bpy.types.Object, "animanifold_deform")
    finally:
        addon.register()
