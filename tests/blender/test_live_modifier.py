"""Live playback through the "Animanifold Live" geometry-nodes modifier, in-process with bpy 4.5.

Inside a topology interval the mesh holds the interval's cut (every vertex's
rate, and a frame of it): on integer frames the handler copies the kept frame's
positions and UV map into the mesh and the modifier passes it through; on other
frames the modifier moves the vertices and rebuilds the UV map. What is checked
is what the user sees: the evaluated mesh, against a direct slice of the cache.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import mesh_vertices, run_fresh_blender, shown  # noqa: E402

pytestmark = pytest.mark.blender

MODIFIER = "Animanifold Live"


def convert(obj):
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects[obj.name + "_manifold"]
    return man, am.load(bpy.path.abspath(man.animanifold.cache_path))


def goto(frame: float) -> None:
    bpy.context.scene.frame_set(int(np.floor(frame)), subframe=float(frame - np.floor(frame)))


def corner_uv(mesh, name) -> np.ndarray:
    uv = np.empty(2 * len(mesh.loops), np.float32)
    mesh.uv_layers[name].data.foreach_get("uv", uv)
    return uv.reshape(-1, 2).astype(np.float64)


def corner_vertex(mesh) -> np.ndarray:
    cv = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", cv)
    return cv


def assert_shows(man, cache, frame):
    """The evaluated mesh is the cache's slice at `frame`: positions, faces, UVs, materials."""
    s = cache.slice(frame)
    mesh = shown(man)
    assert len(mesh.polygons) == len(s.faces), f"frame {frame}: face count"
    np.testing.assert_allclose(mesh_vertices(mesh), s.vertices, atol=1e-6, rtol=0, err_msg=f"frame {frame}")
    cv = corner_vertex(mesh)
    np.testing.assert_array_equal(cv.reshape(-1, 3), s.faces, err_msg=f"frame {frame}: faces")
    np.testing.assert_allclose(corner_uv(mesh, man.animanifold.uv_name), s.vertex_attributes["uv"][cv], atol=1e-6,
                               err_msg=f"frame {frame}: UVs")
    mi = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("material_index", mi)
    np.testing.assert_array_equal(mi, s.face_attributes["material_index"], err_msg=f"frame {frame}: materials")
    # The evaluated mesh carries none of the modifier's attributes (renders, exports).
    assert not [a.name for a in mesh.attributes if a.name.startswith("am_")]
    assert mesh.uv_layers.active is not None and mesh.uv_layers.active.name == man.animanifold.uv_name


def snapshot(mesh) -> dict:
    """The data of the object's own mesh (what a write would change)."""
    out = {"counts": (len(mesh.vertices), len(mesh.edges), len(mesh.loops), len(mesh.polygons))}
    for attr in mesh.attributes:
        if attr.data_type in ("FLOAT_VECTOR", "FLOAT2", "INT", "INT32_2D", "BOOLEAN"):
            width = {"FLOAT_VECTOR": 3, "FLOAT2": 2, "INT32_2D": 2}.get(attr.data_type, 1)
            key = "value" if attr.data_type in ("INT", "INT32_2D", "BOOLEAN") else "vector"
            dtype = np.float32 if key == "vector" else (bool if attr.data_type == "BOOLEAN" else np.int32)
            values = np.empty(width * len(attr.data), dtype)
            attr.data.foreach_get(key, values)
            out[attr.name] = values
    return out


def assert_same(a: dict, b: dict, what: str) -> None:
    assert a.keys() == b.keys(), what
    for key in a:
        assert np.array_equal(a[key], b[key]), f"{what}: {key} changed"


def counted(monkeypatch, module, name: str) -> dict:
    """Counts the calls of module.name (replaced by a counting wrapper): {"n": calls}."""
    count = {"n": 0}
    function = getattr(module, name)

    def counting(*args, **kwargs):
        count["n"] += 1
        return function(*args, **kwargs)

    monkeypatch.setattr(module, name, counting)
    return count


@pytest.fixture()
def writes(monkeypatch):
    """Counts the meshes the add-on writes."""
    from animanifold_blender import mesh_writer

    return counted(monkeypatch, mesh_writer, "write_mesh")


