"""Convert's error-driven sampling (the default) and drivers, in-process with bpy 4.5.

The distance between a manifold frame and the source is measured here independently of
the add-on: brute-force point-to-triangle distances in numpy over small meshes, both
ways (the source's vertices to the frame's triangles, the frame's vertices to the
source's loop triangles), at every frame and half frame of the range.
"""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import mesh_vertices  # noqa: E402
from helpers.surface_checks import distance_to_surface  # noqa: E402

pytestmark = pytest.mark.blender

TOLERANCE = 0.002  # the default: 0.2 % of the bounding-box diagonal


# -- an independent measure ------------------------------------------------------

def point_triangle_distances(points: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Distance from each point (P, 3) to the nearest of the triangles (T, 3, 3), by
    brute force over every triangle (helpers.surface_checks: Ericson's regions)."""
    return distance_to_surface(points, tris)


def two_sided(v1, f1, v2, f2) -> float:
    return max(point_triangle_distances(v1, v2[f2]).max(), point_triangle_distances(v2, v1[f1]).max())


def source_at(obj, frame: float, matrix0: np.ndarray):
    """The source's evaluated vertices and loop triangles at `frame`, in the space of the
    object at the first frame; and its own-space bounding-box diagonal."""
    whole = int(np.floor(frame))
    bpy.context.scene.frame_set(whole, subframe=float(frame - whole))
    ob = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ob.to_mesh()
    try:
        co = mesh_vertices(mesh)
        mesh.calc_loop_triangles()
        tv = np.empty(3 * len(mesh.loop_triangles), np.int32)
        mesh.loop_triangles.foreach_get("vertices", tv)
        rel = np.linalg.inv(matrix0) @ np.array(ob.matrix_world)
    finally:
        ob.to_mesh_clear()
    diagonal = float(np.linalg.norm(co.max(axis=0) - co.min(axis=0)))
    return co @ rel[:3, :3].T + rel[:3, 3], tv.reshape(-1, 3), diagonal


def deviations(source, manifold_object, start: int, end: int):
    """Frames (every frame and half frame), the two-sided distance at each, and the
    tolerance (0.2 % of the largest bounding-box diagonal)."""
    cache = am.load(bpy.path.abspath(manifold_object.animanifold.cache_path))
    matrix0 = np.array(manifold_object.matrix_world)
    frames = np.arange(2 * start, 2 * end + 1) / 2.0
    dev, size = [], 0.0
    for frame in frames:
        v, f, diagonal = source_at(source, frame, matrix0)
        size = max(size, diagonal)
        s = cache.slice(frame)
        dev.append(two_sided(v, f, s.vertices, s.faces))
    return frames, np.array(dev), TOLERANCE * size, cache


def test_the_independent_measure_is_a_distance():
    tri = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    points = np.array([[0.2, 0.2, 0.5], [-1, -1, 0], [2, 0, 0], [0.5, 0.5, 0], [0.5, -1, 3], [1, 1, 0]])
    expected = [0.5, np.sqrt(2), 1.0, 0.0, np.sqrt(10), np.sqrt(0.5)]
    np.testing.assert_allclose(point_triangle_distances(points, tri), expected, atol=1e-12)


def test_candidates_and_the_worst_frame_of_each_interval():
    from animanifold_blender.adaptive_sampling import candidate_frames, worst_per_interval

    frames = candidate_frames(1, 4, np.array([0.0, 2.25, 9.0]))
    np.testing.assert_array_equal(frames, [1, 1.5, 2, 2.25, 2.5, 3, 3.5, 4])
    samples = np.array([1.0, 2.25, 4.0])
    deviation = np.array([0, 0.3, 0.5, 0, 0.05, 0.9, 0.2, 0])
    # (1, 2.25): 2 is worst; (2.25, 4): 3; a sample frame or one within 0.1 is never picked
    np.testing.assert_array_equal(frames[worst_per_interval(frames, deviation, samples, 0.1)], [3.0, 2.0])
    assert len(worst_per_interval(frames, deviation, samples, 1.0)) == 0
    deviation[3] = 5.0  # at a sample: already exact, never added again
    np.testing.assert_array_equal(frames[worst_per_interval(frames, deviation, samples, 0.1)], [3.0, 2.0])


# -- scenes ----------------------------------------------------------------------

def eased_cube(scene, end=24):
    """A cube turning a quarter turn about z and stretching up (a shape key), both eased
    (Bezier keys at the first and last frame, and a pause in the middle)."""
    scene.frame_start, scene.frame_end = 1, end
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    cube = bpy.context.active_object
    cube.shape_key_add(name="Basis")
    stretch = cube.shape_key_add(name="Stretch")
    for v in stretch.data:
        if v.co.z > 0:
            v.co.z += 0.8
    for frame, angle, value in ((1, 0.0, 0.0), (end // 2, 0.5, 1.0), (end, 0.9, 0.3)):
        cube.rotation_euler = (0.0, 0.0, angle)
        cube.keyframe_insert("rotation_euler", frame=frame)
        stretch.value = value
        stretch.keyframe_insert("value", frame=frame)
    scene.frame_set(1)
    return cube


def driven_cube(scene, end=20):
    """A cube whose shape key follows an Empty's x location through a driver; only the
    Empty is keyed (Bezier, at frames 1, 8 and end)."""
    scene.frame_start, scene.frame_end = 1, end
    bpy.ops.object.empty_add(location=(0, 0, 0))
    handle = bpy.context.active_object
    for frame, x in ((1, 0.0), (8, 1.0), (end, 0.2)):
        handle.location.x = x
        handle.keyframe_insert("location", index=0, frame=frame)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(3, 0, 0))
    cube = bpy.context.active_object
    cube.shape_key_add(name="Basis")
    bulge = cube.shape_key_add(name="Bulge")
    for v in bulge.data:
        v.co.x *= 1.8
    fc = bulge.driver_add("value")
    var = fc.driver.variables.new()
    var.name, var.type = "x", "TRANSFORMS"
    var.targets[0].id = handle
    var.targets[0].transform_type = "LOC_X"
    fc.driver.expression = "x"
    scene.frame_set(1)
    return cube, handle


def convert(obj, **kwargs):
    obj.hide_set(False)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.animanifold.convert_action(**kwargs) == {"FINISHED"}
    return bpy.context.view_layer.objects.active


# -- error-driven sampling ---------------------------------------------------------

def test_default_sampling_keeps_every_frame_and_half_frame_within_tolerance(empty_scene):
    cube = eased_cube(empty_scene)
    man = convert(cube)
    frames, dev, tolerance, cache = deviations(cube, man, 1, 24)
    assert cache.metadata["sampling"] == "ADAPTIVE"
    assert dev.max() <= tolerance * (1 + 1e-9), f"frame {frames[dev.argmax()]:g}: {dev.max():.3g} > {tolerance:.3g}"
    # The reported largest deviation is the measure's, where it is.
    settings = man.animanifold
    assert settings.max_deviation == pytest.approx(dev.max(), rel=1e-6)
    assert dev[frames == settings.deviation_frame][0] == pytest.approx(dev.max(), rel=1e-6)
    assert settings.source_size * TOLERANCE == pytest.approx(tolerance, rel=1e-6)
    assert cache.metadata["max_deviation"] == pytest.approx(dev.max(), rel=1e-6)
    # Every keyframe is a sample, reproduced exactly; samples were added between them.
    times = cache.metadata["keyframe_times"]
    assert {1.0, 12.0, 24.0} <= set(times) and 3 < len(times) < len(frames)
    for key in (1, 12, 24):
        v, f, _ = source_at(cube, key, np.array(man.matrix_world))
        s = cache.slice(key)
        np.testing.assert_allclose(np.unique(np.round(s.vertices, 6), axis=0), np.unique(np.round(v, 6), axis=0),
                                   atol=1e-6, err_msg=f"keyframe {key}")
        assert two_sided(v, f, s.vertices, s.faces) < 1e-6


def test_keyframes_only_exceeds_the_tolerance_on_the_same_input(empty_scene):
    cube = eased_cube(empty_scene)
    man = convert(cube, sampling="KEYFRAMES")
    frames, dev, tolerance, cache = deviations(cube, man, 1, 24)
    assert cache.metadata["keyframe_times"] == [1.0, 12.0, 24.0]
    assert dev.max() > 3 * tolerance
    assert man.animanifold.max_deviation < 0  # not measured: the panel shows nothing


def test_a_tolerance_out_of_reach_of_the_sample_cap_warns(empty_scene, capfd):
    cube = eased_cube(empty_scene)
    capfd.readouterr()
    man = convert(cube, tolerance=1e-4, max_samples=5)
    out = capfd.readouterr()
    text = out.out + out.err
    settings = man.animanifold
    frames, dev, tolerance, cache = deviations(cube, man, 1, 24)
    assert len(cache.metadata["keyframe_times"]) == 5
    assert settings.max_deviation == pytest.approx(dev.max(), rel=1e-6)
    percent = 100 * settings.max_deviation / settings.source_size
    assert (f"'Cube': frame {settings.deviation_frame:g} is {percent:.3g} % of the object's size" in text
            and "above the tolerance of 0.0001 %" in text and "cap of 5 samples" in text), text


def test_a_sample_cap_below_the_keyframes_is_refused(empty_scene):
    eased_cube(empty_scene)
    with pytest.raises(RuntimeError, match=r"'Cube': the sample cap \(2\) is below the 3 keyframes"):
        bpy.ops.animanifold.convert_action(max_samples=2)
    assert not any(o.animanifold.is_manifold for o in bpy.data.objects)


# -- drivers -----------------------------------------------------------------------

def test_a_driver_only_shape_key_converts_and_follows_the_driver(empty_scene):
    cube, handle = driven_cube(empty_scene)
    keyed = convert(cube, sampling="KEYFRAMES")
    cache = am.load(bpy.path.abspath(keyed.animanifold.cache_path))
    assert cache.metadata["keyframe_times"] == [1.0, 8.0, 20.0]  # the Empty's keys
    for frame in (1, 8, 20):
        v, _, _ = source_at(cube, frame, np.array(keyed.matrix_world))
        np.testing.assert_allclose(np.unique(np.round(cache.slice(frame).vertices, 6), axis=0),
                                   np.unique(np.round(v, 6), axis=0), atol=1e-6, err_msg=f"frame {frame}")
    assert np.ptp(cache.slice(8).vertices[:, 0]) > 1.7  # the bulge is there: x = 1 at frame 8

    man = convert(cube)
    frames, dev, tolerance, cache = deviations(cube, man, 1, 20)
    assert dev.max() <= tolerance * (1 + 1e-9)
    assert man.animanifold.max_deviation == pytest.approx(dev.max(), rel=1e-6)


def test_a_driver_reading_the_frame_is_sampled_every_frame(empty_scene, capfd):
    """A modifier setting driven by an expression of the frame: no keys to find."""
    empty_scene.frame_start, empty_scene.frame_end = 1, 12
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    cube = bpy.context.active_object
    mod = cube.modifiers.new("Twist", "SIMPLE_DEFORM")
    mod.deform_method, mod.deform_axis = "TWIST", "Z"
    fc = cube.driver_add('modifiers["Twist"].angle')
    fc.driver.expression = "frame * 0.05"
    empty_scene.frame_set(1)
    capfd.readouterr()
    man = convert(cube, sampling="KEYFRAMES")
    out = capfd.readouterr().out
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    assert cache.metadata["keyframe_times"] == [float(f) for f in range(1, 13)]
    assert "sampled at every frame: the driver of object 'Cube' on modifiers[\"Twist\"].angle reads the frame" in out
    adaptive = convert(cube)
    frames, dev, tolerance, _ = deviations(cube, adaptive, 1, 12)
    assert dev.max() <= tolerance * (1 + 1e-9)
