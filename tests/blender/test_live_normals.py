"""Live frames shade like baked ones by default: the same per-corner normals (the source's
smooth normals carried along the manifold), on keyframes and frames between them
(bpy 4.5, where the live modifier moves the mesh)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

from helpers.blender_helpers import shown  # noqa: E402

pytestmark = pytest.mark.blender


def corner_table(mesh) -> np.ndarray:
    """(C, 6): each corner's position and normal, rows sorted (the two meshes' vertex orders may differ)."""
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    corner_vertex = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", corner_vertex)
    normals = np.empty(3 * len(mesh.loops), np.float32)
    mesh.corner_normals.foreach_get("vector", normals)
    rows = np.column_stack([np.round(co.reshape(-1, 3)[corner_vertex], 5), normals.reshape(-1, 3)]).astype(np.float64)
    return rows[np.lexsort(rows.T[::-1])]


def baked_mesh(man, frame):
    from animanifold_blender import bake

    collection = bake.build_frames(man, [frame], "normals_probe")
    return collection, collection.objects[0].data


@pytest.mark.parametrize("frame", [1, 12, 17, 30])
def test_live_frames_have_the_baked_normals(demo, frame):
    from animanifold_blender import bake

    bpy.context.view_layer.objects.active = demo
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    man = bpy.context.active_object
    bpy.context.scene.frame_set(frame)
    live = corner_table(shown(man))
    collection, mesh = baked_mesh(man, frame)
    try:
        baked = corner_table(mesh)
    finally:
        bake.remove_collection(collection)
    assert live.shape == baked.shape
    np.testing.assert_allclose(live[:, :3], baked[:, :3], atol=2e-5)
    np.testing.assert_allclose(live[:, 3:], baked[:, 3:], atol=1e-5, err_msg=f"frame {frame}: normals")
