"""CoreJob: any long core call in a worker thread, told of its steps through the core's one
interrupter and stopped at the next step once cancelled. Plain Python: no Blender needed;
the cancel is tied to a step the call reports, so nothing here depends on timing."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import animanifold as am
from animanifold import _core
from helpers.shapes import icosphere


def _jittered_sphere():
    v, f = icosphere(2)
    return v * (1 + 1e-6 * np.random.default_rng(1).standard_normal(len(v)))[:, None], f


def test_a_cancel_stops_the_call_at_its_next_step_with_no_result():
    steps, ready, holder = [], threading.Event(), {}

    def skeleton_cancelled_during_separability(v, f, progress, interrupted):
        def reporting(step, fraction):
            ready.wait(10.0)  # the job exists
            steps.append(step)
            if step == "separability":
                holder["job"].cancel()  # the user's Esc, between two of the core's steps
            return progress(step, fraction)

        return am.voronoi_skeleton(v, f, side="internal", progress=reporting, interrupted=interrupted)

    job = am.CoreJob(skeleton_cancelled_during_separability, *_jittered_sphere())
    holder["job"] = job
    ready.set()
    assert job.wait(60.0)
    assert job.cancelled and job.cancelling and job.result is None and job.error is None
    assert steps == ["checks", "separability"] and job.stage == "separability"


def test_a_finished_job_gives_what_the_blocking_call_gives():
    v, f = _jittered_sphere()
    job = am.CoreJob(am.voronoi_skeleton, v, f, side="internal")
    assert job.wait(60.0) and not job.cancelled and job.error is None
    blocking = am.voronoi_skeleton(v, f, side="internal")
    assert np.array_equal(job.result.vertices, blocking.vertices) and np.array_equal(job.result.faces, blocking.faces)
    assert job.stage == "assembly" and 0.9 <= job.fraction <= 1.0


def test_an_input_the_core_refuses_is_the_jobs_error_not_raised_in_the_thread():
    v, f = icosphere(1)
    job = am.CoreJob(am.voronoi_skeleton, v, f[1:])
    assert job.wait(30.0) and isinstance(job.error, _core.InputError) and "open" in str(job.error)
    assert not job.cancelled and job.result is None


def _stitching_steps(log):
    """Steps that stitch twice, with work of their own before, between and after (as Convert's
    adaptive sampling does), logging what ran; their result is the two stitches' sizes."""
    v, f = icosphere(1)
    try:
        log.append("before")
        first = yield am.core_job.CoreCall(am.stitch, (np.stack([v, 1.1 * v]), f, [0.0, 1.0]))
        log.append("between")
        second = yield am.core_job.CoreCall(am.stitch, (np.stack([v, 1.2 * v, 1.3 * v]), f, [0.0, 1.0, 2.0]))
        log.append("after")
        return len(first.simplices), len(second.simplices)
    finally:
        log.append("finally")


def test_steps_give_the_same_result_run_here_or_each_call_as_a_job():
    """Steps.run makes the calls in the calling thread; driven call by call as CoreJobs (the add-on's
    modal operators), the same generator gives the same result."""
    log = []
    here = am.core_job.Steps(_stitching_steps(log)).run()
    assert log == ["before", "between", "after", "finally"]
    log.clear()
    steps = am.core_job.Steps(_stitching_steps(log))
    call, jobs = steps.next(), 0
    while call is not None:
        job = call.job()
        assert job.wait(60.0) and job.error is None
        call, jobs = steps.next(job.result), jobs + 1
    assert steps.result == here and jobs == 2 and log == ["before", "between", "after", "finally"]


def test_a_calls_error_is_raised_where_the_steps_asked_for_it_and_a_cancel_runs_their_cleanup():
    log = []
    steps = am.core_job.Steps(_stitching_steps(log))
    steps.next()
    with pytest.raises(_core.InputError):
        steps.next(error=_core.InputError("the stitch refused its input"))
    assert log == ["before", "finally"]
    log.clear()
    steps = am.core_job.Steps(_stitching_steps(log))
    steps.next()
    steps.close()  # a cancelled job: nothing after it runs, the cleanup does
    assert log == ["before", "finally"]


def _piecewise_steps(made, log):
    """Main-thread work in three pieces with a pause after each, rolled back (`made` emptied)
    when it does not end."""
    try:
        for piece in range(3):
            made.append(piece)
            yield am.core_job.Pause("building")
        return list(made)
    except BaseException:
        made.clear()
        log.append("rolled back")
        raise


def test_run_passes_the_pauses_by_and_a_close_at_a_pause_rolls_the_work_back():
    """Steps.run has no events to answer: it goes straight on at each pause. Driven step by step,
    each pause comes back to the driver, and closing the steps there (Esc) runs their rollback."""
    made, log = [], []
    assert am.core_job.Steps(_piecewise_steps(made, log)).run() == [0, 1, 2] and log == []
    made.clear()
    steps = am.core_job.Steps(_piecewise_steps(made, log))
    pause = steps.next()
    assert pause == am.core_job.Pause("building") and made == [0]
    assert isinstance(steps.next(), am.core_job.Pause) and made == [0, 1]
    steps.close()
    assert made == [] and log == ["rolled back"] and steps.result is None
