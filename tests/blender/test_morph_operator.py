"""animanifold.morph_selected: two mesh objects become one manifold object (chapters 5, 8)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from blender_helpers import mesh_vertices, scene_state, shown  # noqa: E402

pytestmark = pytest.mark.blender


def world_vertices(obj) -> np.ndarray:
    m = np.array(obj.matrix_world)
    return mesh_vertices(shown(obj)) @ m[:3, :3].T + m[:3, 3]


def same_points(a, b, tol=1e-5):
    """Every point of a is within tol of a point of b and vice versa."""
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return d.min(axis=1).max() < tol and d.min(axis=0).max() < tol


def select(source, target):
    for o in bpy.context.selected_objects:
        o.select_set(False)
    source.select_set(True)
    target.select_set(True)
    bpy.context.view_layer.objects.active = target


def test_morph_plays_from_source_to_target_in_world_space(empty_scene):
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 24
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0, location=(0, 0, 0))
    source = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(size=1.5, location=(0.5, 0.2, 0))
    target = bpy.context.active_object
    target.rotation_euler = (0.3, 0.0, 0.4)
    bpy.context.view_layer.update()
    select(source, target)
    assert bpy.ops.animanifold.morph_selected() == {"FINISHED"}
    morph = bpy.context.active_object
    assert morph.animanifold.is_manifold and morph.name == "Icosphere_to_Cube"
    assert source.hide_get() and target.hide_get()
    scene.frame_set(1)
    assert same_points(world_vertices(morph), world_vertices(source))
    scene.frame_set(24)
    # the target's 8 corners are all in the last frame, and every frame vertex lies on the cube
    last = world_vertices(morph)
    corners = world_vertices(target)
    assert np.linalg.norm(last[:, None] - corners[None], axis=2).min(axis=0).max() < 1e-5
    scene.frame_set(12)
    assert len(shown(morph).polygons) > 0


def test_open_input_is_refused_and_the_scene_is_unchanged(empty_scene):
    bpy.ops.mesh.primitive_ico_sphere_add()
    source = bpy.context.active_object
    bpy.ops.mesh.primitive_grid_add()
    target = bpy.context.active_object
    select(source, target)
    before = scene_state()
    with pytest.raises(RuntimeError, match=r"Morph failed: the target 'Grid' is open"):
        bpy.ops.animanifold.morph_selected()
    assert scene_state() == before


def test_poll_needs_two_meshes(empty_scene):
    bpy.ops.mesh.primitive_ico_sphere_add()
    assert not bpy.ops.animanifold.morph_selected.poll()
