"""The modal half of an operator whose long core calls run in a worker thread (am.CoreJob):
Add Voronoi Skeleton, Laplacian Deform and Morph Selected (one call), Convert and Bake Frames
(am.core_job.Steps: the scene work between the calls runs here, in the main thread), invoked
from the interface.

While a job runs, timer ticks move the progress bar, view events pass, everything else
waits (so the operator's inputs are still there at the end) and Esc cancels the job at the
core's next step. The steps' own work in the main thread (Bake's frames and files) runs a
slice of pieces per event, up to each am.core_job.Pause; Esc between two slices closes the
steps, whose rollback removes what they made. The result is made by `_finish(context, source,
result)` in the main thread, as execute() makes it, so the operator's undo step is the same
either way.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import bpy

from . import preferences
from ._lib import am
from .progress import VIEW_EVENTS, Progress
from .reporting import reporting

# Seconds between the timer's events while a job runs.
TIMER_STEP = 0.1
# Seconds of the steps' main-thread work made per event: a timer step, so that the timer is due
# again when a slice ends (no idle wait between slices) and the interface answers as often.
MAIN_THREAD_SLICE = TIMER_STEP


@dataclass
class _Ended:
    """How step-wise work ended, read by `_job_done` as it reads a single job."""

    result: object = None
    error: BaseException | None = None
    cancelled: bool = False


class _Between:
    """The steps paused between two pieces of their main-thread work (am.core_job.Pause), in the
    place of a job: done at once, so the next event runs them on, unless Esc cancelled it."""

    done = True
    result = None
    error = None
    cancelling = False

    def __init__(self, stage: str, fraction: float):
        self.stage, self.fraction = stage, fraction
        self.cancelled = False

    def cancel(self) -> None:
        self.cancelled = True


class CoreJobModal:
    """Mixin for an Operator: `_start_job` (one call) or `_start_steps` from invoke(); the
    operator gives `_finish`, `_cancelled_text(source)` (the report of a cancel) and
    `_failure_text(source)`, or overrides `_job_done` (what the end makes). `_job_progress`
    gives its bar; `_status_label`, when set, names the job's stage in the status bar."""

    _steps = None  # am.core_job.Steps driven here, or None for a single job
    _status_label = None
    _job_name = "animanifold job"

    def invoke(self, context, event):
        """From the interface: modal (the operator's `_start`, which starts a job); where no
        window can run a modal operator (`blender -b`, bpy), as execute()."""
        preferences.apply_threads(context)
        if bpy.app.background or context.window is None:
            return self.execute(context)
        return self._start(context)

    def _job_progress(self, wm) -> Progress:
        """The bar a job's fraction fills (all of it unless the operator says otherwise)."""
        return Progress(wm)

    def _start_job(self, context, job, source, progress: Progress | None = None) -> set:
        self._job, self._source = job, source
        self._progress = progress or self._job_progress(context.window_manager)
        wm = context.window_manager
        self._timer = wm.event_timer_add(TIMER_STEP, window=context.window)
        wm.modal_handler_add(self)
        self._tick(context)
        return {"RUNNING_MODAL"}

    def _start_steps(self, context, steps, source, progress: Progress) -> set:
        """Runs `steps` here up to its first long call or pause, then each call in a worker
        thread: its result goes back to the steps in the main thread, which run on to the next
        call or to their end, made by `_finish`; at a pause they wait for the next event. Without
        a call or a pause it ends at once. The steps keep the context invoke() was given:
        Blender's one context, whose members are the operator's window's again whenever modal()
        runs them on."""
        try:
            call = steps.next()
        except BaseException:
            progress.end()
            raise
        if call is None:
            progress.end()
            return self._finish(context, source, steps.result)
        self._steps, self._progress = steps, progress
        return self._start_job(context, self._job_for(call), source, progress)

    def _job_for(self, call):
        """What modal() waits on for the steps' `call`: a long call's job, or a pause's stand-in."""
        if isinstance(call, am.core_job.Pause):
            return _Between(call.stage, self._progress.value / 100.0)
        return call.job(self._job_name)

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
        if not job.done:
            if event.type == "TIMER":
                self._tick(context)
            # only the view may change meanwhile: the inputs must still be there at the end
            return {"PASS_THROUGH"} if event.type in VIEW_EVENTS else {"RUNNING_MODAL"}
        if self._steps is not None and self._next_job():
            self._tick(context)
            return {"RUNNING_MODAL"}
        self._stop_waiting(context)
        return self._job_done(context)

    def _next_job(self) -> bool:
        """The finished job's result (or error) goes back to the steps, which run on to their next
        call, started as the next job, or through their pauses for a slice of time and wait at
        the last: True; False once they ended (`_job` then says how)."""
        job, steps = self._job, self._steps
        if job.cancelled:
            steps.close()  # the steps' rollback runs: what they made before the cancel goes
            return False
        slice_end = time.perf_counter() + MAIN_THREAD_SLICE
        try:
            call = steps.next(job.result, job.error)
            while isinstance(call, am.core_job.Pause) and time.perf_counter() < slice_end:
                call = steps.next()
        except BaseException as e:  # reported by _job_done, as a single job's error is
            self._job = _Ended(error=e)
            return False
        if call is None:
            self._job = _Ended(result=steps.result)
            return False
        self._job = self._job_for(call)
        return True

    def _tick(self, context) -> None:
        """A timer tick while the job runs: the bar (and the status line) follow the core's steps."""
        job = self._job
        if not isinstance(job, _Between):  # the steps' own work sets the bar itself
            self._progress(job.stage, job.fraction)
        if self._status_label:
            context.workspace.status_text_set(self._progress.status(self._status_label, job.stage, job.fraction,
                                                                    job.cancelling))

    def _job_done(self, context) -> set:
        """The job ended (finished, failed or cancelled): report it, or make its result."""
        job, source = self._job, self._source
        if job.cancelled:
            self.report({"WARNING"}, self._cancelled_text(source))
            return {"CANCELLED"}
        with reporting(self, self._failure_text(source)):
            if job.error is not None:
                raise job.error
            return self._finish(context, source, job.result)
        return {"CANCELLED"}

    def _stop_waiting(self, context) -> None:
        context.window_manager.event_timer_remove(self._timer)
        self._progress.end()
        if self._status_label:
            context.workspace.status_text_set(None)

    def cancel(self, context):
        """Blender ends the modal operator itself (a file is opened, the window closes): the job
        is told to stop and left to end on its own (its thread touches no Blender data)."""
        self._job.cancel()
        if self._steps is not None:
            self._steps.close()
        self._stop_waiting(context)
