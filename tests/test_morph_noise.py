"""Which rendered frames show the topological noise a morph's checks found (am.morph_noise), on a
stand-in whose noise is known (helpers/noise_stand_in.py)."""

import numpy as np
import pytest

import animanifold as am

from animanifold.frame_quality import pieces
from animanifold.morph_noise import frames_next_to, noise_on_frames, noise_summary
from helpers.noise_stand_in import TETRAHEDRON, swept_with_island


def test_the_stand_in_has_its_island_only_between_its_times():
    manifold = swept_with_island(0.49, 0.51)
    for t, expected in [(0.3, 1), (0.485, 1), (0.495, 2), (0.5, 2), (0.505, 2), (0.52, 1)]:
        frame = manifold.slice(t)
        assert pieces(frame.vertices, frame.faces) == expected, t
        # the island is an outer shell (positive volume), as the swept tetrahedron
        assert (am.cavities.shell_volumes(frame.vertices, frame.faces) > 0).all(), t


def test_frames_next_to_a_time_are_the_one_at_or_before_it_and_the_one_after():
    frames = [0.0, 0.25, 0.5, 0.75, 1.0]
    assert frames_next_to([0.3], frames) == [0.25, 0.5]
    assert frames_next_to([0.5], frames) == [0.5, 0.75]
    assert frames_next_to([0.3, 0.45, 0.6], frames) == [0.25, 0.5, 0.75]
    assert frames_next_to([1.0], frames) == [1.0]
    assert frames_next_to([], frames) == []


@pytest.mark.parametrize("frame_times, near, noisy", [
    (np.linspace(0, 1, 5), [0.25, 0.5, 0.75], [0.5]),           # a rendered frame lands on the island
    ([0.0, 0.25, 0.48, 0.52, 0.75, 1.0], [0.48, 0.52], []),     # the island lasts less than a frame
    (np.linspace(0, 1, 201), [0.49, 0.495, 0.5, 0.505, 0.51], [0.495, 0.5, 0.505]),
])
def test_the_frames_next_to_the_noise_that_show_it_are_found(frame_times, near, noisy):
    manifold = swept_with_island(0.49, 0.51)
    found = noise_on_frames(manifold, [0.4925, 0.5, 0.5075], frame_times, TETRAHEDRON, TETRAHEDRON)
    assert found.near == pytest.approx(near) and found.noisy == pytest.approx(noisy)


def test_the_summary_says_where_the_noise_is_and_which_frames_show_it():
    manifold = swept_with_island(0.49, 0.51)
    times = [0.4925, 0.5, 0.5075]
    shown = noise_summary(times, noise_on_frames(manifold, times, np.linspace(0, 1, 5), TETRAHEDRON, TETRAHEDRON))
    assert shown == ("topological noise at 3 checked times from 0.4925 to 0.5075; of the frames next to it "
                     "(0.25, 0.5, 0.75), 0.5 shows it")
    found = noise_on_frames(manifold, times, [0.0, 0.48, 0.52, 1.0], TETRAHEDRON, TETRAHEDRON)
    assert noise_summary(times, found, "written frame") == (
        "topological noise at 3 checked times from 0.4925 to 0.5075, lasting less than a written frame: the "
        "written frames next to it (0.48, 0.52) do not show it")
    assert noise_summary([], found) == "no topological noise in the frames checked"


def test_a_bubble_is_not_counted_as_a_piece():
    """A bubble inside a torus for a while: its frames have chi 0 + 2, within the range of a torus and
    a sphere, and one outer shell, so they show no noise (the core reports bubbles on their own);
    the same simplex outside the torus is an island, a second piece."""
    from helpers.shapes import torus

    ring = torus(major_radius=1.0, minor_radius=0.3, major=16, minor=8)
    ends = (TETRAHEDRON, ring)
    inside = swept_with_island(0.4, 0.6, ring, corner=(0.95, -0.04, -0.04), size=0.08, bubble=True)
    frame = inside.slice(0.5)
    assert sorted(np.sign(am.cavities.shell_volumes(frame.vertices, frame.faces))) == [-1, 1]
    assert noise_on_frames(inside, [0.5], [0.0, 0.5, 1.0], *ends).noisy == []
    beside = swept_with_island(0.4, 0.6, ring, corner=(3.0, 0.0, 0.0), size=0.08)
    assert noise_on_frames(beside, [0.5], [0.0, 0.5, 1.0], *ends).noisy == [0.5]
