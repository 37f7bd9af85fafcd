"""Morphing between closed shapes (chapters 5 and 8): numpy in, AnimationManifold out.

What :func:`morph`'s report (``validity``) says of its frames and of the hole space:

Frames are checked for running through themselves (`crossing_frames`), for bubbles enclosed in
the solid that neither input has (`bubble_frames` lists [time, bubbles] where there are,
`largest_bubble_fraction` their largest share of a frame's volume) and, in 3D, for leaving the
inputs' topology (`noise_frames`): in 3D by the core, for every method, on 24 frames spread
over the range (crossings on these), for the field method 7 inside its fill slab, and up to 24
frames bisecting towards the changes of topology, the same frames on any machine
(`frames_checked`, `frames_capped` when changes were left unbisected at that limit,
`topology_changes`); 2D morphs check `hole_checks` evenly spaced frames for crossings (their
frames hold no cavities).

Validity 3 (shared holes are kept): the hole spaces H_S = CH(S) \\ S and
H_T of the inputs (§8.6.5) are intersected into H = H_S ∩ H_T, which the
result keeps (`hole_space`, saved with it) and subtracts from every time
slice strictly between t0 and t1. The report adds `shared_hole_volume`
(the volume of H; its area for 2D inputs), `hole_overlap_volume` (the
largest part of H, relative to H, that a raw frame fills, over
`hole_checks` frames evenly spaced in (t0, t1): what the cut removes,
volume(raw) - volume(raw \\ H)) and `holes_preserved` (every checked frame
could be cut, and no point just inside H lies inside the cut frame,
`hole_frames_verified` of `hole_frames_checked`; what failed is listed in
`hole_errors`). The cut frames, the ones the user gets, are checked too: `cut_crossing_frames`
lists those that run through themselves (the boolean leaves thin slivers), and
`cut_frame_pieces` [t, pieces, cavities of the raw frame, pieces, cavities of the cut one]
those whose shells the cut changes. H is computed first, before the core's stages (`progress`
hears "holes" first), so that a shape CGAL cannot work on stops the morph in
seconds, with an animanifold.BooleanError that names the input; "hole
validity" follows the core's "validity", and `interrupted()` is polled
between its frames.
"""

from __future__ import annotations

import functools
import numbers
import time
from typing import Callable

import numpy as np

from . import _core
from .indices import as_indices
from .holes import (BooleanError, hole_space, inside_solid, intersect_solids, is_empty, points_inside, solid_measure,
                    subtract_solid)
from .cavities import shell_volumes
from .manifold import AnimationManifold
from .morph_surface import SurfaceAttributes, carry_surface_attributes, check_surface_attributes
from ._core import InputError

# The core's names (morph.hpp's tables, bound as enums): the field method (morph_field.hpp, the
# default for surfaces) and the seed's methods (§8.6, §8.5); the seed's fills and perturbations.
METHODS = tuple(_core.MorphMethod.__members__)
FILLS = tuple(_core.FillTriangulation.__members__)
_DEFAULTS = _core.MorphOptions()


