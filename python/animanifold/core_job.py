"""A long core call computed in a worker thread, so that Blender's interface keeps drawing
and Esc can cancel it (the add-on's modal operators: Morph Selected, Skeleton).

Every long call of the package takes ``progress(step, fraction)`` and ``interrupted()``
(the core's one interrupter, cpp/include/animanifold/progress.hpp); the job passes its own,
which record the step and answer a cancel. The core releases the GIL while it works, so the
main thread stays free. The thread touches no Blender data: the inputs are numpy arrays read
beforehand, and the caller reads `stage`, `fraction` and, once `done`, `result` or `error`
from a timer in the main thread. A cancel takes effect at the call's next step (a morph also
polls about every 0.1 s while TetGen runs): the job then ends with `cancelled` and no result.
"""

from __future__ import annotations

import threading
import time
from typing import Callable

from . import _core


class CoreJob:
    """`call(*args, progress=..., interrupted=..., **kwargs)` in a daemon thread, started at once."""

    def __init__(self, call: Callable, *args, name: str = "animanifold job", **kwargs):
        self.stage = "reading the inputs"  # the step the call last reported, for the status bar
        self.fraction = 0.0
        self.result = None
        self.error: BaseException | None = None
        self.cancelled = False
        self.started = time.perf_counter()
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(call, args, kwargs), daemon=True, name=name)
        self._thread.start()

    def _progress(self, stage: str, fraction: float) -> bool:
        self.stage, self.fraction = stage, float(fraction)
        return not self._cancel.is_set()

    def _run(self, call, args, kwargs) -> None:
        try:
            self.result = call(*args, progress=self._progress, interrupted=self._cancel.is_set, **kwargs)
        except _core.Cancelled:
            self.cancelled = True
        except BaseException as e:  # handed to the main thread, which reports it
            self.error = e
        finally:
            self._done.set()

    @property
    def cancelling(self) -> bool:
        """A cancel was asked for (the job may still be finishing its current step)."""
        return self._cancel.is_set()

    @property
    def done(self) -> bool:
        return self._done.is_set()

    def cancel(self) -> None:
        """Asks the call to stop; `done` follows at its next step."""
        self._cancel.set()

    def wait(self, timeout: float | None = None) -> bool:
        """Blocks until the job is done (or `timeout` seconds pass); whether it is done."""
        return self._done.wait(timeout)
