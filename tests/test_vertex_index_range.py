"""Face indices that name no vertex are refused by the numpy-only geometry helpers (winding numbers,
points inside, cavities): numpy indexing would wrap a negative index to the end of the vertex array
and give a silently wrong result (issue 23)."""

from __future__ import annotations

import numpy as np
import pytest

from animanifold import _core
from animanifold.cavities import cavities, shell_volumes, surface_components
from animanifold.holes import points_inside, winding_numbers
from animanifold.indices import as_vertex_indices
from helpers.shapes import icosphere

HELPERS = {
    "winding_numbers": lambda v, f: winding_numbers(v, f, np.zeros((1, 3))),
    "points_inside": lambda v, f: points_inside(v, f, depth=1e-3),
    "surface_components": lambda v, f: surface_components(len(v), f),
    "shell_volumes": shell_volumes,
    "cavities": cavities,
}


@pytest.fixture
def sphere():
    return icosphere(1)


@pytest.mark.parametrize("name", HELPERS)
@pytest.mark.parametrize("value", [-1, -(10**6), "count", 10**8])
def test_a_face_index_naming_no_vertex_is_refused_naming_the_faces(sphere, name, value):
    v, f = sphere
    bad = np.array(f, np.int64)
    bad[3, 2] = len(v) if value == "count" else value
    with pytest.raises(_core.InputError, match=rf"faces holds {bad[3, 2]} at \(3, 2\), not an index of the {len(v)} vertices"):
        HELPERS[name](v, bad)


def test_a_negative_index_in_a_2d_boundary_is_refused():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    edges = np.array([[0, 1], [1, 2], [2, 3], [-1, 0]])
    with pytest.raises(_core.InputError, match="holds -1 at"):
        winding_numbers(square, edges, np.array([[0.5, 0.5]]))


def test_valid_faces_still_give_the_same_answers(sphere):
    v, f = sphere
    assert winding_numbers(v, f, np.array([[0.0, 0, 0], [3, 0, 0]])) == pytest.approx([1, 0], abs=1e-9)
    inside = points_inside(v, f, depth=1e-3)
    assert len(inside) == len(f) and np.all(np.linalg.norm(inside, axis=1) < 1)
    assert len(np.unique(surface_components(len(v), f))) == 1
    assert shell_volumes(v, f)[0] > 0 and len(cavities(v, f)) == 0


def test_empty_faces_are_in_range():
    assert as_vertex_indices(np.zeros((0, 3), np.int64), 0, "the faces").shape == (0, 3)
    assert len(shell_volumes(np.zeros((0, 3)), np.zeros((0, 3), int))) == 0