def morph(
    source: tuple[np.ndarray, np.ndarray],
    target: tuple[np.ndarray, np.ndarray],
    t0: float = 0.0,
    t1: float = 1.0,
    method: str | None = None,
    progress: Callable[[str, float], bool] | None = None,
    max_push: float = _DEFAULTS.max_push,
    fill: str = _DEFAULTS.fill.name,
    hole_checks: int = 5,
    perturbation: str = "auto",
    interrupted: Callable[[], bool] | None = None,
    fan_flat_polygons: bool = True,
    test_hold: tuple[str, float] | None = None,
    mesher_time_limit: float = 0.0,
    field_resolution: float = _DEFAULTS.field_resolution,
    source_attributes: SurfaceAttributes | None = None,
    target_attributes: SurfaceAttributes | None = None,
) -> AnimationManifold:
    """An animation manifold that is `source` at t0 and `target` at t1.

    source, target: (vertices (k, 3), triangles (l, 3)) closed, outward
    oriented meshes — or (vertices (k, 2), edges (l, 2)) closed
    counter-clockwise polygons. `progress(stage, fraction)` is called between
    stages; returning False cancels (raises animanifold._core.Cancelled).
    `interrupted()` is called about every 0.1 s while a mesher runs (TetGen can
    take seconds); returning True cancels the same way. Both may be called from
    the thread the morph runs in (a worker thread: see the add-on's Morph
    Selected).

    method: None (the default) takes "field" for 3D surfaces and "skeleton" for 2D polygons (see
    default_method). "skeleton" (§8.6) fills concavities and holes of the
    source over the first `max_push` of the range and opens the target's over
    the last, with every frame a closed surface; "strip" (§8.5) removes what
    lies outside either shape — ambiguous where the genus changes (frames can
    pinch). The skeleton method pushes its free points into time in a layer
    of prisms between each input and the fill (the core's morph_layers.hpp):
    their heights follow their distance from the input (the frames are close
    to the input's offsets: a hole opens along its axis first and widens),
    levelled so that a frame holds neither a bubble nor an island
    (report: `source_push`, `target_push` as fractions of the range,
    `levelled_vertices`, `split_faces`, `refinement_points`, `peeled_slivers`,
    `sealed_vertices`). fill: the Delaunay triangulation of the fill, "cgal"
    (fast) or "qhull".

    The result's `validity` (also kept in its metadata) is the report of §8.3:
    Theorem 5.2.1's missing faces, inverted/degenerate simplices, and how far
    the end frames are from the inputs (relative to the bounding box).

    perturbation: how the inputs are put in general position — "hull_faces" (each point by an
    offset that is a function of its position, except points on the inputs' convex hulls, which
    stay exact), "position" (every point), or "auto" (the default): "hull_faces", and when that
    fails in a mesher or its frames run through themselves or hold bubbles of more than
    RETRY_BUBBLE_FRACTION (1e-4) of their volume, "position" too, keeping the better — fewer
    crossing frames, then a smaller largest bubble (report: `perturbation_mode`,
    `perturbation_retried`).

    fan_flat_polygons: flat convex polygons of six corners or more (a cylinder's and a cone's caps)
    are triangulated again as fans from their centre before meshing (report:
    `source_fanned_polygons`, `target_fanned_polygons`): Blender's chords between their
    cocircular rim points are what the conforming mesher cannot settle (a 64-sided cylinder ->
    a torus ran through itself). The surface and the ends are the same; False keeps the input's
    triangulation, for comparison.

    Flat sides of an input's hull that span a hole (a torus's caps) get a free point over them
    (report: `source_cap_points`, `target_cap_points`), so the hole opens from its ends.

    Frames are checked (crossings, bubbles, topology) and the shared hole space is kept and cut
    from every frame between the ends: the module's docstring lists what the report says of both.
    method "field": the zero set of a signed-distance field blended over a space-time
    triangulation of a box around both inputs (the core's morph_field.hpp): every frame is a level
    set, so it is embedded and holes open and close cleanly, and the ends are the inputs exactly.
    No hole space is cut (a point outside both inputs stays outside every frame by construction,
    unless the inputs barely meet and the blend is widened at the middle, `middle_widening`: then
    only points within the widening of one input may be inside a frame); its frames are checked as
    above.
    perturbation, max_push, fill, hole_checks and fan_flat_polygons do not apply to it.
    field_resolution: its lattice's cells across the shapes' size (default 24; report:
    `lattice_spacing`, its spacing as a share of the size). Finer resolves thinner parts and
    smaller holes in between, in more time and memory (the lattice is dense only near the surfaces,
    so both grow about as fast as it does); the ends are the inputs at any resolution.

    source_attributes, target_attributes: the inputs' UV maps (per face corner) and material indices
    (per face), as animanifold.morph_surface.SurfaceAttributes, in the order of the faces given
    here; 3D only. The result then carries them as the vertex attribute "uv" and the simplex
    attribute "material_index" (exact at the ends; in between each part of a frame takes the look
    of the input it lies closer to; vertices split where the charts differ: see morph_surface.py;
    report: `surface_attributes`). Material indices are kept as given: number the target's after
    the source's to show both.

    test_hold: (stage, seconds) for tests of cancellation: the core waits `seconds` on a stand-in
    child process at the start of that stage ("conforming" for every method), under the same polling
    of `interrupted` and Ctrl-C as its mesher.

    mesher_time_limit: seconds each TetGen run may take (0: 5 s + 0.5 ms a face), a safety net
    against TetGen looping. A run past it raises animanifold._core.TimeLimitError (a
    MeshingError) and nothing is retried at another perturbation: whether the limit is hit depends
    on the machine's speed and load, and the result must not.

    Where the inputs coincide (`inputs_coincide`: the same shape, Figure 8.9),
    the skeleton method removes what lies outside both instead of pushing it,
    every frame is the input, and the result keeps no hole space (no frame
    enters it; `shared_hole_volume` still reports it). The field method, where
    both are the same surface (the same points and faces, in any order), sweeps
    it over the range: every frame is the input, no simplex flat.
    """
    arrays = _input_arrays(source, target)
    method = default_method(arrays[0].shape[1]) if method is None else method
    _check_options(method, hole_checks, mesher_time_limit, fill, perturbation, field_resolution)
    hold = _core_keywords(method, test_hold, mesher_time_limit, field_resolution)
    looks = (source_attributes, target_attributes)
    if any(look is not None for look in looks):
        _check_looks(arrays[0].shape[1], source, target, *looks)  # before minutes of morphing
    manifold = (_field_morph(arrays, float(t0), float(t1), progress, interrupted, hold) if method == "field" else
                _seed_morph(arrays, float(t0), float(t1), method, progress, max_push, fill, hole_checks, perturbation,
                            interrupted, fan_flat_polygons, hold))
    if any(look is not None for look in looks):
        manifold = carry_surface_attributes(manifold, source, target, *looks)
        _stage_finished(progress, "surface attributes", 1.0)
    return manifold


