"""Real files from ../shared/data (a .blend with a shape-key action, glTF morph
targets), and the smoke test with Debian's `blender` 3.4 binary and the zip."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import DATA, ROOT, SCENES, eval_corners, mesh_corners, shown, BLENDER, NO_BLENDER_BINARY, run_blender_binary_smoke  # noqa: E402

pytestmark = pytest.mark.blender

BLEND = DATA / "blend" / "01_morphed_cube.blend"
GLTF = {name: DATA / "gltf" / f"{name}.gltf" for name in ("AnimatedMorphCube", "AnimatedMorphSphere")}


def _check_keyframes(src, man, frames):
    """Same vertex positions (1e-6) and face count at each keyframe. Blender
    triangulates quads and n-gons by their current shape, while the manifold keeps
    the first sample's triangulation, so triangles are compared as far as they agree."""
    for frame in frames:
        expected = eval_corners(src, frame)
        got = mesh_corners(shown(man))
        assert len(got) == len(expected), f"frame {frame}"
        np.testing.assert_allclose(np.unique(got.reshape(-1, 3), axis=0), np.unique(expected.reshape(-1, 3), axis=0),
                                   atol=1e-6, rtol=0, err_msg=f"frame {frame}")


@pytest.mark.data
@pytest.mark.skipif(not BLEND.is_file(), reason=f"{BLEND} is absent (../shared/data holds the test data)")
def test_khronos_morphed_cube_blend(addon, tmp_path):
    shutil.copy(BLEND, tmp_path / "cube.blend")
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "cube.blend"))
    meshes = [o for o in bpy.data.objects if o.type == "MESH" and o.data.shape_keys is not None]
    assert meshes, "the .blend should hold a mesh with shape keys"
    src = meshes[0]
    bpy.context.view_layer.objects.active = src
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    man = bpy.data.objects[src.name + "_manifold"]
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    times = cache.metadata["keyframe_times"]
    assert len(times) >= 3 and man.animanifold.cache_path.startswith("//")
    _check_keyframes(src, man, [int(t) for t in times if float(t).is_integer()][:6])


def _import_gltf(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import addon_utils

    addon_utils.enable("io_scene_gltf2", default_set=False)
    assert bpy.ops.import_scene.gltf(filepath=str(path)) == {"FINISHED"}
    return [o for o in bpy.data.objects if o.type == "MESH" and o.data.shape_keys is not None][0]


@pytest.mark.data
@pytest.mark.parametrize("name", sorted(GLTF))
def test_gltf_morph_targets(addon, name):
    path = GLTF[name]
    if not path.is_file():
        pytest.skip(f"{path} is absent (../shared/data holds the test data)")
    src = _import_gltf(path)
    scene = bpy.context.scene
    action = src.data.shape_keys.animation_data.action
    start, end = (int(np.floor(action.frame_range[0])), int(np.ceil(action.frame_range[1])))
    scene.frame_start, scene.frame_end = start, end
    bpy.context.view_layer.objects.active = src
    # glTF keys come at fractional frames: sample every 2 frames (first and last always).
    assert bpy.ops.animanifold.convert_action(sampling="EVERY_N", step=2) == {"FINISHED"}
    man = bpy.data.objects[src.name + "_manifold"]
    cache = am.load(bpy.path.abspath(man.animanifold.cache_path))
    k = cache.metadata["keyframe_vertices"]
    assert k >= len(src.data.vertices)  # split at UV seams, never merged
    assert ("uv" in cache.vertex_attributes) == (len(src.data.uv_layers) > 0)
    _check_keyframes(src, man, [start, start + 2, end])
    # The keyframe mode also works on the fractional glTF keys.
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.view_layer.objects.active = src
    src.hide_set(False)
    assert bpy.ops.animanifold.convert_action(sampling="KEYFRAMES") == {"FINISHED"}


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
def test_smoke_blender_binary_installs_zip_converts_and_bakes(tmp_path):
    proc = run_blender_binary_smoke(tmp_path, "smoke_blender34.py")
    assert proc.returncode == 0 and "SMOKE OK" in proc.stdout, proc.stdout[-4000:] + proc.stderr[-4000:]


EXTENSION_PROBE = r"""
import sys
import bpy
import addon_utils
bpy.ops.wm.read_factory_settings(use_empty=True)
assert bpy.ops.extensions.package_install_files(filepath=sys.argv[1], repo="user_default",
                                                enable_on_install=True) == {"FINISHED"}
name = [m for m in sys.modules if m.endswith(".animanifold_blender")][0]
core = [m for m in sys.modules if m.endswith("animanifold._core")]
assert core == [name + ".animanifold._core"], core  # the bundled compiled module
sys.path.insert(0, sys.argv[2])
from build_demo_scene import build_demo_scene
build_demo_scene(segments=8, rings=4)
assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
addon_utils.disable(name)  # bpy as a module hangs at exit with classes registered
print("EXTENSION OK")
"""


@pytest.mark.slow
def test_zip_installs_as_a_blender_42_extension(tmp_path):
    zip_path = tmp_path / "animanifold_blender.zip"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "package_addon.py"), "--output", str(zip_path)],
                   check=True, capture_output=True, text=True)
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "resources"))
    env.pop("PYTHONPATH", None)
    proc = subprocess.run([sys.executable, "-c", EXTENSION_PROBE, str(zip_path), str(SCENES)], capture_output=True,
                          text=True, env=env, timeout=240, cwd="/")
    assert proc.returncode == 0 and "EXTENSION OK" in proc.stdout, proc.stdout[-3000:] + proc.stderr[-3000:]


