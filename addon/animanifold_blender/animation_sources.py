"""What animates a mesh object's evaluated mesh, and at which frames: the actions of the
object, its mesh and shape keys and of the objects its modifiers or armature parent read
(their keyframes), and the drivers on all of these (a shape key or a modifier setting
driven by another object's transform).

A driver has no keyframes of its own: it changes when what it reads changes. Its frames
are the keyframes of the actions of the IDs its variables read (and of their parents);
a driver that reads the frame, a context property or an ID no action keys changes at
times nothing here can name, so the caller samples every frame for it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import bpy
import numpy as np


def _fcurves(anim_data) -> list:
    """F-curves of the action assigned to `anim_data` (legacy or slotted actions)."""
    if anim_data is None or anim_data.action is None:
        return []
    action = anim_data.action
    layers = getattr(action, "layers", None)
    if layers is not None and len(layers) > 0:  # Blender 4.4+: layered (slotted) actions
        slot = getattr(anim_data, "action_slot", None)
        curves = []
        for layer in layers:
            for strip in layer.strips:
                if slot is not None:
                    bag = strip.channelbag(slot)
                    if bag is not None:
                        curves.extend(bag.fcurves)
                else:
                    for bag in strip.channelbags:
                        curves.extend(bag.fcurves)
        return curves
    return list(getattr(action, "fcurves", []))


def _animation_owners(obj) -> list[tuple[str, object]]:
    """(label, AnimData or None) of every ID whose animation can move `obj`'s evaluated mesh:
    the object (transforms, modifier settings), its mesh and shape keys, and the objects its
    modifiers (armature, lattice, hook, ...) or an armature parent read, with their data."""
    sources = [(f"object '{obj.name}'", obj.animation_data)]
    mesh = obj.data
    sources.append((f"mesh '{mesh.name}'", mesh.animation_data))
    if mesh.shape_keys is not None:
        sources.append((f"shape keys of '{mesh.name}'", mesh.shape_keys.animation_data))
    others = []
    for mod in obj.modifiers:
        other = getattr(mod, "object", None)
        if isinstance(other, bpy.types.Object) and other != obj:
            others.append(other)
    if obj.parent is not None and obj.parent_type == "ARMATURE":
        others.append(obj.parent)
    for other in others:
        sources.append((f"object '{other.name}'", other.animation_data))
        if other.data is not None and hasattr(other.data, "animation_data"):
            sources.append((f"data of '{other.name}'", other.data.animation_data))
    return sources


def driving_animation(obj) -> list[tuple[str, object]]:
    """(label, AnimData) of every action that can move `obj`'s evaluated mesh."""
    return [(label, ad) for label, ad in _animation_owners(obj) if ad is not None and ad.action is not None]


def driver_curves(obj) -> list[tuple[str, object]]:
    """(label, driver F-curve) of every valid driver that can move `obj`'s evaluated mesh
    (on its shape keys, its modifiers' or its own settings, or those of the objects it reads)."""
    curves = []
    for label, ad in _animation_owners(obj):
        if ad is None:
            continue
        for fc in ad.drivers:
            if fc.driver is not None and fc.driver.is_valid and not fc.mute:
                curves.append((f"the driver of {label} on {fc.data_path}", fc))
    return curves


def _action_frames(anim_data) -> np.ndarray:
    frames = [np.empty(0)]
    for fc in _fcurves(anim_data):
        n = len(fc.keyframe_points)
        if n:
            co = np.empty(2 * n, dtype=np.float32)
            fc.keyframe_points.foreach_get("co", co)
            frames.append(co[0::2].astype(np.float64))
    return np.concatenate(frames)


def keyframe_frames(obj) -> np.ndarray:
    """Sorted unique frames of every keyframe of every action driving `obj`."""
    return np.unique(np.concatenate([np.empty(0)] + [_action_frames(ad) for _, ad in driving_animation(obj)]))


@dataclass
class DriverFrames:
    frames: np.ndarray  # keyframes of the actions the drivers read
    driven: bool = False  # a driver can move the mesh
    unknown: list = field(default_factory=list)  # why a driver's times cannot be named, one a driver


def _read_ids(driver) -> tuple[list, str | None]:
    """The IDs a driver's variables read, or why its times are unknown."""
    if driver.type == "SCRIPTED" and "frame" in driver.expression:
        return [], "reads the frame"
    ids = []
    for var in driver.variables:
        if var.type == "CONTEXT_PROP":
            return [], f"reads the context ({var.name})"
        count = 2 if var.type in ("LOC_DIFF", "ROTATION_DIFF") else 1
        ids.extend(t.id for t in list(var.targets)[:count] if t.id is not None)
    return ids, None


def _id_frames(id_) -> np.ndarray | None:
    """Keyframes of `id_`'s action and (an object's) its parents' actions; None when no
    action keys any of them."""
    chain, frames, found = [id_], [np.empty(0)], False
    while isinstance(chain[-1], bpy.types.Object) and chain[-1].parent is not None and len(chain) < 64:
        chain.append(chain[-1].parent)
    for item in chain:
        ad = getattr(item, "animation_data", None)
        if ad is not None and ad.action is not None:
            found = True
            frames.append(_action_frames(ad))
    return np.concatenate(frames) if found else None


def driver_frames(obj) -> DriverFrames:
    """The frames `obj`'s drivers change at, as far as their sources' keyframes say."""
    out = DriverFrames(np.empty(0))
    frames = [np.empty(0)]
    for label, fc in driver_curves(obj):
        out.driven = True
        ids, why = _read_ids(fc.driver)
        for id_ in ids:
            if why is None:
                keyed = _id_frames(id_)
                if keyed is None:
                    why = f"reads '{id_.name}', which no action keys"
                else:
                    frames.append(keyed)
        if why is not None:
            out.unknown.append(f"{label} {why}")
    out.frames = np.unique(np.concatenate(frames))
    return out
