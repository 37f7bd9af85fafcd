"""The command line, run in-process through main([...]) and once as `python3 -m animanifold`.

Keyframes are written by the tests themselves (a posed icosphere), so every
expectation is exact: the tet count 3·l·(m−1), the keyframe coming back from a
slice at its time, the boundary being the first and last keyframe.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold.cli import main
from animanifold.frame_quality import euler_characteristic
from animanifold.procedural import icosphere, pose, subdivide_midpoint

REPO = Path(__file__).resolve().parents[1]
TIMES = (0.0, 0.3, 1.0)
POSES = ((1.0, 0.0, (0.0, 0.0, 0.0)), (0.6, 0.8, (0.5, 0.0, -0.2)), (1.4, -0.5, (1.0, 0.3, 0.4)))


@pytest.fixture
def keyframes(tmp_path: Path) -> tuple[list[Path], np.ndarray, np.ndarray]:
    """Three OBJ keyframes of an 80-face icosphere: (files, frames (3, 42, 3), faces (80, 3))."""
    rest, faces = icosphere(1)
    frames = np.stack([pose(rest, *p) for p in POSES])
    files = []
    for i, vertices in enumerate(frames):
        path = tmp_path / f"key{i}.obj"
        am.write_mesh(path, vertices, faces)
        files.append(path)
    return files, frames, faces


@pytest.fixture
def stitched(tmp_path: Path, keyframes) -> Path:
    files, _, _ = keyframes
    out = tmp_path / "anim.amf"
    assert main(["stitch", *map(str, files), "--times", *map(str, TIMES), "-o", str(out)]) == 0
    return out


def run(capsys, *argv) -> tuple[int, str, str]:
    capsys.readouterr()  # drop what fixtures printed
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_user_error(code: int, err: str, *culprits: str) -> None:
    """Exit code 2 and one line `animanifold: error: ...` naming every culprit, no traceback."""
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("animanifold: error: "), err
    for culprit in culprits:
        assert culprit in lines[0]


def canonical_faces(faces: np.ndarray) -> set[tuple[int, ...]]:
    """Faces as a set, each rotated to start at its smallest index (rotation keeps orientation)."""
    faces = np.asarray(faces)
    shift = faces.argmin(axis=1)
    rows = np.arange(len(faces))[:, None]
    return set(map(tuple, faces[rows, (shift[:, None] + np.arange(3)) % 3].tolist()))


# -- help and usage --------------------------------------------------------------


@pytest.mark.parametrize("command", [[], ["stitch"], ["slice"], ["frames"], ["info"], ["demo"]])
def test_help_on_every_command(capsys, command):
    code, out, _ = run(capsys, *command, "--help")
    assert code == 0
    assert out.startswith("usage: animanifold")


def test_usage_errors_exit_2(capsys):
    code, _, err = run(capsys, "slice", "x.amf")  # -t and -o missing
    assert code == 2 and "required" in err


# -- stitch, slice, frames, info ----------------------------------------------------


@pytest.mark.parametrize("key", range(len(TIMES)))
def test_slice_at_a_keyframe_time_returns_that_keyframe(capsys, tmp_path, keyframes, stitched, key):
    _, frames, faces = keyframes
    out = tmp_path / "frame.obj"
    code, _, _ = run(capsys, "slice", stitched, "--t", repr(TIMES[key]), "-o", out)
    assert code == 0
    vertices, sliced = am.read_mesh(out)
    expected = frames[key]
    assert len(vertices) == len(expected) and len(sliced) == len(faces)
    # Set-equal within 1e-12: every slice vertex has a keyframe vertex that close, one to one.
    distance = np.linalg.norm(vertices[:, None, :] - expected[None, :, :], axis=2)
    match = distance.argmin(axis=1)
    assert distance[np.arange(len(vertices)), match].max() <= 1e-12
    assert len(set(match.tolist())) == len(expected)
    # The same oriented triangles, up to rotation of each face's indices.
    assert canonical_faces(match[sliced]) == canonical_faces(faces)


def test_stitch_default_times_are_evenly_spaced_over_0_1(capsys, tmp_path, keyframes):
    files, _, _ = keyframes
    out = tmp_path / "even.amf"
    assert run(capsys, "stitch", *files, "-o", out)[0] == 0
    assert am.load(out).metadata["keyframe_times"] == [0.0, 0.5, 1.0]
    assert run(capsys, "stitch", *files, "--fps", "24", "-o", out)[0] == 0
    assert am.load(out).metadata["keyframe_times"] == pytest.approx([0.0, 1 / 24, 2 / 24], abs=1e-15)


def test_info_json_reports_exact_counts_and_validity(capsys, keyframes, stitched):
    files, frames, faces = keyframes
    code, out, _ = run(capsys, "info", "--json", stitched)
    assert code == 0
    info = json.loads(out)
    m, k, l = len(frames), frames.shape[1], len(faces)
    assert info["simplices"] == 3 * l * (m - 1)
    assert info["points"] == m * k
    assert info["time_range"] == [TIMES[0], TIMES[-1]]
    validity = info["validity"]
    assert validity["misoriented_facets"] == 0 and validity["nonmanifold_facets"] == 0
    assert validity["boundary_facets"] == 2 * l  # exactly the first and last keyframe
    assert validity["is_oriented_manifold"] is True
    assert info["metadata"]["keyframe_times"] == list(TIMES)
    assert info["metadata"]["keyframe_files"] == [f.name for f in files]
    low = frames.reshape(-1, 3).min(axis=0)
    assert [info["bounding_box"][a][0] for a in "xyz"] == pytest.approx(low.tolist(), abs=0)


def test_info_text_names_validity_and_keyframes(capsys, stitched):
    code, out, _ = run(capsys, "info", stitched)
    assert code == 0
    assert "oriented manifold" in out and "0 misoriented" in out
    assert "keyframes       3 at t = 0, 0.3, 1" in out


def test_frames_writes_n_evenly_spaced_meshes(capsys, tmp_path, keyframes, stitched):
    _, _, faces = keyframes
    folder = tmp_path / "frames"
    code, _, err = run(capsys, "frames", stitched, "-n", 7, "-o", folder, "--format", "ply")
    assert code == 0
    written = sorted(folder.iterdir())
    assert [p.name for p in written] == [f"frame_{i:04d}.ply" for i in range(7)]
    assert err.count("\n") == 7  # one progress line per frame
    first, last = am.read_mesh(written[0]), am.read_mesh(written[-1])
    assert len(first[1]) == len(last[1]) == len(faces)  # t0 and t1 are keyframes
    for path in written[1:-1]:
        vertices, triangles = am.read_mesh(path)
        assert len(triangles) > 0 and np.isfinite(vertices).all()


def test_sweep_slice_along_x_has_y_z_t_coordinates(capsys, tmp_path, keyframes, stitched):
    _, frames, _ = keyframes
    out = tmp_path / "sweep.off"
    x = float(np.median(frames[..., 0]))
    assert run(capsys, "slice", stitched, "--axis", "x", "--value", x, "-o", out)[0] == 0
    vertices, triangles = am.read_mesh(out)
    assert len(triangles) > 0
    # Columns are (y, z, t): the last lies in the time range, the first two in the keyframes' y, z box.
    assert vertices[:, 2].min() >= TIMES[0] and vertices[:, 2].max() <= TIMES[-1]
    low, high = frames.reshape(-1, 3).min(axis=0), frames.reshape(-1, 3).max(axis=0)
    assert (vertices[:, :2] >= low[1:] - 1e-12).all() and (vertices[:, :2] <= high[1:] + 1e-12).all()


# -- user errors: exit code 2, one line naming the culprit -------------------------------


def test_mismatched_vertex_count_names_the_keyframe(capsys, tmp_path, keyframes):
    files, _, _ = keyframes
    finer = tmp_path / "finer.obj"
    am.write_mesh(finer, *icosphere(2))
    code, _, err = run(capsys, "stitch", files[0], finer, "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "keyframe 1", "finer.obj", "162 vertices", "42")
    assert not (tmp_path / "x.amf").exists()


def test_mismatched_faces_name_the_first_differing_face(capsys, tmp_path, keyframes):
    files, frames, faces = keyframes
    flipped = faces.copy()
    flipped[5] = flipped[5, ::-1]
    other = tmp_path / "flipped.obj"
    am.write_mesh(other, frames[1], flipped)
    code, _, err = run(capsys, "stitch", files[0], other, "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "keyframe 1", "flipped.obj", "face 5", "({} {} {})".format(*flipped[5]))


def test_non_increasing_times_name_the_keyframe(capsys, tmp_path, keyframes):
    files, _, _ = keyframes
    code, _, err = run(capsys, "stitch", *files, "--times", "0", "0.5", "0.5", "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "keyframe 2", "key2.obj", "increase")
    code, _, err = run(capsys, "stitch", *files, "--times", "0", "1", "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "3 keyframe files but 2 times")


def test_missing_keyframe_file(capsys, tmp_path, keyframes):
    files, _, _ = keyframes
    code, _, err = run(capsys, "stitch", files[0], tmp_path / "absent.obj", "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "absent.obj")


def test_malformed_mesh_file(capsys, tmp_path, keyframes):
    files, _, _ = keyframes
    junk = tmp_path / "junk.off"
    junk.write_text("OFF\n3 1 0\n0 0 0\n1 0\n")
    code, _, err = run(capsys, "stitch", files[0], junk, "-o", tmp_path / "x.amf")
    assert_user_error(code, err, "junk.off")


@pytest.mark.parametrize("command", ["info", "slice", "frames"])
def test_missing_cache_file(capsys, tmp_path, command):
    extra = {"info": [], "slice": ["-t", "0", "-o", tmp_path / "f.obj"], "frames": ["-n", "2", "-o", tmp_path / "f"]}
    code, _, err = run(capsys, command, tmp_path / "absent.amf", *extra[command])
    assert_user_error(code, err, "absent.amf", "does not exist")


@pytest.mark.parametrize("damage", ["flip", "truncate"])
def test_damaged_cache_file(capsys, tmp_path, stitched, damage):
    data = bytearray(stitched.read_bytes())
    if damage == "flip":
        data[len(data) // 2] ^= 0xFF
    else:
        del data[len(data) // 3 :]
    stitched.write_bytes(bytes(data))
    code, _, err = run(capsys, "slice", stitched, "-t", "0.5", "-o", tmp_path / "f.obj")
    assert_user_error(code, err, stitched.name, "damaged")


def test_slice_outside_the_time_range(capsys, tmp_path, stitched):
    code, _, err = run(capsys, "slice", stitched, "-t", "1.5", "-o", tmp_path / "f.obj")
    assert_user_error(code, err, "t=1.5", "[0, 1]")


def test_slice_to_an_unknown_format(capsys, tmp_path, stitched):
    code, _, err = run(capsys, "slice", stitched, "-t", "0.5", "-o", tmp_path / "f.xyz")
    assert_user_error(code, err, "f.xyz", ".obj")


# -- demo ------------------------------------------------------------------------


def test_small_demo_writes_frames_cache_and_picture(capsys, tmp_path):
    code, out, _ = run(capsys, "demo", "--small", "--output", tmp_path)
    assert code == 0
    frames = sorted((tmp_path / "frames").glob("*.obj"))
    assert len(frames) == 12
    manifold = am.load(tmp_path / "demo.amf")
    times = manifold.metadata["keyframe_times"]
    assert len(manifold.simplices) == 3 * 320 * (len(times) - 1)
    assert manifold.check().is_oriented_manifold
    assert (tmp_path / "contact_sheet.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for path in frames:
        vertices, triangles = am.read_mesh(path)
        assert len(triangles) >= 320 and np.isfinite(vertices).all()
    assert "tets" in out and "t = 0.000" in out


def test_icosphere_is_closed_and_consistently_oriented():
    vertices, faces = icosphere(2)
    assert faces.shape == (320, 3) and len(vertices) == 162
    # Closed and oriented: each directed edge exactly once, and its reverse exists.
    directed = np.stack([faces, np.roll(faces, -1, axis=1)], axis=-1).reshape(-1, 2)
    as_set = set(map(tuple, directed.tolist()))
    assert len(as_set) == len(directed)
    assert all((b, a) in as_set for a, b in as_set)
    # Outward: positive enclosed volume.
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0
    # Subdividing the same connectivity twice numbers the midpoints the same way.
    v1, f1 = subdivide_midpoint(vertices, faces)
    v2, f2 = subdivide_midpoint(vertices * 2.0, faces)
    assert np.array_equal(f1, f2) and np.allclose(v2, 2.0 * v1)


# -- the real entry point --------------------------------------------------------


def test_python_dash_m_exit_codes(tmp_path, stitched):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO / "python"), os.environ.get("PYTHONPATH", "")]))

    def module(*argv):
        return subprocess.run(
            [sys.executable, "-m", "animanifold", *map(str, argv)], capture_output=True, text=True, env=env, timeout=120
        )

    ok = module("info", "--json", stitched)
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["simplices"] == 3 * 80 * 2
    failed = module("info", tmp_path / "absent.amf")
    assert failed.returncode == 2
    assert failed.stderr.startswith("animanifold: error: ") and "Traceback" not in failed.stderr


def test_morph_writes_a_manifold_that_starts_and_ends_as_the_inputs(capsys, tmp_path):
    v, f = icosphere(2)
    am.write_mesh(tmp_path / "s.obj", v, f)
    am.write_mesh(tmp_path / "t.obj", v * [1.5, 1.0, 0.7] + [0.2, 0, 0], f)
    code, out, err = run(capsys, "morph", str(tmp_path / "s.obj"), str(tmp_path / "t.obj"), "-o",
                         str(tmp_path / "m"), "--frames", "4")
    assert code == 0, err
    assert "ends reproduced: True" in out
    m = am.load(tmp_path / "m" / "morph.amf")
    assert m.validity["ends_reproduced"] and m.check().is_oriented_manifold
    assert sorted(p.name for p in (tmp_path / "m" / "frames").iterdir()) == [f"frame_000{i}.obj" for i in range(4)]
    first, _ = am.read_mesh(tmp_path / "m" / "frames" / "frame_0000.obj")
    assert np.abs(np.linalg.norm(first, axis=1) - 1).max() < 1e-9  # the source sphere's vertices
    # an open target is refused with the reason
    am.write_mesh(tmp_path / "open.obj", v, f[:-3])
    code, out, err = run(capsys, "morph", str(tmp_path / "s.obj"), str(tmp_path / "open.obj"), "-o", str(tmp_path / "x"))
    assert_user_error(code, err, "target is open")


@pytest.fixture
def sphere_and_torus(tmp_path: Path) -> tuple[Path, Path]:
    """OBJ files of an icosphere (radius 1.5) and a torus: a morph that changes genus."""
    from helpers.shapes import torus

    v, f = icosphere(2)
    source, target = tmp_path / "s.obj", tmp_path / "t.obj"
    am.write_mesh(source, 1.5 * v, f)
    am.write_mesh(target, *torus(minor_radius=0.4, major=16, minor=8))
    return source, target


def morph_in_three_frames(capsys, inputs: tuple[Path, Path], output: Path, *options: str):
    """`morph` of the (source, target) files into `output` with 3 frames, which must succeed:
    (stdout, stderr, the saved manifold, the Euler characteristic of the last frame)."""
    code, out, err = run(capsys, "morph", *inputs, "-o", output, "--frames", "3", *options)
    assert code == 0, err
    last, faces = am.read_mesh(output / "frames" / "frame_0002.obj")
    return out, err, am.load(output / "morph.amf"), euler_characteristic(last, faces)


def test_morph_of_different_genus_with_the_skeleton_method(capsys, tmp_path, sphere_and_torus):
    out, err, m, last_euler = morph_in_three_frames(capsys, sphere_and_torus, tmp_path / "m", "--method", "skeleton",
                                                    "--max-push", "0.3")
    assert "ends reproduced: True" in out and "free vertices pushed" in out
    # the only warning: bubbles enclosed just before the torus's hole opens (a known limit of the
    # push), said when the report has them
    warnings = [line for line in err.splitlines() if "warning" in line]
    assert all("bubbles enclosed" in line for line in warnings), warnings
    assert bool(warnings) == bool(m.validity["bubble_frames"])
    assert m.metadata["morph"]["method"] == "skeleton" and m.validity["target_push"][2] <= 0.3
    assert last_euler == 0  # a torus
    code, out, err = run(capsys, "morph", *sphere_and_torus, "-o", tmp_path / "x", "--max-push", "2")
    assert_user_error(code, err, "--max-push must lie between 0 and 0.5")


def test_morph_takes_the_field_methods_resolution_and_refuses_it_elsewhere(capsys, tmp_path, sphere_and_torus):
    out, err, m, last_euler = morph_in_three_frames(capsys, sphere_and_torus, tmp_path / "m",
                                                    "--field-resolution", "12")
    assert m.metadata["morph"]["method"] == "field" and m.validity["ends_reproduced"]
    assert m.validity["lattice_spacing"] == pytest.approx(1 / 12, rel=1e-12)
    assert last_euler == 0  # a torus
    code, out, err = run(capsys, "morph", *sphere_and_torus, "-o", tmp_path / "x", "--field-resolution", "1")
    assert_user_error(code, err, "--field-resolution must be at least 2 lattice cells, got 1.0")
    code, out, err = run(capsys, "morph", *sphere_and_torus, "-o", tmp_path / "y", "--method", "skeleton",
                         "--field-resolution", "12")
    assert_user_error(code, err, "--field-resolution applies to the field method only")
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


def test_morph_with_the_field_method_says_what_it_checked(capsys, tmp_path, sphere_and_torus):
    out, err, m, last_euler = morph_in_three_frames(capsys, sphere_and_torus, tmp_path / "m", "--method", "field")
    assert m.metadata["morph"]["method"] == "field" and m.validity["ends_reproduced"]
    assert "ends reproduced: True" in out
    assert f"{m.validity['frames_checked']} frames checked" in out, out
    assert f"the topology changes {m.validity['topology_changes']} times" in out, out
    # how crossings were covered, as the report says: ruled out at every time by the certified
    # space-time triangulation and confirmed on the middle frame, or else looked for on all 24
    if m.validity["crossings_certified"]:
        assert m.validity["crossing_frames_checked"] == 1, m.validity
        assert "space-time triangulation certified; 1 frame confirms it" in out, out
    else:
        assert m.validity["crossing_frames_checked"] == 24, m.validity
        assert f"crossings checked on 24 frames (not certified: {m.validity['certificate_failure']})" in out, out
    assert last_euler == 0  # a torus


def test_the_morph_command_says_which_written_frames_show_the_noise_its_checks_found(capsys, tmp_path,
                                                                                       sphere_and_torus, monkeypatch):
    """Where the checks report topological noise (injected here at two times between the first two
    of the 3 written frames), the command names the written frames next to it and says which of them
    show it, as their own topology says."""
    import animanifold.cli as cli

    real = cli.morph

    def with_noise(*args, **kwargs):
        manifold = real(*args, **kwargs)
        manifold.metadata["validity"]["noise_frames"] = [0.2, 0.3]
        return manifold

    monkeypatch.setattr(cli, "morph", with_noise)
    out, err, m, _ = morph_in_three_frames(capsys, sphere_and_torus, tmp_path / "m")
    line = next(line for line in err.splitlines() if "topological noise" in line)
    assert line.startswith("animanifold: warning: topological noise at 2 checked times from 0.2 to 0.3"), line
    ends = [euler_characteristic(*am.read_mesh(path)[:2]) for path in sphere_and_torus]
    frames = [am.read_mesh(tmp_path / "m" / "frames" / f"frame_000{i}.obj") for i in (0, 1)]
    showing = [t for t, (v, f) in zip((0, 0.5), frames) if not min(ends) <= euler_characteristic(v, f) <= max(ends)
               or am.frame_quality.pieces(v, f) > 1]
    if showing:
        assert line.endswith(f"of the written frames next to it (0, 0.5), {', '.join(map(str, showing))} "
                             f"{'shows' if len(showing) == 1 else 'show'} it"), line
    else:
        assert line.endswith("lasting less than a written frame: the written frames next to it (0, 0.5) do not "
                             "show it"), line


def test_the_default_morph_of_shapes_apart_says_nothing_travels_between_them(capsys, tmp_path):
    """No --method: the field method. A sphere and a torus 4 units apart (their files place them) do not
    overlap: the morph shrinks one away and grows the other, and the command says so; the same shapes
    one over the other do not get the warning."""
    from helpers.shapes import torus

    v, f = icosphere(1)
    am.write_mesh(tmp_path / "s.obj", v, f)
    tv, tf = torus(minor_radius=0.3, major=12, minor=6)
    for name, offset in (("apart", 4.0), ("over", 0.0)):
        am.write_mesh(tmp_path / f"{name}.obj", tv + [offset, 0.0, 0.0], tf)
        out, err, m, _ = morph_in_three_frames(capsys, (tmp_path / "s.obj", tmp_path / f"{name}.obj"),
                                               tmp_path / name, "-q")
        assert m.metadata["morph"]["method"] == "field" and "morph: field method" in out
        assert m.validity["inputs_apart"] == (name == "apart"), name
        assert ("do not overlap where they are" in err) == (name == "apart"), err


def test_a_morph_whose_inputs_barely_meet_says_it_widened_the_middle(capsys, tmp_path):
    """Blender's cone in its torus's hole, both at the origin: they touch nowhere, yet lie too close
    to be dissolved where each stands. The command says the middle was widened (by how much), and
    does not warn that nothing travels between them."""
    from helpers.shapes import cone, torus

    am.write_mesh(tmp_path / "cone.obj", *cone(32))
    am.write_mesh(tmp_path / "torus.obj", *torus(minor_radius=0.25, major=48, minor=12))
    out, err, m, _ = morph_in_three_frames(capsys, (tmp_path / "cone.obj", tmp_path / "torus.obj"), tmp_path / "m",
                                           "-q")
    widening = m.validity["middle_widening"]
    assert widening > 0 and not m.validity["inputs_apart"]
    assert f"the blend is widened at the middle by {100 * widening:.2g} % of the size" in out, out
    assert "do not overlap where they are" not in err, err


def test_a_shape_cgal_cannot_cut_ends_the_morph_with_one_line_and_exit_code_3(capsys, tmp_path, monkeypatch):
    from helpers.shapes import torus

    def refuse(vertices, faces, *, interrupted=None):  # a stand-in for CGAL refusing a real model's hole space
        raise am.BooleanError("CGAL failed while computing the hole space of the shape: Unauthorized "
                              "intersections of constraints")

    monkeypatch.setattr(sys.modules["animanifold.morph_pipeline"], "hole_space", refuse)
    am.write_mesh(tmp_path / "s.obj", *torus(minor_radius=0.4, major=16, minor=8))
    am.write_mesh(tmp_path / "t.obj", *torus(minor_radius=0.3, major=16, minor=8))
    code, out, err = run(capsys, "morph", str(tmp_path / "s.obj"), str(tmp_path / "t.obj"), "-o", str(tmp_path / "m"),
                         "--method", "skeleton")
    assert code == 3
    assert err.startswith("animanifold: error: the hole space of the source cannot be computed: CGAL failed")
    assert "method='field'" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "m" / "morph.amf").exists()


def test_skeleton_sub_command_is_wired_in(capsys, tmp_path):
    v, f = icosphere(2)
    am.write_mesh(tmp_path / "ball.obj", v * [2.0, 1.0, 1.0], f)
    code, out, err = run(capsys, "skeleton", str(tmp_path / "ball.obj"), "-o", str(tmp_path / "skel.obj"), "--side", "internal")
    assert code == 0, err
    skeleton, faces = am.read_mesh(tmp_path / "skel.obj")
    assert len(faces) > 0 and (np.abs(skeleton) <= [2.0, 1.0, 1.0]).all()
