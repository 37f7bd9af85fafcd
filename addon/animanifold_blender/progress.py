"""Blender's progress bar (the window manager's progress cursor) for blocking operators, and
the one mapping of the core's interrupter (``progress(step, fraction)``, see
cpp/include/animanifold/progress.hpp) onto it.

A blocking operator (execute: scripts, `blender -b`) gets no events while the core runs, so
there the core stops only on Ctrl-C in the terminal (its bindings check for it at every step).
Run from the interface, Morph Selected, Add Voronoi Skeleton and Laplacian Deform compute in a
worker thread (am.MorphJob, am.CoreJob; job_modal), the bar follows the job's fraction and Esc
cancels it.
"""

from __future__ import annotations

# Events that only move the view, passed on while a modal operator waits on a core job
# (am.CoreJob): everything else waits, so the operator's inputs are still there at the end.
VIEW_EVENTS = {"MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "TRACKPADPAN", "TRACKPADZOOM", "MOUSEMOVE",
               "INBETWEEN_MOUSEMOVE", "MOUSEROTATE", "NDOF_MOTION"}


class Progress:
    """Steps 0..total of a blocking operator; `end()` once done (in a finally)."""

    def __init__(self, context, total):
        self.wm = context.window_manager
        self.total = max(int(total), 1)
        self.wm.progress_begin(0, self.total)

    def __call__(self, done):
        self.wm.progress_update(min(int(done), self.total))

    def core_steps(self, done: int):
        """A core call's `progress` that fills step `done` to `done + 1` of the bar."""

        def progress(step: str, fraction: float) -> bool:
            self.wm.progress_update(min(done + min(max(float(fraction), 0.0), 1.0), self.total))
            return True  # never cancels

        return progress

    def end(self):
        self.wm.progress_end()


class CoreProgress:
    """The bar (0–100) of a blocking operator whose work is mostly one core call: the call's
    steps fill `low`–`high` of it as the core reports them; `at()` sets it for the operator's
    own steps. `where` names the step running, for the failure report."""

    def __init__(self, wm, low: float = 0.0, high: float = 100.0, where: str = "reading the inputs"):
        self.wm, self.low, self.high = wm, float(low), float(high)
        self.where = where
        wm.progress_begin(0, 100)

    def describe(self, step: str) -> str:
        return f"in the core's {step} step"

    def __call__(self, step: str, fraction: float) -> bool:
        self.where = self.describe(step)
        self.wm.progress_update(self.low + (self.high - self.low) * min(max(float(fraction), 0.0), 1.0))
        return True  # never cancels

    def at(self, where: str, value: float) -> None:
        self.where = where
        self.wm.progress_update(value)

    def end(self) -> None:
        self.wm.progress_end()


class MorphStages(CoreProgress):
    """A blocking morph's bar: reading the inputs (0–5), the core's stages (5–85: it reports
    each one as it finishes, with the fraction of the whole done), saving the cache and making
    the object."""

    def __init__(self, wm):
        super().__init__(wm, 5.0, 85.0)

    def describe(self, step: str) -> str:
        return f"after the core's {step} stage"
