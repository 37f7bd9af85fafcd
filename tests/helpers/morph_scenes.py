"""Input pairs for Morph Selected and the check that a morph's frame is one of its inputs,
shared by the in-process Blender tests and the Blender 3.4 smoke script (import after bpy)."""

from __future__ import annotations

import math

import bpy
import numpy as np

from helpers.blender_helpers import mesh_corners, mesh_vertices
from helpers.surface_checks import compare_frame, frame_matches


def add_sphere_and_turned_mirrored_cube(x: float = 0.0):
    """A UV sphere at (x, 0, 0) and a cube overlapping it, turned and mirrored by a negative
    scale: a pair of the same genus, so every method reproduces both ends."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0, location=(x, 0.0, 0.0))
    sphere = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(x + 0.4, 0.1, -0.2), rotation=(0.3, 0.2, 0.6))
    cube = bpy.context.active_object
    cube.scale = (1.4, -1.1, 0.9)
    bpy.context.view_layer.update()
    return sphere, cube


def add_sphere_and_torus():
    """A UV sphere and a torus (different genus, quads), moved, turned and scaled differently."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0, location=(0.3, -0.2, 1.0),
                                         rotation=(0.4, 0.0, 0.2))
    sphere = bpy.context.active_object
    bpy.ops.mesh.primitive_torus_add(major_segments=16, minor_segments=8, major_radius=0.7, minor_radius=0.3,
                                     location=(0.35, -0.1, 1.05), rotation=(math.radians(70), 0.0, 0.5))
    torus = bpy.context.active_object
    torus.scale = (1.1, 1.1, 1.1)
    bpy.context.view_layer.update()
    return sphere, torus


def evaluated(obj) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, triangle corners) of the evaluated mesh, in the object's local space."""
    ob_eval = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ob_eval.to_mesh()
    try:
        return mesh_vertices(mesh), mesh_corners(mesh)
    finally:
        ob_eval.to_mesh_clear()


def compare_with(morph, obj) -> dict:
    """The morph's current frame against `obj`'s evaluated mesh, both in the morph's frame
    (surface_checks.compare_frame's report)."""
    frame_vertices, frame_corners = evaluated(morph)
    vertices, corners = evaluated(obj)
    m = np.linalg.inv(np.array(morph.matrix_world)) @ np.array(obj.matrix_world)
    mirrored = np.linalg.det(m[:3, :3]) < 0  # keep the triangles outward
    vertices = vertices @ m[:3, :3].T + m[:3, 3]
    corners = corners @ m[:3, :3].T + m[:3, 3]
    return compare_frame(frame_vertices, frame_corners, vertices, corners[:, ::-1] if mirrored else corners)


def assert_morph_shows(morph, obj, *frames: int) -> None:
    """At each of `frames` the morph's frame is `obj`'s evaluated mesh, within frame_matches's
    tolerance."""
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        report = compare_with(morph, obj)
        assert frame_matches(report), (obj.name, frame, report)
