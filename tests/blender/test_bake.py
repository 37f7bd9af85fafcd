"""Bake: node-group frames collection, Alembic + Mesh Sequence Cache, OBJ/PLY
sequence, frame-range chunks; the baked .blend is checked in a fresh process
without the add-on."""

from __future__ import annotations

import json

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import canonical, mesh_corners, run_fresh_blender, scene_state  # noqa: E402

pytestmark = pytest.mark.blender

FRAMES = (1, 6, 12, 19, 30, 41, 48)
HELD = {0: 1, 60: 48}  # outside the baked range the first / last frame holds

# Runs in a fresh python3 + bpy without animanifold: opens the .blend, prints per frame
# the evaluated mesh of the manifold object as JSON (corners, material indices, UVs).
PROBE = r"""
import json, sys
import bpy, numpy as np
blend, name, frames = sys.argv[1], sys.argv[2], [int(f) for f in sys.argv[3].split(",")]
assert "animanifold" not in sys.modules and "animanifold_blender" not in sys.modules
bpy.ops.wm.open_mainfile(filepath=blend)
handlers = [h.__name__ for h in bpy.app.handlers.frame_change_post]
assert not any("animanifold" in h for h in handlers), handlers
obj = bpy.data.objects[name]
out = {}
for f in frames:
    bpy.context.scene.frame_set(f)
    me = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    me.calc_loop_triangles()
    co = np.empty(3 * len(me.vertices), np.float32); me.vertices.foreach_get("co", co)
    tv = np.empty(3 * len(me.loop_triangles), np.int32); me.loop_triangles.foreach_get("vertices", tv)
    mi = np.empty(len(me.loop_triangles), np.int32); me.loop_triangles.foreach_get("material_index", mi)
    uv_names = [a.name for a in me.attributes if a.data_type == "FLOAT2" and a.domain == "CORNER"]
    out[f] = {"corners": co.reshape(-1, 3)[tv.reshape(-1, 3)].tolist(), "materials": sorted(set(mi.tolist())),
              "slots": [s.material.name if s.material else None for s in obj.material_slots],
              "triangle_materials": mi.tolist(), "material_names": [m.name if m else None for m in me.materials],
              "uv": uv_names, "modifiers": [m.type for m in obj.modifiers if m.show_render and m.name != "Animanifold Live"]}
bpy.ops.wm.read_factory_settings(use_empty=True)
print("PROBE" + json.dumps(out))
"""
# (The live modifier, first in the stack, passes the mesh through once baked: not listed.)


def probe(blend, name, frames):
    out = run_fresh_blender(PROBE, str(blend), name, ",".join(map(str, frames)))
    line = [ln for ln in out.splitlines() if ln.startswith("PROBE")][-1]
    return {int(k): v for k, v in json.loads(line[5:]).items()}


@pytest.fixture()
def converted(demo, tmp_path):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "bake.blend"))
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    return man, am.load(bpy.path.abspath(man.animanifold.cache_path)), tmp_path


def expected_corners(cache, frame):
    s = cache.slice(frame)
    return s.vertices.astype(np.float32).astype(np.float64)[s.faces]  # as Blender stores them


def test_node_group_bake_plays_without_the_addon(converted):
    man, cache, tmp = converted
    meshes_before = len(bpy.data.meshes)
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    assert man.animanifold.mode == "BAKED"
    coll = man.animanifold.bake_collection
    assert coll is not None and len(coll.objects) == 48
    assert len(bpy.data.meshes) == meshes_before + 48
    # In this process too (the handler leaves baked objects alone).
    bpy.context.scene.frame_set(19)
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    np.testing.assert_allclose(canonical(mesh_corners(ev)), canonical(expected_corners(cache, 19)), atol=1e-6)
    bpy.ops.wm.save_mainfile()

    result = probe(tmp / "bake.blend", "Blob_manifold", FRAMES + tuple(HELD))
    for f in FRAMES + tuple(HELD):
        got = np.array(result[f]["corners"])
        np.testing.assert_allclose(canonical(got), canonical(expected_corners(cache, HELD.get(f, f))), atol=1e-6,
                                   err_msg=f"frame {f}")
        assert len(got) == cache.metadata["keyframe_faces"], f"frame {f}: not the source's triangles"  # prism frames
        assert result[f]["materials"] == [0, 1] and result[f]["slots"] == ["BlobSkin", "BlobCap"]
        assert "UVMap" in result[f]["uv"]
        assert result[f]["modifiers"] == ["NODES"]

    # Re-bake replaces the old bake (nothing left behind).
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    assert len(bpy.data.meshes) == meshes_before + 48
    assert [c.name for c in bpy.data.collections] == ["Blob_manifold_bake"]
    assert [m.name for m in man.modifiers if m.name != "Animanifold Live"] == ["Animanifold Bake"]