def default_method(dimension: int) -> str:
    """The method morph() takes when none is given: the core's default, the field method, for 3D
    surfaces (its in-betweens are level sets: embedded, and they change from the first frame to the
    last); the skeleton method for 2D polygons, which the field method does not morph."""
    return _DEFAULTS.method.name if dimension == 3 else "skeleton"


def _core_keywords(method: str, test_hold: tuple[str, float] | None, mesher_time_limit: float,
                   field_resolution: float) -> dict:
    """The core's options that morph() passes to _core.morph as keywords: the test hold, the
    mesher's time limit (when set) and the field method's lattice resolution."""
    keywords = dict(hold_stage=str(test_hold[0]), hold_seconds=float(test_hold[1])) if test_hold else {}
    if mesher_time_limit:
        keywords["mesher_time_limit"] = float(mesher_time_limit)
    if method == "field":
        keywords["field_resolution"] = float(field_resolution)
    return keywords


def _check_looks(dimension: int, source, target, source_look, target_look) -> None:
    """InputError where UV maps or materials come with 2D inputs, or do not fit their mesh."""
    if dimension != 3:
        raise InputError("UV maps and materials are carried onto 3D morphs (triangle meshes) only")
    for name, mesh, look in (("source", source, source_look), ("target", target, target_look)):
        check_surface_attributes(name, mesh, look)