@pytest.fixture()
def frame_work(monkeypatch):
    """Records the frames the handler copies into the mesh (write_frame), the frames it
    computes (interval_cuts.interval_frame, but for a cut's own frame) and the corner
    gathers of UV maps (interval_cuts.corner_values), on each frame's first visit: nothing
    is made ahead (cut_prefetch, tested on its own in tests/test_cut_prefetch.py)."""
    from animanifold import cut_prefetch, interval_cuts
    from animanifold_blender import mesh_writer

    monkeypatch.setattr(cut_prefetch, "prefetch", lambda *args: (0, 0))

    work = {"written": [], "computed": [], "gathers": 0}
    write, compute, gather = mesh_writer.write_frame, interval_cuts.interval_frame, interval_cuts.corner_values

    def counted_write(mesh, uv_name, frame):
        scene = bpy.context.scene
        work["written"].append(scene.frame_current + scene.frame_subframe)
        return write(mesh, uv_name, frame)

    def counted_compute(cut, frame):
        if frame != cut.value:
            work["computed"].append(frame)
        return compute(cut, frame)

    def counted_gather(*args):
        work["gathers"] += 1
        return gather(*args)

    monkeypatch.setattr(mesh_writer, "write_frame", counted_write)
    monkeypatch.setattr(interval_cuts, "interval_frame", counted_compute)
    monkeypatch.setattr(interval_cuts, "corner_values", counted_gather)
    return work


def assert_bounds_and_normals(man, s, what):
    """The evaluated object's bounding box and vertex normals are those of slice `s`
    (stale caches would keep another frame's)."""
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get())
    box = np.array([tuple(c) for c in ev.bound_box])
    np.testing.assert_allclose(box.min(0), s.vertices.min(0), atol=1e-5, err_msg=f"{what}: bounds")
    np.testing.assert_allclose(box.max(0), s.vertices.max(0), atol=1e-5, err_msg=f"{what}: bounds")
    from animanifold_blender import mesh_writer

    fresh = bpy.data.meshes.new("fresh")
    try:
        # The smooth normals (the default, as baked) or, without them, Blender's own.
        normals = am.display.slice_normals(s) if man.animanifold.live_normals else None
        mesh_writer.write_mesh(fresh, s.vertices, s.faces, normals=normals)
        expected = np.empty(3 * len(fresh.vertices), np.float32)
        fresh.vertices.foreach_get("normal", expected)
    finally:
        bpy.data.meshes.remove(fresh)
    got = np.empty(3 * len(ev.data.vertices), np.float32)
    ev.data.vertices.foreach_get("normal", got)
    np.testing.assert_allclose(got, expected, atol=1e-4, err_msg=f"{what}: normals")


def modifier_inputs(man) -> dict:
    mod = man.modifiers[MODIFIER]
    return {item.name: mod[item.identifier] for item in mod.node_group.interface.items_tree
            if item.in_out == "INPUT" and item.socket_type != "NodeSocketGeometry"}


