"""The core's contracts as properties over random inputs (hypothesis): random keyframe sets
stitch and slice into closed, oriented frames; slicing at any time inside the range never
fails and reproduces the keyframes at their times; refinement keeps the measure; save/load is
the identity. Sizes are small so the file runs in well under a minute."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import animanifold as am
from animanifold import _core
from animanifold.procedural import icosphere

SETTINGS = settings(deadline=None, max_examples=25, suppress_health_check=[HealthCheck.function_scoped_fixture])
SPHERE = icosphere(1)


@st.composite
def keyframe_sets(draw):
    """(frames (m, k, 3), faces, strictly increasing times): an icosphere moved, scaled and jittered."""
    count = draw(st.integers(2, 4))
    steps = draw(st.lists(st.floats(0.05, 3.0), min_size=count - 1, max_size=count - 1))
    start = draw(st.floats(-10.0, 10.0))
    times = start + np.concatenate([[0.0], np.cumsum(steps)])
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    v, f = SPHERE
    frames = [v * rng.uniform(0.5, 2.0) + rng.uniform(-3, 3, 3) + rng.normal(0.0, 0.05, v.shape) for _ in times]
    assume(np.all(np.diff(times) > 0))
    return np.stack(frames), f, times


def assert_closed_and_oriented(faces: np.ndarray) -> None:
    """Every directed edge appears once, and its reverse once: closed, consistently oriented."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    assert len(directed) == len(edges), "an edge is used twice in the same direction"
    assert all((b, a) in directed for a, b in directed), "an edge has no opposite half"


@SETTINGS
@given(keyframe_sets(), st.floats(0.0, 1.0))
def test_random_keyframes_stitch_and_slice_into_closed_oriented_frames(keys, where):
    frames, faces, times = keys
    manifold = am.stitch(frames, faces, times)
    assert manifold.check().is_oriented_manifold
    t = float(times[0] + where * (times[-1] - times[0]))
    frame = manifold.slice(t)
    assert len(frame.faces) > 0
    assert_closed_and_oriented(np.asarray(frame.faces))


@SETTINGS
@given(keyframe_sets(), st.data())
def test_slicing_at_a_keyframe_time_gives_that_keyframe(keys, data):
    frames, faces, times = keys
    key = data.draw(st.integers(0, len(times) - 1))
    frame = am.stitch(frames, faces, times).slice(float(times[key]))
    assert len(frame.faces) == len(faces)
    got = np.asarray(frame.vertices)
    assert np.allclose(np.sort(got, axis=0), np.sort(frames[key], axis=0), atol=1e-9)


@SETTINGS
@given(keyframe_sets(), st.lists(st.tuples(st.integers(0, 10**6), st.integers(1, 4), st.integers(0, 2**32 - 1)),
                                 min_size=1, max_size=6))
def test_refinement_keeps_the_measure(keys, split_draws):
    frames, faces, times = keys
    manifold = am.stitch(frames, faces, times)
    splits = []
    for simplex, corners, seed in split_draws:
        rng = np.random.default_rng(seed)
        ids = rng.permutation(manifold.simplices[simplex % len(manifold.simplices)])[:corners]
        weights = rng.uniform(0.05, 1.0, corners)
        splits.append((ids.tolist(), (weights / weights.sum()).tolist()))
    refined, _ = am.refine(manifold, splits)
    before = _core._testing.simplex_volumes(manifold.points, manifold.simplices).sum()
    after = _core._testing.simplex_volumes(refined.points, refined.simplices).sum()
    assert after == pytest.approx(before, rel=1e-9)
    assert refined.check().is_oriented_manifold


json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2**53, 2**53) | st.floats(allow_nan=False) | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=8)


@SETTINGS
@given(keyframe_sets(), st.dictionaries(st.text(min_size=1, max_size=8), json_values, max_size=4),
       st.integers(1, 3), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_save_then_load_is_the_identity(tmp_path_factory, keys, metadata, uv_width, material_width, seed):
    frames, faces, times = keys
    rng = np.random.default_rng(seed)
    manifold = am.stitch(frames, faces, times,
                         vertex_attributes={"uv": rng.normal(size=(frames.shape[1], uv_width))},
                         face_attributes={"material": rng.integers(-5, 5, (len(faces), material_width))})
    manifold.metadata.update(metadata)
    path = am.save(manifold, tmp_path_factory.mktemp("cache") / "m.amf")
    loaded = am.load(path)
    assert loaded.points.tobytes() == manifold.points.tobytes()
    assert loaded.simplices.tobytes() == manifold.simplices.tobytes()
    for mine, theirs in [(loaded.vertex_attributes, manifold.vertex_attributes),
                         (loaded.simplex_attributes, manifold.simplex_attributes)]:
        assert mine.keys() == theirs.keys()
        assert all(mine[k].tobytes() == theirs[k].tobytes() and mine[k].shape == theirs[k].shape for k in mine)
    assert loaded.metadata == manifold.metadata
