"""Hostile arrays and files at the core's entry points: refused with an animanifold.Error naming
the input, never a crash, a wrapped index or a silently wrong result (issue 23)."""

from __future__ import annotations

import dataclasses
import os
import re

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere

T = _core._testing
BAD_INDICES = [10**8, -(10**6)]


@pytest.fixture
def sphere():
    v, f = icosphere(1)
    return np.ascontiguousarray(v, np.float64), np.ascontiguousarray(f, np.int32)


def with_index(faces: np.ndarray, value: int, dtype=np.int32) -> np.ndarray:
    bad = faces.astype(dtype)
    bad[1, 1] = value
    return bad


def tetrahedron_4d():
    points = np.array([[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float)
    return points, np.array([[0, 1, 2, 3]], np.int32)


# Each of these read points through indices without checking them and crashed the interpreter.
UNCHECKED_ENTRY_POINTS = {
    "frame_vertex_normals": lambda v, f: _core.frame_vertex_normals(v, f),
    "vertex_normals": lambda v, f: _core.vertex_normals(v, f),
    "distances_to_surface": lambda v, f: _core.distances_to_surface(v, v, f),
    "self_intersections": lambda v, f: _core.self_intersections(v, f),
    "simplex_volumes": lambda v, f: T.simplex_volumes(v, f),
    "boundary_vertices": lambda v, f: T.boundary_vertices(f, len(v)),
    "dual_operator": lambda v, f: T.dual_operator(f, len(v)),
}


@pytest.mark.parametrize("value", BAD_INDICES)
@pytest.mark.parametrize("name", sorted(UNCHECKED_ENTRY_POINTS))
def test_out_of_range_indices_are_refused_before_memory_is_read(sphere, name, value):
    v, f = sphere
    with pytest.raises(_core.InputError, match=f"1 refers to vertex {value}, outside 0..{len(v) - 1}"):
        UNCHECKED_ENTRY_POINTS[name](v, with_index(f, value))


@pytest.mark.parametrize("value", BAD_INDICES)
def test_simplex_normals_and_volumes_of_4d_simplices_check_their_indices(value):
    points, simplices = tetrahedron_4d()
    bad = simplices.copy()
    bad[0, 2] = value
    with pytest.raises(_core.InputError, match=f"simplex 0 refers to vertex {value}"):
        T.signed_volumes(np.ascontiguousarray(points[:, :3]), bad)
    with pytest.raises(_core.InputError, match=f"simplex 0 refers to vertex {value}"):
        T.simplex_normals(points[:4], bad)


def test_an_interval_frame_with_altered_faces_is_refused_not_crashed(sphere):
    v, f = sphere
    manifold = am.stitch([v, v * 1.5], f, [0.0, 1.0])
    frame = manifold.interval_frame(0.5)
    faces = frame.slice.faces.copy()
    faces[3, 0] = 10**8
    altered = dataclasses.replace(frame, slice=dataclasses.replace(frame.slice, faces=faces))
    with pytest.raises(am.Error, match="face 3 refers to vertex 100000000"):
        altered.at(0.6)


# numpy would convert index arrays wider than int32 silently (2**32 wraps to 0): the
# bindings refuse them instead (cpp/bindings/index_arrays.hpp).
@pytest.mark.parametrize("value", [2**31, 2**32, 2**32 + 1, -(2**31) - 1])
def test_int64_indices_beyond_32_bits_are_refused_not_wrapped(sphere, value):
    v, f = sphere
    bad = with_index(f, value, np.int64)
    message = f"holds {value} at row 1, column 1, which does not fit a 32-bit index"
    for call in (
        lambda: _core.frame_vertex_normals(v, bad),
        lambda: _core.hole_space(v, bad),
        lambda: _core.voronoi_skeleton(v, bad),
        lambda: _core.subdivide_frame(v, bad),
        lambda: _core.Complex(v, bad),
        lambda: _core.check_morph_input(v, bad, "source"),
        lambda: _core.stitch(np.vstack([v, v]), bad, np.array([0.0, 1.0])),
    ):
        with pytest.raises(_core.InputError, match=message):
            call()


def test_int64_indices_that_fit_are_still_accepted(sphere):
    v, f = sphere
    np.testing.assert_array_equal(_core.frame_vertex_normals(v, f.astype(np.int64)),
                                  _core.frame_vertex_normals(v, f))


def test_float_simplex_indices_are_refused_not_truncated(sphere):
    v, f = sphere
    with pytest.raises(_core.InputError, match="dtype float64"):
        _core.Complex(v, f + 0.7)
    with pytest.raises(_core.InputError, match="an index array has dtype bool: indices must be integers"):
        _core.frame_vertex_normals(v, f > 3)
    points, simplices = tetrahedron_4d()
    with pytest.raises(am.Error, match="simplices must be integer indices, got dtype float64"):
        am.AnimationManifold.from_arrays(points, simplices + 0.5)
    with pytest.raises(am.Error, match=r"simplices holds 4294967296 at \(0, 0\)"):
        am.AnimationManifold.from_arrays(points, simplices.astype(np.int64) + 2**32)


def test_int64_face_attributes_beyond_32_bits_are_refused(sphere):
    v, f = sphere
    material = np.zeros(len(f), np.int64)
    material[5] = 2**32
    with pytest.raises(_core.InputError, match="integer attribute 'material' holds 4294967296 at row 5"):
        _core.stitch(np.vstack([v, v]), f, np.array([0.0, 1.0]), face_attributes={"material": material})
    with pytest.raises(am.Error, match="face attribute 'material' holds 4294967296"):
        am.stitch([v, v], f, [0.0, 1.0], face_attributes={"material": material})


def test_deformer_anchors_and_crease_edges_beyond_32_bits_are_refused(sphere):
    v, f = sphere
    with pytest.raises(_core.InputError, match="holds 4294967296 at row 0"):
        _core.Deformer(v, f, np.array([2**32], np.int64), np.array([1], np.int32))
    with pytest.raises(_core.InputError, match="holds 4294967296 at row 1"):
        _core.Deformer(v, f, np.array([0], np.int32), np.array([1], np.int32), zero_detail_vertices=[5, 2**32])
    with pytest.raises(_core.InputError, match="holds 4294967297 at row 0, column 1"):
        _core.subdivide_frame(v, f, crease_edges=np.array([[0, 2**32 + 1]], np.int64))


# --- mesh files: counts checked against the file's size before CGAL allocates -------------

def write(tmp_path, name: str, text: str):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_an_off_face_claiming_400_million_corners_is_refused_before_reading(tmp_path):
    path = write(tmp_path, "corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n400000000 0 1 2\n")
    assert path.stat().st_size == 44
    with pytest.raises(_core.FileError, match=r"corners.off': face 0 declares 400000000 corners, more than its 44 bytes"):
        _core.read_mesh(str(path))


def test_off_and_ply_headers_claiming_more_than_the_file_holds_are_refused(tmp_path):
    off = write(tmp_path, "counts.off", "OFF\n100000000 100000000 0\n")
    with pytest.raises(_core.FileError, match="counts.off' declares 100000000 vertices and 100000000 faces"):
        _core.read_mesh(str(off))
    ply = write(tmp_path, "counts.ply", "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\n"
                "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                "end_header\n0 0 0\n")
    with pytest.raises(_core.FileError, match="counts.ply' declares 100000000 vertex elements"):
        _core.read_mesh(str(ply))


PLY_HEADER = ("ply\nformat {format} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list {count} int vertex_indices\nend_header\n")


def binary_ply(tmp_path, corners: int, indices: list[int]):
    body = np.zeros(9, "<f4").tobytes() + np.array([corners], "<i4").tobytes() + np.array(indices, "<i4").tobytes()
    path = tmp_path / "binary.ply"
    path.write_bytes(PLY_HEADER.format(format="binary_little_endian", count="int").encode() + body)
    return path


def test_ply_lists_claiming_more_items_than_the_file_holds_are_refused(tmp_path):
    text = PLY_HEADER.format(format="ascii", count="int") + "0 0 0\n1 0 0\n0 1 0\n400000000 0 1 2\n"
    ascii_ply = write(tmp_path, "ascii.ply", text)
    with pytest.raises(_core.FileError, match="ascii.ply': face 0 declares a list of 400000000 items"):
        _core.read_mesh(str(ascii_ply))
    with pytest.raises(_core.FileError, match="binary.ply': face 0 declares a list of 400000000 items"):
        _core.read_mesh(str(binary_ply(tmp_path, 400_000_000, [0, 1, 2])))


def test_honest_ply_files_still_read(tmp_path):
    text = PLY_HEADER.format(format="ascii", count="uchar") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    vertices, faces, _ = _core.read_mesh(str(write(tmp_path, "ascii.ply", text)))
    assert vertices.shape == (3, 3) and faces.tolist() == [[0, 1, 2]]
    vertices, faces, _ = _core.read_mesh(str(binary_ply(tmp_path, 3, [0, 1, 2])))
    assert vertices.shape == (3, 3) and faces.tolist() == [[0, 1, 2]]


def test_honest_off_files_still_read(tmp_path):
    body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3"  # no final newline
    for header in ("OFF 4 4 0\n", "OFF\n# a comment\n\n4 4 0\n"):
        vertices, faces, _ = _core.read_mesh(str(write(tmp_path, "tetra.off", header + body)))
        assert vertices.shape == (4, 3) and faces.shape == (4, 3)


TRIANGLE = "0 0 0{c}\n1 0 0{c}\n0 1 0{c}\n"


@pytest.mark.parametrize("colour", ["", " 255 0 0", " 1 0 0 0.5", " 7"])
def test_coloured_off_files_read_with_colours_of_0_1_3_or_4_numbers(tmp_path, colour):
    path = write(tmp_path, "colour.off", "COFF\n3 1 0\n" + TRIANGLE.format(c=colour) + f"3 0 1 2{colour}\n")
    vertices, faces, _ = _core.read_mesh(str(path))
    assert vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and faces.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize("header, body, message", [
    # CGAL 5.5 reads a third colour entry that is not there (the mesh fuzzer's crash)
    ("COFF\n3 1 0", TRIANGLE.format(c=" 1 1") + "3 0 1 2\n", "vertex 0 has 5 numbers, which leaves 2 for its colour"),
    ("COFF\n3 1 0", TRIANGLE.format(c=" 700") + "3 0 1 2\n", "vertex 0 names colour-map entry 700, not one of 0..148"),
    ("COFF\n3 1 0", "0 0 0 1 1 1\n1 0 0\n0 1 0 1 1 1\n3 0 1 2\n", "vertex 1 has a colour of 0 numbers where the first had 3"),
    ("COFF\n3 1 0", "0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "vertex 0 has 2 numbers"),
    ("COFF\n3 1 0", TRIANGLE.format(c="") + "3 0 1 2 5 5\n", "face 0 has 6 numbers, which leaves 2 for its colour"),
    ("COFF\n3 1 0", TRIANGLE.format(c="") + "3 0 1 2 -4\n", "face 0 names colour-map entry -4"),
    ("STOFF\n3 1 0", TRIANGLE.format(c=" 0 0") + "3 0 1 2\n", "'STOFF' files are not supported"),
    ("COFF\n3 1", TRIANGLE.format(c="") + "3 0 1 2\n", "the counts line of a 'COFF' file must hold the vertex, face and edge counts"),
])
def test_off_lines_that_cgal_would_read_out_of_bounds_are_refused(tmp_path, header, body, message):
    path = write(tmp_path, "bad.off", header + "\n" + body)
    with pytest.raises(_core.FileError, match=re.escape(f"bad.off': {message}")):
        _core.read_mesh(str(path))


TETRA_POINTS = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TETRA_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def binary_off(tmp_path, header: bytes = b"OFF BINARY\n", counts=(4, 4), corners=None, name="binary.off"):
    """A binary OFF tetrahedron: big-endian int32 counts, float32 points, int32 faces; `counts`
    and face 0's `corners` as declared (the data stays the tetrahedron's)."""
    body = np.array([*counts, 0], ">i4").tobytes() + np.array(TETRA_POINTS, ">f4").tobytes()
    for i, face in enumerate(TETRA_FACES):
        body += np.array([len(face) if i or corners is None else corners, *face], ">i4").tobytes()
    path = tmp_path / name
    path.write_bytes(header + body)
    return path


@pytest.mark.parametrize("header", [b"OFF BINARY\n", b"OFF\n# made by hand\nBINARY\n", b"OFF BINARY  trailing words\n"])
def test_honest_binary_off_files_still_read(tmp_path, header):
    vertices, faces, _ = _core.read_mesh(str(binary_off(tmp_path, header)))
    assert vertices.tolist() == TETRA_POINTS and faces.tolist() == TETRA_FACES


@pytest.mark.parametrize("counts, corners, message", [
    ((100_000_000, 4), None, "declares 100000000 vertices and 4 faces, more than its 135 bytes can hold"),
    ((4, 100_000_000), None, "declares 4 vertices and 100000000 faces, more than its 135 bytes can hold"),
    ((-1, 4), None, "declares -1 vertices and 4 faces"),
    ((4, 4), 400_000_000, "face 0 declares 400000000 corners, more than its 135 bytes can hold"),
    ((4, 4), -3, "face 0 declares -3 corners"),
])
def test_binary_off_counts_the_file_cannot_hold_are_refused_before_reading(tmp_path, counts, corners, message):
    path = binary_off(tmp_path, counts=counts, corners=corners, name="hostile.off")
    assert path.stat().st_size == 135
    with pytest.raises(_core.FileError, match=re.escape("hostile.off' (binary OFF)") + ".*" + re.escape(message)):
        _core.read_mesh(str(path))


def binary_stl(tmp_path, declared: int, header: bytes = b"made by hand", name="binary.stl"):
    """A binary STL of one triangle (normal, three corners, attribute bytes) declaring `declared`."""
    triangle = np.array([0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0], "<f4").tobytes() + b"\0\0"
    path = tmp_path / name
    path.write_bytes(header.ljust(80, b" ") + np.array([declared], "<u4").tobytes() + triangle)
    return path


def test_a_binary_stl_claiming_more_triangles_than_it_holds_is_refused(tmp_path):
    path = binary_stl(tmp_path, 4_000_000_000, name="hostile.stl")
    with pytest.raises(_core.FileError, match=re.escape(
            "hostile.stl' (binary STL: it does not start with 'solid') declares 4000000000 triangles, "
            "more than its 134 bytes can hold")):
        _core.read_mesh(str(path))


def test_honest_binary_and_ascii_stl_files_still_read(tmp_path):
    vertices, faces, _ = _core.read_mesh(str(binary_stl(tmp_path, 1)))
    assert vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and faces.tolist() == [[0, 1, 2]]
    # ASCII: its bytes 80..83 (here "vert", 1.9e9 as a count) are no triangle count.
    text = ("solid made_by_hand\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
            "      vertex 0 1 0\n    endloop\n  endfacet\nendsolid made_by_hand\n")
    assert int.from_bytes(text.encode()[80:84], "little") > 10**9
    vertices, faces, _ = _core.read_mesh(str(write(tmp_path, "ascii.stl", text)))
    assert vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and faces.tolist() == [[0, 1, 2]]


def test_mesh_paths_that_are_not_regular_files_are_refused(tmp_path):
    fifo = tmp_path / "pipe.off"
    os.mkfifo(fifo)
    for path in (str(fifo), "/dev/zero", str(tmp_path)):
        with pytest.raises(_core.InputError, match=f"mesh file '{re.escape(path)}' is not a regular file"):
            _core.read_mesh(path)


# --- extreme numbers: a right result or an error, never a silently wrong one -------------

@pytest.mark.parametrize("scale", [1e154, 1e300, 1e-160])
def test_frame_normals_of_huge_and_tiny_frames_are_those_of_the_unit_frame(sphere, scale):
    v, f = sphere
    normals = _core.frame_vertex_normals(v * scale, f)
    assert np.isfinite(normals).all()
    np.testing.assert_allclose(normals, _core.frame_vertex_normals(v, f), atol=1e-14)


def test_slices_of_a_manifold_at_1e200_have_the_unit_manifolds_normals(sphere):
    v, f = sphere
    small = am.stitch([v, v * 1.5], f, [0.0, 1.0]).slice(0.5)
    big = am.stitch([v * 1e200, v * 1.5e200], f, [0.0, 1.0]).slice(0.5)
    assert np.isfinite(big.normals).all()
    np.testing.assert_allclose(big.normals, small.normals, atol=1e-12)


def test_keyframe_times_whose_span_overflows_are_refused(sphere):
    v, f = sphere
    with pytest.raises(_core.InputError, match=r"keyframe times from t=-1e\+308 \(keyframe 0\) to t=1e\+308"):
        am.stitch([v, v], f, [-1e308, 1e308])
    points, simplices = tetrahedron_4d()
    points[4, 3] = 1e308
    points[0, 3] = -1e308
    with pytest.raises(_core.InputError, match="coordinates 3 span from -1e\\+308 to 1e\\+308"):
        am.AnimationManifold.from_arrays(points, simplices)


def test_a_face_and_its_reverse_in_the_keyframes_are_refused(sphere):
    v, f = sphere
    faces = np.vstack([f, f[7, [0, 2, 1]]])
    with pytest.raises(_core.InputError, match=f"faces 7 and {len(f)} are one triangle in opposite orientations"):
        am.stitch([v, v * 1.2], faces, [0.0, 1.0])
