"""MorphJob: a morph in a worker thread that the caller polls and can cancel (the add-on's
Morph Selected runs it from the interface). Plain Python: no Blender needed."""

from __future__ import annotations

import time

import numpy as np

import animanifold as am
from animanifold.morph_job import MorphJob
from helpers.held_morph import BEFORE_THE_HOLD, HELD_METHOD, HOLD
from helpers.shapes import icosphere, torus


def test_a_morph_job_runs_beside_the_interface_and_stops_when_cancelled():
    """Morph Selected from the interface runs the core in a worker thread (MorphJob), so Blender
    keeps drawing and Esc can stop it. The core is held 30 s at its conforming stage (its test
    hold: a stand-in child process where the mesher would run): meanwhile the main thread gets the
    GIL (the interface can run Python: 50 ticks run while the job is held), and a cancel ends the
    job with nothing built (left alone, the job would build the morph after the hold)."""
    job = MorphJob(icosphere(1), torus(), t0=1.0, t1=24.0, test_hold=HOLD, method=HELD_METHOD)
    for _ in range(50):  # the interface's ticks, run while the worker holds the core
        time.sleep(0.01)
    assert not job.done
    job.cancel()
    assert job.wait(120.0)  # a bound against a hang, far beyond the 30 s hold
    assert job.cancelled and job.cancelling and job.manifold is None and job.error is None
    assert job.stage in BEFORE_THE_HOLD, job.stage

    # a job left to finish gives what the blocking call gives
    source, target = icosphere(1), torus()
    job = MorphJob(source, target, t0=1.0, t1=24.0, method=HELD_METHOD)
    assert job.wait(120.0) and not job.cancelled and job.error is None
    blocking = am.morph(source, target, t0=1.0, t1=24.0, method=HELD_METHOD)
    assert np.array_equal(job.manifold.simplices, blocking.simplices)
    assert np.array_equal(job.manifold.points, blocking.points)
    assert job.stage == "hole validity" and job.fraction == 1.0

    # an input the core refuses comes back as the job's error, not raised in the thread
    v, f = icosphere(1)
    job = MorphJob((v, f[1:]), target)
    assert job.wait(30.0) and isinstance(job.error, ValueError) and "open" in str(job.error)
