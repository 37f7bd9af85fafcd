"""The manifold a manifold object shows: its cache's manifold (loaded once per file
version, live_registry), subdivided as its Smooth settings say (am.subdivision_cache),
and the frame it shows at a value: a slice, refined by OpenSubdiv when its Frame
Levels > 0. Live playback and bakes both slice through frame_slice, so they bake
what plays live."""

from __future__ import annotations

import math

import bpy

from . import cache_paths
from ._lib import am
from .live_registry import registry


def is_manifold_object(obj) -> bool:
    """Whether `obj` (None included) is a manifold object: one whose frames are slices of its
    cache (made by Convert or Morph Selected)."""
    settings = getattr(obj, "animanifold", None)
    return settings is not None and settings.is_manifold


def manifold_for(obj):
    """The manifold of a manifold object, loaded (and validated) once per file version."""
    return registry.manifold(cache_paths.cache_abspath(obj), obj.name)


def loaded_manifold(obj):
    """The manifold of `obj` if it is loaded already (no file access; for the panel)."""
    try:
        return registry.loaded(cache_paths.cache_abspath(obj))
    except (am.CacheError, ValueError, OSError):  # no path, bad path: the panel shows nothing
        return None


def shown_manifold(obj, progress=None):
    """The manifold whose slices `obj` shows: its cache's manifold, subdivided as its
    Smooth settings say. Each subdivision is computed once per loaded manifold and
    kept; a failure (or a result that would not fit in memory) raises SmoothingError
    and is remembered until a setting changes. `progress(step, fraction)` follows the
    subdivision's steps when it is computed here (an operator's bar)."""
    return am.core_job.Steps(shown_manifold_steps(obj)).run(progress)


def shown_manifold_steps(obj):
    """shown_manifold as am.core_job.Steps: a subdivision not kept yet is its long call, so an
    operator may compute it in a worker thread (reads the object's settings first, here)."""
    base = manifold_for(obj)
    settings = obj.animanifold
    levels = int(settings.subdivision_levels)
    if levels <= 0:
        return base
    path, keep = cache_paths.cache_abspath(obj), bool(settings.keep_keyframe_times)
    kept = registry.subdivisions.kept_manifold(path, base, levels, keep)
    if kept is not None:
        return kept
    return (yield am.core_job.CoreCall(registry.subdivisions.subdivided, (path, base, levels, keep, obj.name)))


def prune_subdivided() -> None:
    """Drops the subdivisions no manifold object asks for any more (their memory) and
    the remembered failures (a settings change may retry them)."""
    wanted = set()
    for obj in bpy.data.objects:
        settings = getattr(obj, "animanifold", None)
        if settings is None or not settings.is_manifold or settings.subdivision_levels <= 0:
            continue
        try:
            path = cache_paths.cache_abspath(obj)
        except am.CacheError:  # no cache path yet: nothing of its to keep
            continue
        wanted.add((path, int(settings.subdivision_levels), bool(settings.keep_keyframe_times)))
    registry.subdivisions.prune(wanted)


def smoothing(obj) -> bool:
    """Whether `obj` shows a smoothed manifold or smoothed frames (not plain slices)."""
    settings = obj.animanifold
    return settings.subdivision_levels > 0 or settings.smooth_levels > 0


def frame_slice(obj, manifold, value: float, axis: str = "t"):
    """The slice `obj` shows of `manifold` (its shown_manifold) at `value` along `axis`:
    refined by OpenSubdiv when its smooth_levels > 0."""
    settings = obj.animanifold
    s = manifold.slice(value, axis)
    if settings.smooth_levels <= 0:
        return s
    return am.smooth_slice(s, int(settings.smooth_levels), math.degrees(settings.crease_angle))


def frame_slices(obj, manifold, values, axis: str = "t"):
    """frame_slice at each of `values`, one at a time and the same frames, bit for bit: the
    slices come from manifold.slices, which reuses each topology interval's cut (bakes)."""
    settings = obj.animanifold
    for s in manifold.slices(values, axis):
        if settings.smooth_levels <= 0:
            yield s
        else:
            yield am.smooth_slice(s, int(settings.smooth_levels), math.degrees(settings.crease_angle))


def slice_value(obj, manifold, frame: float) -> float:
    """What scene frame `frame` slices the object's `manifold` at (display.slice_value)."""
    settings = obj.animanifold
    return am.display.slice_value(manifold, frame, settings.axis, settings.sweep_value)


def slice_for(obj, frame: float):
    """The Slice the object shows at scene frame `frame` (axis t), or at its sweep value."""
    manifold = manifold_for(obj)
    return manifold, manifold.slice(slice_value(obj, manifold, frame), obj.animanifold.axis)