@pytest.mark.skipif(not bpy.app.alembic.supported, reason="this bpy has no Alembic")
def test_alembic_mesh_sequence_cache_bake(converted):
    man, cache, tmp = converted
    assert bpy.ops.animanifold.bake(alembic=True, use_mesh_cache=True) == {"FINISHED"}
    abc = tmp / "animanifold_bake" / "Blob_manifold.abc"
    assert abc.is_file() and abc.stat().st_size > 0
    mod = man.modifiers["Animanifold Alembic"]
    assert mod.type == "MESH_SEQUENCE_CACHE" and mod.cache_file.filepath == "//animanifold_bake/Blob_manifold.abc"
    assert not man.modifiers["Animanifold Bake"].show_render
    for f in FRAMES:  # the cache's frames carry none of the object's own (live) layers at defaults
        bpy.context.scene.frame_set(f)
        me = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        normals = np.empty(3 * len(me.loops), np.float32)
        me.corner_normals.foreach_get("vector", normals)
        np.testing.assert_allclose(np.linalg.norm(normals.reshape(-1, 3), axis=1), 1.0, atol=1e-4,
                                   err_msg=f"frame {f}: zero normals (they render black)")
    bpy.ops.wm.save_mainfile()
    result = probe(tmp / "bake.blend", "Blob_manifold", FRAMES)
    names = ["BlobSkin", "BlobCap"]
    for f in FRAMES:
        # The cache reads the archive's first part (one per material) into an empty mesh; the
        # join adds the others.
        assert result[f]["modifiers"] == ["NODES", "MESH_SEQUENCE_CACHE", "NODES"]
        got = np.array(result[f]["corners"])
        np.testing.assert_allclose(canonical(got, 5), canonical(expected_corners(cache, f), 5), atol=2e-5,
                                   err_msg=f"frame {f}")
        assert len(got) == cache.metadata["keyframe_faces"], f"frame {f}: not the source's triangles"  # prism frames
        # Each triangle's material (by name), whatever the order of triangles and slots.
        s = cache.slice(f)
        want = sorted(zip(np.round(s.vertices[s.faces].mean(axis=1), 4).tolist(),
                          [names[i] for i in s.face_attributes["material_index"]]))
        got_mat = sorted(zip(np.round(got.mean(axis=1), 4).tolist(),
                             [result[f]["material_names"][i] for i in result[f]["triangle_materials"]]))
        assert [m for _, m in got_mat] == [m for _, m in want], f"frame {f}: materials differ"


def test_obj_and_ply_sequences_and_farm_chunks(converted):
    man, cache, tmp = converted
    assert bpy.ops.animanifold.bake(alembic=False, export="OBJ", use_scene_range=False, frame_start=10,
                                    frame_end=14, directory=str(tmp / "objs")) == {"FINISHED"}
    files = sorted(p.name for p in (tmp / "objs").iterdir())
    assert files == sorted([f"Blob_manifold_{f:06d}.obj" for f in range(10, 15)] + ["Blob_manifold_000010-000014.mtl"])
    assert "mtllib Blob_manifold_000010-000014.mtl" in (tmp / "objs" / "Blob_manifold_000012.obj").read_text()
    for f in (10, 12, 14):
        v, faces = am.read_mesh(tmp / "objs" / f"Blob_manifold_{f:06d}.obj")
        np.testing.assert_allclose(canonical(v[faces], 5), canonical(expected_corners(cache, f), 5), atol=1e-5)
    # The chunk's collection holds only its frames; the node group maps frame 10 to child 0.
    assert len(man.animanifold.bake_collection.objects) == 5
    bpy.context.scene.frame_set(12)
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    np.testing.assert_allclose(canonical(mesh_corners(ev)), canonical(expected_corners(cache, 12)), atol=1e-6)
    # PLY, another chunk into the same folder, as a second farm job would.
    assert bpy.ops.animanifold.bake(alembic=False, export="PLY", use_scene_range=False, frame_start=15,
                                    frame_end=16, directory=str(tmp / "objs")) == {"FINISHED"}
    assert (tmp / "objs" / "Blob_manifold_000016.ply").is_file()