def _check_options(method: str, hole_checks: int, mesher_time_limit: float, fill: str, perturbation: str,
                   field_resolution: float) -> None:
    """InputError naming the first of morph()'s options that is not one it takes."""
    if method not in METHODS:
        raise InputError(f"unknown morph method {method!r}: available are {', '.join(METHODS)}")
    if isinstance(hole_checks, bool) or int(hole_checks) != hole_checks or hole_checks < 0:
        raise InputError(f"hole_checks must be a non-negative integer, got {hole_checks!r}")
    if isinstance(mesher_time_limit, bool) or not (float(mesher_time_limit) >= 0):
        raise InputError(f"mesher_time_limit must be a number of seconds >= 0, got {mesher_time_limit!r}")
    if isinstance(field_resolution, bool) or not isinstance(field_resolution, numbers.Real) or \
            not (float(field_resolution) >= 2):
        raise InputError(f"field_resolution must be a number of lattice cells >= 2, got {field_resolution!r}")
    if fill not in FILLS:
        raise InputError(f"unknown fill {fill!r}: use one of {', '.join(FILLS)}")
    if perturbation not in PERTURBATIONS:
        raise InputError(f"unknown perturbation {perturbation!r}: use one of {', '.join(PERTURBATIONS)}")


def _input_arrays(source, target) -> list[np.ndarray]:
    """[source vertices, source faces, target vertices, target faces] as the core takes them;
    ValueError naming the input whose arrays have the wrong shape or type."""
    arrays = []
    for name, (v, f) in (("source", source), ("target", target)):
        v = np.ascontiguousarray(v, dtype=np.float64)
        f = np.asarray(f)
        if v.ndim != 2 or v.shape[1] not in (2, 3):
            raise InputError(f"the {name}'s vertices must be (k, 3) or (k, 2), got shape {v.shape}")
        if f.ndim != 2 or f.shape[1] != v.shape[1] or (f.size and not np.issubdtype(f.dtype, np.integer)):
            raise InputError(f"the {name}'s faces must be integer (l, {v.shape[1]}), got {f.dtype} {f.shape}")
        arrays += [v, _canonical_faces(as_indices(f, f"the {name}'s faces"))]
    return arrays


def _seed_morph(arrays: list[np.ndarray], t0: float, t1: float, method: str, progress, max_push: float, fill: str,
                hole_checks: int, perturbation: str, interrupted, fan_flat_polygons: bool,
                hold: dict) -> AnimationManifold:
    """The seed's methods (see morph()), with the perturbation retry."""
    if progress is not None:  # a retry (below) starts its stages again: the fraction never goes back
        user_progress, done = progress, [0.0]

        def progress(stage: str, fraction: float) -> bool:
            done[0] = max(done[0], float(fraction))
            return user_progress(stage, done[0])

    for name, v, f in (("source", *arrays[:2]), ("target", *arrays[2:])):  # what the core refuses, before the holes
        _core.check_morph_input(v, f, name)
    shared = _shared_holes_first(arrays, progress, interrupted)  # its seconds are in every report's "holes"
    start = time.perf_counter()
    once = dict(t0=float(t0), t1=float(t1), method=method, progress=progress, max_push=float(max_push),
                fill=fill, hole_checks=int(hole_checks), interrupted=interrupted,
                fan_flat_polygons=bool(fan_flat_polygons), hold=hold, shared=shared)
    mode = "position" if perturbation == "position" else "hull_faces"
    try:
        manifold = _morph_once(arrays, perturbation=mode, **once)
    except RuntimeError as e:  # a mesher or the fill refused the hulls' exact points: the plain perturbation
        # (a cancel is no RuntimeError; a time limit hit is the machine's speed, not the input's verdict)
        if perturbation != "auto" or isinstance(e, (BooleanError, _core.TimeLimitError)):
            raise
        failed_seconds = time.perf_counter() - start
        manifold = _morph_once(arrays, perturbation="position", **once)
        manifold.validity["perturbation_mode"] = "position"
        manifold.validity["perturbation_retried"] = True
        manifold.validity["stage_seconds"].insert(0, [f"hull points in place (failed: {e})", failed_seconds])
        return manifold
    manifold.validity["perturbation_mode"] = mode
    first = manifold.validity
    if perturbation != "auto" or not (first["frames_cross_themselves"]
                                      or first["largest_bubble_fraction"] > RETRY_BUBBLE_FRACTION):
        return manifold
    # Frames that run through themselves come from cells of the fill flat at the exact coordinates;
    # keeping the hulls' points exact avoids most (a voxel model's flat sides, collinear points along
    # its hull edges, Blender's primitives), and the plain perturbation is the second opinion.
    # Once more with every point perturbed, and the better of the two is kept: fewer crossing
    # frames, then a smaller largest bubble.
    first_seconds = time.perf_counter() - start
    try:
        retry = _morph_once(arrays, perturbation="position", **once)
    except _core.TimeLimitError:  # not a refusal: keeping the first would depend on the machine's speed
        raise
    except (RuntimeError, ValueError):  # a mesher or the fill refused it: keep the first
        first["stage_seconds"].append(["retry, every point perturbed (failed)", time.perf_counter() - start - first_seconds])
        first["perturbation_retried"] = True
        return manifold
    second = retry.validity

    def flaws(report: dict) -> tuple[int, float]:
        return len(report["crossing_frames"]), report["largest_bubble_fraction"]

    if (second["ends_reproduced"] and second["inverted_simplices"] == 0 and flaws(second) < flaws(first)
            and retry.check().is_oriented_manifold):
        second["perturbation_mode"] = "position"
        why = "frames crossed" if first["frames_cross_themselves"] else "bubbles"
        second["stage_seconds"].insert(0, [f"first perturbation ({why})", first_seconds])
        manifold = retry
    else:  # its time still counts
        first["stage_seconds"].append(["retry, every point perturbed (not kept)", time.perf_counter() - start - first_seconds])
    manifold.validity["perturbation_retried"] = True
    return manifold


