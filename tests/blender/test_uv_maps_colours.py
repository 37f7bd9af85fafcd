"""Every UV map and colour attribute of the source is carried: Convert, live frames and
the node-group bake show both UV maps (the second one is what a material's UV Map node
names) and the point and corner colours, equal to the source's at the keyframes. Under
Debian's Blender 3.4 the node-group bake's result has real UV maps (not plain FLOAT2
attributes, which render as one colour)."""

from __future__ import annotations

import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import BLENDER, NO_BLENDER_BINARY, run_blender_binary_smoke, shown  # noqa: E402

pytestmark = pytest.mark.blender

KEYS = (1, 10, 20)
BETWEEN = (4, 15)
SECOND = "Detail"


def _source():
    """A subdivided cube: shape keys keyed at KEYS, the active map "UVMap", a second map
    with a seam at every face (an island per face, so seams where UVMap has none), a byte
    colour per point and a float colour per corner; a material sampling the second map."""
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    obj = bpy.context.active_object
    obj.name = "Painted"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=1)
    bpy.ops.object.mode_set(mode="OBJECT")
    me = obj.data
    L, n = len(me.loops), len(me.vertices)
    detail = me.uv_layers.new(name=SECOND, do_init=False)
    poly_of_loop = np.repeat(np.arange(len(me.polygons)), [p.loop_total for p in me.polygons])
    corner_in_poly = np.concatenate([np.arange(p.loop_total) for p in me.polygons])
    detail_uv = np.column_stack([0.01 * poly_of_loop + 0.003 * corner_in_poly, 0.5 - 0.002 * corner_in_poly])
    detail.data.foreach_set("uv", detail_uv.astype(np.float32).reshape(-1))
    me.uv_layers.active = me.uv_layers["UVMap"]
    point = me.color_attributes.new("Tint", "BYTE_COLOR", "POINT")
    point.data.foreach_set("color", np.column_stack([np.linspace(0, 1, n), np.full(n, 0.5), np.linspace(1, 0, n),
                                                     np.ones(n)]).astype(np.float32).reshape(-1))
    corner = me.color_attributes.new("Wear", "FLOAT_COLOR", "CORNER")
    corner.data.foreach_set("color", np.column_stack([np.linspace(0, 2, L), np.full(L, 0.25), np.zeros(L),
                                                      np.ones(L)]).astype(np.float32).reshape(-1))
    mat = bpy.data.materials.new("Painted")
    mat.use_nodes = True
    uv_node = mat.node_tree.nodes.new("ShaderNodeUVMap")
    uv_node.uv_map = SECOND
    me.materials.append(mat)
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Bend")
    co = np.empty(3 * n, np.float32)
    me.vertices.foreach_get("co", co)
    co = co.reshape(n, 3)
    co[:, 0] += 0.6 * co[:, 2] ** 2
    key.data.foreach_set("co", co.reshape(-1))
    for frame, value in zip(KEYS, (0.0, 1.0, 0.3)):
        key.value = value
        key.keyframe_insert("value", frame=frame)
    return obj


