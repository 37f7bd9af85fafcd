"""Caches follow the .blend (bpy 4.5): Save As into another folder, the first save of an
unsaved file, Save Copy; and Relink Cache for a missing or damaged cache."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import mesh_vertices, shown  # noqa: E402

pytestmark = pytest.mark.blender


def convert(obj):
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    return bpy.data.objects[obj.name + "_manifold"]


def assert_plays(name, cache_file, frames=(7, 24, 40)):
    man = bpy.data.objects[name]
    cache = am.load(str(cache_file))
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        np.testing.assert_allclose(mesh_vertices(shown(man)), cache.slice(frame).vertices, atol=1e-6,
                                   err_msg=f"frame {frame}")


def reopen(blend):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(blend))


def test_save_as_into_another_folder_keeps_the_cache(demo, tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    bpy.ops.wm.save_as_mainfile(filepath=str(first / "shot.blend"))
    man = convert(demo)
    assert man.animanifold.cache_path == "//shot.Blob_manifold.amf"
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.save_as_mainfile(filepath=str(second / "shot.blend"))  # a folder Save As makes
    assert (second / "shot.Blob_manifold.amf").is_file()
    assert man.animanifold.cache_path == "//shot.Blob_manifold.amf"
    assert_plays(man.name, second / "shot.Blob_manifold.amf")
    reopen(second / "shot.blend")
    assert_plays("Blob_manifold", second / "shot.Blob_manifold.amf")
    reopen(first / "shot.blend")  # the old file keeps its own
    assert_plays("Blob_manifold", first / "shot.Blob_manifold.amf")


def test_another_file_of_the_same_name_is_not_overwritten(demo, tmp_path):
    (tmp_path / "b").mkdir()
    other = tmp_path / "b" / "shot.Blob_manifold.amf"
    other.write_bytes(b"another file")
    (tmp_path / "a").mkdir()
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "a" / "shot.blend"))
    man = convert(demo)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "b" / "shot.blend"))
    assert other.read_bytes() == b"another file"
    assert man.animanifold.cache_path == "//shot.Blob_manifold.1.amf"
    reopen(tmp_path / "b" / "shot.blend")
    assert_plays("Blob_manifold", tmp_path / "b" / "shot.Blob_manifold.1.amf")


def test_first_save_brings_the_temporary_cache_beside_the_blend(demo, tmp_path):
    man = convert(demo)
    temporary = man.animanifold.cache_path
    assert os.path.isabs(temporary)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "new.blend"))
    assert man.animanifold.cache_path == "//new.Blob_manifold.amf"
    assert (tmp_path / "new.Blob_manifold.amf").read_bytes() == Path(temporary).read_bytes()
    reopen(tmp_path / "new.blend")
    assert_plays("Blob_manifold", tmp_path / "new.Blob_manifold.amf")


def test_save_copy_leaves_the_session_on_its_cache(demo, tmp_path):
    (tmp_path / "copy").mkdir()
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "shot.blend"))
    man = convert(demo)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "copy" / "shot.blend"), copy=True)
    assert bpy.data.filepath == str(tmp_path / "shot.blend")
    assert man.animanifold.cache_path == "//shot.Blob_manifold.amf"
    reopen(tmp_path / "copy" / "shot.blend")
    assert_plays("Blob_manifold", tmp_path / "copy" / "shot.Blob_manifold.amf")


def test_relink_cache(demo, tmp_path):
    from animanifold_blender import live

    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "shot.blend"))
    man = convert(demo)
    cache_file = tmp_path / "shot.Blob_manifold.amf"
    moved = tmp_path / "moved.amf"
    os.replace(cache_file, moved)
    bpy.context.scene.frame_set(30)
    assert "does not exist" in live.last_error(man)
    objects = len(bpy.data.objects)
    damaged = tmp_path / "damaged.amf"
    damaged.write_bytes(moved.read_bytes()[:100])
    with pytest.raises(RuntimeError, match=r"damaged.amf is truncated or damaged"):
        bpy.ops.animanifold.relink_cache(filepath=str(damaged))
    assert man.animanifold.cache_path == "//shot.Blob_manifold.amf"  # unchanged
    with pytest.raises(RuntimeError, match=r"no cache file"):
        bpy.ops.animanifold.relink_cache(filepath=str(tmp_path / "nothing.amf"))
    assert bpy.ops.animanifold.relink_cache(filepath=str(moved)) == {"FINISHED"}
    assert man.animanifold.cache_path == "//moved.amf" and live.last_error(man) is None
    assert len(bpy.data.objects) == objects  # no second manifold object
    assert_plays(man.name, moved, frames=(30, 12))


def test_relink_cache_needs_a_manifold_object(demo):
    assert not bpy.ops.animanifold.relink_cache.poll()


def test_report_missing_caches_names_the_object(demo, tmp_path, capfd):
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "shot.blend"))
    convert(demo)
    capfd.readouterr()
    assert bpy.ops.animanifold.report_missing_caches() == {"FINISHED"}
    assert "No manifold cache is missing" in capfd.readouterr().out
    # Blender's own Report Missing Files walks data-block paths only: it says nothing of it.
    os.remove(tmp_path / "shot.Blob_manifold.amf")
    bpy.ops.file.report_missing_files()
    assert "shot.Blob_manifold.amf" not in "".join(capfd.readouterr())
    assert bpy.ops.animanifold.report_missing_caches() == {"FINISHED"}
    out = capfd.readouterr().out
    assert "'Blob_manifold': cache //shot.Blob_manifold.amf not found" in out
    from animanifold_blender import ops_cache  # in File > External Data

    assert ops_cache.draw_external_data_menu in bpy.types.TOPBAR_MT_file_external_data._dyn_ui_initialize()