PERTURBATIONS = ("auto", *_core.Perturbation.__members__)
# Bubbles smaller than this share of a frame's volume are reported but not worth a second morph;
# near zero, whether a checked frame holds one at all can come down to rounding, and the choice of
# perturbation should not.
RETRY_BUBBLE_FRACTION = 1e-4


def _canonical_faces(faces: np.ndarray) -> np.ndarray:
    """The same faces in an order that depends on the faces only: each triangle turned to start at
    its smallest vertex (its orientation kept), then all sorted. The mesher's and the fill's
    choices follow the order of their input, and Blender hands out the same mesh's triangles in
    different orders from one session to the next: a morph of the same objects came out with 3,109
    tets in one and 3,111 in another."""
    if faces.shape[1] == 3 and len(faces):
        start = np.argmin(faces, axis=1)
        rows = np.arange(len(faces))
        faces = np.stack([faces[rows, (start + k) % 3] for k in range(3)], axis=1)
    return np.ascontiguousarray(faces[np.lexsort(faces.T[::-1])], dtype=np.int32)


# The way out, said where a hole space cannot be computed (API, CLI, Morph Selected).
_FIELD_NEEDS_NO_HOLES = "The field method (method='field', --method field, Method: Field) needs no hole space."


class _SharedHoles:
    """H_S ∩ H_T, computed once before the morph (seconds, where the morph takes minutes, and the
    same for every retry), or why CGAL could not compute it."""

    def __init__(self, solid: tuple[np.ndarray, np.ndarray] | None, error: BooleanError | None, seconds: float):
        self.solid, self.error, self.seconds = solid, error, seconds


def _shared_holes_first(arrays: list[np.ndarray], progress, interrupted) -> _SharedHoles:
    """The shared hole space, before the morph runs. When CGAL cannot compute it, the morph stops
    here with that error, unless source and target are the same mesh: then every frame is the input
    and no frame can enter a hole space, so none is needed (checked again against the core's
    `inputs_coincide`)."""
    start = time.perf_counter()
    try:
        solid, error = _shared_hole_space(arrays, interrupted), None
    except BooleanError as e:
        if not _same_mesh(arrays):
            raise BooleanError(f"{e}. {_FIELD_NEEDS_NO_HOLES}") from None
        solid, error = None, e
    _stage_finished(progress, "holes", 0.0)
    return _SharedHoles(solid, error, time.perf_counter() - start)