def test_inside_an_interval_the_handler_copies_only_kept_frames(demo, writes, frame_work):
    man, cache = convert(demo)  # at frame 1: the first keyframe, written by Convert
    times = cache.metadata["keyframe_times"]  # [1, 12, 24, 36, 48]
    uv_name = man.animanifold.uv_name
    writes["n"] = 0
    goto(2)  # enters the interval (1, 12): one cut written, holding frame 2
    assert writes["n"] == 1 and frame_work["written"] == [] and frame_work["computed"] == [2.0]
    assert man.modifiers[0].name == MODIFIER and man.modifiers[MODIFIER].type == "NODES"
    inputs = modifier_inputs(man)
    assert inputs["Active"] and (inputs["Start"], inputs["End"]) == (times[0], times[1])
    assert inputs["Frame"] == 2.0 and inputs["Cut Frame"] == 6.5
    assert inputs["Animate UV"] and inputs["UV Map"] == uv_name
    before = snapshot(man.data)
    for name in ("am_rate", "am_uv", "am_uv_rate"):
        assert name in before, name
    del before[uv_name], before["position"]
    cv = corner_vertex(man.data)
    frames = (2.0, 2.25, 5.5, 6.5, 7.0, 9.75, 11.5, 3.125, 3.0, 7.0, 11.0)
    integer = [f for f in frames if f == int(f)]
    held = 2.0  # the frame the mesh holds
    for loop in range(2):
        gathers = frame_work["gathers"]
        for frame in frames:
            written = len(frame_work["written"])
            goto(frame)
            assert writes["n"] == 1, f"frame {frame}: the handler wrote the mesh"
            if frame == int(frame) and frame != held:
                held = frame
                assert frame_work["written"][written:] == [frame], f"frame {frame}: not copied once"
            else:  # a subframe (the modifier moves the mesh) or the frame held
                assert len(frame_work["written"]) == written, f"frame {frame}: a frame was copied"
            now = snapshot(man.data)
            uv = now.pop(uv_name).reshape(-1, 2).astype(np.float64)
            positions = now.pop("position").reshape(-1, 3).astype(np.float64)
            assert_same(now, before, f"frame {frame}")  # rates, faces, edges as cut
            s = cache.slice(held)
            np.testing.assert_allclose(positions, s.vertices, atol=1e-6, err_msg=f"frame {frame}: the mesh")
            np.testing.assert_allclose(uv, s.vertex_attributes["uv"][cv], atol=1e-6, err_msg=f"frame {frame}: its UVs")
            assert modifier_inputs(man)["Frame"] == held
            assert_shows(man, cache, frame)
        # Each integer frame computed once; the second loop copies kept frames only.
        assert sorted(frame_work["computed"]) == sorted(set(integer)), f"loop {loop}"
        if loop == 1:
            assert frame_work["gathers"] == gathers, "numpy work on kept frames"
    assert len(frame_work["written"]) > len(set(integer))  # the second loop copied them again


@pytest.mark.parametrize("prisms", [True, False], ids=["prism frames", "tets' slice"])
def test_the_node_graph_plays_the_cores_interval_frame(demo, monkeypatch, prisms):
    """The graph of live_nodes._build mirrors Slicer::interval_frame: with the handler
    silenced once the cut is written, the modifier alone moves the mesh, and the
    evaluated vertices and UVs at times across the interval are the core's interval
    frame there (to float32: the mesh and the modifier hold single precision)."""
    from animanifold_blender import live

    man, cache = convert(demo)
    if not prisms:  # a cache without prisms (from before them): its UVs move inside the interval
        cache = _without_prisms(man)
    goto(5.5)
    frame = cache.interval_frame(5.5)
    lo, hi = frame.interval
    faces = len(frame.slice.faces)
    # Between two keys the prism frame has the source's triangles; the tets' slice about 4x.
    assert faces == cache.metadata["keyframe_faces"] if prisms else faces > 3 * cache.metadata["keyframe_faces"]
    assert modifier_inputs(man)["Active"] and (modifier_inputs(man)["Start"], modifier_inputs(man)["End"]) == (lo, hi)
    monkeypatch.setattr(live, "update_scene", lambda *args, **kwargs: 0)
    times = [lo + 0.25, 5.5, float(np.floor(hi)) if np.floor(hi) < hi else hi - 0.5, hi - 0.25]
    for t in times:
        goto(t)
        expected = frame.at(t)
        mesh = shown(man)
        np.testing.assert_allclose(mesh_vertices(mesh), expected.vertices, atol=float32_tolerance(expected.vertices),
                                   rtol=0, err_msg=f"frame {t}")
        cv = corner_vertex(mesh)
        np.testing.assert_array_equal(cv.reshape(-1, 3), expected.faces, err_msg=f"frame {t}: faces")
        assert len(mesh.polygons) == faces, f"frame {t}: face count"
        uv = expected.vertex_attributes["uv"][cv]
        np.testing.assert_allclose(corner_uv(mesh, man.animanifold.uv_name), uv, atol=float32_tolerance(uv), rtol=0,
                                   err_msg=f"frame {t}: UVs")


