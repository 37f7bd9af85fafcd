"""The command line on bad input, as a new user or an attacker would give it: every case ends
with a nonzero exit code and one line naming the problem, never a traceback (an exception out
of main() is what prints one); writes that fail are reported, never silently lost."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold import meshio
from animanifold.cli import main
from animanifold.procedural import icosphere
from helpers.cache_files import assemble, split

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture
def files(tmp_path: Path) -> dict[str, Path]:
    """Two OBJ keyframes, their cache, text-STL keyframes, hostile caches, a FIFO and a folder."""
    v, f = icosphere(1)
    made = {"a": tmp_path / "a.obj", "b": tmp_path / "b.obj", "cache": tmp_path / "m.amf"}
    am.write_mesh(made["a"], v, f)
    am.write_mesh(made["b"], v * 1.2, f)
    assert main(["stitch", str(made["a"]), str(made["b"]), "-o", str(made["cache"])]) == 0
    for name, scale in [("s1", 1.0), ("s2", 1.2)]:
        made[name] = tmp_path / f"{name}.stl"
        made[name].write_text(text_stl(v * scale, f))
    made["stl_as_obj"] = tmp_path / "stl.obj"
    made["stl_as_obj"].write_text(text_stl(v, f))
    version, header, payload = split(made["cache"].read_bytes())
    made["nested"] = tmp_path / "nested.amf"
    made["nested"].write_bytes(assemble(1, b"[" * 100_000 + b"]" * 100_000, payload))
    made["huge"] = tmp_path / "huge.amf"
    made["huge"].write_bytes(assemble(version, {**header, "points": 10**18}, payload))
    made["float"] = tmp_path / "float.amf"
    made["float"].write_bytes(assemble(version, {**header, "simplices": 1e308}, payload))
    made["fifo"] = tmp_path / "pipe"
    os.mkfifo(made["fifo"])
    made["dir"] = tmp_path / "folder.amf"
    made["dir"].mkdir()
    return made


def text_stl(vertices: np.ndarray, faces: np.ndarray) -> str:
    facets = "".join("facet normal 0 0 0\n outer loop\n" + "".join(f"  vertex {x} {y} {z}\n" for x, y, z in vertices[t])
                     + " endloop\nendfacet\n" for t in faces)
    return f"solid keyframe\n{facets}endsolid keyframe\n"


BAD = {  # name: (argv with {file} placeholders, a word the message must hold)
    "stitch to a FIFO": ("stitch {a} {b} -o {fifo}", "FIFO"),
    "stitch to a folder": ("stitch {a} {b} -o {dir}", "directory"),
    "stitch text STL": ("stitch {s1} {s2} -o {tmp}/x.amf", "STL"),
    "stitch STL text named .obj": ("stitch {stl_as_obj} {a} -o {tmp}/x.amf", "STL"),
    "stitch a missing file": ("stitch {a} {tmp}/missing.obj -o {tmp}/x.amf", "missing.obj"),
    "slice a FIFO": ("slice {fifo} -t 0.5 -o {tmp}/f.obj", "FIFO"),
    "info a FIFO": ("info {fifo}", "FIFO"),
    "info a folder": ("info {dir}", "directory"),
    "info a nested header": ("info {nested}", "nested"),
    "info a huge count": ("info {huge}", "huge.amf"),
    "slice a float count": ("slice {float} -t 0.5 -o {tmp}/f.obj", "integer"),
    "slice to an unknown format": ("slice {cache} -t 0.5 -o {tmp}/f.xyz", ".obj"),
    "slice to a folder": ("slice {cache} -t 0.5 -o {dir}", "extension"),
    "frames -n 10^10": ("frames {cache} -n 10000000000 -o {tmp}/frames", "-n"),
    "frames -n 0": ("frames {cache} -n 0 -o {tmp}/frames", "-n"),
    "morph --frames huge": ("morph {a} {b} -o {tmp}/morph --frames 10000000000", "--frames"),
    "demo --frames huge": ("demo -o {tmp}/demo --frames 10000000000 --no-picture", "--frames"),
    "skeleton --wrap-density 100000": ("skeleton {a} -o {tmp}/s.obj --wrap-density 100000", "wrap_density"),
    "skeleton --wrap-density 0": ("skeleton {a} -o {tmp}/s.obj --wrap-density 0", "wrap-density"),
    "skeleton of an STL text .obj": ("skeleton {stl_as_obj} -o {tmp}/s.obj", "stl.obj"),
    "subdivide a FIFO": ("subdivide {fifo} -o {tmp}/s.amf", "FIFO"),
    "subdivide a nested header": ("subdivide {nested} -o {tmp}/s.amf", "nested"),
    "subdivide to a folder": ("subdivide {cache} -o {dir} -q", "directory"),
    "deform a huge count": ("deform {huge} -o {tmp}/d.amf --anchors t::0 --handles t:1: --translate 0 0 1 0", "huge.amf"),
    "deform to a FIFO": ("deform {cache} -o {fifo} --anchors t::0 --handles t:1: --translate 0 0 1 0 -q", "FIFO"),
}
if os.path.exists("/dev/zero"):
    BAD["info /dev/zero"] = ("info /dev/zero", "character device")
    BAD["slice /dev/zero"] = ("slice /dev/zero -t 0 -o {tmp}/f.obj", "character device")
    BAD["subdivide /dev/zero"] = ("subdivide /dev/zero -o {tmp}/s.amf", "character device")


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_ends_in_one_line_and_a_nonzero_exit(capsys, tmp_path, files, case):
    argv, word = BAD[case]
    names = {**{k: str(v) for k, v in files.items()}, "tmp": str(tmp_path)}
    capsys.readouterr()
    code = main(argv.format(**names).split())
    err = capsys.readouterr().err
    assert code != 0
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("animanifold: error: ") and word in lines[0], err


def test_a_full_disk_while_saving_fails_the_stitch_and_leaves_nothing(capsys, tmp_path, files, monkeypatch):
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    capsys.readouterr()
    assert main(["stitch", str(files["a"]), str(files["b"]), "-o", str(tmp_path / "out.amf")]) == 2
    assert "No space left on device" in capsys.readouterr().err
    assert not list(tmp_path.glob("*out.amf*"))


def test_a_mesh_that_reaches_the_disk_incomplete_fails_the_slice(capsys, tmp_path, files, monkeypatch):
    real = meshio._core.write_mesh

    def loses_its_last_buffer(path, vertices, faces):  # what CGAL's unchecked final flush does on a full disk
        real(path, vertices, faces)
        os.truncate(path, os.path.getsize(path) // 2)

    monkeypatch.setattr(meshio._core, "write_mesh", loses_its_last_buffer)
    out = tmp_path / "frame.obj"
    out.write_text("the user's older frame\n")
    capsys.readouterr()
    assert main(["slice", str(files["cache"]), "-t", "0.5", "-o", str(out)]) == 2
    assert "frame.obj" in capsys.readouterr().err
    assert out.read_text() == "the user's older frame\n"
    assert sorted(p.name for p in tmp_path.glob(".frame.obj*")) == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (a device that is always full)")
def test_a_report_that_cannot_be_printed_fails_the_command(files):
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "animanifold", "info", str(files["cache"])], stdout=full,
                              stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONPATH": str(REPO / "python")})
    assert done.returncode == 2 and "No space left" in done.stderr and "Traceback" not in done.stderr


def test_negative_relative_obj_indices_are_read_as_the_obj_format_says(tmp_path):
    """`f -3 -2 -1` names the last three vertices read so far (handled by CGAL's reader)."""
    v, f = icosphere(0)
    lines = []
    for face in f:  # each face written after its own copies of its corners, with relative indices
        lines += [f"v {x} {y} {z}" for x, y, z in v[face]] + ["f -3 -2 -1"]
    (tmp_path / "relative.obj").write_text("\n".join(lines) + "\n")
    vertices, faces = am.read_mesh(tmp_path / "relative.obj")
    assert np.array_equal(faces, np.arange(3 * len(f)).reshape(-1, 3))
    assert np.array_equal(vertices[faces], v[f])


def test_skeleton_of_the_shared_torus_ends_cleanly(capsys, tmp_path, shared_data):
    capsys.readouterr()
    assert main(["skeleton", str(shared_data / "meshes" / "torus.obj"), "-o", str(tmp_path / "s.obj")]) == 0
    out, err = capsys.readouterr()
    assert "Traceback" not in err and "skeleton:" in out
    assert len(am.read_mesh(tmp_path / "s.obj")[1]) > 0


def test_an_empty_skeleton_is_called_convex_only_when_the_shape_is(capsys, tmp_path):
    """A primitive torus (regular sampling: many sites on one sphere) gets an empty skeleton from
    the core; the message must blame the sampling, not call a torus convex."""
    from helpers.shapes import torus

    am.write_mesh(tmp_path / "torus.obj", *torus())
    am.write_mesh(tmp_path / "ball.obj", *icosphere(2))
    capsys.readouterr()
    assert main(["skeleton", str(tmp_path / "torus.obj"), "-o", str(tmp_path / "s.obj")]) == 2
    torus_error = capsys.readouterr().err
    assert main(["skeleton", str(tmp_path / "ball.obj"), "-o", str(tmp_path / "s.obj"), "--side", "external"]) == 2
    ball_error = capsys.readouterr().err
    assert "not convex" in torus_error and "noise" in torus_error and "the skeleton of" in torus_error
    assert "the external skeleton of" in ball_error and "the shape is convex" in ball_error
