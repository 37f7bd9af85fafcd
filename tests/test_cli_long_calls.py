"""The command line's long calls, `python3 -m animanifold subdivide`, `deform`, `skeleton` and
`morph`: the package's calls with the core's steps on stderr and Ctrl-C stopping them at a step.

Every expectation is exact: the files hold what the Python API makes, bit for bit; anchors stay
exactly; Ctrl-C is raised from inside the call (a signal sent at a named step), so nothing
depends on how fast the machine is.
"""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold import cli_deform, cli_skeleton, cli_subdivide
from animanifold.cli import main
from animanifold.cli_common import StepPrinter
from helpers.contours import blob, polygons
from helpers.keyframes import TIMES, wobble
from helpers.shapes import icosphere


@pytest.fixture
def stitched(tmp_path: Path) -> tuple[Path, am.AnimationManifold]:
    """A wobbling icosphere over three keyframes (t = 0, 0.3, 1), saved: (file, manifold)."""
    v, f = icosphere(1)
    manifold = am.stitch(wobble(v, TIMES[:3]), f, TIMES[:3])
    path = tmp_path / "anim.amf"
    am.save(manifold, path)
    return path, am.load(path)


@pytest.fixture
def ball(tmp_path: Path) -> Path:
    """An icosphere off the cospherical case (a regular one has an empty skeleton), as OBJ."""
    v, f = icosphere(2)
    v = v * (1 + 1e-6 * np.random.default_rng(1).standard_normal(len(v)))[:, None]
    path = tmp_path / "ball.obj"
    am.write_mesh(path, v, f)
    return path


def run(capsys, *argv) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def step_names(err: str) -> list[str]:
    """The steps printed on stderr, each once, in the order they first appear."""
    names = [line.strip().rsplit(" (", 1)[0] for line in err.splitlines() if line.startswith("  ")]
    return list(dict.fromkeys(names))


def test_the_step_printer_prints_each_step_and_each_further_tenth():
    printer = StepPrinter(quiet=True)
    for step, fraction in [("checks", 0.0), ("a", 0.0), ("a", 0.05), ("a", 0.1), ("a", 0.19), ("b", 0.19), ("b", 0.2),
                           ("b", 0.55)]:
        assert printer(step, fraction) is True
    assert printer.printed == [("a", 0.0), ("a", 0.1), ("b", 0.19), ("b", 0.2), ("b", 0.55)]


def test_an_input_refused_at_the_checks_step_ends_in_one_error_line(capsys, tmp_path):
    v, f = icosphere(1)
    am.write_mesh(tmp_path / "open.obj", v, f[1:])
    code, _, err = run(capsys, "skeleton", tmp_path / "open.obj", "-o", tmp_path / "s.obj")
    assert code == 2 and err.startswith("animanifold: error: ") and err.count("\n") == 1, err


def test_subdivide_writes_what_the_api_makes_and_prints_the_cores_steps(capsys, stitched, tmp_path):
    source, manifold = stitched
    out = tmp_path / "smooth.amf"
    code, stdout, err = run(capsys, "subdivide", source, "-o", out, "--levels", 2)
    assert code == 0, err
    written, expected = am.load(out), am.subdivide(manifold, 2)
    assert np.array_equal(written.points, expected.points) and np.array_equal(written.simplices, expected.simplices)
    assert len(written.simplices) == 64 * len(manifold.simplices) == am.subdivided_simplex_count(manifold, 2)
    assert written.metadata["subdivisions"] == expected.metadata["subdivisions"]
    assert step_names(err) == ["refining", "averaging", "octahedra"], err  # the input's checks are not shown
    assert f"into {len(written.simplices):,} tets" in stdout and str(out) in stdout

    linear = tmp_path / "linear.amf"
    code, _, err = run(capsys, "subdivide", source, "-o", linear, "--scheme", "linear", "--keep-keyframe-times", "-q")
    assert code == 0 and err == ""
    expected = am.subdivide(manifold, 1, scheme="linear", keep_keyframe_times=True)
    assert np.array_equal(am.load(linear).points, expected.points)


