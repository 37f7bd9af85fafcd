"""Turning failures into operator reports: `with reporting(self, "Bake failed"): ...`.

Inside the block an operator (or what it calls) raises; the context manager reports the
failure with `operator.report({'ERROR'}, ...)` and swallows it, so the operator goes on
to return {'CANCELLED'}. Whatever the operator changed must already have been rolled
back by the code that changed it (each keeps its own `except BaseException: undo; raise`),
so the manager only words the report:

* ReportedError (the add-on's own failures) and the package's failures worded for the
  user (am.CacheError, am.subdivision_cache.SmoothingError): its message is the report;
* am.Cancelled (the user stopped the core: Esc, or Ctrl-C in the terminal): "<failure>: cancelled",
  as a warning;
* what the core or the file system raise (ValueError, RuntimeError, OSError: their
  messages name the input and the problem): "<failure>: <message>";
* anything else is a bug: still reported, never a traceback through Blender's UI, and
  the traceback printed to the console for the bug report.
"""

from __future__ import annotations

import traceback
from contextlib import contextmanager
from typing import Callable

from ._lib import am


class ReportedError(am.Error):
    """A failure whose message is the report to the user."""


class OperatorError(ReportedError):
    """An operator's refusal: the input or the scene is not what the operator needs."""


# The package's own error classes that name the file or input and the problem in full.
ALREADY_WORDED = (ReportedError, am.CacheError, am.subdivision_cache.SmoothingError)


@contextmanager
def reporting(operator, failure: str | Callable[[], str], name_type: bool = False):
    """Reports a failure raised in the block on `operator` and swallows it (see the module).
    `failure` starts the report of the core's errors; a callable is asked only on failure
    (it may name the stage reached). `name_type`: prefix every message not already worded
    with its exception class."""
    try:
        yield
    except ALREADY_WORDED as e:
        operator.report({"ERROR"}, str(e))
    except am.Cancelled:
        what = failure() if callable(failure) else failure
        operator.report({"WARNING"}, f"{what}: cancelled")
    except (ValueError, RuntimeError, OSError) as e:
        what = failure() if callable(failure) else failure
        operator.report({"ERROR"}, f"{what}: {type(e).__name__}: {e}" if name_type else f"{what}: {e}")
    except Exception as e:  # a bug: Blender's UI must not get the traceback
        traceback.print_exc()
        what = failure() if callable(failure) else failure
        operator.report({"ERROR"}, f"{what}: {type(e).__name__}: {e}" if name_type
                        else f"{what} unexpectedly: {type(e).__name__}: {e}")