def float32_tolerance(values: np.ndarray) -> float:
    """A few roundings of single precision at the magnitude of `values`."""
    return 8 * float(np.finfo(np.float32).eps) * max(1.0, float(np.abs(values).max()))


def test_copied_frames_have_their_own_bounds_and_normals(demo):
    man, cache = convert(demo)
    for frame in (25, 27, 33, 30, 27.5):  # copied by the handler, the cut's own, moved by the modifier
        goto(frame)
        assert_bounds_and_normals(man, cache.slice(frame), f"frame {frame}")
    man.modifiers[MODIFIER].show_viewport = False  # the handler moves the vertices itself (write_positions)
    for frame in (26, 28.5):
        goto(frame)
        assert_bounds_and_normals(man, cache.slice(frame), f"handler-moved frame {frame}")


def test_frames_beyond_the_frame_budget_are_moved_by_the_modifier(demo, frame_work, monkeypatch):
    from animanifold_blender.live_registry import registry

    man, cache = convert(demo)
    goto(25)  # enters (24, 36), whose middle is 30: frame 25 computed and kept
    assert frame_work["computed"] == [25.0] and registry.cuts.frame_nbytes > 0
    monkeypatch.setattr(registry.cuts, "_frame_budget", registry.cuts.frame_nbytes)  # no room for another (the budget preference, stood in)
    for frame in (26, 27, 25, 30, 26, 31):
        goto(frame)
        assert_shows(man, cache, frame)
    # 26, 27, 31 not kept, so not computed either: the modifier moved the mesh to them.
    # 25 was still in the mesh; 30 is the cut's own frame.
    assert frame_work["computed"] == [25.0] and frame_work["written"] == [30.0]
    assert modifier_inputs(man)["Frame"] == 30.0


def test_without_uvs_frames_are_positions_only(demo, frame_work):
    for layer in list(demo.data.uv_layers):
        demo.data.uv_layers.remove(layer)
    demo.data.update()  # (removing a UV map does not tag the mesh: the evaluated one kept it)
    man, cache = convert(demo)
    assert "uv" not in cache.vertex_attributes
    for frame in (25, 26, 27.5, 28, 30):
        goto(frame)
        mesh = shown(man)
        np.testing.assert_allclose(mesh_vertices(mesh), cache.slice(frame).vertices, atol=1e-6, err_msg=f"frame {frame}")
        assert len(mesh.uv_layers) == 0
    assert not modifier_inputs(man)["Animate UV"]
    assert frame_work["written"] == [26.0, 28.0, 30.0] and frame_work["gathers"] == 0


def test_a_node_group_of_an_older_layout_is_replaced(demo):
    from animanifold_blender import live_nodes

    man, cache = convert(demo)
    goto(25)
    old = man.modifiers[MODIFIER].node_group
    old[live_nodes.GROUP_TAG] = live_nodes.GROUP_VERSION - 1  # as a file of an earlier add-on holds it
    goto(26)
    group = man.modifiers[MODIFIER].node_group
    assert group != old and group[live_nodes.GROUP_TAG] == live_nodes.GROUP_VERSION
    assert_shows(man, cache, 26)
    goto(26.5)
    assert_shows(man, cache, 26.5)


def test_crossing_keyframes_and_intervals_writes_once_each(demo, writes):
    man, cache = convert(demo)
    meshes, groups = len(bpy.data.meshes), len(bpy.data.node_groups)
    mesh = man.data
    expected_writes = writes["n"]
    last = ("at", 1.0)  # Convert wrote the first keyframe
    for frame in (3, 4.5, 11, 12, 12.5, 13, 23.5, 24, 24, 30, 12, 11.5, 1, 0, 60, 47.25, 47.5):
        goto(frame)
        interval = cache.topology_interval(min(max(frame, 1), 48))
        key = interval if interval is not None else ("at", min(max(frame, 1), 48))
        if key != last:
            expected_writes += 1
        last = key
        assert writes["n"] == expected_writes, f"frame {frame}"
        assert_shows(man, cache, min(max(frame, 1), 48))
        inputs = modifier_inputs(man)
        assert inputs["Active"] == (interval is not None), f"frame {frame}"
        if interval is not None:
            assert (inputs["Start"], inputs["End"]) == interval
    assert man.data == mesh
    assert len(bpy.data.meshes) == meshes
    assert len(bpy.data.node_groups) == max(groups, 1) == 1  # one shared group (made by Convert's first frame)


