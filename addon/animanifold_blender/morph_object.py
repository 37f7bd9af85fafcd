"""Morph Selected's result: the manifold saved to a cache beside the .blend and shown by a
new manifold object (in world space: identity transform), the inputs hidden; on a failure
nothing is left behind. Then what the validity checks (§8.3) found, as warnings.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import bpy
import numpy as np

from . import live_nodes
from ._lib import am
from .cache_paths import morph_cache_path
from .live import scene_frame
from .live_registry import registry
from .mesh_input import morph_looks
from .object_names import unique_object_name
from .playback import update_object

# The methods the core has (animanifold.morph_pipeline.METHODS); the default is the one am.morph takes
# for surfaces, the field method: its in-betweens are level sets that change from the first frame to
# the last, with no crossing and exact ends (the bar of bench/bench_morph.py). The skeleton method of
# §8.6 and stripping (§8.5) stay selectable.
METHODS = tuple(am.morph_pipeline.METHODS)
BEST_METHOD = am.morph_pipeline.default_method(3)
_METHOD_TEXT = {
    "skeleton": ("Skeleton", "Conforming fill with the external skeletons pushed into time (§8.6): "
                             "handles shapes of different genus"),
    "field": ("Field", "Zero set of a blended signed-distance field over space-time: smooth in-betweens, holes "
                       "open and close cleanly, ends exact"),
    "strip": ("Strip", "Conforming fill and stripping only (§8.5): exact for shapes of the same topology, "
                       "in-between frames may pinch when the genus changes"),
}
METHOD_ITEMS = tuple((m.upper(), *_METHOD_TEXT.get(m, (m.title(), f"The core's '{m}' method")))
                     for m in sorted(METHODS, key=lambda m: m != BEST_METHOD))


# End frames this close to the inputs (of the size) are exact for a single-precision mesh.
SINGLE_PRECISION = 1e-7




@dataclass
class MorphObject:
    obj: object
    stored: str  # the cache path stored on the object
    note: str | None  # a warning for the report (a cache in a temporary folder)


def make_morph_object(context, source, target, start, end, source_input, target_input, manifold) -> MorphObject:
    """Saves the morph's cache and makes its object (see the module)."""
    slots, uv_name, _, _ = morph_looks(source_input, target_input)
    name = unique_object_name(f"{source.name}_to_{target.name}")
    stored, absolute, note = morph_cache_path(name)
    created = []
    try:
        manifold.metadata.update({"source_object": source.name, "target_object": target.name,
                                  "frame_range": [float(start), float(end)], "blender": bpy.app.version_string})
        am.save(manifold, absolute)
        created.append(absolute)
        new = _create_object(context, source, target, name, stored, absolute, manifold, start, end, slots, uv_name)
    except BaseException:
        _undo(created)
        raise
    return MorphObject(new, stored, note)


def _undo(created):
    for path in created:
        registry.forget(path)
        try:
            os.unlink(path)
        except OSError:
            pass

def _create_object(context, source, target, name, stored, absolute, manifold, start, end, slots, uv_name):
    mesh = bpy.data.meshes.new(name)
    for material in slots:  # the source's materials, then the target's (mesh_input.morph_looks)
        mesh.materials.append(material)
    new = bpy.data.objects.new(name, mesh)  # world-space geometry: identity transform
    (source.users_collection[0] if source.users_collection else context.scene.collection).objects.link(new)
    settings = new.animanifold
    settings.frame_start, settings.frame_end = float(start), float(end)
    settings.source = source
    lo, hi = manifold.bounding_box
    settings.time_scale = 2.0 * (float(np.linalg.norm((hi - lo)[:3])) or 1.0) / max(float(end - start), 1.0)
    settings.sweep_value = float((lo[0] + hi[0]) / 2)
    settings.cache_path = stored
    if uv_name:
        settings.uv_name = uv_name
    settings.is_manifold = True
    try:
        registry.remember(absolute, manifold)
        update_object(new, scene_frame(context.scene))
    except BaseException:
        bpy.data.objects.remove(new)
        bpy.data.meshes.remove(mesh)
        live_nodes.remove_unused_group()  # made for the new object's first frame
        raise
    context.scene.render.use_lock_interface = True  # live updates during renders (see operators.py)
    for obj in (source, target):
        obj.hide_render = True
        if obj.name in context.view_layer.objects:
            obj.hide_set(True)
            obj.select_set(False)
    new.select_set(True)
    context.view_layer.objects.active = new
    return new


def all_checks_passed(validity: dict) -> bool:
    """Whether the core's frame checks of a 3D morph (morph_validity.hpp) found nothing: no crossing,
    bubble or topological noise in the frames checked, no inverted or flat simplex."""
    return not (validity["crossing_frames"] or validity["bubble_frames"] or validity["noise_frames"]
                or validity["inverted_simplices"] or validity["degenerate_simplices"])


