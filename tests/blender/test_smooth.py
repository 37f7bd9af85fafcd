"""Smooth panel settings of manifold objects: manifold subdivision (Schaefer et al.)
and OpenSubdiv frame smoothing, live and baked, and how their failures show."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import (canonical, eval_corners, mesh_corners, mesh_vertices, record_core_progress,  # noqa: E402
                                     scene_state, shown)

pytestmark = pytest.mark.blender

# The demo blob has radius 1 and 16 x 8 segments: one Loop level moves a frame's
# points towards its limit surface by a few hundredths of the radius (measured 0.04).
SMOOTH_TOLERANCE = 0.06
# Schaefer subdivision is approximating: with keyframe times kept, a keyframe's points
# stay at its time but are averaged with its neighbours in space and time. At the ends
# only the spatial smoothing acts (as Loop: 0.04 measured); inner keyframes of the demo's
# squash/stretch/twist are pulled towards their neighbours (0.24 measured at frame 24)
# and stay nearer their own keyframe than any other.
END_TOLERANCE = 0.06
INNER_TOLERANCE = 0.3


def convert(obj):
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    return bpy.data.objects[obj.name + "_manifold"]


def cache_of(obj):
    return am.load(bpy.path.abspath(obj.animanifold.cache_path))


def corner_vertices(mesh) -> np.ndarray:
    corners = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", corners)
    return corners.reshape(-1, 3)


def is_closed(mesh) -> bool:
    """Whether the triangles of `mesh`, welded by position (slices split vertices at
    UV seams), form a closed oriented surface: every edge in two faces, once each way."""
    co = np.round(mesh_vertices(mesh), 5)
    _, weld = np.unique(co, axis=0, return_inverse=True)
    tri = weld.reshape(-1)[corner_vertices(mesh)]
    directed = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    if np.any(directed[:, 0] == directed[:, 1]):
        return False
    _, once = np.unique(directed, axis=0, return_counts=True)
    undirected, twice = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    return bool(np.all(once == 1) and np.all(twice == 2))


def surface_distance(points: np.ndarray, corners: np.ndarray, samples: int = 12) -> np.ndarray:
    """Distance of each point to the triangles `corners` (T, 3, 3), through points
    sampled on a barycentric grid of `samples` steps per edge."""
    i, j = np.meshgrid(np.arange(samples + 1), np.arange(samples + 1))
    keep = i + j <= samples
    w = np.stack([i[keep], j[keep], samples - i[keep] - j[keep]], 1) / samples  # (B, 3)
    cloud = np.einsum("bk,tkd->tbd", w, corners).reshape(-1, 3)
    squared = (cloud ** 2).sum(1)
    out = np.empty(len(points))
    for start in range(0, len(points), 128):
        chunk = points[start:start + 128]
        d2 = (chunk ** 2).sum(1)[:, None] - 2 * chunk @ cloud.T + squared[None, :]
        out[start:start + 128] = np.sqrt(np.maximum(d2.min(1), 0.0))
    return out


def mesh_state(mesh) -> dict:
    """Everything a full write puts in the mesh, as arrays."""
    uv = np.empty(2 * len(mesh.loops), np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    material = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("material_index", material)
    return {"co": mesh_vertices(mesh), "corners": corner_vertices(mesh), "uv": uv, "material": material}


def test_frame_smoothing_gives_loop_counts_close_to_the_slice(demo):
    from animanifold_blender import object_manifold
    from animanifold_blender.live_registry import registry

    man = convert(demo)
    cache = cache_of(man)
    settings = man.animanifold
    scene = bpy.context.scene
    scene.frame_set(17)
    base_corners = mesh_corners(shown(man))
    F = len(shown(man).polygons)
    # Welded by position (the slice splits vertices along UV seams): V points, E edges.
    welded = np.unique(np.round(mesh_vertices(shown(man)), 6), axis=0, return_inverse=True)[1].reshape(-1)
    tri = welded[corner_vertices(shown(man))]
    V = welded.max() + 1
    E = len(np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0))
    assert V < len(shown(man).vertices)  # the demo has seams
    assert is_closed(shown(man))

    settings.smooth_levels = 1  # re-slices at once
    mesh = shown(man)
    assert len(mesh.polygons) == 4 * F  # Loop: every triangle in four
    assert len(mesh.vertices) == V + E  # a point per vertex and per edge: seams are not boundaries
    assert is_closed(mesh)  # still closed: no cracks along the UV seams
    s = object_manifold.frame_slice(man, object_manifold.shown_manifold(man), 17.0)
    np.testing.assert_allclose(mesh_vertices(mesh), s.vertices, atol=1e-6, rtol=0)
    np.testing.assert_array_equal(corner_vertices(mesh), s.faces)
    distance = surface_distance(mesh_vertices(mesh), base_corners)
    assert distance.max() < SMOOTH_TOLERANCE
    assert distance.max() > 1e-3  # it did move: a limit surface, not the slice
    # Attributes come along: both materials, the UV map, smooth shading.
    assert set(np.unique(mesh_state(mesh)["material"])) == {0, 1}
    assert mesh.uv_layers.active.name == settings.uv_name
    assert all(p.use_smooth for p in mesh.polygons[:10])
    # Playing inside a keyframe interval cuts and refines every frame (no vertex sliding).
    assert registry.shown(man).interval_frame is None and not registry.shown(man).driven
    for frame in (18, 19.5, 23):
        scene.frame_set(int(frame), subframe=frame - int(frame))
        s = cache.slice(frame)
        assert len(shown(man).polygons) == 4 * len(s.faces)
        assert is_closed(shown(man)), f"frame {frame}"
        if frame == 19.5:
            assert surface_distance(mesh_vertices(shown(man)), s.vertices[s.faces]).max() < SMOOTH_TOLERANCE
        assert registry.shown(man).interval_frame is None and not registry.shown(man).driven
    # A crease angle change re-slices at once; two levels: 16x.
    scene.frame_set(17)
    smooth = mesh_vertices(shown(man))
    settings.crease_angle = math.radians(5.0)  # most edges sharp: the frame keeps to its faces
    creased = mesh_vertices(shown(man))
    assert len(creased) == len(smooth) and not np.allclose(creased, smooth, atol=1e-4)
    assert (surface_distance(creased, base_corners, 6).mean()
            < 0.5 * surface_distance(smooth, base_corners, 6).mean())
    settings.smooth_levels = 2
    assert len(shown(man).polygons) == 16 * F
    assert is_closed(shown(man))


def test_manifold_subdivision_keeps_keyframes(demo, monkeypatch):
    from animanifold_blender import cache_paths, object_manifold
    from animanifold_blender.live_registry import registry

    man = convert(demo)
    cache = cache_of(man)
    settings = man.animanifold
    assert settings.keep_keyframe_times
    scene = bpy.context.scene
    sources = {f: eval_corners(demo, f) for f in (1, 12, 24, 36, 48)}
    scene.frame_set(24)
    F = len(shown(man).polygons)
    calls = []
    real = am.subdivision.subdivide

    def counting(manifold, *args, **kwargs):
        calls.append(kwargs.get("keep_keyframe_times"))
        return real(manifold, *args, **kwargs)

    monkeypatch.setattr(am.subdivision, "subdivide", counting)  # what the subdivision cache calls
    settings.subdivision_levels = 1
    assert calls == [True]
    for frame in (24, 1, 48):
        scene.frame_set(frame)
        mesh = shown(man)
        assert len(mesh.polygons) == 4 * F, f"frame {frame}: the keyframe refined, nothing else"
        assert is_closed(mesh), f"frame {frame}: not closed"
        co = mesh_vertices(mesh)
        own = surface_distance(co, sources[frame])
        tolerance = INNER_TOLERANCE if frame == 24 else END_TOLERANCE
        assert own.max() < tolerance, f"frame {frame}: {own.max():.3f} from the source"
        for other, corners in sources.items():
            if other not in (frame, 1 if frame == 48 else 48 if frame == 1 else None):  # the ends are alike
                assert own.mean() < surface_distance(co, corners).mean(), f"frame {frame} nearer frame {other}"
    # Computed once: playing frames and re-drawing reuse it.
    for frame in (5, 13, 30, 47):
        scene.frame_set(frame)
    assert calls == [True]
    subdivided = object_manifold.shown_manifold(man)
    assert len(subdivided.simplices) == 8 * len(cache.simplices)
    assert subdivided.time_range == cache.time_range  # the first and last frame stay at their times
    assert set(np.unique(subdivided.points[subdivided.boundary(), 3])) == {1.0, 48.0}
    for t in cache.metadata["keyframe_times"]:  # and, with the option, every keyframe
        assert np.count_nonzero(subdivided.points[:, 3] == t) > 0
    # Between keyframes the fast path (the live modifier sliding the vertices along
    # manifold edges) works on it.
    scene.frame_set(30)
    scene.frame_set(31)
    assert registry.shown(man).driven
    np.testing.assert_allclose(mesh_vertices(shown(man)), subdivided.slice(31.0).vertices, atol=1e-6, rtol=0)
    # Without keyframe times kept: another subdivision; the first one, which no object
    # asks for any more, is freed (so switching back computes it again, once).
    settings.keep_keyframe_times = False
    assert calls == [True, False]
    assert registry.subdivisions.kept(cache_paths.cache_abspath(man)) == [(1, False)]
    settings.keep_keyframe_times = True
    scene.frame_set(2)
    assert calls == [True, False, True]
    subdivided = object_manifold.shown_manifold(man)
    scene.frame_set(1)
    np.testing.assert_allclose(mesh_vertices(shown(man)), subdivided.slice(1.0).vertices, atol=1e-6, rtol=0)


def test_back_to_zero_gives_exactly_the_old_mesh(demo):
    from animanifold_blender import live
    from animanifold_blender.live_registry import registry

    man = convert(demo)
    settings = man.animanifold
    bpy.context.scene.frame_set(40)
    bpy.context.scene.frame_set(17)
    before = mesh_state(shown(man))
    settings.subdivision_levels = 2
    settings.smooth_levels = 1
    smoothed = mesh_state(shown(man))
    assert len(smoothed["corners"]) > 4 * len(before["corners"])
    assert len(registry.subdivisions)
    settings.smooth_levels = 0
    settings.subdivision_levels = 0
    after = mesh_state(shown(man))
    for name in before:
        np.testing.assert_array_equal(after[name], before[name], err_msg=name)
    assert not len(registry.subdivisions)  # nobody asks for the subdivision: its memory is freed
    assert live.last_error(man) is None


def test_bake_with_smoothing_bakes_what_plays_live(demo, tmp_path):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "smooth.blend"))
    man = convert(demo)
    settings = man.animanifold
    settings.subdivision_levels = 1
    settings.smooth_levels = 1
    frames = (10, 12, 15, 20)
    scene = bpy.context.scene
    live_corners = {}
    for frame in frames:
        scene.frame_set(frame)
        live_corners[frame] = mesh_corners(shown(man))
    assert bpy.ops.animanifold.bake(alembic=False, export="OBJ", use_scene_range=False, frame_start=10,
                                    frame_end=20, directory=str(tmp_path / "objs")) == {"FINISHED"}
    coll = settings.bake_collection
    assert len(coll.objects) == 11
    for frame in frames:
        baked = coll.objects[f"Blob_manifold_f{frame:06d}"].data
        np.testing.assert_array_equal(canonical(mesh_corners(baked)), canonical(live_corners[frame]),
                                      err_msg=f"frame {frame}")
        scene.frame_set(frame)  # and the node group shows it
        np.testing.assert_allclose(canonical(mesh_corners(shown(man))), canonical(live_corners[frame]), atol=1e-6)
        v, f = am.read_mesh(str(tmp_path / "objs" / f"Blob_manifold_{frame:06d}.obj"))
        assert len(f) == len(live_corners[frame])
        np.testing.assert_allclose(canonical(v[f]), canonical(live_corners[frame]), atol=1e-5)


def test_bake_shows_the_subdivisions_steps_on_the_progress_bar(demo, tmp_path, monkeypatch):
    from animanifold_blender import bake_object
    from animanifold_blender.live_registry import registry

    steps, ended = record_core_progress(bake_object, monkeypatch)
    man = convert(demo)
    man.animanifold.subdivision_levels = 1  # computed by the property update, without a bar
    registry.subdivisions.clear()  # so that the bake computes it
    assert bpy.ops.animanifold.bake(alembic=False, export="NONE", use_scene_range=False, frame_start=10,
                                    frame_end=12, directory=str(tmp_path / "objs")) == {"FINISHED"}
    fractions = [f for _, f in steps]
    assert len(steps) >= 2 and fractions == sorted(fractions) and 0.0 <= fractions[0] and fractions[-1] <= 1.0
    assert ended == [True]
    steps.clear()
    assert bpy.ops.animanifold.bake(alembic=False, export="NONE", use_scene_range=False, frame_start=10,
                                    frame_end=12, directory=str(tmp_path / "objs")) == {"FINISHED"}
    assert steps == []  # kept: nothing to compute the second time


def test_failures_show_in_the_panel_and_never_raise(demo, monkeypatch):
    from animanifold_blender import live
    from animanifold_blender.deform_constraints import slice_constraints
    from animanifold_blender.reporting import OperatorError

    man = convert(demo)
    settings = man.animanifold
    scene = bpy.context.scene
    scene.frame_set(17)
    before = mesh_state(shown(man))
    calls = []

    def out_of_memory(manifold, *args, **kwargs):
        calls.append(1)
        raise MemoryError()

    monkeypatch.setattr(am.subdivision, "subdivide", out_of_memory)  # what the subdivision cache calls
    settings.subdivision_levels = 2  # must not raise
    assert "out of memory" in live.last_error(man)
    for frame in (18, 30):
        scene.frame_set(frame)  # the handler neither raises nor retries every frame
    assert calls == [1]
    assert "out of memory" in live.last_error(man)
    state = scene_state()
    with pytest.raises(RuntimeError, match="out of memory"):
        bpy.ops.animanifold.bake(alembic=False)
    assert scene_state() == state
    # A result beyond the package's memory limit is refused by the core before it allocates.
    monkeypatch.undo()
    previous = am.memory_limit() if am.memory_limits.memory_limit_is_set() else None
    am.set_memory_limit(2**20)
    try:
        settings.subdivision_levels = 1
    finally:
        am.set_memory_limit(previous)
    assert "(21504 simplices)" in live.last_error(man) and "memory limit" in live.last_error(man)
    assert calls == [1]
    settings.subdivision_levels = 0
    scene.frame_set(17)
    assert live.last_error(man) is None
    for name, value in mesh_state(shown(man)).items():
        np.testing.assert_array_equal(value, before[name])
    # Deform works on the manifold's own slices: a smoothed object says so.
    settings.smooth_levels = 1
    with pytest.raises(OperatorError, match="smoothed"):
        slice_constraints(man, 17.0, "", "", "NEARER", False)


def test_smooth_panel_registers_and_draws(demo, addon):
    assert bpy.types.VIEW3D_PT_animanifold_smooth.bl_parent_id == "VIEW3D_PT_animanifold"
    man = convert(demo)
    props = man.animanifold.bl_rna.properties
    assert (props["subdivision_levels"].hard_min, props["subdivision_levels"].hard_max) == (0, 2)
    assert (props["smooth_levels"].hard_min, props["smooth_levels"].hard_max) == (0, 3)
    assert man.animanifold.subdivision_levels == 0 and man.animanifold.smooth_levels == 0
    assert man.animanifold.keep_keyframe_times
    assert math.isclose(math.degrees(man.animanifold.crease_angle), 30.0, abs_tol=1e-4)
    addon.unregister()
    try:
        assert not hasattr(bpy.types, "VIEW3D_PT_animanifold_smooth")
    finally:
        addon.register()
    assert hasattr(bpy.types, "VIEW3D_PT_animanifold_smooth")


class _Layout:
    """Records what a panel draws (labels and properties), as a UILayout would take it."""

    def __init__(self, log):
        self.log = log
        self.enabled = True

    def column(self, **_):
        return _Layout(self.log)

    row = box = column

    def label(self, text="", icon="NONE"):
        self.log.append(("label", text, icon))

    def prop(self, data, name, **_):
        assert name in data.bl_rna.properties, name
        self.log.append(("prop", name, self.enabled))

    def operator(self, name, **_):
        self.log.append(("operator", name))


def test_smooth_panel_draws_settings_and_warnings(demo, monkeypatch):
    from types import SimpleNamespace

    from animanifold_blender import ui

    man = convert(demo)
    bpy.context.scene.frame_set(17)
    context = SimpleNamespace(active_object=man, scene=bpy.context.scene)
    assert ui.VIEW3D_PT_animanifold_smooth.poll(context)
    assert not ui.VIEW3D_PT_animanifold_smooth.poll(SimpleNamespace(active_object=demo, scene=bpy.context.scene))

    def draw():
        log = []
        ui.VIEW3D_PT_animanifold_smooth.draw(SimpleNamespace(layout=_Layout(log)), context)
        return log

    log = draw()
    assert ("prop", "subdivision_levels", True) in log and ("prop", "keep_keyframe_times", False) in log
    assert ("prop", "smooth_levels", True) in log and ("prop", "crease_angle", False) in log
    man.animanifold.subdivision_levels = 1
    man.animanifold.smooth_levels = 1
    log = draw()
    assert ("label", "21,504 tets", "INFO") in log
    assert ("label", f"{len(shown(man).polygons):,} faces this frame", "INFO") in log
    assert ("prop", "keep_keyframe_times", True) in log and ("prop", "crease_angle", True) in log
    monkeypatch.setattr(ui, "LARGE_TETS", 10_000)
    assert ("label", "21,504 tets: slow slicing, much memory", "ERROR") in draw()
