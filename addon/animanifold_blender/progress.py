"""Blender's progress bar (the window manager's progress cursor) and status line for a long
operation, and the one mapping of the core's interrupter (``progress(step, fraction)``, see
cpp/include/animanifold/progress.hpp) onto them.

A blocking operator (execute: scripts, `blender -b`) gets no events while the core runs, so
there the core stops only on Ctrl-C in the terminal (its bindings check for it at every step).
Run from the interface, Morph Selected, Add Voronoi Skeleton, Laplacian Deform, Convert and
Bake Frames make their long core calls in a worker thread (am.CoreJob, am.core_job.Steps;
job_modal): the bar follows the job through the same Progress, and Esc cancels it.
"""

from __future__ import annotations

import time

# Events that only move the view, passed on while a modal operator waits on a core job
# (am.CoreJob): everything else waits, so the operator's inputs are still there at the end.
VIEW_EVENTS = {"MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "TRACKPADPAN", "TRACKPADZOOM", "MOUSEMOVE",
               "INBETWEEN_MOUSEMOVE", "MOUSEROTATE", "NDOF_MOTION"}


class Progress:
    """The bar (0–100) of one operation, begun at once; `end()` once done (in a finally).

    A core call fills the span `low`–`high` of the bar as it reports its steps: pass the
    object itself as the call's `progress` (blocking), or its job's (stage, fraction) from a
    modal operator's timer. The operator's own steps set the bar with `at` or `counter`.
    `where` names what runs, for a failure's report (`words` words a core step)."""

    def __init__(self, wm, low: float = 0.0, high: float = 100.0, where: str = "reading the inputs",
                 words: str = "in the core's {} step"):
        self.wm, self.low, self.high = wm, float(low), float(high)
        self.where, self.words = where, words
        self.value = 0.0  # where the bar is
        self.started = time.perf_counter()
        wm.progress_begin(0, 100)

    def __call__(self, step: str, fraction: float) -> bool:
        self.where = self.words.format(step)
        self._show(self.low + (self.high - self.low) * min(max(float(fraction), 0.0), 1.0))
        return True  # never cancels: a cancel comes through interrupted() (a job's Esc) or Ctrl-C

    def span(self, low: float, high: float) -> None:
        """The part of the bar the next core call fills (none when `low` == `high`: the bar stays)."""
        self.low, self.high = float(low), float(high)

    def at(self, value: float, where: str | None = None) -> None:
        if where is not None:
            self.where = where
        self._show(min(max(float(value), 0.0), 100.0))

    def counter(self, total: int):
        """`progress(done)` of the operator's own steps: `done` of `total` is that share of the bar."""
        total = max(int(total), 1)
        return lambda done: self.at(100.0 * min(done, total) / total)

    def status(self, label: str, stage: str, fraction: float, cancelling: bool) -> str:
        """The status line of a modal operator while its job runs."""
        text = "cancelling…" if cancelling else f"{stage}, {fraction:.0%}"
        return f"{label}: {text} ({time.perf_counter() - self.started:.0f} s) — Esc to cancel"

    def _show(self, value: float) -> None:
        self.value = value
        self.wm.progress_update(value)

    def end(self) -> None:
        self.wm.progress_end()