@pytest.mark.slow
def test_the_readme_main_job_runs_end_to_end(tmp_path):
    """The README's first command runs blender_scenes/run_main_job.py: convert, morph, bake, save and
    render, through the add-on's own modules. Run here as a child process (its own bpy session) at a
    small size, so a module the job reaches into cannot move without this test failing."""
    import json

    done = subprocess.run([sys.executable, str(SCENES / "run_main_job.py"), "--out", str(tmp_path), "--frames", "1,48",
                           "--samples", "1", "--resolution", "64x48", "--segments", "16"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads((tmp_path / "main_job.json").read_text())
    assert report["convert"]["tets"] > 0 and report["bake"]["frames"] == [1, 48]
    # the add-on's default sampling: every frame within 0.2 % of the source, the figure reported
    assert report["convert"]["sampling"] == "ADAPTIVE" and 0 <= report["convert"]["deviation_percent"] <= 0.2
    morph = report["morph"]
    assert morph["ends_reproduced"] and morph["oriented_manifold"] and morph["inverted_simplices"] == 0
    # whole frames showing noise are listed (1..48 here), and there are none where every check passed
    shown = morph["frames_showing_noise"]
    assert all(float(f).is_integer() and 1 < f < 48 for f in shown) and not (shown and morph["all_checks_passed"])
    assert (tmp_path / "contact_sheet.png").stat().st_size > 0 and (tmp_path / "animanifold_demo.blend").is_file()


@pytest.mark.slow
def test_the_main_job_morphs_with_the_method_asked_and_refuses_an_unknown_one(tmp_path):
    """`--morph-method field` renders the demo's morph with the field method (the report says which
    ran); an unknown method stops the job before it builds anything, naming the choices."""
    import json

    common = [sys.executable, str(SCENES / "run_main_job.py"), "--frames", "1,48", "--samples", "1",
              "--resolution", "64x48", "--segments", "16"]
    bad = subprocess.run(common + ["--out", str(tmp_path / "bad"), "--morph-method", "magic"],
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode != 0 and "unknown --morph-method 'magic'; use one of" in bad.stderr, bad.stderr[-2000:]
    assert not (tmp_path / "bad" / "animanifold_demo.blend").exists()
    done = subprocess.run(common + ["--out", str(tmp_path), "--morph-method", "field"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    morph = json.loads((tmp_path / "main_job.json").read_text())["morph"]
    assert morph["method"] == "field" and morph["ends_reproduced"] and morph["oriented_manifold"]
