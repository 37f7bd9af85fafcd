"""Playback: showing a manifold object's frame in its mesh, with as little work per frame
as its settings allow. Three strategies, chosen per frame by update_object:

* driven (Blender 4.2+, time axis, plain slices: can_drive): inside a topology interval
  the interval's cut is written once with the rate of every vertex, and the "Animanifold
  Live" geometry-nodes modifier (live_nodes) moves the vertices (and rebuilds the UV map)
  with the scene frame; on integer frames the frame kept per interval (am.cut_cache) is
  copied into the mesh's positions and UV map instead, and the modifier passes it
  through. At a vertex time (a keyframe) the frame is written as sliced. Cuts and frames
  are kept between visits (live_registry), so looping playback slices nothing and Blender
  computes no edges; for prism frames they are made ahead, on the first frame played
  (am.cut_prefetch).
* moved (sweep views, custom normals, older Blender): the first frame of an interval is
  cut and written in full, the next ones slide its vertices along their manifold edges
  (am.IntervalFrame), rewriting positions, UVs and normals.
* full (frames refined by OpenSubdiv, which are not on manifold edges): every frame is
  sliced, refined and written in full.

The user, renders and exports see the evaluated mesh; obj.data holds the last frame
written (for a driven interval, the last integer frame shown or the cut's frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import bpy
import numpy as np

from . import extra_layers, live_nodes, mesh_writer
from ._lib import am
from .live_registry import registry
from .object_manifold import frame_slice, shown_manifold, slice_value


@dataclass
class Shown:
    """What an object's mesh holds after a full write: the frame `value`, and for
    a cut of a topology interval either its am.IntervalFrame, from which the
    handler writes later frames, or, when `driven`, nothing to do: the live
    modifier moves them."""

    key: tuple
    interval: tuple | None
    interval_frame: object  # am.IntervalFrame of the written cut (handler-moved intervals)
    corner_vertex: np.ndarray | None  # the corners as written (for the UV layer)
    counts: tuple  # (vertices, faces) of the mesh as written
    value: float = math.nan
    driven: bool = False
    cut: am.interval_cuts.Cut | None = None  # driven: the cut written
    mesh_value: float = math.nan  # driven: the frame the mesh's positions and UV map hold


# A custom property every live object carries, for whoever opens the file without the
# add-on (Object Properties > Custom Properties): the mesh holds one frame only. Blender
# 4.2+ also shows live_nodes.WARNING in the viewport at other frames.
NOTE_KEY = "animanifold_note"
NOTE = ("live animanifold object: its mesh follows the scene frame only with the animanifold add-on "
        "enabled; bake it (Animanifold > Bake) to play without the add-on")


def _counts(mesh) -> tuple[int, int]:
    return len(mesh.vertices), len(mesh.polygons)


def can_drive(obj, scene=None) -> bool:
    """Whether the live modifier can play `obj`: Blender 4.2+, the time axis, frames
    that are plain slices (no frame smoothing, no custom normals to carry), the
    modifier not switched off by the user, and a scene whose Scene Time is its
    frame (no Time Stretching)."""
    settings = obj.animanifold
    if not (live_nodes.SUPPORTED and settings.axis == "t" and settings.smooth_levels <= 0
            and (live_nodes.NORMALS_SUPPORTED or not settings.live_normals) and live_nodes.usable(obj)):
        return False
    return _time_is_frame(scene)


def _time_is_frame(scene) -> bool:
    """Whether the scene's Scene Time (the modifier's clock) is its frame: no Time Stretching."""
    scene = scene if scene is not None else bpy.context.scene
    return scene is None or scene.render.frame_map_old == scene.render.frame_map_new


def update_object(obj, frame: float, force: bool = True, scene=None) -> None:
    """Shows the object's slice at `frame` (or its sweep value).

    Between two vertex times (two keyframes, for a converted action) every
    frame has the same faces. Where the live modifier can play the object
    (can_drive), the first frame there writes the interval's cut with the
    rate of every vertex; on later integer frames the handler copies the kept
    frame into the mesh, and on other frames the modifier moves the vertices
    (and rebuilds the UV map) with the scene frame. Elsewhere the first frame is cut and
    written in full and the next ones slide the vertices along their manifold
    edges (AnimationManifold.interval_frame), rewriting positions, UVs and normals.
    Frames refined by OpenSubdiv (smooth_levels > 0) are not on manifold
    edges: each is cut, refined and written in full.

    `force=False` (frame changes) skips the write when the mesh already shows
    this frame; other callers (settings, operators) always rewrite, since they
    may have changed the mesh or the manifold."""
    settings = obj.animanifold
    if obj.get(NOTE_KEY) != NOTE:
        obj[NOTE_KEY] = NOTE
    manifold = shown_manifold(obj)
    value = slice_value(obj, manifold, frame)
    mesh = obj.data
    smoothed = settings.smooth_levels > 0
    normals_wanted = settings.axis == "t" and settings.live_normals
    key = (id(manifold), mesh.as_pointer(), settings.axis, settings.time_scale, normals_wanted, settings.uv_name,
           settings.subdivision_levels, settings.keep_keyframe_times, settings.smooth_levels, settings.crease_angle)
    shown = registry.shown(obj)
    if shown is not None and (shown.key != key or shown.counts != _counts(mesh)):
        shown = None  # another mesh, manifold or setting, or the mesh was edited
    # The live modifier rebuilds the active UV map only: a manifold carrying more UV maps
    # or colours (extra_layers) is played by the handler, which rewrites them all.
    extra = extra_layers.carried(manifold.vertex_attributes)
    if not extra and can_drive(obj, scene):
        if registry.first_played(manifold):
            _prefetch(obj, manifold, scene or bpy.context.scene, frame)
        _update_driven(obj, manifold, value, key, None if force else shown)
        return

    if not force and shown is not None and shown.value == value and not shown.driven:
        return  # a sweep view (or a vertex time) on a frame change: nothing moved
    # Sweeps are right at any frame; with Time Stretching the modifier's clock is not the frame.
    timed = settings.axis == "t" and _time_is_frame(scene)
    live_nodes.release(obj, _shown_range(manifold, value) if timed else None)
    interval = None if smoothed else manifold.topology_interval(value, settings.axis)
    carried = ["uv"] + extra + (["normal"] if normals_wanted else [])
    if (shown is not None and interval is not None and shown.interval == interval
            and shown.interval_frame is not None):
        s = shown.interval_frame.at(value, attributes=carried, normals=False)
        positions = am.display.display_vertices(manifold, s, settings.axis, settings.time_scale)
        mesh_writer.write_positions(mesh, positions, shown.corner_vertex, uv=s.vertex_attributes.get("uv"),
                                    uv_name=settings.uv_name or "UVMap",
                                    normals=am.display.slice_normals(s) if normals_wanted else None,
                                    extra=s.vertex_attributes if extra else None)
        shown.value = value
        return

    registry.forget_shown_of(obj)  # until the write is done, the mesh shows nothing known
    moving = None if interval is None else manifold.interval_frame(value, settings.axis)
    s = frame_slice(obj, manifold, value, settings.axis) if moving is None else moving.slice
    uv = s.vertex_attributes.get("uv")
    faces = s.faces
    if settings.axis == "y":  # (x, z, t) shown as (x, t, z): an odd permutation, keep faces outward
        faces = faces[:, ::-1]
    mesh_writer.write_mesh(
        mesh,
        am.display.display_vertices(manifold, s, settings.axis, settings.time_scale),
        faces,
        uv=uv,
        uv_name=settings.uv_name or "UVMap",
        material_index=s.face_attributes.get("material_index"),
        smooth=s.face_attributes.get("smooth"),
        normals=am.display.frame_normals(s, smoothed) if normals_wanted else None,
        extra=s.vertex_attributes if extra else None,
    )
    registry.set_shown(obj, Shown(key, interval, moving, np.ascontiguousarray(faces, dtype=np.int32).reshape(-1),
                                  _counts(mesh), value))


def _update_driven(obj, manifold, value: float, key: tuple, shown: Shown | None) -> None:
    """update_object where the live modifier plays the intervals (see can_drive)."""
    mesh = obj.data
    interval = manifold.topology_interval(value, "t")
    if shown is not None:
        if interval is None:
            if shown.interval is None and shown.value == value and not _has_rates(mesh):
                return  # this vertex time is shown
        elif (shown.driven and shown.interval == interval and _has_rates(mesh)
              and live_nodes.drives(obj, *interval, frame=shown.mesh_value, cut_frame=shown.cut.value)):
            # The O(1) path of playback: the modifier moves the mesh, or on an integer
            # frame the kept frame is copied in.
            if _show_frame(obj, manifold, shown, value):
                return
    registry.forget_shown_of(obj)  # until the write is done, the mesh shows nothing known
    if interval is None:  # a vertex time (a keyframe): the frame as sliced, the modifier off
        cut_key = ("at", value)
        cut = _cut(manifold, cut_key, lambda: am.interval_cuts.time_cut(manifold, value)[1])
        vectors = None
        vertices, corner_uv, mesh_value = cut.vertices, cut.corner_uv, value
    else:
        cut_key = interval
        cut = _cut(manifold, cut_key, lambda: am.interval_cuts.time_cut(manifold, value)[1])
        vectors = {live_nodes.RATE: cut.rate}
        if cut.uv_rate is not None:
            vectors[live_nodes.UV] = cut.uv
            vectors[live_nodes.UV_RATE] = cut.uv_rate
        # The mesh holds this frame if it is kept (the modifier passes it through), else
        # the cut's frame (the modifier moves it).
        frame = _frame(manifold, cut_key, cut, value) or am.interval_cuts.interval_frame(cut, cut.value)
        vertices, corner_uv, mesh_value = frame.positions.reshape(-1, 3), frame.corner_uv, frame.value
    uv_name = obj.animanifold.uv_name or "UVMap"
    normals = obj.animanifold.live_normals and cut.normal is not None
    if normals and vectors is not None:
        vectors[live_nodes.NORMAL] = cut.normal
        vectors[live_nodes.NORMAL_RATE] = cut.normal_rate
    kept_topology = mesh_writer.write_mesh(
        mesh, vertices, cut.faces, uv_name=uv_name, corner_uv=corner_uv, material_index=cut.material_index,
        smooth=cut.smooth, edges=cut.edges, vectors=vectors,
        normals=_unit(cut.normal) if normals and vectors is None else None, owner=obj)
    # A cut written over the faces the mesh held (frames of an animation that keeps its
    # faces) made no edges: reading them back would cost more than the write.
    if cut.edges is None and not kept_topology:
        cut.edges = mesh_writer.mesh_edges(mesh)
        registry.cuts.resized(manifold, cut_key)
    if interval is None:
        live_nodes.release(obj, _shown_range(manifold, value))
    else:
        live_nodes.drive(obj, mesh_value, cut.value, interval[0], interval[1],
                         uv_name if cut.uv_rate is not None else None, normals=normals)
    registry.set_shown(obj, Shown(key, interval, None, None, _counts(mesh), value, driven=interval is not None,
                                  cut=cut if interval is not None else None, mesh_value=mesh_value))


def _prefetch(obj, manifold, scene, frame: float) -> None:
    """Makes the cuts and kept frames of the scene's frame range ahead (am.cut_prefetch),
    from `frame` on, then the frames before it (playback's order)."""
    frames = list(range(scene.frame_start, scene.frame_end + 1))
    start = next((i for i, f in enumerate(frames) if f >= frame), 0)
    values = [slice_value(obj, manifold, f) for f in frames[start:] + frames[:start]]
    am.cut_prefetch.prefetch(manifold, values, registry.cuts)


def _shown_range(manifold, value: float) -> tuple[float, float]:
    """The scene frames at which the time slice at `value` is the right frame: that one,
    and before the manifold's first time or after its last all frames that hold it."""
    t0, t1 = manifold.time_range
    return (-live_nodes.ALWAYS if value <= t0 else value), (live_nodes.ALWAYS if value >= t1 else value)


def _unit(normals: np.ndarray) -> np.ndarray:
    """Normals of unit length, as the bake sets them (am.display.slice_normals)."""
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals / np.where(length > 0, length, 1.0)


def _has_rates(mesh) -> bool:
    """Whether the mesh holds an interval cut's rates. By name among the keys: `name in
    mesh.attributes` looks the layer up for writing, which copies it when the
    evaluated mesh shares it (every frame after a copied frame), several times the
    cost of listing the keys."""
    return live_nodes.RATE in mesh.attributes.keys()


def _frame(manifold, key, cut: am.interval_cuts.Cut, value: float) -> am.interval_cuts.Frame | None:
    """Interval cut `cut` (kept as `key`) at integer frame `value`: kept from an
    earlier visit, or computed now and kept if the frame budget has room; None for
    other frames, or when it has none (the modifier moves those)."""
    if value != math.floor(value):
        return None
    if value == cut.value:
        return am.interval_cuts.interval_frame(cut, value)  # the cut's own arrays: nothing to keep
    frame = registry.cuts.frame(manifold, key, value)
    if frame is not None:
        return frame
    # Computed only to be kept: one that could not be would cost a gather over every
    # corner on each visit, more than the modifier's work.
    if (registry.cuts.get(manifold, key) is not cut
            or not registry.cuts.frame_room(manifold, key, am.interval_cuts.frame_nbytes(cut))):
        return None
    frame = am.interval_cuts.interval_frame(cut, value)
    return frame if registry.cuts.keep_frame(manifold, key, frame) else None


def _show_frame(obj, manifold, shown: Shown, value: float) -> bool:
    """On a frame change inside the driven interval: copies the kept frame of an
    integer frame into the mesh (and tells the modifier); other frames write
    nothing (the modifier moves the mesh to them). False if the mesh is not as
    written (the caller writes the cut again)."""
    if shown.mesh_value == value:
        return True  # shown (the post-frame handler, a repeated frame)
    frame = _frame(manifold, shown.interval, shown.cut, value)
    if frame is None:
        return True  # the modifier moves the mesh from the frame it holds
    if not mesh_writer.write_frame(obj.data, obj.animanifold.uv_name or "UVMap", frame):
        return False
    live_nodes.set_frame(obj, value)
    shown.mesh_value = value
    return True


def _cut(manifold, key, make) -> am.interval_cuts.Cut:
    cut = registry.cuts.get(manifold, key)
    if cut is None:
        cut = make()
        registry.cuts.put(manifold, key, cut)
    return cut
