"""The farm bake (issue 25): the OpenJD bake bundle run with `openjd run` over a converted demo
scene in 3 chunks, then assembled; the assembled .blend and Alembic checked against live
slicing in a fresh process without the add-on; a chunk killed partway and re-run; two chunk
tasks at once; the farm module imported from a 4.2+ extension install.

Blender here is bpy 4.5 behind tests/helpers/bpy_blender.py (Debian's Blender 3.4 has no
Alembic); the add-on and the package come from the repository on PYTHONPATH, as a farm
node with the add-on folder on PYTHONPATH would have them."""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy", reason="bpy (Blender as a Python module: pip install 'bpy>=4.5,<4.6') is not installed")

import animanifold as am  # noqa: E402
from helpers.blender_helpers import (BLENDER, NO_BLENDER_BINARY, ROOT, _packed_addon_and_env,  # noqa: E402
                                     run_blender_binary_smoke, run_fresh_blender)

pytestmark = pytest.mark.blender

OPENJD = shutil.which("openjd")
NO_OPENJD = "openjd-cli (pip install openjd-cli, scripts/install-deps.sh) is not installed"
STAND_IN = str(ROOT / "tests" / "helpers" / "bpy_blender.py")
TEMPLATE = ROOT / "farm" / "openjd" / "bake" / "template.yaml"
CHUNKS = ((1, 16), (17, 32), (33, 48))
CHECKED_FRAMES = (1, 9, 16, 17, 25, 32, 33, 41, 48)  # both ends and the middle of every chunk
FARM_EXPR = "from animanifold_blender import farm; farm.main()"

# Fresh python3 + bpy without animanifold: per frame, the evaluated mesh of the manifold object
# of a .blend (or every mesh object an Alembic file imports as: one per material) as loop
# triangles: corners, UVs of the active map and each triangle's material name.
PROBE = r"""
import json, sys
import bpy, numpy as np
path, name, frames = sys.argv[1], sys.argv[2], [int(f) for f in sys.argv[3].split(",")]
assert "animanifold" not in sys.modules and "animanifold_blender" not in sys.modules
if path.endswith(".abc"):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.alembic_import(filepath=path, as_background_job=False)
    objects = [o for o in bpy.data.objects if o.type == "MESH"]
else:
    bpy.ops.wm.open_mainfile(filepath=path)
    objects = [bpy.data.objects[name]]
out = {}
for f in frames:
    bpy.context.scene.frame_set(f)
    frame = {"corners": [], "uv": [], "materials": [], "objects": len(objects)}
    for obj in objects:
        me = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        me.calc_loop_triangles()
        co = np.empty(3 * len(me.vertices), np.float32); me.vertices.foreach_get("co", co)
        tv = np.empty(3 * len(me.loop_triangles), np.int32); me.loop_triangles.foreach_get("vertices", tv)
        tl = np.empty(3 * len(me.loop_triangles), np.int32); me.loop_triangles.foreach_get("loops", tl)
        mi = np.empty(len(me.loop_triangles), np.int32); me.loop_triangles.foreach_get("material_index", mi)
        uv = np.empty(2 * len(me.loops), np.float32); me.uv_layers.active.data.foreach_get("uv", uv)
        names = [m.name if m else None for m in me.materials]
        frame["corners"] += co.reshape(-1, 3)[tv.reshape(-1, 3)].tolist()
        frame["uv"] += uv.reshape(-1, 2)[tl.reshape(-1, 3)].tolist()
        frame["materials"] += [names[i] for i in mi]
    out[f] = frame
print("PROBE" + json.dumps(out))
"""


def probe(path, name, frames):
    out = run_fresh_blender(PROBE, str(path), name, ",".join(map(str, frames)))
    line = [ln for ln in out.splitlines() if ln.startswith("PROBE")][-1]
    return {int(k): v for k, v in json.loads(line[5:]).items()}