def test_an_animation_that_keeps_its_faces_is_played_without_rewriting_the_topology(demo, writes, monkeypatch):
    """Keys and in-between frames of a converted action share the source's faces: after
    Convert's first write, crossing keys and intervals writes layers only, the mesh's
    edges stay as Blender made them, and every frame shows the slice."""
    from animanifold_blender import mesh_writer

    man, cache = convert(demo)
    assert cache.prisms is not None
    edges = snapshot(man.data)[".edge_verts"]
    in_place = counted(monkeypatch, mesh_writer, "_rewrite_in_place")
    writes["n"] = 0
    frames = (3, 4.5, 11, 12, 12.5, 13, 24, 30, 12, 1, 47.5, 48)
    for frame in frames:
        goto(frame)
        assert_shows(man, cache, frame)
        assert np.array_equal(snapshot(man.data)[".edge_verts"], edges), f"frame {frame}: edges rewritten"
        assert man.data.validate(verbose=True) is False, f"frame {frame}"
    shown = [cache.topology_interval(f) or ("at", f) for f in frames]  # what each frame writes, if new
    changes = 1 + sum(a != b for a, b in zip(shown, shown[1:]))
    assert writes["n"] == changes and in_place["n"] == changes  # each over the faces the mesh held


def test_the_first_pass_over_prism_frames_finds_every_cut_and_frame_made_ahead(demo, monkeypatch):
    """Convert's first frame makes the range's cuts and integer frames (cut_prefetch):
    the first pass then cuts nothing and computes no frame, and shows every frame right."""
    from animanifold import interval_cuts

    man, cache = convert(demo)
    assert cache.prisms is not None
    cuts = counted(monkeypatch, interval_cuts, "time_cut")
    made_frames, interval_frame = [], interval_cuts.interval_frame

    def counted_frame(cut, frame):
        if frame != cut.value:  # a cut's own frame is its arrays: nothing made
            made_frames.append(frame)
        return interval_frame(cut, frame)

    monkeypatch.setattr(interval_cuts, "interval_frame", counted_frame)
    scene = bpy.context.scene
    for frame in range(scene.frame_start, scene.frame_end + 1):
        goto(frame)
        assert_shows(man, cache, frame)
    assert cuts["n"] == 0 and made_frames == []


def test_kept_cuts_are_reused_and_match_fresh_ones(demo):
    from animanifold_blender.live_registry import registry

    man, cache = convert(demo)
    goto(5.5)
    first = snapshot(man.data)
    goto(12)
    goto(30)
    registry.cuts.clear()  # the next visit slices again and lets Blender compute the edges
    goto(5.5)
    fresh = snapshot(man.data)
    goto(30)
    goto(5.5)  # from the kept cut, with the kept edges
    assert_same(snapshot(man.data), fresh, "kept cut")
    assert_same(fresh, first, "fresh cut")
    assert man.data.validate(verbose=True) is False  # nothing to fix in a mesh written with kept edges
    assert_shows(man, cache, 5.5)


def test_two_objects_share_the_node_group(demo):
    man, cache = convert(demo)
    demo.hide_set(False)
    bpy.context.view_layer.objects.active = demo
    assert bpy.ops.animanifold.convert_action(sampling="EVERY_N", step=10) == {"FINISHED"}
    other = bpy.data.objects["Blob_manifold.001"]
    other_cache = am.load(bpy.path.abspath(other.animanifold.cache_path))
    goto(17.5)
    assert man.modifiers[MODIFIER].node_group == other.modifiers[MODIFIER].node_group
    assert_shows(man, cache, 17.5)
    assert_shows(other, other_cache, 17.5)
    assert modifier_inputs(man)["Start"] == 12 and modifier_inputs(other)["Start"] == 11