def _same_mesh(arrays: list[np.ndarray]) -> bool:
    """Source and target are the same mesh (faces already in canonical order)."""
    return np.array_equal(arrays[0], arrays[2]) and np.array_equal(arrays[1], arrays[3])


def _stage_finished(progress, stage: str, fraction: float) -> None:
    """Tells `progress` that `stage` has finished; raises Cancelled when it answers False."""
    if progress is not None and not progress(stage, fraction):
        raise _core.Cancelled("cancelled")


def _check_interrupted(interrupted) -> None:
    """Raises Cancelled when the caller's `interrupted()` says so (between checked frames)."""
    if interrupted is not None and interrupted():
        raise _core.Cancelled("cancelled")


def _morph_once(arrays: list[np.ndarray], t0: float, t1: float, method: str, progress, max_push: float,
                fill: str, hole_checks: int, perturbation: str, interrupted: Callable[[], bool] | None,
                fan_flat_polygons: bool, hold: dict, shared: _SharedHoles) -> AnimationManifold:
    """One morph with the core's `perturbation` (see morph()), cut by the `shared` hole space."""
    complex_, report = _core.morph(*arrays, t0=t0, t1=t1, method=method, progress=progress,
                                   max_push=max_push, fill=fill, perturbation=perturbation,
                                   interrupted=interrupted, fan_flat_polygons=fan_flat_polygons, **hold)
    report = _plain_report(report)
    core_checked = arrays[0].shape[1] == 3  # the core checked the frames (morph_validity.hpp); 2D: below
    if not core_checked:
        for key in _CORE_FRAME_CHECKS:
            report.pop(key, None)

    report["stage_seconds"].append(["holes", shared.seconds])
    # Where the inputs coincide everywhere, every frame is the input (the fill is
    # the product of the two, what lies outside both removed): no frame enters the
    # shared hole space, and cutting frames that lie on its walls would only meet
    # rounding (report: inputs_coincide).
    coincide = bool(report.get("inputs_coincide"))
    if shared.error is not None and not coincide:
        raise BooleanError(f"{shared.error}. {_FIELD_NEEDS_NO_HOLES}")
    cut = None if coincide or is_empty(shared.solid) else shared.solid
    manifold = AnimationManifold(complex_, metadata={"morph": {"method": method, "fill": fill, "t0": float(t0),
                                                               "t1": float(t1)},
                                                     "validity": report},
                                 hole_space=cut)
    start = time.perf_counter()
    report.update(_hole_validity(manifold, float(t0), float(t1), int(hole_checks), interrupted))
    if coincide and shared.solid is not None:
        report["shared_hole_volume"] = solid_measure(*shared.solid)
    if shared.error is not None:
        report["hole_errors"].append(f"no hole space: {shared.error} (none is needed: the inputs coincide)")
    if core_checked:
        report.update(_core_frame_checks(report))
    else:
        report.update(_crossing_validity(manifold, float(t0), float(t1), int(hole_checks),
                                         functools.partial(_check_interrupted, interrupted)))
        report.update({"bubble_frames": [], "bubble_frames_checked": 0, "largest_bubble_fraction": 0.0})  # 2D
    report["stage_seconds"].append(["hole validity", time.perf_counter() - start])
    _stage_finished(progress, "hole validity", 1.0)
    return manifold