@pytest.mark.parametrize("levels", [0, -1, cli_subdivide.MAX_LEVELS + 1])
def test_subdivide_refuses_a_level_count_out_of_range(capsys, stitched, tmp_path, levels):
    out = tmp_path / "smooth.amf"
    code, _, err = run(capsys, "subdivide", stitched[0], "-o", out, "--levels", levels)
    assert code == 2 and "--levels must be from 1 to" in err and "Traceback" not in err
    assert not out.exists()


def deform_args(source, out, *extra):
    return ("deform", source, "-o", out, "--anchors", "t::0", "--handles", "t:1:", *extra)


def test_deform_writes_what_the_api_makes_anchors_stay_and_handles_move(capsys, stitched, tmp_path):
    source, manifold = stitched
    out = tmp_path / "moved.amf"
    code, stdout, err = run(capsys, *deform_args(source, out, "--translate", 0, 0, 0.5, 0))
    assert code == 0, err
    t = manifold.points[:, 3]
    anchors, handles = np.flatnonzero(t <= 0), np.flatnonzero(t >= 1)
    expected = am.deform(manifold, anchors, handles, am.handle_transform(translation=[0, 0, 0.5, 0]))
    written = am.load(out)
    assert np.array_equal(written.points, expected.points) and np.array_equal(written.simplices, manifold.simplices)
    assert np.array_equal(written.points[anchors], manifold.points[anchors])
    assert np.allclose(written.points[handles], manifold.points[handles] + [0, 0, 0.5, 0], rtol=0, atol=1e-12)
    names = step_names(err)
    assert names[:2] == ["laplacian", "factorising"] and "deforming" in names and "restoring" in names, err
    assert f"({len(anchors):,} anchors, {len(handles):,} handles; dual)" in stdout


def test_deform_reports_a_huge_finite_motion_without_overflowing(capsys, stitched, tmp_path):
    code, stdout, err = run(capsys, *deform_args(stitched[0], tmp_path / "far.amf", "--translate", 0, 0, 1e308, 0, "-q"))
    assert code == 0 and "largest motion 1e+308" in stdout, err


def test_deform_rotates_the_handles_about_their_centre(capsys, stitched, tmp_path):
    source, manifold = stitched
    out = tmp_path / "turned.amf"
    code, _, err = run(capsys, *deform_args(source, out, "--rotate", 0, 0, 1, 90, "--method", "graph", "-q"))
    assert code == 0 and err == ""
    handles = np.flatnonzero(manifold.points[:, 3] >= 1)
    before, after = manifold.points[handles], am.load(out).points[handles]
    centre = before[:, :3].mean(axis=0)
    turned = (before[:, :3] - centre) @ np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]]) + centre  # +90° about z
    assert np.allclose(after[:, :3], turned, rtol=0, atol=1e-9) and np.array_equal(after[:, 3], before[:, 3])


