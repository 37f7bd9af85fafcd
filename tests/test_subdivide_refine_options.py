"""subdivide and refine take options objects (SubdivideOptions, RefineOptions), like
deform's DeformOptions, LaplacianOptions and RegulariseOptions; the keywords they
replace still work and mean the same; giving both is refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import animanifold as am
from helpers.shapes import icosphere


@pytest.fixture(scope="module")
def stitched():
    v, f = icosphere(1)
    return am.stitch([v + [0.2 * t, 0, 0] for t in range(3)], f, [0.0, 1.0, 2.0])


def assert_same(a, b):
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.simplices, b.simplices)
    assert a.metadata == b.metadata


@pytest.mark.parametrize("fields", [{}, {"scheme": "linear"}, {"keep_keyframe_times": True},
                                    {"keep_keyframe_times": True, "keyframe_times": [0.0, 1.0, 2.0]}])
def test_subdivide_options_mean_what_the_keywords_mean(stitched, fields):
    assert_same(am.subdivide(stitched, 1, options=am.SubdivideOptions(**fields)), am.subdivide(stitched, 1, **fields))


def test_subdivide_options_are_checked_and_frozen(stitched):
    options = am.SubdivideOptions(scheme=am._core.ManifoldScheme.linear, keyframe_times=np.array([0, 2]))
    assert options.scheme == "linear" and options.keyframe_times == (0.0, 2.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.scheme = "schaefer"
    with pytest.raises(ValueError, match="unknown scheme 'loop'"):
        am.SubdivideOptions(scheme="loop")
    with pytest.raises(ValueError, match="keep_keyframe_times must be True or False"):
        am.SubdivideOptions(keep_keyframe_times="yes")
    with pytest.raises(ValueError, match="keyframe_times must be finite"):
        am.SubdivideOptions(keyframe_times=[0.0, float("nan")])
    with pytest.raises(ValueError, match="give options or the keywords scheme, not both"):
        am.subdivide(stitched, options=am.SubdivideOptions(), scheme="linear")
    with pytest.raises(ValueError, match="options must be a SubdivideOptions"):
        am.subdivide(stitched, options=am.RefineOptions())


@pytest.mark.parametrize("fields", [{}, {"order": "given"}, {"epsilon": 0.0}, {"epsilon": 0.2, "order": "given"}])
def test_refine_options_mean_what_the_keywords_mean(stitched, fields):
    a0, a1, a2, _ = (int(i) for i in stitched.simplices[0])
    splits = [([a0, a1], [0.5, 0.5]), ([a1, a2], [0.9, 0.1]), ([a0, a1], [0.3, 0.7]), ([a0, a1, a2], [0.1, 0.1, 0.8])]
    a, ra = am.refine(stitched, splits, options=am.RefineOptions(**fields))
    b, rb = am.refine(stitched, splits, **fields)
    assert_same(a, b)
    np.testing.assert_array_equal(ra.new_vertex_of_split, rb.new_vertex_of_split)
    c = am.refine_complex(stitched.points, stitched.simplices, splits, options=am.RefineOptions(**fields))
    np.testing.assert_array_equal(c.points, a.points)


def test_refine_options_are_checked(stitched):
    assert am.RefineOptions(order=am._core.RefineOrder.given).order == "given"
    with pytest.raises(ValueError, match="unknown order 'random'"):
        am.RefineOptions(order="random")
    for bad in (0.5, -0.1, float("nan"), True):
        with pytest.raises(ValueError, match="epsilon must be a number in"):
            am.RefineOptions(epsilon=bad)
    with pytest.raises(ValueError, match="give options or the keywords epsilon, order, not both"):
        am.refine(stitched, [], options=am.RefineOptions(), epsilon=0.1, order="given")
