"""animanifold.display: what a scene frame slices at and where a slice's vertices are shown
(the add-on's live playback and bake lay frames out through these)."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from animanifold import display
from helpers.shapes import cube


@pytest.fixture
def translating_cube():
    v, f = cube()
    frames = [v, v + [2.0, 0.0, 0.0]]
    normals = [np.tile([0.0, 0.0, 2.0], (len(v), 1))] * 2
    return am.stitch(frames, f, [1.0, 11.0], vertex_attributes={"normal": np.stack(normals)})


def test_a_time_slice_holds_the_first_and_last_samples_beyond_them(translating_cube):
    assert display.slice_value(translating_cube, -5.0, "t", 0.0) == 1.0
    assert display.slice_value(translating_cube, 40.0, "t", 0.0) == 11.0
    assert display.slice_value(translating_cube, 4.25, "t", 0.0) == 4.25
    assert display.slice_value(translating_cube, 4.25, "x", 0.3) == 0.3  # a sweep view ignores the frame


def test_a_time_slice_is_shown_where_it_is(translating_cube):
    s = translating_cube.slice(6.0, "t")
    assert np.array_equal(display.display_vertices(translating_cube, s, "t", 0.5), s.vertices)


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_a_sweep_view_lays_time_from_the_start_along_the_sliced_axis(translating_cube, axis):
    i = "xyz".index(axis)
    lo, hi = translating_cube.bounding_box
    s = translating_cube.slice(float((lo[i] + hi[i]) / 2), axis)
    shown = display.display_vertices(translating_cube, s, axis, 0.5)
    others = [c for c in range(3) if c != i]
    assert np.allclose(shown[:, others], s.vertices[:, :2])
    assert np.allclose(shown[:, i], (s.vertices[:, 2] - 1.0) * 0.5)
    assert shown[:, i].min() >= -1e-12 and shown[:, i].max() <= 10.0 * 0.5 + 1e-12


def test_carried_normals_come_back_unit_length(translating_cube):
    s = translating_cube.slice(6.0, "t")
    normals = display.slice_normals(s)
    assert normals is not None and np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    assert np.allclose(normals, [0.0, 0.0, 1.0])
    assert np.array_equal(display.frame_normals(s, smoothed=False), normals)


def test_a_flat_shaded_source_has_no_normals_to_carry():
    v, f = cube()
    m = am.stitch([v, v + 1.0], f, [0.0, 1.0])
    assert display.slice_normals(m.slice(0.5, "t")) is None