def triangle_table(corners, uv, materials):
    """Triangles as rows (position 9, uv 6, material), each rotated to start at its smallest
    corner and the rows sorted by position: equal meshes give equal tables whatever their order."""
    corners, uv = np.asarray(corners, np.float64), np.asarray(uv, np.float64)
    start = np.array([min(range(3), key=lambda k: tuple(np.round(tri[k], 5))) for tri in corners])
    idx = (start[:, None] + np.arange(3)[None, :]) % 3
    pos = np.take_along_axis(corners, idx[:, :, None], axis=1).reshape(len(corners), 9)
    uvs = np.take_along_axis(uv, idx[:, :, None], axis=1).reshape(len(corners), 6)
    order = np.lexsort(np.round(pos, 5).T[::-1])
    return pos[order], uvs[order], [materials[i] for i in order]


def live_table(cache, material_names, frame):
    s = cache.slice(frame)
    corners = s.vertices.astype(np.float32).astype(np.float64)[s.faces]  # as Blender stores them
    uv = s.vertex_attributes["uv"].astype(np.float32).astype(np.float64)[s.faces]
    return triangle_table(corners, uv, [material_names[i] for i in s.face_attributes["material_index"]])


def farm_env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "addon"), str(ROOT / "python")])
    return env


def run_chunk(blend, directory, start, end, outputs="blend,obj", env=None):
    return subprocess.run([sys.executable, STAND_IN, "-b", str(blend), "--python-exit-code", "1", "--python-expr",
                           FARM_EXPR, "--", "bake-chunk", "--start", str(start), "--end", str(end),
                           "--directory", str(directory), "--outputs", outputs],
                          capture_output=True, text=True, timeout=240, cwd="/", env=env or farm_env())


@pytest.fixture(scope="module")
def scene(addon, tmp_path_factory):
    """The demo scene converted and saved, its frames the tets' slices: (blend path, loaded
    cache, material names)."""
    from build_demo_scene import build_demo_scene

    tmp = tmp_path_factory.mktemp("farm")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_demo_scene(segments=16, rings=8)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp / "scene.blend"))
    assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
    man = bpy.data.objects["Blob_manifold"]
    # Played as the tets' slices (its prisms dropped), whose faces change at every sample, so
    # the archive's materials are checked across topology changes (prism frames keep the faces).
    path = bpy.path.abspath(man.animanifold.cache_path)
    converted = am.load(path)
    am.save(am.AnimationManifold(converted.core_complex, converted.metadata), path)
    bpy.ops.wm.save_mainfile()
    cache = am.load(path)
    assert cache.prisms is None
    names = [m.name for m in man.data.materials]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return tmp / "scene.blend", cache, names


@pytest.fixture(scope="module")
def baked(scene):
    """The bake bundle run by `openjd run`: 3 chunks of 16 frames, then Assemble."""
    if OPENJD is None:
        pytest.skip(NO_OPENJD)
    blend, cache, names = scene
    out = blend.parent / "out"
    inputs = {p.name: p.read_bytes() for p in blend.parent.iterdir() if p.suffix in (".blend", ".amf")}
    proc = subprocess.run([OPENJD, "run", str(TEMPLATE), "-p", f"BlendFile={blend}", "-p", f"OutputDir={out}",
                           "-p", "FrameStart=1", "-p", "FrameEnd=48", "-p", "ChunkSize=16",
                           "-p", "ChunkOutputs=blend,obj,ply", "-p", f"Blender={STAND_IN}"],
                          capture_output=True, text=True, timeout=600, cwd=str(blend.parent), env=farm_env())
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert {p.name: p.read_bytes() for p in blend.parent.iterdir() if p.suffix in (".blend", ".amf")} == inputs, \
        "the tasks changed the .blend or its cache"
    return out


def test_bake_bundle_writes_every_chunk_and_the_assembly(baked):
    names = set(os.listdir(baked))
    for a, b in CHUNKS:
        tag = f"Blob_manifold_{a:06d}-{b:06d}"
        assert {tag + ".blend", tag + ".done.json", tag + ".mtl"} <= names
    assert {f"Blob_manifold_{f:06d}.{ext}" for f in range(1, 49) for ext in ("obj", "ply")} <= names
    assert {"assembled.blend", "Blob_manifold.abc"} <= names
    assert not [n for n in names if n.startswith(".")], "temporary files left behind"
    umask = os.umask(0)
    os.umask(umask)
    for name in ("Blob_manifold_000020.obj", "Blob_manifold_000017-000032.blend", "Blob_manifold.abc",
                 "assembled.blend", "Blob_manifold_000017-000032.done.json"):
        assert stat.S_IMODE((baked / name).stat().st_mode) == 0o666 & ~umask, name  # others on the share read them


