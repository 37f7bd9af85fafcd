"""How many threads the core's parallel work uses (docs/ARCHITECTURE.md, "Threads").

One setting for the core's OpenMP loops (stitch, subdivision, the morph's per-simplex
loops, distance queries) and for the tiles of the Laplacian's factorisation, which run
OpenBLAS under CHOLMOD one tile per thread: `cpp/include/animanifold/threads.hpp`,
`cpp/src/tiled_blas.hpp`. Results are bit for bit the same for any count.
"""

from __future__ import annotations

import numbers

from . import _core


def set_threads(count: int) -> int:
    """Use `count` threads (>= 1), or every core for 0; returns the count now in use.

    Raises `_core.InputError` (an `animanifold.Error`) naming the value when it is not
    a whole number from 0 to 1024."""
    if isinstance(count, bool) or not isinstance(count, numbers.Integral):
        raise _core.InputError(f"thread count must be a whole number (0 for every core), got {count!r}")
    if not 0 <= int(count) <= _core.MAX_THREADS:
        raise _core.InputError(f"thread count must be from 1 to {_core.MAX_THREADS}, or 0 for every core; "
                               f"got {int(count)}")
    return _core.set_threads(int(count))


def threads() -> int:
    """The number of threads the core's parallel work uses now."""
    return _core.threads()
