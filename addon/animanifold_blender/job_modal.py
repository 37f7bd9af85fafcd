"""The modal half of an operator whose long core call runs in a worker thread (am.CoreJob):
Add Voronoi Skeleton, Laplacian Deform and Morph Selected, invoked from the interface.

While the job runs, timer ticks move the progress bar, view events pass, everything else
waits (so the operator's inputs are still there at the end) and Esc cancels the job at the
core's next step. The result is made by `_finish(context, source, result)` in the main
thread, as execute() makes it, so the operator's undo step is the same either way.
"""

from __future__ import annotations

from .progress import VIEW_EVENTS
from .reporting import reporting


class CoreJobModal:
    """Mixin for an Operator: `_start_job` from invoke(); the operator gives `_finish`,
    `_cancelled_text(source)` (the report of a cancel) and `_failure_text(source)`, or
    overrides `_tick` (what a timer tick shows) and `_job_done` (what the end makes)."""

    def _start_job(self, context, job, source) -> set:
        self._job, self._source = job, source
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
        if not job.done:
            if event.type == "TIMER":
                self._tick(context)
            # only the view may change meanwhile: the inputs must still be there at the end
            return {"PASS_THROUGH"} if event.type in VIEW_EVENTS else {"RUNNING_MODAL"}
        self._stop_waiting(context)
        return self._job_done(context)

    def _tick(self, context) -> None:
        """A timer tick while the job runs: the bar follows the core's steps."""
        context.window_manager.progress_update(100.0 * min(max(self._job.fraction, 0.0), 1.0))

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
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()

    def cancel(self, context):
        """Blender ends the modal operator itself (a file is opened, the window closes): the job
        is told to stop and left to end on its own (its thread touches no Blender data)."""
        self._job.cancel()
        self._stop_waiting(context)