@pytest.mark.parametrize("output", ["assembled.blend", "Blob_manifold.abc"])
def test_assembled_output_shows_live_frames_of_every_chunk(scene, baked, output):
    blend, cache, material_names = scene
    result = probe(baked / output, "Blob_manifold", CHECKED_FRAMES)
    for f in CHECKED_FRAMES:
        want_pos, want_uv, want_mat = live_table(cache, material_names, f)
        got_pos, got_uv, got_mat = triangle_table(result[f]["corners"], result[f]["uv"], result[f]["materials"])
        assert got_pos.shape == want_pos.shape, f"frame {f}: {len(got_pos)} triangles, live {len(want_pos)}"
        np.testing.assert_allclose(got_pos, want_pos, atol=1e-6, err_msg=f"{output} frame {f}")
        np.testing.assert_allclose(got_uv, want_uv, atol=1e-6, err_msg=f"{output} frame {f} UVs")
        assert got_mat == want_mat, f"{output} frame {f}: materials differ"


def test_assembled_alembic_materials_follow_topology_changes(scene, baked):
    """Blender's exporter writes face sets (materials) at the first frame only; the archive holds
    one object per material, so a plain import shows every face's material at every frame,
    also after the topology changes (frames 1 and 9 have the same triangle count, connected
    otherwise)."""
    blend, cache, material_names = scene
    frames = (1, 2, 9, 17, 48)
    result = probe(baked / "Blob_manifold.abc", "Blob_manifold", frames)
    assert not np.array_equal(cache.slice(1).faces, cache.slice(9).faces), "the demo's topology no longer changes"
    for f in frames:
        assert result[f]["objects"] == len(material_names)
        got_pos, _, got_mat = triangle_table(result[f]["corners"], result[f]["uv"], result[f]["materials"])
        want_pos, _, want_mat = live_table(cache, material_names, f)
        np.testing.assert_allclose(got_pos, want_pos, atol=1e-6, err_msg=f"frame {f}")
        assert got_mat == want_mat, f"frame {f}: {sum(a != b for a, b in zip(got_mat, want_mat))} triangles " \
                                    f"of {len(want_mat)} show the wrong material"


def test_chunk_frame_files_carry_uvs_normals_and_materials(scene, baked):
    blend, cache, material_names = scene
    text = (baked / "Blob_manifold_000020.obj").read_text()
    s = cache.slice(20)
    assert text.count("\nvt ") == len(s.vertices) and text.count("\nvn ") > 0
    assert "mtllib Blob_manifold_000017-000032.mtl" in text
    assert {ln.split()[1] for ln in text.splitlines() if ln.startswith("usemtl")} == set(material_names)
    mtl = (baked / "Blob_manifold_000017-000032.mtl").read_text()
    assert all(f"newmtl {n}" in mtl for n in material_names)
    for ext in ("obj", "ply"):
        v, faces = am.read_mesh(baked / f"Blob_manifold_000020.{ext}")
        np.testing.assert_allclose(v[faces], s.vertices[s.faces], atol=1e-7)
    header = (baked / "Blob_manifold_000020.ply").read_text().split("end_header")[0]
    for prop in ("nx", "ny", "nz", "s", "t"):
        assert f"property double {prop}\n" in header
    assert "property int material_index" in header