def _check_cut_frame(t: float, raw: tuple[np.ndarray, np.ndarray], cut: tuple[np.ndarray, np.ndarray],
                     report: dict) -> None:
    """The frame the user gets (cut by the hole space) looked at as the raw frames are: whether the
    boolean's slivers make it run through itself (`cut_crossing_frames`), and [t, pieces, cavities]
    of the raw frame and then of the cut one where the cut changes them (`cut_frame_pieces`, 3D)."""
    size = float(np.linalg.norm(np.ptp(raw[0], axis=0))) if len(raw[0]) else 0.0
    try:
        if len(cut[1]) and _core.self_intersections(*cut, 1, CROSSING_TOLERANCE * size):
            report["cut_crossing_frames"].append(t)
    except ValueError:  # the cut frame is not a manifold surface
        report["cut_crossing_frames"].append(t)

    def shells(frame) -> tuple[int, int]:
        volumes = shell_volumes(*frame) if len(frame[1]) else np.zeros(0)
        return int((volumes > 0).sum()), int((volumes < 0).sum())

    if raw[1].shape[1] != 3:  # 2D frames are polygons: no shells
        return
    before, after = shells(raw), shells(cut)
    if before != after:
        report["cut_frame_pieces"].append([t, *before, *after])


def cut_frame_warnings(report: dict) -> list[str]:
    """What the checks of the hole-cut frames found, as sentences (for the CLI and Morph Selected)."""
    lines = []
    if report.get("cut_crossing_frames"):
        lines.append("frames cut by the shared holes run through themselves (slivers of the boolean) at times "
                     + ", ".join(f"{t:.3g}" for t in report["cut_crossing_frames"]))
    if report.get("cut_frame_pieces"):
        lines.append("cutting the shared holes changes the frames' pieces (time: pieces+cavities before -> after) "
                     + ", ".join(f"{t:.3g}: {p0}+{c0} -> {p1}+{c1}" for t, p0, c0, p1, c1 in report["cut_frame_pieces"]))
    return lines


# Report keys of the core's frame checks (morph_validity.hpp), which it runs on 3D morphs only.
_CORE_FRAME_CHECKS = ("frames_checked", "frames_capped", "topology_changes", "noise_frames")


def _core_frame_checks(report: dict) -> dict:
    """The crossing and bubble entries of the report, from the core's frame checks (24 frames spread
    over the range and towards every change of topology). Crossings: on `crossing_frames_checked` of
    the spread frames; for the field method, when `crossings_certified`, its space-time
    triangulation is embedded, so no frame at any time runs through itself, and the middle frame confirms it."""
    return {"frames_cross_themselves": bool(report["crossing_frames"]),
            "bubble_frames_checked": report["frames_checked"]}


def _plain_report(report) -> dict:
    """The core's MorphReport as a dict of lists (as the cache's JSON gives them back)."""
    return {k: ([list(item) for item in v] if k in ("stage_seconds", "bubble_frames") else
                list(v) if isinstance(v, tuple) else v) for k, v in report.to_dict().items()}


def _field_morph(arrays: list[np.ndarray], t0: float, t1: float, progress, interrupted, hold: dict) -> AnimationManifold:
    """The field method (see morph()): the core builds and checks it; no hole space is cut."""
    complex_, report = _core.morph(*arrays, t0=t0, t1=t1, method="field", progress=progress,
                                   interrupted=interrupted, **hold)
    report = _plain_report(report)
    report.update(_core_frame_checks(report))
    return AnimationManifold(complex_, metadata={"morph": {"method": "field", "t0": t0, "t1": t1},
                                                 "validity": report})


def _shared_hole_space(arrays: list[np.ndarray], interrupted) -> tuple[np.ndarray, np.ndarray]:
    """H_S ∩ H_T, or a BooleanError that says which input CGAL refused."""
    spaces = []
    for name, (v, f) in (("source", arrays[:2]), ("target", arrays[2:])):
        try:
            spaces.append(hole_space(v, f, interrupted=interrupted))
        except BooleanError as e:
            raise BooleanError(f"the hole space of the {name} cannot be computed: {e}") from None
        if is_empty(spaces[-1]):  # a convex input: nothing is shared (the other's boolean is not needed)
            return spaces[-1]
    try:
        return intersect_solids(*spaces, interrupted=interrupted)
    except BooleanError as e:
        raise BooleanError(f"the holes the source and target share cannot be computed: {e}") from None


