"""Convert and live slicing, in-process with bpy 4.5."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import canonical, eval_corners, mesh_corners, mesh_vertices, shown, triangle_looks  # noqa: E402
from build_demo_scene import KEYFRAMES  # noqa: E402

pytestmark = pytest.mark.blender


def convert(obj, **kwargs):
    """Converts `obj`, by default at its keyframes only (these tests are about keyframes;
    error-driven sampling, the operator's default, is tested in test_adaptive_sampling)."""
    kwargs.setdefault("sampling", "KEYFRAMES")
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.animanifold.convert_action(**kwargs) == {"FINISHED"}
    return bpy.data.objects[obj.name + "_manifold"]


def cache_of(obj):
    return am.load(bpy.path.abspath(obj.animanifold.cache_path))


def test_keyframes_come_back_exactly(demo):
    man = convert(demo)
    cache = cache_of(man)
    assert cache.metadata["keyframe_times"] == sorted(float(f) for f in KEYFRAMES)
    for frame in KEYFRAMES:
        expected = eval_corners(demo, frame)  # also sets the frame: the handler re-slices
        got = mesh_corners(shown(man))
        assert len(shown(man).polygons) == len(expected), f"frame {frame}: face count"
        np.testing.assert_allclose(canonical(got), canonical(expected), atol=1e-6, rtol=0, err_msg=f"frame {frame}")
    # The manifold object sits where the source is; the source is hidden, not changed.
    assert demo.hide_get() and demo.hide_render
    assert np.allclose(np.array(man.matrix_world), np.array(demo.matrix_world))
    assert man.animanifold.source == demo
    assert [s.material for s in man.material_slots] == [s.material for s in demo.material_slots]


def test_uvs_and_materials_carried(demo):
    man = convert(demo)
    bpy.context.scene.frame_set(12)
    src = demo.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    me = shown(man)
    assert me.uv_layers.active is not None and me.uv_layers.active.name == src.uv_layers.active.name

    def per_face(mesh):
        corners, uvs, material_index = triangle_looks(mesh)
        # corners (x, y, z, u, v) plus the material, as a canonical table
        return canonical_rows(np.concatenate([corners, uvs], axis=2), material_index)

    np.testing.assert_allclose(per_face(me), per_face(src), atol=1e-6, rtol=0)
    assert set(np.unique([p.material_index for p in me.polygons])) == {0, 1}


def canonical_rows(table, material):
    T = len(table)
    flat = table.reshape(T * 3, -1)
    rank = np.lexsort(flat.T[::-1]).argsort().reshape(T, 3)
    start = rank.argmin(axis=1)
    idx = (start[:, None] + np.arange(3)[None, :]) % 3
    rows = np.take_along_axis(table, idx[:, :, None], axis=1).reshape(T, -1)
    rows = np.column_stack([rows, material])
    return rows[np.lexsort(rows.T[::-1])]


def test_between_keyframes_vertices_lie_on_manifold_edges(demo):
    man = convert(demo)
    cache = cache_of(man)
    points = cache.points
    times = np.array(cache.metadata["keyframe_times"])
    for frame in (5, 17, 30, 45):
        bpy.context.scene.frame_set(frame)
        s = cache.slice(frame)
        co = mesh_vertices(shown(man))
        assert co.shape == s.vertices.shape, f"frame {frame}"
        np.testing.assert_allclose(co, s.vertices, atol=1e-6, rtol=0)
        a, b = s.vertex_edges[:, 0], s.vertex_edges[:, 1]
        pa, pb = points[a], points[b]
        # the edge joins the two keyframes around this frame
        lo, hi = times[times <= frame].max(), times[times >= frame].min()
        assert np.all(np.minimum(pa[:, 3], pb[:, 3]) == lo) and np.all(np.maximum(pa[:, 3], pb[:, 3]) == hi)
        seg = pb[:, :3] - pa[:, :3]
        u = np.einsum("ij,ij->i", co - pa[:, :3], seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300)
        assert np.all(u > -1e-6) and np.all(u < 1 + 1e-6)
        closest = pa[:, :3] + np.clip(u, 0, 1)[:, None] * seg
        assert np.max(np.linalg.norm(co - closest, axis=1)) < 1e-6, f"frame {frame}: off the segment"
    # Keyframe points are the source's evaluated vertices (via source_vertex).
    k = cache.metadata["keyframe_vertices"]
    src_index = cache.vertex_attributes["source_vertex"][:k, 0].astype(int)
    for i, t in enumerate(times):
        bpy.context.scene.frame_set(int(t))
        ev = demo.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        np.testing.assert_allclose(points[i * k:(i + 1) * k, :3], mesh_vertices(ev)[src_index], atol=1e-6, rtol=0)


def test_scrubbing_reuses_the_mesh(demo):
    man = convert(demo)
    mesh = man.data
    counts = (len(bpy.data.meshes), len(bpy.data.objects))
    shapes = set()
    for frame in list(range(1, 49, 3)) + [48, 1]:
        bpy.context.scene.frame_set(frame)
        assert man.data == mesh
        shapes.add(mesh_vertices(mesh).tobytes())
    assert (len(bpy.data.meshes), len(bpy.data.objects)) == counts
    # Frames differ: the handler really re-sliced (in positions: between keys a frame has the
    # source's vertices, so the vertex count does not change).
    assert len(shapes) > 1


def test_every_n_frames_sampling(demo):
    man = convert(demo, sampling="EVERY_N", step=10)
    assert cache_of(man).metadata["keyframe_times"] == [1.0, 11.0, 21.0, 31.0, 41.0, 48.0]
    bpy.context.scene.frame_set(21)
    np.testing.assert_allclose(canonical(mesh_corners(shown(man))), canonical(eval_corners(demo, 21)), atol=1e-6)


def test_sweep_axes_and_back_to_t(demo):
    man = convert(demo)
    settings = man.animanifold
    cache = cache_of(man)
    bpy.context.scene.frame_set(20)
    at_t = mesh_vertices(shown(man))
    t0 = cache.time_range[0]
    for axis, column in (("x", 0), ("y", 1), ("z", 2)):
        settings.axis = axis
        settings.sweep_value = 0.1
        s = cache.slice(0.1, axis)
        co = mesh_vertices(shown(man))
        assert len(co) == len(s.vertices) > 0, axis
        others = [c for c in range(3) if c != column]
        np.testing.assert_allclose(co[:, others], s.vertices[:, :2], atol=1e-5)
        np.testing.assert_allclose(co[:, column], (s.vertices[:, 2] - t0) * settings.time_scale, atol=1e-5)
        bpy.context.scene.frame_set(30)  # frame changes do not move a sweep view
        np.testing.assert_allclose(mesh_vertices(shown(man)), co, atol=1e-6)
        bpy.context.scene.frame_set(20)
    settings.axis = "t"
    np.testing.assert_allclose(mesh_vertices(shown(man)), at_t, atol=1e-6)


def test_frame_changes_check_each_object_once_unless_animated(demo, monkeypatch):
    """The post-frame handler skips objects the pre-frame one showed at this frame,
    unless they are animated: a keyframed sweep value is read after evaluation."""
    from animanifold_blender import playback

    man = convert(demo)
    cache = cache_of(man)
    calls = []
    update_object = playback.update_object
    monkeypatch.setattr(playback, "update_object", lambda obj, frame, **kw: (calls.append(frame), update_object(obj, frame, **kw)))
    for frame in (20, 21, 21):
        calls.clear()
        bpy.context.scene.frame_set(frame)
        assert calls == [frame], f"frame {frame}: {calls}"
    settings = man.animanifold
    settings.axis = "x"
    for frame, value in ((1, -0.2), (21, 0.3)):
        settings.sweep_value = value
        man.keyframe_insert("animanifold.sweep_value", frame=frame)
    for frame in (11, 16, 21, 6):
        calls.clear()
        bpy.context.scene.frame_set(frame)
        assert calls == [frame, frame], f"frame {frame}: an animated object is looked at again after evaluation"
        value = settings.sweep_value  # as animated at this frame
        assert -0.2 < value < 0.3 or frame == 21
        s = cache.slice(value, "x")
        co = mesh_vertices(shown(man))
        assert len(co) == len(s.vertices) > 0, f"frame {frame}"
        np.testing.assert_allclose(co[:, 1:], s.vertices[:, :2], atol=1e-5, err_msg=f"frame {frame}: sweep at {value}")


def test_object_level_keyframes_in_local_space(empty_scene):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, 0))
    cube = bpy.context.active_object
    scene = empty_scene
    scene.frame_start, scene.frame_end = 1, 20
    for frame, loc, rot in ((1, (0, 0, 0), 0.0), (10, (2, 0, 1), 0.5), (20, (2, 3, 0), 1.5)):
        cube.location = loc
        cube.rotation_euler = (0, 0, rot)
        cube.keyframe_insert("location", frame=frame)
        cube.keyframe_insert("rotation_euler", frame=frame)
    scene.frame_set(1)
    man = convert(cube)
    assert cache_of(man).metadata["object_motion_baked"] is True
    for frame in (1, 10, 20):
        scene.frame_set(frame)
        mw = np.array(cube.matrix_world)
        src = eval_corners(cube)
        src_world = src @ mw[:3, :3].T + mw[:3, 3]
        mm = np.array(man.matrix_world)
        got = mesh_corners(shown(man)) @ mm[:3, :3].T + mm[:3, 3]
        np.testing.assert_allclose(canonical(got, 5), canonical(src_world, 5), atol=1e-5, err_msg=f"frame {frame}")


