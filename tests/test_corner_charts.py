"""The corner charts' bookkeeping (cpp/include/animanifold/corner_charts.hpp), which
morph_surface.py uses to split a morph's vertices where the UV charts of their corners disagree."""

from __future__ import annotations

import numpy as np
import pytest

from animanifold import _core


def charts_by_search(owner: np.ndarray, uv: np.ndarray, tolerance: np.ndarray) -> np.ndarray:
    """chart_labels' rule, spelled out: the joins of neighbours in both orders, then the groups by
    a search over those joins, numbered in the order of each group's first item."""
    n = len(owner)
    neighbours = [[] for _ in range(n)]
    for first, second in ((0, 1), (1, 0)):
        order = np.lexsort((uv[:, second], uv[:, first], owner))
        for a, b in zip(order[:-1], order[1:]):
            if owner[a] == owner[b] and np.abs(uv[a] - uv[b]).max() <= tolerance[a]:
                neighbours[a].append(b)
                neighbours[b].append(a)
    label = np.full(n, -1)
    count = 0
    for start in range(n):
        if label[start] >= 0:
            continue
        label[start], stack = count, [start]
        while stack:
            for other in neighbours[stack.pop()]:
                if label[other] < 0:
                    label[other] = count
                    stack.append(other)
        count += 1
    return label


def test_a_chart_joined_in_one_order_stays_joined_when_the_other_order_joins_it_to_more():
    """Items 1 and 2 are neighbours in the order of u only, 2 and 0 in the order of v only (3 and 4
    come between the others in the other order, far off in the other coordinate): all three are one
    chart. Labels spread from the joins of the second order alone left item 1 on its own."""
    uv = np.array([[0.10, 0.12], [0.00, 0.00], [0.05, 0.05], [0.07, 0.90], [0.90, 0.03]])
    labels = _core.chart_labels(np.zeros(5, dtype=np.int64), uv, np.full(5, 0.1))
    assert labels.tolist() == [0, 0, 0, 1, 2]


def test_items_of_different_owners_or_with_a_nan_join_nothing():
    uv = np.array([[0.0, 0.0], [0.0, 0.0], [np.nan, 0.0], [0.0, 0.0]])
    labels = _core.chart_labels(np.array([0, 1, 1, 1], dtype=np.int64), uv, np.full(4, 0.5))
    assert labels.tolist() == [0, 1, 2, 1]


@pytest.mark.parametrize("seed", range(6))
def test_charts_are_the_groups_the_neighbours_joins_make(seed):
    """Random items with few owners, UVs on a coarse grid (ties) plus small offsets, some NaN, and
    tolerances from 0 to a grid step: the same labels as the rule spelled out."""
    rng = np.random.default_rng(seed)
    n = 3000
    owner = np.sort(rng.integers(0, 10, n)) if seed % 2 else rng.integers(0, 10, n)
    uv = np.round(rng.random((n, 2)) * 5) / 5 + rng.normal(0, 0.01, (n, 2)) * (rng.random((n, 1)) < 0.5)
    uv[rng.random(n) < 0.01, rng.integers(0, 2)] = np.nan
    tolerance = 0.06 * rng.random(n)
    labels = _core.chart_labels(owner.astype(np.int64), uv, tolerance)
    assert np.array_equal(labels, charts_by_search(owner, uv, tolerance))
    assert labels.max() < 2 * n // 3  # the case joins many items, not a handful


@pytest.mark.parametrize("seed", range(4))
def test_vertex_face_pairs_are_the_distinct_pairs_of_the_corners_in_order(seed):
    rng = np.random.default_rng(seed)
    vertices, faces = 500, 60
    simplices = rng.integers(0, vertices, (4000, 4)).astype(np.int32)
    face = rng.integers(0, faces, len(simplices)).astype(np.int32)
    vertex, pair_face, corner_pair = _core.vertex_face_pairs(simplices, face, vertices)
    keys, inverse = np.unique(simplices.astype(np.int64) * faces + face[:, None], return_inverse=True)
    assert np.array_equal(vertex, keys // faces) and np.array_equal(pair_face, keys % faces)
    assert np.array_equal(corner_pair, inverse.reshape(simplices.shape))


def test_bad_input_is_refused_with_what_is_wrong():
    simplices = np.array([[0, 1, 2, 3], [0, 1, 2, 7]], dtype=np.int32)
    with pytest.raises(_core.InputError, match="simplex 1 has vertex 7, out of range for 5 vertices"):
        _core.vertex_face_pairs(simplices, np.array([0, 0], dtype=np.int32), 5)
    with pytest.raises(_core.InputError, match="one face per simplex: 1 for 2"):
        _core.vertex_face_pairs(simplices, np.array([0], dtype=np.int32), 8)
    with pytest.raises(_core.InputError, match="2 UVs and 3 tolerances for 2 items"):
        _core.chart_labels(np.zeros(2, dtype=np.int64), np.zeros((2, 2)), np.zeros(3))