def report_validity(report, new, manifold, method: str, source, target, source_mesh, target_mesh) -> None:
    """Reports (on `report`, Operator.report) what the morph's validity checks (§8.3) found."""
    validity = manifold.validity
    chi_s, chi_t = (am.frame_quality.euler_characteristic(*mesh) for mesh in (source_mesh, target_mesh))
    topology = "" if chi_s == chi_t else (f"'{source.name}' (Euler characteristic {chi_s}) and '{target.name}' "
                                          f"({chi_t}) differ in topology")
    skeleton_hint = ("the skeleton method of §8.6 handles that: choose Method: Skeleton" if "skeleton" in METHODS
                     else "that needs the skeleton method of §8.6, which this build does not have yet")
    # Blender meshes are single precision: a quad is planar only to ~1e-7 of its size, and the
    # end frame may take its other diagonal — ends that close count as reproduced here (the
    # core's own test, at 1e-9, stays in the validity report).
    ends_off = max(validity["source_distance"], validity["target_distance"])
    if ends_off > SINGLE_PRECISION or validity["inverted_simplices"]:
        hint = f" ({topology}: {skeleton_hint})" if topology and method == "strip" else ""
        report({"WARNING"}, f"'{new.name}': the morph is not fully valid: end frames off by "
                                 f"{validity['source_distance']:.2g} / {validity['target_distance']:.2g} of the size, "
                                 f"{validity['inverted_simplices']} inverted simplices{hint}")
    if validity.get("inputs_apart"):
        report({"WARNING"}, f"'{new.name}': '{source.name}' and '{target.name}' do not overlap where they stand: the "
                                 f"{method} morph shrinks one away and grows the other in its place, nothing travels "
                                 "between them; to morph one into the other, move the target onto the source (their "
                                 "transforms place them)")
    if validity.get("middle_widening"):
        report({"INFO"}, f"'{new.name}': '{source.name}' and '{target.name}' barely meet, so the blend of their "
                              f"distances is widened at the middle (by {100 * validity['middle_widening']:.2g} % of the "
                              "size): the shape passes through the space between them instead of vanishing there")
    limit = "a known limit of the skeleton push; " if method == "skeleton" else ""
    if validity.get("frames_cross_themselves"):
        report({"WARNING"}, f"'{new.name}': in-between frames run through themselves at "
                                 f"{len(validity['crossing_frames'])} of {validity['crossing_frames_checked']} "
                                 f"checked times ({limit}see the validity report)")
    if validity.get("bubble_frames"):
        counts = ", ".join(f"{count} at {time_:.3g}" for time_, count in validity["bubble_frames"])
        report({"WARNING"}, f"'{new.name}': some in-between frames hold bubbles enclosed in the solid "
                                 f"({counts}; at most {100 * validity['largest_bubble_fraction']:.2g} % of the "
                                 f"volume): hidden under opaque materials, visible through glass ({limit}see the "
                                 "validity report)")
    if not validity.get("holes_preserved", True):
        report({"WARNING"}, f"'{new.name}': the holes both inputs share could not be cut out of "
                                 f"{len(validity['hole_errors'])} checked frames (those frames show uncut)")
    for line in am.morph_pipeline.cut_frame_warnings(validity):
        report({"WARNING"}, f"'{new.name}': {line}")
    if not manifold.check().is_oriented_manifold:
        hint = (f": {topology}: {skeleton_hint}" if topology and method == "strip"
                else f" (the {method} method did not give a clean manifold for these shapes)")
        report({"WARNING"}, f"'{new.name}': some in-between frames pinch (not a clean surface){hint}")
    if "frames_checked" in validity:  # the core's frame checks of 3D morphs (morph_validity.hpp)
        passed = all_checks_passed(validity)
        crossings = len(validity["crossing_frames"])
        # the field method's certificate rules crossings out at every time; else they are counted
        # on the frames looked at
        crossing_note = ("0 crossing (none at any time: space-time certified)"
                         if validity.get("crossings_certified") and not crossings
                         else f"{crossings} of {validity.get('crossing_frames_checked', 0)} crossing")
        report({"INFO"} if passed else {"WARNING"},
                    f"'{new.name}': {validity['frames_checked']} frames checked"
                    f"{' (changes left unbisected at the frame limit)' if validity['frames_capped'] else ''}, the topology "
                    f"changes {validity['topology_changes']} times between them; all checks passed: "
                    f"{'yes' if passed else 'no'} ({crossing_note}, "
                    f"{len(validity['bubble_frames'])} with bubbles, {len(validity['noise_frames'])} with "
                    f"topological noise, {validity['degenerate_simplices']} flat simplices)")
        if validity["noise_frames"]:
            found = noise_on_whole_frames(manifold, source_mesh, target_mesh)
            report({"WARNING"}, f"'{new.name}': {am.morph_noise.noise_summary(validity['noise_frames'], found)}")


def noise_on_whole_frames(manifold, source_mesh, target_mesh):
    """Which whole frames (the morph's t0 and t1 are frames) next to the topological noise the
    checks found show it: they look between frames too, where it may last less than a frame
    (am.morph_noise.NoiseOnFrames)."""
    start, end = manifold.time_range
    frames = np.arange(math.ceil(start), math.floor(end) + 1, dtype=np.float64)
    return am.morph_noise.noise_on_frames(manifold, manifold.validity["noise_frames"], frames, source_mesh,
                                          target_mesh)