def test_armature_action(empty_scene):
    scene = empty_scene
    scene.frame_start, scene.frame_end = 1, 30
    bpy.ops.mesh.primitive_cylinder_add(vertices=8, depth=2.0, location=(0, 0, 1))
    body = bpy.context.active_object
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=3)
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.armature_add(location=(0, 0, 0))
    rig = bpy.context.active_object
    rig.data.bones  # one bone from (0,0,0) to (0,0,1)
    body.parent = rig
    mod = body.modifiers.new("Armature", "ARMATURE")
    mod.object = rig
    group = body.vertex_groups.new(name="Bone")
    group.add(list(range(len(body.data.vertices))), 1.0, "REPLACE")
    pose_bone = rig.pose.bones[0]
    pose_bone.rotation_mode = "XYZ"
    for frame, angle in ((1, 0.0), (15, 0.6), (30, -0.4)):
        pose_bone.rotation_euler = (angle, 0, 0)
        pose_bone.keyframe_insert("rotation_euler", frame=frame)
    scene.frame_set(1)
    man = convert(body)
    assert cache_of(man).metadata["keyframe_times"] == [1.0, 15.0, 30.0]
    for frame in (1, 15, 30):
        # n-gon caps are triangulated by shape, so compare vertices and counts (the
        # manifold keeps the triangulation of the first sample)
        expected = eval_corners(body, frame)
        got = mesh_corners(shown(man))
        assert len(got) == len(expected)
        np.testing.assert_allclose(np.unique(got.reshape(-1, 3), axis=0), np.unique(expected.reshape(-1, 3), axis=0),
                                   atol=1e-6, err_msg=f"frame {frame}")