# Faces of a frame that pass through each other by less than this share of the manifold's size
# (the diagonal of its bounding box in space) are rounding, not crossing: its coordinates are
# rounded, and next to cells flat to rounding (inputs with exactly coplanar or cocircular points:
# a torus's rings, an icosphere's) the exact test finds neighbours crossing by ~1e-16 of the size.
# The same share bounds how far the ends may be from the inputs (validity 2).
CROSSING_TOLERANCE = 1e-9


def _crossing_validity(manifold: AnimationManifold, t0: float, t1: float, checks: int,
                       poll: Callable[[], None]) -> dict:
    """Validity 1 beyond positive simplices: the raw frames at `checks` times strictly inside (t0, t1)
    do not run through themselves (by more than CROSSING_TOLERANCE of the size). Positive simplices rule out local folds only; the push can still
    let a part of the boundary pass through another (seen where free vertices lie on the convex
    hull of an input whose hull is larger than the other's)."""
    crossing = []
    low, high = manifold.bounding_box
    tolerance = CROSSING_TOLERANCE * float(np.linalg.norm((high - low)[:-1]))
    for t in t0 + (t1 - t0) * np.arange(1, checks + 1) / (checks + 1):
        poll()
        frame = manifold.slice(float(t), honour_holes=False)
        try:
            if _core.self_intersections(frame.vertices, frame.faces, 1, tolerance):
                crossing.append(float(t))
        except ValueError:  # not even a manifold there (the strip method's pinches)
            crossing.append(float(t))
    return {"crossing_frames_checked": checks, "crossing_frames": crossing, "frames_cross_themselves": bool(crossing)}


def _hole_validity(manifold: AnimationManifold, t0: float, t1: float, checks: int,
                   interrupted: Callable[[], bool] | None) -> dict:
    """Validity 3 on `checks` frames evenly spaced strictly inside (t0, t1); `interrupted()`, polled
    before each frame and while CGAL cuts it, stops the checks with Cancelled."""
    poll = functools.partial(_check_interrupted, interrupted)
    hole = manifold.hole_space
    report = {"shared_hole_volume": 0.0, "hole_overlap_volume": 0.0, "holes_preserved": True,
              "hole_frames_checked": 0, "hole_frames_verified": 0, "hole_errors": [],
              "cut_crossing_frames": [], "cut_frame_pieces": []}
    if hole is None:
        return report
    volume = solid_measure(*hole)
    report["shared_hole_volume"] = volume
    samples = points_inside(*hole, depth=1e-6 * float(np.linalg.norm(np.ptp(hole[0], axis=0))))
    for t in t0 + (t1 - t0) * np.arange(1, checks + 1) / (checks + 1):
        poll()
        raw = manifold.slice(float(t), honour_holes=False)
        frame = (raw.vertices, raw.faces)
        report["hole_frames_checked"] += 1
        try:
            cut = subtract_solid(frame, hole, interrupted=interrupted)
        except (RuntimeError, ValueError) as e:
            report["holes_preserved"] = False
            report["hole_errors"].append(f"t={float(t):g}: the frame cannot be cut: {e}")
            continue
        _check_cut_frame(float(t), frame, cut, report)
        # raw = (raw \ H) + (raw ∩ H): what the cut removed is the overlap.
        overlap = solid_measure(*frame) - solid_measure(*cut)
        report["hole_overlap_volume"] = max(report["hole_overlap_volume"], overlap / volume)
        # Independently: no point inside H lies inside the cut frame (an exact side test). An
        # intersection by CGAL is no check here: where H lies inside the frame, the cut's cavity
        # is H's own boundary, and booleans of coincident surfaces are degenerate.
        report["hole_frames_verified"] += 1
        inside = inside_solid(*cut, samples)
        if inside.any():
            report["holes_preserved"] = False
            report["hole_errors"].append(f"t={float(t):g}: {int(inside.sum())} of {len(samples)} points inside the "
                                         "hole space lie inside the cut frame")
    return report
