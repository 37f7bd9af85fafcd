"""How much memory one call may take: :func:`set_memory_limit`, :func:`memory_limit`.

The calls whose output size follows from their input — :func:`~animanifold.stitch`,
:func:`~animanifold.subdivide`, :func:`~animanifold.refine` and frame subdivision
(:func:`~animanifold.subdivide_frame`, :func:`~animanifold.smooth_slice`, smoothed slices) —
estimate their peak memory before they allocate it and raise :class:`MemoryLimitError` (an
:class:`animanifold.Error` and a :class:`MemoryError`) naming the call, the estimate and the
limit when it exceeds the limit. By default the limit is half of the memory available when the
call starts: MemAvailable, or what the process's cgroups (v2 ``memory.max``, v1
``memory.limit_in_bytes``, less their working set) still allow where that is less, as in a
container. The limit is process-wide (the core's, ``animanifold/memory_limit.hpp``).
"""

from __future__ import annotations

import operator

from . import _core
from ._core import InputError, MemoryLimitError

_MAX_BYTES = 2**64 - 1


def set_memory_limit(bytes: int | None) -> None:
    """Sets the limit in bytes (a positive integer) for every thread; None returns to the
    default, half of the memory available at each call."""
    if bytes is None:
        _core.set_memory_limit(None)
        return
    if isinstance(bytes, bool):
        raise InputError(f"the memory limit must be a number of bytes or None, got {bytes!r}")
    try:
        limit = operator.index(bytes)
    except TypeError:
        raise InputError(f"the memory limit must be a whole number of bytes or None, got {bytes!r}") from None
    if not 1 <= limit <= _MAX_BYTES:
        raise InputError(f"the memory limit must be between 1 and 2**64 - 1 bytes, got {limit}")
    _core.set_memory_limit(limit)


def memory_limit() -> int:
    """The limit in force, in bytes: the one set, else half of the memory available now."""
    return int(_core.memory_limit())


def memory_limit_is_set() -> bool:
    """Whether :func:`set_memory_limit` fixed the limit (False: the default applies)."""
    return _core.memory_limit_setting() is not None


__all__ = ["MemoryLimitError", "memory_limit", "memory_limit_is_set", "set_memory_limit"]