def test_bake_failures_leave_the_scene_unchanged(converted, monkeypatch):
    man, cache, tmp = converted
    before = scene_state()
    with pytest.raises(RuntimeError, match="outside the manifold's frames 1–48"):
        bpy.ops.animanifold.bake(alembic=False, use_scene_range=False, frame_start=100, frame_end=120)
    assert scene_state() == before
    # A failure in the middle of building the frames removes what was built.
    from animanifold_blender import mesh_writer

    real = mesh_writer.write_mesh
    calls = {"n": 0}

    def failing(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 10:
            raise RuntimeError("disk on fire")
        return real(*args, **kwargs)

    monkeypatch.setattr(mesh_writer, "write_mesh", failing)
    with pytest.raises(RuntimeError, match="Bake failed: disk on fire"):
        bpy.ops.animanifold.bake(alembic=False)
    monkeypatch.undo()
    assert scene_state() == before
    assert man.animanifold.mode == "LIVE"


def test_failed_rebake_restores_the_previous_bake(converted, monkeypatch):
    man, cache, tmp = converted
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    before = scene_state()
    group = man.modifiers["Animanifold Bake"].node_group
    from animanifold_blender import bake

    def failing_export(*args, **kwargs):
        raise bake.BakeError("exporter exploded")

    monkeypatch.setattr(bake, "export_alembic", failing_export)
    monkeypatch.setattr(bake, "alembic_supported", lambda: True)
    with pytest.raises(RuntimeError, match="exporter exploded"):
        bpy.ops.animanifold.bake(alembic=True)
    assert scene_state() == before
    assert man.modifiers["Animanifold Bake"].node_group == group and man.animanifold.mode == "BAKED"
    assert man.animanifold.bake_collection.name == "Blob_manifold_bake"
    bpy.context.scene.frame_set(30)
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    np.testing.assert_allclose(canonical(mesh_corners(ev)), canonical(expected_corners(cache, 30)), atol=1e-6)


def test_back_to_live_after_bake(converted):
    man, cache, tmp = converted
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    assert bpy.ops.animanifold.make_live.poll()
    assert bpy.ops.animanifold.make_live() == {"FINISHED"}
    assert man.animanifold.mode == "LIVE" and not man.modifiers["Animanifold Bake"].show_viewport
    bpy.context.scene.frame_set(33)
    ev = man.evaluated_get(bpy.context.evaluated_depsgraph_get()).data  # what is shown and rendered
    co = np.empty(3 * len(ev.vertices), np.float32)
    ev.vertices.foreach_get("co", co)
    np.testing.assert_allclose(co.reshape(-1, 3), cache.slice(33).vertices, atol=1e-6)
    assert bpy.context.scene.render.use_lock_interface


def test_farm_chunks_in_separate_processes(converted):
    """Two processes bake two chunks from the same .blend and cache (add-on from the
    repository, as a farm node would have it installed)."""
    import subprocess
    import sys

    from helpers.blender_helpers import SCENES

    man, cache, tmp = converted
    bpy.ops.wm.save_mainfile()
    procs = [subprocess.run([sys.executable, str(SCENES / "farm_bake_chunk.py"), str(tmp / "bake.blend"), "bake-chunk",
                             "--start", str(a), "--end", str(b), "--outputs", "obj", "--directory", "//farm/"],
                            capture_output=True, text=True, timeout=240, cwd="/")
             for a, b in ((1, 24), (25, 48))]
    for p in procs:
        assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    files = sorted(f.name for f in (tmp / "farm").iterdir() if f.suffix == ".obj")
    assert files == [f"Blob_manifold_{f:06d}.obj" for f in range(1, 49)]
    assert (tmp / "farm" / "Blob_manifold_000025-000048.done.json").is_file()
    for f in (1, 24, 25, 37):
        v, faces = am.read_mesh(tmp / "farm" / f"Blob_manifold_{f:06d}.obj")
        np.testing.assert_allclose(canonical(v[faces], 5), canonical(expected_corners(cache, f), 5), atol=1e-5)