def test_killed_chunk_leaves_no_half_written_file_and_rerun_is_identical(scene, baked, tmp_path):
    blend = scene[0]
    env = dict(farm_env(), ANIMANIFOLD_FARM_KILL_AFTER_FILES="5")
    killed = run_chunk(blend, tmp_path, 17, 32, "blend,obj,ply", env)
    assert killed.returncode == 137, killed.stdout[-2000:] + killed.stderr[-2000:]
    visible = [n for n in os.listdir(tmp_path) if not n.startswith(".")]
    assert len(visible) == 5 and not any(n.endswith(".done.json") for n in visible)
    for name in visible:  # every file that has its final name is complete
        assert (tmp_path / name).read_bytes() == (baked / name).read_bytes(), name
    assert len([n for n in os.listdir(tmp_path) if n.startswith(".")]) == 1  # the half-written temporary

    rerun = run_chunk(blend, tmp_path, 17, 32, "blend,obj,ply")
    assert rerun.returncode == 0, rerun.stdout[-2000:] + rerun.stderr[-2000:]
    names = sorted(os.listdir(tmp_path))
    assert not [n for n in names if n.startswith(".")]
    for name in names:
        if not name.endswith((".blend", ".done.json")):  # a .blend holds its save time
            assert (tmp_path / name).read_bytes() == (baked / name).read_bytes(), name
    manifest = json.loads((tmp_path / "Blob_manifold_000017-000032.done.json").read_text())
    assert set(manifest["files"]) == set(names) - {"Blob_manifold_000017-000032.done.json"}

    stamps = {n: (tmp_path / n).stat().st_mtime_ns for n in names}
    again = run_chunk(blend, tmp_path, 17, 32, "blend,obj,ply")
    assert again.returncode == 0 and "complete already" in again.stdout
    assert {n: (tmp_path / n).stat().st_mtime_ns for n in os.listdir(tmp_path)} == stamps

    damaged = tmp_path / "Blob_manifold_000020.ply"  # changed behind the manifest's back: not complete
    damaged.write_bytes(damaged.read_bytes()[:100])
    repaired = run_chunk(blend, tmp_path, 17, 32, "blend,obj,ply")
    assert repaired.returncode == 0 and "complete already" not in repaired.stdout
    assert damaged.read_bytes() == (baked / damaged.name).read_bytes()


