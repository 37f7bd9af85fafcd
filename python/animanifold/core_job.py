"""A long core call computed in a worker thread, so that Blender's interface keeps drawing
and Esc can cancel it (the add-on's modal operators: Morph Selected, Skeleton).

Every long call of the package takes ``progress(step, fraction)`` and ``interrupted()``
(the core's one interrupter, cpp/include/animanifold/progress.hpp); the job passes its own,
which record the step and answer a cancel. The core releases the GIL while it works, so the
main thread stays free. The thread touches no Blender data: the inputs are numpy arrays read
beforehand, and the caller reads `stage`, `fraction` and, once `done`, `result` or `error`
from a timer in the main thread. A cancel takes effect at the call's next step (a morph also
polls about every 0.1 s while TetGen runs): the job then ends with `cancelled` and no result.

An operation that mixes long core calls with work that must stay in the main thread (Blender's
Convert samples the scene between stitches; Bake builds frames after the subdivision) is
written once as :class:`Steps`: a generator that yields each long call as a :class:`CoreCall`
and receives its result. Between two pieces of its main-thread work (a frame built, a file
written) it may yield a :class:`Pause`: a modal operator hands the interface its events there,
so Esc can stop the operation between pieces too (the generator is closed: its rollback runs).
`Steps.run` makes the calls in the calling thread (scripts, `blender -b`) and passes the pauses
by; a modal operator makes each call as a CoreJob instead, so Esc can stop it. Either way the
generator runs the same code, so both give the same result.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from typing import Callable, Generator

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


@dataclass
class CoreCall:
    """A long call that a :class:`Steps` generator asks its driver to make:
    `call(*args, progress=..., interrupted=..., **kwargs)`."""

    call: Callable
    args: tuple = ()
    kwargs: dict = field(default_factory=dict)

    def __call__(self, progress=None, interrupted=None):
        return self.call(*self.args, progress=progress, interrupted=interrupted, **self.kwargs)

    def job(self, name: str = "animanifold job") -> CoreJob:
        """The call in a worker thread, started at once."""
        return CoreJob(self.call, *self.args, name=name, **self.kwargs)


@dataclass
class Pause:
    """A point between two pieces of a :class:`Steps` generator's main-thread work where its
    driver may stop it (by closing it) or let the interface run before going on; `stage` names
    the work, for the status line."""

    stage: str


class Steps:
    """An operation written as a generator that yields its long calls (:class:`CoreCall`) and
    gets each one's result back, so that whoever drives it decides where the calls run (see
    the module). Its return value is `result` once `next` has returned None."""

    def __init__(self, generator: Generator):
        self._generator = generator
        self.result = None

    def next(self, result=None, error: BaseException | None = None) -> CoreCall | Pause | None:
        """Runs the operation on, in the calling thread, with the last call's `result` (or its
        `error` raised where it was asked for) up to its next call or pause; None once it has
        returned."""
        try:
            if error is not None:
                return self._generator.throw(error)
            return self._generator.send(result)
        except StopIteration as end:
            self.result = end.value
            return None

    def close(self) -> None:
        """Drops a cancelled operation: its generator's `except`/`finally` blocks (its rollback)
        run, here."""
        self._generator.close()

    def run(self, progress=None, interrupted=None):
        """The whole operation in the calling thread, each call given `progress` and
        `interrupted`; its result."""
        call = self.next()
        while call is not None:
            if isinstance(call, Pause):  # no events to answer here: straight on
                call = self.next()
                continue
            try:
                value = call(progress, interrupted)
            except BaseException as e:  # raised in the generator, where the call was asked for
                call = self.next(error=e)
            else:
                call = self.next(value)
        return self.result
