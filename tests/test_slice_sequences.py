"""Slicing at production scale (issue 24): the cut that runs on OpenMP's threads and welds
without a hash gives the points and faces the serial implementation gave, in an order pinned
bit for bit, the same for any thread count; frames of a sequence that reuse their interval's
cut equal fresh slices; and the interval index reports its size."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from animanifold.procedural import icosphere
from helpers.surface_checks import triangles

TIME_AXIS = 3


def exact_animation(subdivisions: int = 5, keyframes: int = 3) -> am.AnimationManifold:
    """A sphere sheared and bulged over `keyframes` keys at times 0, 1, 2, ...: every coordinate
    a multiple of 2^-24, so the slices' arithmetic is the same on every machine (no sin or cos)."""
    v, f = icosphere(subdivisions)
    v = np.round(v * 4096) / 4096
    frames = np.stack([v + (k / 8) * v[:, [1, 2, 0]] + (k / 16) * v[:, [2, 0, 1]] ** 2 + [k / 4, 0, k / 16]
                       for k in range(keyframes)])
    uv = v[:, :2] / 2 + 0.5
    return am.stitch(frames, f, np.arange(keyframes, dtype=float), vertex_attributes={"uv": uv},
                     face_attributes={"material_index": np.arange(len(f)) % 3})


def digest(s) -> str:
    """sha256 of every array of a slice, in a fixed order and dtype."""
    h = hashlib.sha256()
    arrays = [s.vertices, s.faces, s.normals, s.vertex_edges, s.edge_parameter, s.face_simplex,
              s.vertex_attributes["uv"], s.face_attributes["material_index"]]
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str(a.shape).encode())
        h.update(a.astype(np.float64 if a.dtype.kind == "f" else np.int64).tobytes())
    return h.hexdigest()[:16]


# (axis, value): in between, a keyframe, a rounding off a keyframe, both ends, sweep views.
SLICES = [(3, 0.3125), (3, 1.7), (3, 1.0), (3, 1.0 + 1e-13), (3, 0.0), (3, 2.0), (0, 0.1), (1, -0.2), (2, 0.45)]


def assert_identical(got, want) -> None:
    for name in ("vertices", "faces", "normals", "vertex_edges", "edge_parameter", "face_simplex"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name), err_msg=name)
    assert got.vertex_attributes.keys() == want.vertex_attributes.keys()
    for name in want.vertex_attributes:
        np.testing.assert_array_equal(got.vertex_attributes[name], want.vertex_attributes[name], err_msg=name)
    for name in want.face_attributes:
        np.testing.assert_array_equal(got.face_attributes[name], want.face_attributes[name], err_msg=name)


def canonical_digest(s) -> str:
    """sha256 of what a slice is, whatever its order: its points by manifold edge (coordinates,
    edge parameter, uv) and its faces as cycles of those edges (rotated to start at the
    smallest) with their simplex and material. Normals are left out: each is a sum over the
    point's faces, whose order sets its last bits."""
    edges = [tuple(e) for e in np.asarray(s.vertex_edges).tolist()]
    points = sorted(zip(edges, np.asarray(s.vertices).tolist(), np.asarray(s.edge_parameter).tolist(),
                        np.asarray(s.vertex_attributes["uv"]).tolist()))
    faces = []
    for corners, simplex, material in zip(np.asarray(s.faces).tolist(), np.asarray(s.face_simplex).tolist(),
                                          np.asarray(s.face_attributes["material_index"]).ravel().tolist()):
        cycle = [edges[c] for c in corners]
        first = cycle.index(min(cycle))
        faces.append((cycle[first:] + cycle[:first], simplex, material))
    return hashlib.sha256(repr((points, sorted(faces))).encode()).hexdigest()[:16]


# Digests of the slices of exact_animation() as this implementation gives them: the index's
# hits in its nodes' order (by low, then simplex), chunk by chunk.
PINNED = {
    (3, 0.3125): "a0f1502e54f69992",
    (3, 1.7): "eda98be17e955209",
    (3, 1.0): "101473d4253b31c2",
    (3, 1.0 + 1e-13): "101473d4253b31c2",
    (3, 0.0): "2a7918e367055765",
    (3, 2.0): "21ae528f9e782a23",
    (0, 0.1): "2113235ba49f6a4b",
    (1, -0.2): "2134043a3d9de3d1",
    (2, 0.45): "f060c2e7ff5971af",
}

# Canonical digests of the slices of exact_animation() by the serial implementation with a
# global hash weld and 32-byte index nodes (commit ff9858d): every slice must have these
# points and faces, in whatever order the cut meets them.
SERIAL = {
    (3, 0.3125): "a99543b6a36f27aa",
    (3, 1.7): "42fd76b3a3eb1657",
    (3, 1.0): "4390a169240f5a87",
    (3, 1.0 + 1e-13): "4390a169240f5a87",
    (3, 0.0): "fbd069814f586ede",
    (3, 2.0): "1300d23450b72985",
    (0, 0.1): "a1cba1144f3c0fc5",
    (1, -0.2): "dff8d76ec273ab32",
    (2, 0.45): "c26be397472a0450",
}


