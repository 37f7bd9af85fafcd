"""The one interrupter of long core calls (cpp/include/animanifold/progress.hpp):
stitch, voronoi_skeleton, the Deformer's factorisation, subdivide, and the
package's chains of them (laplacian_deform, regularise, deform) report their
steps with fractions growing in [0, 1], and stop with animanifold.Cancelled at the
step where the caller's progress() answers False or its interrupted() True. The
calls are counted, so nothing here depends on how fast the machine is."""

from __future__ import annotations

import numpy as np
import pytest

import animanifold as am
from helpers.laplacian_shapes import block
from helpers.shapes import icosphere


def _stitch(**callbacks):
    v, f = icosphere(1)
    frames = np.stack([v * (1 + 0.1 * i) for i in range(4)])
    return am.stitch(frames, f, [0.0, 1.0, 2.0, 3.0], **callbacks)


def _skeleton(**callbacks):
    v, f = icosphere(2)
    v = v * (1 + 1e-6 * np.random.default_rng(1).standard_normal(len(v)))[:, None]  # off the cospherical case
    return am.voronoi_skeleton(v, f, side="internal", **callbacks)


def _deformer(**callbacks):
    v, f = block(2, 2, 4)
    bottom, top = np.flatnonzero(v[:, 2] < 1e-9), np.flatnonzero(v[:, 2] > v[:, 2].max() - 1e-9)
    return am.Deformer(v, f, bottom, top, **callbacks)


_STITCHED = None


def _subdivide(**callbacks):
    global _STITCHED
    if _STITCHED is None:
        _STITCHED = _stitch()
    return am.subdivide(_STITCHED, levels=2, **callbacks)


def _pulled_sphere():
    """An icosphere with its bottom anchored and its top cap pulled 4 radii up: regularise splits."""
    v, f = icosphere(2)
    z = v[:, 2]
    return v, f, np.flatnonzero(z < -0.5), np.flatnonzero(z > 0.8), am.handle_transform(translation=[0, 0, 4.0],
                                                                                       dimension=3)


def _laplacian_deform(**callbacks):
    return am.laplacian_deform(*_pulled_sphere(), **callbacks)


def _regularise(**callbacks):
    return am.regularise(*_pulled_sphere(), **callbacks)


def _deform(**callbacks):
    global _STITCHED
    if _STITCHED is None:
        _STITCHED = _stitch()
    t = _STITCHED.points[:, 3]
    anchors, handles = np.flatnonzero(t == t.min()), np.flatnonzero(t == t.max())
    return am.deform(_STITCHED, anchors, handles, am.handle_transform(translation=[0, 0, 0.5, 0]),
                     options=am.DeformOptions(regularise=am.RegulariseOptions(max_iterations=2)), **callbacks)


CALLS = {"stitch": _stitch, "voronoi_skeleton": _skeleton, "Deformer": _deformer, "subdivide": _subdivide,
         "laplacian_deform": _laplacian_deform, "regularise": _regularise, "deform": _deform}
CHAINS = ("laplacian_deform", "regularise", "deform")


class Recorder:
    """progress() and interrupted() that count their calls; one of them stops at call `stop_at`."""

    def __init__(self, stop_progress_at: int = 0, stop_interrupted_at: int = 0):
        self.steps: list[tuple[str, float]] = []
        self.polls = 0
        self.stop_progress_at, self.stop_interrupted_at = stop_progress_at, stop_interrupted_at

    def progress(self, step: str, fraction: float) -> bool:
        self.steps.append((step, fraction))
        return len(self.steps) != self.stop_progress_at

    def interrupted(self) -> bool:
        self.polls += 1
        return self.polls == self.stop_interrupted_at

    def callbacks(self) -> dict:
        return {"progress": self.progress, "interrupted": self.interrupted}


@pytest.mark.parametrize("name", CALLS)
def test_progress_runs_through_named_steps_with_fractions_growing_in_the_unit_interval(name):
    recorder = Recorder()
    CALLS[name](**recorder.callbacks())
    fractions = [f for _, f in recorder.steps]
    assert len(fractions) >= 3, recorder.steps
    assert all(0.0 <= f <= 1.0 for f in fractions), recorder.steps
    assert fractions == sorted(fractions), recorder.steps
    assert all(isinstance(step, str) and step for step, _ in recorder.steps)
    assert recorder.polls == len(recorder.steps)  # interrupted() is polled at every step


@pytest.mark.parametrize("name", CALLS)
def test_false_from_progress_stops_the_call_at_that_step(name):
    recorder = Recorder(stop_progress_at=3)
    with pytest.raises(am.Cancelled):
        CALLS[name](**recorder.callbacks())
    assert len(recorder.steps) == 3  # nothing ran past the refused step


@pytest.mark.parametrize("name", CALLS)
def test_true_from_interrupted_stops_the_call_at_that_poll(name):
    recorder = Recorder(stop_interrupted_at=2)
    with pytest.raises(am.Cancelled):
        CALLS[name](**recorder.callbacks())
    assert recorder.polls == 2 and len(recorder.steps) == 2


@pytest.mark.parametrize("name", CHAINS)
def test_a_chain_of_core_calls_stops_at_any_counted_poll_past_its_first_factorisation(name):
    counted = Recorder()
    CALLS[name](**counted.callbacks())
    names = [step for step, _ in counted.steps]
    assert "deforming" in names and names[-1] == "done", names
    for stop in (names.index("deforming") + 1, counted.polls - 1, counted.polls):
        recorder = Recorder(stop_interrupted_at=stop)
        with pytest.raises(am.Cancelled):
            CALLS[name](**recorder.callbacks())
        assert recorder.polls == stop and len(recorder.steps) == stop


def test_regularise_reports_a_factorisation_per_round():
    recorder = Recorder()
    _, _, maps = _regularise(**recorder.callbacks())
    assert maps.iterations >= 1
    assert [step for step, _ in recorder.steps].count("deforming") == maps.iterations + 1
    assert recorder.steps[-1] == ("done", 1.0)


def test_an_exception_in_a_callback_reaches_the_caller_unchanged():
    def broken(step, fraction):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        _stitch(progress=broken)


def test_cancelled_is_an_animanifold_error():
    assert issubclass(am.Cancelled, am.Error)