def test_two_chunk_tasks_at_once_write_the_bytes_of_one_process(scene, tmp_path):
    blend = scene[0]
    one = tmp_path / "one"
    expr = ("from animanifold_blender import farm; "
            f"farm.bake_chunk(1, 24, directory={str(one)!r}, outputs='obj'); "
            f"farm.bake_chunk(25, 48, directory={str(one)!r}, outputs='obj')")
    single = subprocess.run([sys.executable, STAND_IN, "-b", str(blend), "--python-exit-code", "1",
                             "--python-expr", expr], capture_output=True, text=True, timeout=240, env=farm_env())
    assert single.returncode == 0, single.stdout[-2000:] + single.stderr[-2000:]
    two = tmp_path / "two"
    procs = [subprocess.Popen([sys.executable, STAND_IN, "-b", str(blend), "--python-exit-code", "1",
                               "--python-expr", FARM_EXPR, "--", "bake-chunk", "--start", str(a), "--end", str(b),
                               "--directory", str(two), "--outputs", "obj"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=farm_env())
             for a, b in ((1, 24), (25, 48))]
    for p in procs:
        out, _ = p.communicate(timeout=240)
        assert p.returncode == 0, out[-3000:]
    names = sorted(os.listdir(one))
    assert names == sorted(os.listdir(two)) and len([n for n in names if n.endswith(".obj")]) == 48
    for name in names:
        assert (one / name).read_bytes() == (two / name).read_bytes(), name


def test_assemble_names_missing_frames(scene, tmp_path):
    blend = scene[0]
    for a, b in ((1, 10), (15, 20)):
        assert run_chunk(blend, tmp_path, a, b, "blend").returncode == 0
    proc = subprocess.run([sys.executable, STAND_IN, "-b", str(blend), "--python-exit-code", "1", "--python-expr",
                           FARM_EXPR, "--", "assemble", "--directory", str(tmp_path), "--outputs", "blend"],
                          capture_output=True, text=True, timeout=240, env=farm_env())
    assert proc.returncode == 1
    assert "'Blob_manifold': frames 11–14 are in no chunk" in proc.stdout + proc.stderr
    assert not (tmp_path / "assembled.blend").exists()


def test_farm_module_imports_from_an_extension_install(scene, tmp_path):
    """Installed as a 4.2+ extension (bl_ext.user_default.animanifold_blender, from the add-on
    zip), `from animanifold_blender import farm` names the extension's own module, and bakes."""
    blend = scene[0]
    zip_path = tmp_path / "animanifold_blender.zip"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "package_addon.py"), "--output", str(zip_path)],
                   check=True, capture_output=True)
    script = f"""
import sys, bpy
bpy.ops.wm.open_mainfile(filepath={str(blend)!r})
assert bpy.ops.extensions.package_install_files(filepath={str(zip_path)!r}, repo="user_default",
                                                enable_on_install=True) == {{"FINISHED"}}
from animanifold_blender import farm
import animanifold_blender.bake
real = "bl_ext.user_default.animanifold_blender"
assert farm is sys.modules[real + ".farm"] and farm.__spec__.name == real + ".farm", farm.__spec__
assert animanifold_blender.bake is sys.modules[real + ".bake"]
farm.bake_chunk(3, 4, directory={str(tmp_path / "out")!r}, outputs="obj")
"""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["BLENDER_USER_RESOURCES"] = str(tmp_path / "resources")
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=240, env=env,
                          cwd="/")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    assert sorted(os.listdir(tmp_path / "out")) == ["Blob_manifold_000003-000004.done.json",
                                                    "Blob_manifold_000003-000004.mtl",
                                                    "Blob_manifold_000003.obj", "Blob_manifold_000004.obj"]


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(BLENDER), reason=NO_BLENDER_BINARY)
def test_blender_binary_with_the_legacy_addon_runs_the_farm_command_line(tmp_path):
    """Debian's Blender 3.4 with the zip installed and enabled as a legacy add-on: the bake
    template's command line bakes two chunks and assembles them (no Alembic in 3.4)."""
    setup = run_blender_binary_smoke(tmp_path, "setup_farm_blender34.py")
    assert setup.returncode == 0 and "FARM SETUP OK" in setup.stdout, setup.stdout[-3000:] + setup.stderr[-3000:]
    _, env = _packed_addon_and_env(tmp_path)
    blend = tmp_path / "farm.blend"
    for args in (["bake-chunk", "--start", "1", "--end", "48", "--chunk-size", "24"],
                 ["bake-chunk", "--start", "25", "--end", "48", "--chunk-size", "24"],
                 ["assemble", "--outputs", "blend"]):
        proc = subprocess.run([BLENDER, "-b", str(blend), "--python-exit-code", "1", "--python-expr", FARM_EXPR,
                               "--", *args, "--directory", "//out/"],
                              capture_output=True, text=True, env=env, timeout=300)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    cache = am.load(tmp_path / "farm.Blob_manifold.amf")
    result = probe(tmp_path / "out" / "assembled.blend", "Blob_manifold", (1, 24, 25, 48))
    for f, got in result.items():
        want = live_table(cache, ["BlobSkin", "BlobCap"], f)
        got = triangle_table(got["corners"], got["uv"], got["materials"])
        np.testing.assert_allclose(got[0], want[0], atol=1e-6, err_msg=f"frame {f}")
        np.testing.assert_allclose(got[1], want[1], atol=1e-6, err_msg=f"frame {f} UVs")
        assert got[2] == want[2], f"frame {f}: materials differ"


def test_chunk_tasks_name_what_is_wrong(scene, tmp_path):
    blend = scene[0]
    proc = run_chunk(blend, tmp_path, 1, 4, "blend,gif")
    assert proc.returncode == 1 and "unknown farm outputs ['gif']: choose from blend, abc, obj, ply" in proc.stderr
    proc = subprocess.run([sys.executable, STAND_IN, "-b", str(blend), "--python-exit-code", "1", "--python-expr",
                           FARM_EXPR, "--", "bake-chunk", "--start", "1", "--end", "4", "--object", "Nope",
                           "--directory", str(tmp_path)], capture_output=True, text=True, timeout=240, env=farm_env())
    assert proc.returncode == 1
    assert f"no manifold object 'Nope' in {blend} (manifold objects: ['Blob_manifold'])" in proc.stderr
    assert os.listdir(tmp_path) == []