@pytest.fixture(scope="module")
def manifold() -> am.AnimationManifold:
    """exact_animation() without its prisms: these tests are about the core's cut of the tets
    (frames between keys played as prisms: tests/test_prism_frames.py)."""
    stitched = exact_animation()
    return am.AnimationManifold(stitched.core_complex, stitched.metadata)


@pytest.fixture
def threads():
    """Sets the core's thread count for the test, then restores it."""
    previous = am.threads()
    yield am.set_threads
    am.set_threads(previous)


@pytest.mark.parametrize("axis, value", SLICES)
def test_slices_are_the_pinned_ones_bit_for_bit(manifold, axis, value):
    assert digest(manifold.slice(value, axis=axis)) == PINNED[(axis, value)]


@pytest.mark.parametrize("axis, value", SLICES)
def test_slices_have_the_points_and_faces_of_the_serial_implementation(manifold, axis, value):
    assert canonical_digest(manifold.slice(value, axis=axis)) == SERIAL[(axis, value)]


@pytest.mark.parametrize("value", [0.0, 1.0, 1.0 + 1e-13, 2.0])
def test_a_stitched_manifold_with_its_prisms_gives_the_keys_triangles_bit_for_bit(manifold, value):
    """With its prisms a key is the key's faces over its vertices; the same triangles,
    bit for bit, as the tets' slice (whose digest is pinned above)."""
    stitched = exact_animation()
    assert stitched.prisms is not None
    assert digest(manifold.slice(value)) == PINNED[(TIME_AXIS, value)]
    assert triangles(stitched.slice(value)) == triangles(manifold.slice(value))



@pytest.mark.parametrize("axis, value", SLICES)
def test_one_and_two_threads_give_identical_slices(manifold, threads, axis, value):
    slicer = _core.Slicer(manifold.core_complex)
    threads(1)
    one = slicer.slice(axis, value)
    threads(2)
    two = slicer.slice(axis, value)
    assert_identical(two, one)
    assert len(one.faces) > 4096  # several chunks of the parallel cut


class CountingSlicer:
    """A _core.Slicer that counts the calls that cut afresh and those that reuse a cut."""

    def __init__(self, slicer):
        self._slicer, self.fresh, self.reused = slicer, 0, 0

    def interval_frame(self, *args):
        self.fresh += 1
        return self._slicer.interval_frame(*args)

    def slice(self, *args):
        self.fresh += 1
        return self._slicer.slice(*args)

    def slice_in_interval(self, *args):
        self.reused += 1
        return self._slicer.slice_in_interval(*args)

    def __getattr__(self, name):
        return getattr(self._slicer, name)


@pytest.mark.parametrize("axis", ["t", "x"])
def test_frames_of_a_sequence_reuse_their_intervals_cut_and_equal_fresh_slices(manifold, axis):
    a = TIME_AXIS if axis == "t" else 0
    lo, hi = manifold.points[:, a].min(), manifold.points[:, a].max()
    # increasing values, several per topology interval, with keyframes, ends and outside among them
    values = np.concatenate([[lo - 1.0], np.linspace(lo, hi, 41), [hi + 1.0]])
    if axis != "t":  # vertex coordinates along x are dense: pairs a hair apart share an interval
        values = np.sort(np.concatenate([values, values[1:-1] + 1e-9]))
    counting = CountingSlicer(manifold._core_slicer())
    manifold._slicer = counting
    try:
        frames = list(manifold.slices(values, axis))
    finally:
        manifold._slicer = counting._slicer
    assert len(frames) == len(values)
    for value, frame in zip(values, frames):
        assert frame.value == value
        assert_identical(frame, manifold.slice(value, axis=axis))
    if axis == "t":
        assert counting.reused == 36  # 19 frames inside each of 2 intervals: all but the first reuse a cut
    assert counting.reused > 0 and counting.fresh + counting.reused == len(values)


def test_a_frame_is_moved_only_inside_its_topology_interval(manifold):
    slicer = _core.Slicer(manifold.core_complex)
    frame = slicer.interval_frame(TIME_AXIS, 0.5)
    assert_identical(slicer.slice_in_interval(frame, 0.75), slicer.slice(TIME_AXIS, 0.75))
    for value in (1.0, 1.5, 1.0 - 1e-14, -0.5, float("nan")):
        with pytest.raises(ValueError):
            slicer.slice_in_interval(frame, value)
    other = _core.Slicer(exact_animation(3).core_complex)
    with pytest.raises(ValueError):
        other.slice_in_interval(frame, 0.75)  # a frame of another manifold


def test_the_interval_index_takes_twelve_bytes_a_tet(manifold):
    slicer = _core.Slicer(manifold.core_complex)
    tets = len(manifold.simplices)
    distinct_times = len(np.unique(manifold.points[:, TIME_AXIS]))
    assert slicer.index_memory_bytes(TIME_AXIS) == 12 * tets + 8 * distinct_times