@pytest.mark.parametrize("extra, culprit", [
    (("--anchors", "t:0", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "'t:0' is not AXIS:LOW:HIGH"),
    (("--anchors", "w:0:1", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "unknown axis 'w'"),
    (("--anchors", "t:a:", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "'a' is not a number"),
    (("--anchors", "t:5:", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "--anchors 't:5:' selects no vertex"),
    (("--anchors", "t::1", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "is chosen by both --anchors"),
    (("--anchors", "t::0", "--handles", "t:1:"), "give the handles' motion"),
    (("--anchors", "t::0", "--handles", "t:1:", "--translate", 0, 1), "--translate takes 4 finite numbers"),
    (("--anchors", "t::0", "--handles", "t:1:", "--rotate", 0, 0, 0, 90), "--rotate needs a non-zero axis"),
])
def test_deform_refuses_bad_choices_naming_the_option(capsys, stitched, tmp_path, extra, culprit):
    out = tmp_path / "moved.amf"
    code, _, err = run(capsys, "deform", stitched[0], "-o", out, *extra)
    assert code == 2 and culprit in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


def test_morph_prints_each_stage_as_it_ends(capsys, tmp_path):
    v, f = icosphere(1)
    am.write_mesh(tmp_path / "s.obj", v, f)
    am.write_mesh(tmp_path / "t.obj", v * [1.5, 1.0, 0.7], f)
    code, _, err = run(capsys, "morph", tmp_path / "s.obj", tmp_path / "t.obj", "-o", tmp_path / "m")
    assert code == 0, err
    stages = []
    am.morph((v, f), (v * [1.5, 1.0, 0.7], f), progress=lambda stage, fraction: stages.append(stage) or True)
    assert [name.removesuffix(" done") for name in step_names(err)] == list(dict.fromkeys(stages)), err
    assert all(name.endswith(" done") for name in step_names(err))
    code, _, err = run(capsys, "morph", tmp_path / "s.obj", tmp_path / "t.obj", "-o", tmp_path / "q", "-q")
    assert code == 0 and step_names(err) == []


def test_a_2d_animation_subdivides_into_triangles_and_deforms_with_three_numbers(capsys, tmp_path):
    """Animated contours (x, y, t): a level makes 4 triangles of each, a motion has 3 coordinates."""
    points, edges = polygons(blob(12, 1.0, (0, 0), wobble=0.2))
    manifold = am.stitch(np.stack([points, points * 1.3, points * [1.0, 0.6]]), edges, [0.0, 0.5, 1.0])
    source = tmp_path / "contour.amf"
    am.save(manifold, source)
    code, stdout, err = run(capsys, "subdivide", source, "-o", tmp_path / "s.amf", "-q")
    assert code == 0 and f"into {4 * len(manifold.simplices):,} triangles" in stdout, err
    moved = tmp_path / "m.amf"
    code, _, err = run(capsys, "deform", source, "-o", moved, "--anchors", "t::0", "--handles", "t:1:",
                       "--translate", 0.5, 0, 0, "-q")
    assert code == 0, err
    handles = np.flatnonzero(manifold.points[:, 2] >= 1)
    assert np.allclose(am.load(moved).points[handles], manifold.points[handles] + [0.5, 0, 0], rtol=0, atol=1e-12)
    for motion, culprit in [(("--translate", 0, 0, 0, 0), "--translate takes 3 finite numbers (x y t)"),
                            (("--rotate", 0, 0, 1, 90), "--rotate turns animated surfaces")]:
        code, _, err = run(capsys, "deform", source, "-o", tmp_path / "x.amf", "--anchors", "t::0", "--handles",
                           "t:1:", *motion)
        assert code == 2 and culprit in err, err


class CtrlCAt(StepPrinter):
    """A progress printer that sends this process SIGINT (Ctrl-C) when `step` starts."""

    step = None

    def __call__(self, step: str, fraction: float) -> bool:
        answer = super().__call__(step, fraction)
        if step == self.step:
            os.kill(os.getpid(), signal.SIGINT)
        return answer


def test_skeleton_prints_the_cores_steps_and_writes_what_the_api_makes(capsys, ball, tmp_path):
    out = tmp_path / "skeleton.obj"
    code, _, err = run(capsys, "skeleton", ball, "-o", out, "--side", "internal")
    assert code == 0, err
    names = step_names(err)
    assert names[0] == "separability" and "bisectors" in names, err
    v, f = am.read_mesh(ball)
    expected = am.voronoi_skeleton(v, f, side="internal", warn=False)
    assert np.array_equal(am.read_mesh(out)[1], expected.faces)
    code, _, err = run(capsys, "skeleton", ball, "-o", out, "--side", "internal", "-q")
    assert code == 0 and step_names(err) == []


@pytest.mark.parametrize("module, argv, step", [
    (cli_subdivide, ("subdivide", "--levels", 2), "averaging"),
    (cli_skeleton, ("skeleton", "--side", "internal"), "bisectors"),
    (cli_deform, ("deform", "--anchors", "t::0", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "factorising"),
    (cli_deform, ("deform", "--anchors", "t::0", "--handles", "t:1:", "--translate", 0, 0, 1, 0), "restoring"),
])
def test_ctrl_c_stops_the_call_at_a_step_and_writes_nothing(capsys, monkeypatch, stitched, ball, tmp_path, module,
                                                            argv, step):
    monkeypatch.setattr(module, "StepPrinter", type("At", (CtrlCAt,), {"step": step}))
    source, out = (ball, tmp_path / "out.obj") if argv[0] == "skeleton" else (stitched[0], tmp_path / "out.amf")
    code, stdout, err = run(capsys, argv[0], source, "-o", out, *argv[1:])
    assert code == 130 and err.strip().endswith("animanifold: interrupted") and stdout == "", (code, err)
    assert step_names(err)[-1] == step and not out.exists()