def test_settings_that_need_every_frame_written_release_the_modifier(demo, writes):
    man, cache = convert(demo)
    settings = man.animanifold
    goto(5.5)
    # Sweep views: the modifier passes the mesh through; frames do not move the view.
    settings.axis = "x"
    assert not modifier_inputs(man)["Active"]
    sweep = mesh_vertices(shown(man))
    n = writes["n"]
    goto(7)
    assert writes["n"] == n, "a frame change rewrote an unchanged sweep view"
    np.testing.assert_allclose(mesh_vertices(shown(man)), sweep, atol=0)
    settings.axis = "t"
    assert_shows(man, cache, 7)
    # Smooth normals (the default): the modifier sets them too (Blender 4.5+).
    assert settings.live_normals
    goto(8.5)
    assert modifier_inputs(man)["Active"] and modifier_inputs(man)["Animate Normals"]
    assert_shows(man, cache, 8.5)
    settings.live_normals = False
    goto(8.75)
    assert modifier_inputs(man)["Active"] and not modifier_inputs(man)["Animate Normals"]
    # Frame smoothing: written by the handler every frame.
    settings.smooth_levels = 1
    goto(9.5)
    assert not modifier_inputs(man)["Active"]
    assert len(shown(man).polygons) == 4 * len(cache.slice(9.5).faces)
    settings.smooth_levels = 0
    goto(10.5)
    assert modifier_inputs(man)["Active"]
    assert_shows(man, cache, 10.5)
    # The user switches the modifier off: the handler writes every frame again.
    man.modifiers[MODIFIER].show_viewport = False
    for frame in (3.5, 4.5):
        goto(frame)
        np.testing.assert_allclose(mesh_vertices(man.data), cache.slice(frame).vertices, atol=1e-6)
        assert_shows(man, cache, frame)
    man.modifiers[MODIFIER].show_viewport = True
    goto(5.25)
    assert modifier_inputs(man)["Active"]
    assert_shows(man, cache, 5.25)
    # Time Stretching: the Scene Time is no longer the frame the handler slices at.
    scene = bpy.context.scene
    scene.render.frame_map_new = 50
    goto(6.5)
    assert not modifier_inputs(man)["Active"]
    assert_shows(man, cache, 6.5)
    scene.render.frame_map_new = scene.render.frame_map_old
    goto(7.5)
    assert modifier_inputs(man)["Active"]
    assert_shows(man, cache, 7.5)


def test_bake_releases_and_back_to_live_drives_again(demo):
    man, cache = convert(demo)
    goto(30)
    assert modifier_inputs(man)["Active"]
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    assert not modifier_inputs(man)["Active"]  # the bake shows the frames alone
    goto(31)
    np.testing.assert_allclose(mesh_vertices(shown(man)), cache.slice(31).vertices, atol=1e-6)
    bpy.context.view_layer.objects.active = man
    assert bpy.ops.animanifold.make_live() == {"FINISHED"}
    assert modifier_inputs(man)["Active"]
    goto(32.5)
    assert_shows(man, cache, 32.5)


def test_undo_and_redo(demo):
    man, cache = convert(demo)
    goto(5)
    bpy.ops.ed.undo_push(message="at 5")
    goto(30)
    bpy.ops.ed.undo_push(message="at 30")
    bpy.ops.ed.undo()
    man = bpy.data.objects["Blob_manifold"]
    frame = bpy.context.scene.frame_current
    assert_shows(man, cache, frame)
    for f in (6, 30.5, 7):
        goto(f)
        assert_shows(man, cache, f)
    bpy.ops.ed.redo()
    man = bpy.data.objects["Blob_manifold"]
    goto(29)
    assert_shows(man, cache, 29)