def _corner_rows(mesh, with_positions: bool) -> np.ndarray:
    """Per face corner: (position,) UVMap, Detail, Tint, Wear: one row each, sorted."""
    L = len(mesh.loops)
    loop_vertex = np.empty(L, np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    columns = []
    if with_positions:
        co = np.empty(3 * len(mesh.vertices), np.float32)
        mesh.vertices.foreach_get("co", co)
        columns.append(co.reshape(-1, 3)[loop_vertex])
    for name in ("UVMap", SECOND):
        layer = mesh.uv_layers.get(name)
        assert layer is not None, f"no UV map {name!r} (maps: {[m.name for m in mesh.uv_layers]})"
        uv = np.empty(2 * L, np.float32)
        layer.data.foreach_get("uv", uv)
        columns.append(uv.reshape(L, 2))
    for name in ("Tint", "Wear"):
        attribute = mesh.color_attributes.get(name)
        assert attribute is not None, f"no colour attribute {name!r}"
        values = np.empty(4 * len(attribute.data), np.float32)
        attribute.data.foreach_get("color", values)
        values = values.reshape(-1, 4)
        columns.append(values[loop_vertex] if attribute.domain == "POINT" else values)
    rows = np.hstack(columns).astype(np.float64)
    # One row per distinct corner (grouped at 1e-5), in a canonical order; values as stored.
    _, first = np.unique(np.round(rows, 5), axis=0, return_index=True)
    return rows[first]


def _source_rows(source, frame, with_positions):
    bpy.context.scene.frame_set(frame)
    ob_eval = source.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ob_eval.to_mesh()
    try:
        return _corner_rows(mesh, with_positions)
    finally:
        ob_eval.to_mesh_clear()


def _check_frames(source, obj, what):
    """At the keyframes the corners (position, both maps, both colours) are the source's; in
    between (where a slice also cuts the prisms' diagonal edges, blending two corners'
    values) both maps and colours are there, within the range of the source's values."""
    for frame in KEYS + BETWEEN:
        keyed = frame in KEYS
        expected = _source_rows(source, frame, keyed)
        bpy.context.scene.frame_set(frame)
        got = _corner_rows(shown(obj), keyed)
        if keyed:
            assert got.shape == expected.shape, f"{what}, frame {frame}: {len(got)} distinct corners, source {len(expected)}"
            np.testing.assert_allclose(got, expected, rtol=0, atol=1e-6, err_msg=f"{what}, frame {frame}")
        else:
            assert np.all(got >= expected.min(axis=0) - 1e-5) and np.all(got <= expected.max(axis=0) + 1e-5), \
                f"{what}, frame {frame}: values outside the source's"
            assert len(got) >= len(expected)


@pytest.fixture()
def painted(empty_scene):
    source = _source()
    empty_scene.frame_start, empty_scene.frame_end = KEYS[0], KEYS[-1]
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    return source, bpy.data.objects["Painted_manifold"]


def test_convert_carries_every_uv_map_and_colour(painted):
    source, man = painted
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    attrs = cache.vertex_attributes
    assert {"uv", "uv:" + SECOND, "color:Tint", "corner_color:Wear"} <= set(attrs)
    assert cache.metadata["uv_maps"] == [SECOND]
    assert sorted(cache.metadata["color_attributes"]) == ["Tint", "Wear"]
    assert man.animanifold.uv_name == "UVMap"


def test_live_frames_show_both_maps_and_the_colours(painted):
    source, man = painted
    _check_frames(source, man, "live")
    named = man.data.materials[0].node_tree.nodes["UV Map"].uv_map
    assert named == SECOND and named in shown(man).uv_layers
    assert shown(man).uv_layers.active.name == "UVMap"  # the active map stays active


def test_node_group_bake_keeps_both_maps_and_the_colours(painted):
    source, man = painted
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    _check_frames(source, man, "baked")


def _alembic_baked(painted, tmp_path):
    source, man = painted
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "painted.blend"))
    assert bpy.ops.animanifold.bake(alembic=True, use_mesh_cache=True) == {"FINISHED"}
    assert man.modifiers["Animanifold Alembic"].show_viewport
    return source, man


@pytest.mark.skipif(not bpy.app.alembic.supported, reason="this bpy has no Alembic")
def test_alembic_bake_keeps_both_uv_maps(painted, tmp_path):
    source, man = _alembic_baked(painted, tmp_path)
    for frame in KEYS:
        expected = _source_rows(source, frame, True)[:, :7]  # position, UVMap, Detail
        bpy.context.scene.frame_set(frame)
        got = _corner_rows(shown(man), True)[:, :7]
        assert got.shape == expected.shape, f"alembic, frame {frame}"
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-6, err_msg=f"alembic, frame {frame}")


@pytest.mark.skipif(not bpy.app.alembic.supported, reason="this bpy has no Alembic")
def test_alembic_bake_keeps_the_colours(painted, tmp_path):
    source, man = _alembic_baked(painted, tmp_path)
    _check_frames(source, man, "alembic")


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
def test_blender34_node_group_bake_has_real_uv_maps(tmp_path):
    """scripts/bake_uv_maps_blender34.py: both UV maps of the baked evaluated mesh equal the
    live frame's, in the baking process and in the file reopened without the add-on."""
    proc = run_blender_binary_smoke(tmp_path, "bake_uv_maps_blender34.py")
    assert proc.returncode == 0 and "UVMAPS OK" in proc.stdout, proc.stdout[-4000:] + proc.stderr[-4000:]