def test_cache_beside_saved_blend_and_reload(demo, tmp_path):
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    man = convert(demo)
    assert man.animanifold.cache_path == "//scene.Blob_manifold.amf"
    assert (tmp_path / "scene.Blob_manifold.amf").is_file()
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    man = bpy.data.objects["Blob_manifold"]
    names = [h.__name__ for h in bpy.app.handlers.frame_change_post]
    assert names.count("animanifold_frame_change_post") == 1
    cache = am.load(tmp_path / "scene.Blob_manifold.amf")
    meshes = len(bpy.data.meshes)
    for frame in (7, 24, 40):
        bpy.context.scene.frame_set(frame)
        np.testing.assert_allclose(mesh_vertices(shown(man)), cache.slice(frame).vertices, atol=1e-6)
    assert len(bpy.data.meshes) == meshes


def test_unsaved_blend_uses_temp_folder(demo, capfd):
    man = convert(demo)
    path = man.animanifold.cache_path
    assert not path.startswith("//") and os.path.isabs(path) and os.path.isfile(path)
    assert "animanifold" in path
    out = capfd.readouterr()
    assert "not saved" in out.out + out.err and "temporary folder" in out.out + out.err


def test_damaged_cache_never_breaks_playback(demo, tmp_path, capfd):
    man = convert(demo)
    path = bpy.path.abspath(man.animanifold.cache_path)
    data = bytearray(Path(path).read_bytes())
    data[100] ^= 0xFF
    Path(path).write_bytes(bytes(data))
    os.utime(path, ns=(1, 1))  # a new stamp: the add-on reloads and finds the damage
    bpy.context.scene.frame_set(10)
    bpy.context.scene.frame_set(11)
    from animanifold_blender import live

    assert "damaged" in (live.last_error(man) or "")
    assert capfd.readouterr().out.count("cannot slice") == 1  # printed once, not per frame


