"""Bad input raises errors that name the culprit."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere


@pytest.fixture
def sphere():
    return icosphere(1)


def test_fewer_than_two_keyframes(sphere):
    v, f = sphere
    with pytest.raises(ValueError, match="at least two keyframes, got 1"):
        am.stitch([v], f, [0.0])
    with pytest.raises(ValueError, match="at least two keyframes, got 0"):
        am.stitch([], f, [])


def test_mismatched_vertex_counts_name_the_keyframe(sphere):
    v, f = sphere
    with pytest.raises(ValueError, match="keyframe 2 has 41 vertices.*keyframe 0 has 42"):
        am.stitch([v, v, v[:-1]], f, [0, 1, 2])


def test_non_increasing_times_name_the_keyframe(sphere):
    v, f = sphere
    with pytest.raises(ValueError, match="keyframe 2 at t=1 follows t=1"):
        am.stitch([v, v, v], f, [0, 1, 1])
    with pytest.raises(ValueError, match="keyframe 1 at t=-1"):
        am.stitch([v, v], f, [0, -1])
    with pytest.raises(ValueError, match="3 keyframes but 2 times"):
        am.stitch([v, v, v], f, [0, 1])
    with pytest.raises(ValueError, match="time of keyframe 1 is not finite"):
        am.stitch([v, v], f, [0, np.inf])


def test_non_finite_coordinates_name_keyframe_and_vertex(sphere):
    v, f = sphere
    bad = v.copy()
    bad[17, 1] = np.nan
    with pytest.raises(ValueError, match="keyframe 1, vertex 17 has a non-finite coordinate"):
        am.stitch([v, bad], f, [0, 1])


def test_face_indices_out_of_range_or_repeated(sphere):
    v, f = sphere
    bad = f.copy()
    bad[5, 2] = len(v)
    with pytest.raises(ValueError, match="face 5 refers to vertex 42, outside 0..41"):
        am.stitch([v, v], bad, [0, 1])
    bad = f.copy()
    bad[3, 1] = -1
    with pytest.raises(ValueError, match="face 3 refers to vertex -1"):
        am.stitch([v, v], bad, [0, 1])
    bad = f.copy()
    bad[7, 1] = bad[7, 0]
    with pytest.raises(ValueError, match="face 7 repeats vertex"):
        am.stitch([v, v], bad, [0, 1])


def test_wrong_shapes_and_types(sphere):
    v, f = sphere
    with pytest.raises(ValueError, match=r"faces must be \(l, 3\)"):
        am.stitch([v, v], f[:, :2], [0, 1])
    with pytest.raises(ValueError, match="faces must be integer"):
        am.stitch([v, v], f.astype(float), [0, 1])
    with pytest.raises(ValueError, match=r"frames must be \(m, k, d\)"):
        am.stitch(np.zeros((2, 3)), f, [0, 1])
    with pytest.raises(ValueError, match="keyframe points must be 2D or 3D"):
        am.stitch(np.zeros((2, 4, 4)), np.zeros((1, 4), int), [0, 1])


def test_attribute_sizes_are_checked(sphere):
    v, f = sphere
    with pytest.raises(ValueError, match="vertex attribute 'uv' has 41 rows; expected 42"):
        am.stitch([v, v], f, [0, 1], vertex_attributes={"uv": v[:-1, :2]})
    with pytest.raises(ValueError, match="face attribute 'material_index' has 3 rows for 80 faces"):
        am.stitch([v, v], f, [0, 1], face_attributes={"material_index": [0, 1, 2]})


def test_from_arrays_validates(sphere):
    with pytest.raises(ValueError, match="simplex 1 refers to vertex 9"):
        am.AnimationManifold.from_arrays(np.zeros((4, 4)), np.array([[0, 1, 2, 3], [0, 1, 2, 9]]))
    pts = np.zeros((4, 4))
    pts[2, 3] = np.inf
    with pytest.raises(ValueError, match="vertex 2 has a non-finite coordinate 3"):
        am.AnimationManifold.from_arrays(pts, np.array([[0, 1, 2, 3]]))


def test_mesh_io_errors_name_the_file(tmp_path):
    with pytest.raises(OSError, match="nope.obj' does not exist"):
        am.read_mesh(tmp_path / "nope.obj")
    (tmp_path / "empty.off").write_text("OFF\n0 0 0\n")
    with pytest.raises(OSError, match="empty.off"):
        am.read_mesh(tmp_path / "empty.off")


# -- one error model: every error is an animanifold.Error and keeps its builtin --


def test_the_package_error_is_the_cores():
    assert am.Error is _core.Error
    assert issubclass(am.Error, Exception)


def test_bad_input_is_an_input_error_and_a_value_error():
    simplices = np.array([[0, 1, 2, 3], [0, 1, 2, 9]])
    with pytest.raises(_core.InputError, match="simplex 1 refers to vertex 9") as caught:
        am.AnimationManifold.from_arrays(np.zeros((4, 4)), simplices)
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, ValueError)


def test_a_missing_file_is_a_file_error_and_an_os_error(tmp_path):
    with pytest.raises(_core.FileError, match="nope.obj' does not exist") as caught:
        am.read_mesh(tmp_path / "nope.obj")
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, OSError)


def test_a_refused_boolean_operand_is_a_boolean_error_and_a_runtime_error(sphere):
    v, f = sphere
    with pytest.raises(am.BooleanError, match=r"the shape is not closed \(3 boundary edges\)") as caught:
        am.hole_space(v, f[:-1])
    assert am.BooleanError is _core.BooleanError
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, RuntimeError)


def test_a_cancelled_morph_is_an_error_but_no_runtime_error(sphere):
    # Callers retry a failed mesher on RuntimeError; a cancel must not be retried.
    v, f = sphere
    with pytest.raises(_core.Cancelled) as caught:
        _core.morph(v, f, v * 1.2, f, progress=lambda stage, fraction: False)
    assert isinstance(caught.value, am.Error) and not isinstance(caught.value, RuntimeError)


@pytest.mark.parametrize("core_type, python_type, builtin", [
    ("InputError", "InputError", ValueError),
    ("NotManifoldError", "NotManifoldError", ValueError),
    ("IOError", "FileError", OSError),
    ("BooleanError", "BooleanError", RuntimeError),
    ("MeshingError", "MeshingError", RuntimeError),
    ("TimeLimitError", "TimeLimitError", RuntimeError),
    ("MemoryLimitError", "MemoryLimitError", MemoryError),
])
def test_each_core_exception_goes_through_the_translator_with_its_message(core_type, python_type, builtin):
    message = f"TetGen failed while meshing the source (face 7): {core_type}"
    with pytest.raises(getattr(_core, python_type)) as caught:
        _core._testing.raise_error(core_type, message)
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, builtin)
    assert str(caught.value) == message


def test_cancelled_goes_through_the_translator():
    with pytest.raises(_core.Cancelled, match="cancelled") as caught:
        _core._testing.raise_error("Cancelled", "")
    assert isinstance(caught.value, am.Error)


def test_the_packages_own_errors_are_animanifold_errors(tmp_path, sphere):
    from animanifold import cli
    (tmp_path / "junk.amf").write_bytes(b"not a cache")
    with pytest.raises(am.CacheError, match="junk.amf") as caught:
        am.load(tmp_path / "junk.amf")
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, ValueError)
    with pytest.raises(cli.UserError, match="--fps must be a positive number") as caught:
        cli.keyframe_times(2, None, -1.0, ["a.obj", "b.obj"])
    assert isinstance(caught.value, am.Error)


def test_the_package_raises_only_animanifold_errors():
    # A caller catches animanifold.Error for every refusal of ours; a builtin raised by the
    # package itself would slip past it. Library errors caught and re-raised keep their type
    # as the cause only.
    package = Path(am.__file__).parent
    builtins_raised = []
    for module in sorted(package.glob("*.py")):
        for node in ast.walk(ast.parse(module.read_text())):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) \
                    and isinstance(node.exc.func, ast.Name) and node.exc.func.id in _BUILTIN_ERRORS:
                builtins_raised.append(f"{module.name}:{node.lineno} raises {node.exc.func.id}")
    assert builtins_raised == []


_BUILTIN_ERRORS = {"ValueError", "TypeError", "RuntimeError", "OSError", "KeyError", "IndexError", "Exception"}


@pytest.mark.parametrize("call", [
    lambda v, f: am.stitch([v, v], f, [0.0, 1.0]).slice(0.5, smooth_levels=-1),
    lambda v, f: am.stitch([v, v], f, [0.0, 1.0]).slice(0.5, axis="w"),
    lambda v, f: am.LaplacianOptions(method="magic"),
    lambda v, f: am.refine(am.stitch([v, v], f, [0.0, 1.0]), [[0, 1]], order="sideways"),
], ids=["smoothing levels", "slice axis", "laplacian method", "refine order"])
def test_the_packages_own_checks_raise_input_errors(sphere, call):
    v, f = sphere
    with pytest.raises(am.InputError) as caught:
        call(v, f)
    assert isinstance(caught.value, am.Error) and isinstance(caught.value, ValueError)