# Fresh python3 + bpy without animanifold: the saved modifier still plays the interval
# it holds (clamped to it outside: no handler writes the next cut), UVs included (the
# mesh holds the frame it was saved at; the modifier moves it to the others).
PROBE = r"""
import json, sys
import bpy, numpy as np
blend, frames = sys.argv[1], [float(f) for f in sys.argv[2].split(",")]
assert "animanifold_blender" not in sys.modules
bpy.ops.wm.open_mainfile(filepath=blend)
obj = bpy.data.objects["Blob_manifold"]
out = {}
for f in frames:
    bpy.context.scene.frame_set(int(f), subframe=f - int(f))
    me = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = np.empty(3 * len(me.vertices), np.float32); me.vertices.foreach_get("co", co)
    uv = np.empty(2 * len(me.loops), np.float32); me.uv_layers.active.uv.foreach_get("vector", uv)
    cv = np.empty(len(me.loops), np.int32); me.loops.foreach_get("vertex_index", cv)
    out[f] = {"co": co.tolist(), "uv": uv.tolist(), "corner_vertex": cv.tolist()}
bpy.ops.wm.read_factory_settings(use_empty=True)
print("PROBE" + json.dumps(out))
"""


def test_save_and_reload(demo, tmp_path):
    blend = tmp_path / "live.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    man, cache = convert(demo)
    goto(20)
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    man = bpy.data.objects["Blob_manifold"]
    assert man.modifiers[MODIFIER].type == "NODES" and modifier_inputs(man)["Active"]
    groups = len(bpy.data.node_groups)
    for frame in (20, 21.5, 24, 26.75, 13.5):
        goto(frame)
        assert_shows(man, cache, frame)
    assert len(bpy.data.node_groups) == groups
    goto(18)
    bpy.ops.wm.save_mainfile()

    out = run_fresh_blender(PROBE, str(blend), "14.5,18,23.25")
    line = [ln for ln in out.splitlines() if ln.startswith("PROBE")][-1]
    probed = {float(k): v for k, v in json.loads(line[5:]).items()}
    for frame in (14.5, 18.0, 23.25):  # inside the saved interval (12, 24); the UV map saved at 18
        s = cache.slice(frame)
        got = probed[frame]
        np.testing.assert_allclose(np.reshape(got["co"], (-1, 3)), s.vertices, atol=1e-6, err_msg=f"frame {frame}")
        np.testing.assert_allclose(np.reshape(got["uv"], (-1, 2)), s.vertex_attributes["uv"][got["corner_vertex"]],
                                   atol=1e-6, err_msg=f"frame {frame}: UVs")


def _read(path, scene) -> np.ndarray:
    image = bpy.data.images.load(str(path))
    try:
        px = np.empty(len(image.pixels), np.float32)
        image.pixels.foreach_get(px)
    finally:
        bpy.data.images.remove(image)
    return px.reshape(scene.render.resolution_y, scene.render.resolution_x, 4)


def _without_prisms(man):
    """The object's cache rewritten without its prisms (as a cache from before them, a morph or
    a subdivided manifold plays): frames between keys are the tets' slice, whose vertices slide
    along edges between different source vertices, so their UVs move with the frame. (A prism
    frame's vertex keeps its source vertex's UV, constant in the demo.)"""
    from animanifold_blender.live_registry import registry

    path = bpy.path.abspath(man.animanifold.cache_path)
    stitched = am.load(path)
    am.save(am.AnimationManifold(stitched.core_complex, stitched.metadata), path)
    registry.forget(path)
    registry.forget_shown()
    tets = am.load(path)
    assert tets.prisms is None
    return tets


def _render(scene, path) -> np.ndarray:
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return _read(path, scene)


def _uv_colour_cycles(man, scene) -> None:
    """Tiny float renders with Cycles whose colour is the UV: any UV error shows."""
    for mat in man.data.materials:
        mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        nodes.clear()
        coords, emit, out = (nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeEmission"),
                             nodes.new("ShaderNodeOutputMaterial"))
        links.new(coords.outputs["UV"], emit.inputs["Color"])
        links.new(emit.outputs[0], out.inputs["Surface"])
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 2
    scene.cycles.use_denoising = False
    if hasattr(scene.cycles, "use_adaptive_sampling"):
        scene.cycles.use_adaptive_sampling = False
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 48, 100
    scene.render.threads_mode, scene.render.threads = "FIXED", 2
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"  # floats: small UV differences show
    scene.render.image_settings.color_depth = "32"