def test_shape_holds_outside_the_range(demo):
    man = convert(demo)
    cache = cache_of(man)
    for frame, held in ((0, 1), (-5, 1), (60, 48)):
        bpy.context.scene.frame_set(frame)
        np.testing.assert_allclose(mesh_vertices(shown(man)), cache.slice(held).vertices, atol=1e-6)


def test_converting_twice_keeps_both_caches(demo, tmp_path):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "twice.blend"))
    first = convert(demo)
    demo.hide_set(False)
    bpy.context.view_layer.objects.active = demo
    assert bpy.ops.animanifold.convert_action(sampling="EVERY_N", step=4) == {"FINISHED"}
    second = bpy.data.objects["Blob_manifold.001"]
    assert first.animanifold.cache_path != second.animanifold.cache_path
    assert len(cache_of(first).metadata["keyframe_times"]) == 5
    assert len(cache_of(second).metadata["keyframe_times"]) == 13
    assert second.data.name == "Blob_manifold.001"


def test_frames_within_a_keyframe_interval_only_move_vertices(demo):
    """Playback between two keyframes moves the vertices of one cut (the live modifier):
    the shown mesh is the same as a fresh cut, UVs included."""
    from animanifold_blender.live_registry import registry

    man = convert(demo)
    cache = cache_of(man)
    times = np.array(cache.metadata["keyframe_times"])
    lo, hi = times[0], times[1]
    frames = [lo + 1, lo + 2, (lo + hi) / 2, hi - 1, hi, hi + 1, lo + 1]
    for frame in frames:
        bpy.context.scene.frame_set(int(frame), subframe=float(frame) - int(frame))
        s = cache.slice(frame)
        mesh = shown(man)
        np.testing.assert_allclose(mesh_vertices(mesh), s.vertices, atol=1e-6, rtol=0, err_msg=f"frame {frame}")
        assert len(mesh.polygons) == len(s.faces)
        corner_uv = np.empty(2 * len(mesh.loops), np.float32)
        mesh.uv_layers[man.animanifold.uv_name].data.foreach_get("uv", corner_uv)
        corner_vertex = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", corner_vertex)
        np.testing.assert_allclose(corner_uv.reshape(-1, 2), s.vertex_attributes["uv"][corner_vertex], atol=1e-6)
        inside = times[0] < frame < times[-1] and frame not in times
        entry = registry.shown(man)
        assert entry is not None and (entry.interval is not None) == inside, \
            f"frame {frame}: the shown interval is {'missing' if inside else 'stale'}"
