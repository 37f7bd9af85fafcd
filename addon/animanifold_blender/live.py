"""Live playback of a scene: every live manifold object shown at the scene's frame
(playback.update_object), from the frame-change handlers, after a file loads and
when a setting changes. A failure is kept per object (live_registry), printed once
and shown in the panel, never raised into Blender's frame change.
"""

from __future__ import annotations

import traceback
import warnings

from . import playback, visibility
from ._lib import am
from .live_registry import registry
from .reporting import ALREADY_WORDED


def scene_frame(scene) -> float:
    return scene.frame_current + scene.frame_subframe


def is_live(obj) -> bool:
    settings = getattr(obj, "animanifold", None)
    return (settings is not None and settings.is_manifold and settings.mode == "LIVE"
            and obj.type == "MESH" and obj.data is not None and obj.library is None)


def last_error(obj) -> str | None:
    return registry.error(obj)


def show_object(obj, frame: float, force: bool = True, scene=None) -> bool:
    """playback.update_object that never raises: the failure is kept as the object's error (printed
    when it is new); whether the object shows its frame."""
    try:
        # A morph frame that its shared hole space cannot cut is shown uncut: Morph
        # Selected said so once; a warning per frame (an error where warnings are
        # errors) would stop playback for nothing.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", am.HoleSpaceWarning)
            playback.update_object(obj, frame, force=force, scene=scene)
    except Exception as e:  # a broken cache must not break playback
        message = f"{type(e).__name__}: {e}"
        if registry.set_error(obj, message):
            if not isinstance(e, ALREADY_WORDED):
                traceback.print_exc()
            print(f"animanifold: cannot slice '{obj.name}': {message}")
        return False
    registry.clear_error(obj)
    return True


def update_scene(scene, force: bool = False, after_evaluation: bool = False) -> int:
    """Shows every live manifold object of `scene` that Blender evaluates
    (visibility.is_evaluated) at its frame (playback.update_object; on a frame change
    nothing is written for objects whose mesh shows it already); never raises
    (show_object). Objects skipped as hidden are kept (live_registry) and shown by
    show_revealed once visible. Returns the count shown.

    `after_evaluation` (the post-frame handler): objects shown at this frame before
    the evaluation are skipped unless animated (an animated setting, a keyframed
    sweep value say, has its new value only now): a still object is not shown
    twice at one frame."""
    frame = scene_frame(scene)
    checked = (scene.as_pointer(), frame)
    count = 0
    for obj in scene.objects:
        if not is_live(obj):
            continue
        if not visibility.is_evaluated(obj, scene):
            registry.set_skipped(obj)
            continue
        if after_evaluation and not force and registry.shown_at(obj, checked) and obj.animation_data is None:
            count += 1
            continue
        count += _show_at(obj, scene, frame, force)
    return count


def _show_at(obj, scene, frame: float, force: bool) -> bool:
    checked = (scene.as_pointer(), frame)
    registry.set_shown_at(obj, None)
    if show_object(obj, frame, force=force, scene=scene):
        registry.set_shown_at(obj, checked)
        return True
    return False


def show_revealed(scene) -> int:
    """Shows at the scene's frame the objects update_scene skipped as hidden that Blender
    evaluates now (after a depsgraph update: unhidden, a collection included again).
    Returns the count shown."""
    frame = scene_frame(scene)
    count = 0
    # By name (live objects are local: name_full is the name): a hidden object costs
    # a look-up per depsgraph update, not a pass over the scene.
    for name in registry.skipped_names():
        obj = scene.objects.get(name)
        if obj is not None and is_live(obj) and visibility.is_evaluated(obj, scene):
            registry.clear_skipped(obj)
            count += _show_at(obj, scene, frame, force=True)
    return count
