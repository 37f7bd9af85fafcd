"""Blender's progress bar (the window manager's progress cursor) for blocking operators."""

from __future__ import annotations


class Progress:
    """Steps 0..total of a blocking operator; `end()` once done (in a finally)."""

    def __init__(self, context, total):
        self.wm = context.window_manager
        self.total = max(int(total), 1)
        self.wm.progress_begin(0, self.total)

    def __call__(self, done):
        self.wm.progress_update(min(int(done), self.total))

    def end(self):
        self.wm.progress_end()


class MorphStages:
    """The progress bar (0–100) of a blocking morph through reading the inputs (0–5), the
    core's stages (5–85: it reports each one as it finishes, with the fraction of the
    whole done), saving the cache and making the object; `where` names the stage
    running, for the failure report."""

    def __init__(self, wm):
        self.wm = wm
        self.where = "reading the inputs"
        wm.progress_begin(0, 100)

    def __call__(self, finished: str, fraction: float) -> bool:
        self.where = f"after the core's {finished} stage"
        self.wm.progress_update(5.0 + 80.0 * min(max(float(fraction), 0.0), 1.0))
        return True  # never cancels

    def at(self, where: str, value: float) -> None:
        self.where = where
        self.wm.progress_update(value)

    def end(self) -> None:
        self.wm.progress_end()
