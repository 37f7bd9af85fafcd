"""What the add-on remembers between frames in one Blender session: one LiveRegistry,
`registry`, whose methods are the only way in.

* manifolds loaded from cache files, once per file version (path, mtime, size), so a
  frame costs one slice and one mesh write, never a load;
* their subdivisions (am.subdivision_cache) and the interval cuts kept for playback
  (am.cut_cache);
* per manifold object (by its full name): the last error (shown in the panel), what
  its mesh shows (so a frame change that moves nothing writes nothing) and the scene
  frame it was last shown at without error, and whether the frame handlers skipped it
  as hidden (it is shown when it becomes visible).

A new file forgets everything (another file's objects may have the same names);
undo and redo forget what the meshes show (they may have gone back).
"""

from __future__ import annotations

import os
import weakref

from . import preferences
from ._lib import am


def _file_version(path: str) -> tuple[int, int]:
    st = os.stat(path)
    return st.st_mtime_ns, st.st_size


class LiveRegistry:
    """See the module."""

    def __init__(self):
        self._manifolds: dict[str, tuple[tuple[int, int], object]] = {}
        self._errors: dict[str, str] = {}
        self._shown: dict[str, object] = {}
        self._checked: dict[str, tuple] = {}
        self._skipped: set[str] = set()
        self._played: weakref.WeakSet = weakref.WeakSet()  # manifolds playback has shown
        self.subdivisions = am.subdivision_cache.SubdivisionCache()
        budget = preferences.frame_cache_budget_bytes
        self.cuts = am.cut_cache.CutCache(budget=budget, frame_budget=budget)

    def clear(self) -> None:
        self._manifolds.clear()
        self._errors.clear()
        self._shown.clear()
        self._checked.clear()
        self._skipped.clear()
        self._played.clear()
        self.subdivisions.clear()
        self.cuts.clear()

    def forget_shown(self) -> None:
        """Next frame changes write every object in full (after undo/redo)."""
        self._shown.clear()
        self._checked.clear()

    # -- manifolds by cache file ---------------------------------------------------
    def manifold(self, path: str, owner: str):
        """The manifold in cache file `path` (of object `owner`), loaded and validated once per file version."""
        try:
            version = _file_version(path)
        except OSError:
            raise am.CacheError(f"cache file {path} of '{owner}' does not exist") from None
        hit = self._manifolds.get(path)
        if hit is not None and hit[0] == version:
            return hit[1]
        manifold = am.load(path)
        self._manifolds[path] = (version, manifold)
        return manifold

    def loaded(self, path: str):
        """The manifold of `path` if it is loaded already (no file access), else None."""
        hit = self._manifolds.get(path)
        return None if hit is None else hit[1]

    def remember(self, path: str, manifold) -> None:
        """Registers a manifold just written to `path` (saves reloading it)."""
        path = os.path.normpath(path)
        self._manifolds[path] = (_file_version(path), manifold)
        self.subdivisions.drop(path)

    def forget(self, path: str) -> None:
        path = os.path.normpath(path)
        self._manifolds.pop(path, None)
        self.subdivisions.drop(path)

    def first_played(self, manifold) -> bool:
        """True the first time playback shows `manifold` (a loaded manifold, by identity)."""
        if manifold in self._played:
            return False
        self._played.add(manifold)
        return True

    # -- per object ------------------------------------------------------------------
    def error(self, obj) -> str | None:
        return self._errors.get(obj.name_full)

    def set_error(self, obj, message: str) -> bool:
        """Keeps `message` as the object's error; whether it differs from the one kept."""
        changed = self._errors.get(obj.name_full) != message
        self._errors[obj.name_full] = message
        return changed

    def clear_error(self, obj) -> None:
        self._errors.pop(obj.name_full, None)

    def shown(self, obj):
        """What the object's mesh shows (playback.Shown), None when unknown."""
        return self._shown.get(obj.name_full)

    def set_shown(self, obj, shown) -> None:
        self._shown[obj.name_full] = shown

    def forget_shown_of(self, obj) -> None:
        self._shown.pop(obj.name_full, None)

    def shown_at(self, obj, checked: tuple) -> bool:
        """Whether the object was last shown without error at `checked` (scene, frame)."""
        return self._checked.get(obj.name_full) == checked

    def set_shown_at(self, obj, checked: tuple | None) -> None:
        if checked is None:
            self._checked.pop(obj.name_full, None)
        else:
            self._checked[obj.name_full] = checked

    def set_skipped(self, obj) -> None:
        """The frame handlers skipped `obj` as hidden: its mesh may show another frame."""
        self._skipped.add(obj.name_full)
        self._checked.pop(obj.name_full, None)

    def skipped_names(self) -> list[str]:
        return sorted(self._skipped)

    def clear_skipped(self, obj) -> None:
        self._skipped.discard(obj.name_full)


registry = LiveRegistry()