@pytest.mark.slow
def test_render_between_keyframes_matches_the_handler_written_frame(demo, tmp_path, monkeypatch):
    """Cycles renders the modifier's frame (positions and UVs) as it renders the same frame
    written by the handler; with the UVs left as cut, it would not."""
    from animanifold_blender import playback
    from animanifold_blender.live_registry import registry

    man, cache = convert(demo)
    cache = _without_prisms(man)
    scene = bpy.context.scene
    _uv_colour_cycles(man, scene)
    frame = 34.5  # inside (24, 36), away from the cut's middle (30): the modifier moves the mesh
    goto(frame)
    assert modifier_inputs(man)["Active"] and modifier_inputs(man)["Frame"] == 30.0
    driven = _render(scene, tmp_path / "driven.exr")

    monkeypatch.setattr(playback, "can_drive", lambda *a, **k: False)  # the handler writes the frame
    registry.forget_shown()
    goto(frame)
    assert not modifier_inputs(man)["Active"]
    np.testing.assert_allclose(mesh_vertices(man.data), cache.slice(frame).vertices, atol=1e-6)
    written = _render(scene, tmp_path / "written.exr")
    assert written[..., 3].max() > 0.5 and (written[..., 3] > 0.5).mean() > 0.1  # the blob is in view
    assert np.abs(driven - written).max() < 1e-4  # measured 5e-7

    monkeypatch.undo()  # the modifier again, its UV map left as cut (frame 30)
    registry.forget_shown()
    goto(frame)
    mod = man.modifiers[MODIFIER]
    mod[{i.name: i.identifier for i in mod.node_group.interface.items_tree}["Animate UV"]] = False
    man.update_tag()
    stale = _render(scene, tmp_path / "stale.exr")
    assert np.abs(stale - written).max() > 1e-2  # measured 0.04


@pytest.mark.slow
def test_animation_render_gets_each_copied_frame(demo, tmp_path, monkeypatch, frame_work):
    """An animation render changes frames through the render pipeline, which calls the
    frame-change handlers: on integer frames they copy the kept frame into the mesh,
    and Cycles renders what the handler-written frame renders. Were the copy missing
    (the modifier told the mesh holds the frame while it holds another), the render
    would show the cut's frame."""
    from animanifold_blender import mesh_writer, playback
    from animanifold_blender.live_registry import registry

    man, cache = convert(demo)
    scene = bpy.context.scene
    _uv_colour_cycles(man, scene)
    frames = (34, 35)  # inside (24, 36), away from its middle (30): the UVs differ enough to show

    def animation(prefix):
        goto(30)  # the cut's own frame in the mesh
        scene.frame_start, scene.frame_end = frames
        scene.render.filepath = str(tmp_path / f"{prefix}_####")
        bpy.ops.render.render(animation=True)
        return {f: _read(tmp_path / f"{prefix}_{f:04d}.exr", scene) for f in frames}

    rendered = animation("driven")
    assert frame_work["written"][:len(frames)] == [float(f) for f in frames]  # by the render pipeline's frame changes
    assert modifier_inputs(man)["Active"]

    def lie(mesh, uv_name, frame):  # says it copied the frame, writes nothing
        return True

    monkeypatch.setattr(mesh_writer, "write_frame", lie)
    registry.forget_shown()
    stale = animation("stale")

    monkeypatch.setattr(playback, "can_drive", lambda *a, **k: False)  # the handler writes whole frames
    registry.forget_shown()
    for f in frames:
        goto(f)
        assert not modifier_inputs(man)["Active"]
        assert_shows(man, cache, f)
        written = _render(scene, tmp_path / f"written_{f}.exr")
        assert written[..., 3].max() > 0.5 and (written[..., 3] > 0.5).mean() > 0.1  # the blob is in view
        assert np.abs(rendered[f] - written).max() < 1e-4, f"frame {f}"  # measured 1e-6
        assert np.abs(stale[f] - written).max() > 1e-2, f"frame {f}: the check cannot fail"  # measured 0.04, 0.05
