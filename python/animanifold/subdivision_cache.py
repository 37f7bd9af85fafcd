"""Subdivisions of loaded manifolds (the add-on's Manifold Levels of a manifold object),
each computed once and kept, within the package's memory limit.

The shown manifold of an object with Manifold Levels > 0 is its cache's manifold
subdivided (Schaefer et al.) that many times, keyed by (levels, keep_keyframe_times)
beside the loaded manifold it came from; a new version of the file makes them stale.
A subdivision that fails, or would not fit in the package's memory limit (by default
half the free memory: am.set_memory_limit), is remembered as failed so that playback does
not retry it on every frame; a settings change (prune) forgets the failures and frees what
no object asks for any more.

An operator that needs a subdivision (Bake Frames) passes a `progress(step, fraction)`
that moves the window manager's bar through the core's levels and, from the interface,
computes it in a worker thread whose `interrupted()` answers Esc. Playback cannot offer
Esc: a subdivision asked for by a frame-change handler or a property update runs in the
main thread, which handles no events until it returns, and a cancelled one would be
asked for again on the next frame. There only Ctrl-C in the terminal stops it (the
core's bindings check for it at every step); nothing is remembered then, so the next
frame tries again.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import subdivision, welding
from ._core import Error
from .memory_limits import MemoryLimitError


class SmoothingError(Error):
    """Subdivision of a manifold object's manifold failed or would not fit in memory; the
    message names the object and says what to do (the add-on reports it as it is)."""


@dataclass
class _Subdivided:
    """The subdivisions of one loaded manifold (`base`), by (levels, keep_keyframe_times);
    `failed` keeps the message of a subdivision that failed, so that playback does not
    retry it on every frame (a settings change clears it)."""

    base: object
    manifolds: dict
    failed: dict


class SubdivisionCache:
    """Subdivided manifolds by cache path (see the module)."""

    def __init__(self):
        self._entries: dict[str, _Subdivided] = {}

    def subdivided(self, path: str, base, levels: int, keep_keyframe_times: bool, name: str, progress=None,
                   interrupted=None):
        """`base` (the manifold loaded from `path`) subdivided `levels` times, computed once and
        kept; raises SmoothingError (and remembers it) when it fails or would not fit in memory.
        `name` (the object's) words the errors; `progress(step, fraction)` follows the core's
        steps when it computes and `interrupted()` can stop it (a Cancelled it raises is passed
        on, not remembered). An operator's worker thread may compute it (Bake Frames): the
        main thread meanwhile runs no playback (the operator holds its events)."""
        manifold = self.kept_manifold(path, base, levels, keep_keyframe_times)
        if manifold is not None:
            return manifold
        entry, key = self._entries[path], (levels, bool(keep_keyframe_times))
        try:
            manifold = _subdivide(base, levels, key[1], name, progress, interrupted)
        except SmoothingError as e:
            entry.failed[key] = str(e)
            raise
        entry.manifolds[key] = manifold
        return manifold

    def kept_manifold(self, path: str, base, levels: int, keep_keyframe_times: bool):
        """The subdivision `subdivided` would give if it is kept, else None; raises the
        SmoothingError of one remembered as failed."""
        entry = self._entries.get(path)
        if entry is None or entry.base is not base:  # a new file version: older subdivisions are stale
            entry = self._entries[path] = _Subdivided(base, {}, {})
        key = (levels, bool(keep_keyframe_times))
        if key in entry.failed:
            raise SmoothingError(entry.failed[key])
        return entry.manifolds.get(key)

    def kept(self, path: str) -> list[tuple[int, bool]]:
        """The (levels, keep_keyframe_times) kept for `path`."""
        entry = self._entries.get(path)
        return [] if entry is None else list(entry.manifolds)

    def __len__(self) -> int:
        return len(self._entries)

    def drop(self, path: str) -> None:
        self._entries.pop(path, None)

    def clear(self) -> None:
        self._entries.clear()

    def prune(self, wanted: set[tuple[str, int, bool]]) -> None:
        """Keeps only the (path, levels, keep_keyframe_times) in `wanted` and forgets the failures."""
        for path, entry in list(self._entries.items()):
            entry.failed.clear()
            for key in list(entry.manifolds):
                if (path,) + key not in wanted:
                    del entry.manifolds[key]
            if not entry.manifolds:
                del self._entries[path]


def _subdivide(base, levels: int, keep_keyframe_times: bool, name: str, progress=None, interrupted=None):
    tets = subdivision.subdivided_simplex_count(base, levels)
    try:
        return subdivision.subdivide(welding.weld(base), levels=levels, scheme="schaefer",
                                     keep_keyframe_times=keep_keyframe_times, progress=progress,
                                     interrupted=interrupted)
    except MemoryLimitError as e:  # the package's limit (am.set_memory_limit), checked before allocating
        raise SmoothingError(f"{levels} subdivision levels of '{name}': {e}; use fewer levels") from None
    except MemoryError:
        raise SmoothingError(f"out of memory subdividing '{name}' {levels} levels ({tets:,} tets): "
                             "use fewer levels") from None
    except (ValueError, RuntimeError) as e:
        raise SmoothingError(f"cannot subdivide '{name}': {e}") from e
