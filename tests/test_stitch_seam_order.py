"""The stitch's seam order (stitching._seam_order): copies of one point follow the
first copy. The order is defined by np.unique over whole position tracks
(_seam_order_by_unique); _seam_order reaches the same order by comparing tracks only
among vertices whose hash is shared."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import animanifold as am
from animanifold import stitching
from helpers.keyframes import TIMES, wobble
from helpers.shapes import icosphere


def split_seam(vertices: np.ndarray, faces: np.ndarray, seam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`vertices` with the `seam` vertices copied to the end, and the faces on one side
    (those whose first vertex lies at x > 0) using the copies: a mesh split along a seam."""
    copies = len(vertices) + np.arange(len(seam))
    remap = np.arange(len(vertices))
    remap[seam] = copies
    side = vertices[faces[:, 0], 0] > 0
    faces = faces.copy()
    faces[side] = remap[faces[side]]
    return np.concatenate([vertices, vertices[seam]]), faces


def refusing_unique_over_tracks(unique):
    """np.unique that refuses rows (axis=...): the comparison of whole tracks the hashes should spare."""
    def refuse(values, *args, **kwargs):
        if kwargs.get("axis") is not None:
            raise AssertionError("np.unique over tracks called though the hashes settle the order")
        return unique(values, *args, **kwargs)
    return refuse


def test_seamless_mesh_keeps_index_order_without_comparing_tracks(monkeypatch):
    v, f = icosphere(3)
    frames = wobble(v, TIMES)

    monkeypatch.setattr(stitching.np, "unique", refusing_unique_over_tracks(np.unique))
    assert np.array_equal(stitching._seam_order(frames), np.arange(len(v)))


def test_seam_copies_follow_their_first_copy_as_np_unique_orders_them():
    v, f = icosphere(3)
    seam = np.flatnonzero(np.abs(v[:, 1]) < 0.3)[::2]
    v, f = split_seam(v, f, seam)
    frames = wobble(v, TIMES)
    order = stitching._seam_order(frames)
    assert np.array_equal(order, stitching._seam_order_by_unique(frames))
    position = np.empty_like(order)
    position[order] = np.arange(len(order))
    copies = len(v) - len(seam) + np.arange(len(seam))
    assert np.array_equal(position[copies], position[seam] + 1)


def test_seam_copies_are_grouped_by_whole_track_hashes_without_np_unique(monkeypatch):
    """Copies whose whole-track hashes group them exactly need no np.unique over tracks."""
    v, f = icosphere(3)
    v, f = split_seam(v, f, np.flatnonzero(np.abs(v[:, 2]) < 0.5))
    frames = wobble(v, TIMES)
    expected = stitching._seam_order_by_unique(frames)

    monkeypatch.setattr(stitching.np, "unique", refusing_unique_over_tracks(np.unique))
    assert np.array_equal(stitching._seam_order(frames), expected)


def test_stitched_seam_welds_shut():
    v, f = icosphere(2)
    seam = np.flatnonzero(np.abs(v[:, 1]) < 0.4)
    v, f = split_seam(v, f, seam)
    frames = wobble(v, TIMES)
    welded = am.weld(am.stitch(frames, f, TIMES))
    assert len(welded.points) == len(TIMES) * (len(v) - len(seam))
    report = welded.check()
    assert report.nonmanifold_facets == 0 and report.misoriented_facets == 0
    assert report.is_oriented_manifold


def test_order_is_exact_when_every_hash_collides(monkeypatch):
    """Hashes only pick the candidates: a hash that maps every track alike must still give
    the np.unique order (tracks equal in the hashed keyframes but not in others stay apart)."""
    rng = np.random.default_rng(3)
    frames = rng.integers(0, 3, size=(5, 200, 3)).astype(np.float64)
    frames[[0, 2, 4]] = 0.0  # first, middle and last keyframes alike for every vertex
    frames[:, 150:] = frames[:, :50]  # fifty exact copies
    monkeypatch.setattr(stitching, "_track_hashes", lambda flat, *keyframes: np.zeros(flat.shape[1], dtype=np.uint64))
    assert np.array_equal(stitching._seam_order(frames), stitching._seam_order_by_unique(frames))


def test_vertices_alike_in_hashed_keyframes_but_apart_in_others_are_not_copies():
    frames = np.zeros((5, 4, 3))
    frames[1, 1] = [1.0, 0.0, 0.0]  # vertex 1 leaves vertex 0's position in keyframe 1 only
    frames[3, 2] = [0.0, -0.0, 2.0]
    order = stitching._seam_order(frames)
    assert np.array_equal(order, stitching._seam_order_by_unique(frames))
    assert np.array_equal(order, [0, 3, 1, 2])


def test_negative_zero_is_a_copy_of_zero():
    frames = np.array([[[0.0, 1.0, 2.0], [5.0, 5.0, 5.0], [-0.0, 1.0, 2.0]]] * 3)
    assert np.array_equal(stitching._seam_order(frames), [0, 2, 1])
    assert np.array_equal(stitching._seam_order(frames), stitching._seam_order_by_unique(frames))


@st.composite
def keyframes_with_copies(draw):
    """(m, k, d) keyframes over a few values (so coordinates collide often), some vertices
    exact copies of others, some with −0.0 for 0.0, in float64, float32 or int."""
    m = draw(st.integers(1, 6))
    k = draw(st.integers(0, 40))
    d = draw(st.sampled_from([2, 3]))
    values = draw(st.lists(st.sampled_from([0.0, -0.0, 1.0, 0.5, 2.0]), min_size=m * k * d, max_size=m * k * d))
    frames = np.array(values, dtype=np.float64).reshape(m, k, d)
    for target, source in draw(st.lists(st.tuples(st.integers(0, 39), st.integers(0, 39)), max_size=10)):
        if target < k and source < k:
            frames[:, target] = frames[:, source]
    dtype = draw(st.sampled_from([np.float64, np.float32, np.int64]))
    return frames.astype(dtype)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(keyframes_with_copies())
def test_seam_order_matches_np_unique_definition(frames):
    assert np.array_equal(stitching._seam_order(frames), stitching._seam_order_by_unique(frames))


@pytest.mark.parametrize("shape", [(0, 4, 3), (1, 4, 3), (2, 0, 3), (2, 4, 0)])
def test_degenerate_shapes_match_np_unique_definition(shape):
    frames = np.zeros(shape)
    assert np.array_equal(stitching._seam_order(frames), stitching._seam_order_by_unique(frames))
