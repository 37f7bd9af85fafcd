"""A morph computed in a worker thread, so that Blender's interface keeps drawing
and Esc can cancel it (the add-on's Morph Selected, run from the interface).

The core releases the GIL for its stages and TetGen runs in a child process,
so the main thread stays free while the thread waits on them. The thread
touches no Blender data: the inputs are numpy arrays read beforehand, and the
caller reads `stage`, `fraction` and, once `done`, `manifold` or `error` from
a timer in the main thread. A cancel takes effect at the core's next stage,
or within about 0.1 s while TetGen runs (its `interrupted` check): the job
then ends with `cancelled` and no result.
"""

from __future__ import annotations

import threading
import time

from . import _core
from .morph_pipeline import morph


class MorphJob:
    """`morph(source, target, **options)` in a daemon thread, started at once."""

    def __init__(self, source, target, **options):
        self.stage = "reading the inputs"  # the core's last finished stage, for the status bar
        self.fraction = 0.0
        self.manifold = None
        self.error: BaseException | None = None
        self.cancelled = False
        self.started = time.perf_counter()
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(source, target, options), daemon=True,
                                        name="animanifold morph")
        self._thread.start()

    def _progress(self, stage: str, fraction: float) -> bool:
        self.stage, self.fraction = stage, float(fraction)
        return not self._cancel.is_set()

    def _run(self, source, target, options) -> None:
        try:
            self.manifold = morph(source, target, progress=self._progress, interrupted=self._cancel.is_set,
                                  **options)
        except _core.Cancelled:
            self.cancelled = True
        except BaseException as e:  # handed to the main thread, which reports it
            self.error = e
        finally:
            self._done.set()

    @property
    def cancelling(self) -> bool:
        """A cancel was asked for (the job may still be finishing its current check)."""
        return self._cancel.is_set()

    @property
    def done(self) -> bool:
        return self._done.is_set()

    def cancel(self) -> None:
        """Asks the morph to stop; `done` follows at its next check."""
        self._cancel.set()

    def wait(self, timeout: float | None = None) -> bool:
        """Blocks until the job is done (or `timeout` seconds pass); whether it is done."""
        return self._done.wait(timeout)
