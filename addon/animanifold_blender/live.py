"""Slices of manifolds into Blender meshes: the cache registry and mesh writing.

A manifold object stores the path of its cache file (relative to the .blend);
manifolds are loaded once per file version (path, mtime, size) and their slicer
kept, so a frame costs one slice plus one mesh rewrite (numpy + foreach_set).
The mesh data block of the object is rewritten in place: scrubbing creates no
data blocks.

Smoothing (the object's Smooth settings): the shown manifold is the loaded one
subdivided `subdivision_levels` times (Schaefer et al.), computed once per
(loaded manifold, levels, keep_keyframe_times) and kept beside it; each frame
is its slice refined `smooth_levels` times by OpenSubdiv. Bakes slice through
the same functions (frame_slice, frame_normals), so they bake what plays live.

Playback inside a topology interval (Blender 4.2+, time axis, no smoothing or
custom normals): the interval's cut is written once with the rate of every
vertex, and the "Animanifold Live" geometry-nodes modifier (live_nodes) moves
the vertices (and rebuilds the UV map) with the scene frame. On integer frames
the handler instead copies the frame, kept per frame (live_cuts), into the
mesh's positions and UV map (two copies, no other work) and the modifier passes
it through. The user, renders and exports see the evaluated mesh; obj.data holds
the last integer frame shown (or the interval's middle). Cuts and frames are
kept between visits, so looping playback slices nothing and Blender computes no
edges.
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass

import bpy
import numpy as np

from . import live_cuts, live_nodes
from ._lib import am

AXES = ("t", "x", "y", "z")
_CACHE: dict[str, tuple[tuple[int, int], object]] = {}
_ERRORS: dict[str, str] = {}


class SmoothingError(am.Error, RuntimeError):
    """Subdivision of a manifold object's manifold failed or would not fit in memory."""


@dataclass
class _Subdivided:
    """The subdivisions of one loaded manifold (`base`), by (levels, keep_keyframe_times);
    `failed` keeps the message of a subdivision that failed, so that playback does not
    retry it on every frame (a settings change clears it)."""

    base: object
    manifolds: dict
    failed: dict


_SUBDIVIDED: dict[str, _Subdivided] = {}
# Peak memory of one subdivision, per output tet (measured ~45 bytes: points, tets,
# attributes, the intermediate level); with room for the slicer's index built later.
BYTES_PER_TET = 100
# The panel warns from this many shown tets on (slower slicing, more memory).
LARGE_TETS = 2_000_000


def clear():
    _CACHE.clear()
    _ERRORS.clear()
    _SHOWN.clear()
    _CHECKED.clear()
    _SUBDIVIDED.clear()
    _CUTS.clear()


def forget_shown():
    """Next frame changes write every object in full (after undo/redo)."""
    _SHOWN.clear()
    _CHECKED.clear()


def last_error(obj) -> str | None:
    return _ERRORS.get(obj.name_full)


def cache_abspath(obj) -> str:
    path = obj.animanifold.cache_path
    if not path:
        raise am.CacheError(f"'{obj.name}' has no manifold cache path")
    return os.path.normpath(bpy.path.abspath(path, library=obj.library))


def manifold_for(obj):
    """The manifold of a manifold object, loaded (and validated) once per file version."""
    path = cache_abspath(obj)
    try:
        st = os.stat(path)
    except OSError:
        raise am.CacheError(f"cache file {path} of '{obj.name}' does not exist") from None
    stamp = (st.st_mtime_ns, st.st_size)
    hit = _CACHE.get(path)
    if hit is not None and hit[0] == stamp:
        return hit[1]
    manifold = am.load(path)
    _CACHE[path] = (stamp, manifold)
    return manifold


def remember(path: str, manifold) -> None:
    """Registers a manifold just written to `path` (saves reloading it)."""
    path = os.path.normpath(path)
    st = os.stat(path)
    _CACHE[path] = ((st.st_mtime_ns, st.st_size), manifold)
    _SUBDIVIDED.pop(path, None)


def forget(path: str) -> None:
    path = os.path.normpath(path)
    _CACHE.pop(path, None)
    _SUBDIVIDED.pop(path, None)


def loaded_manifold(obj):
    """The manifold of `obj` if it is loaded already (no file access; for the panel)."""
    try:
        hit = _CACHE.get(cache_abspath(obj))
    except Exception:  # no path, bad path: the panel shows nothing
        return None
    return None if hit is None else hit[1]


def subdivided_tets(manifold, levels: int) -> int:
    """Simplices after `levels` of subdivision: each level splits a tet into 8
    (a triangle of a 2D animation into 4)."""
    return len(manifold.simplices) * (2 ** (manifold.dimension - 1)) ** int(levels)


def _available_memory() -> int | None:
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # not Linux: no check
        return None


def shown_manifold(obj):
    """The manifold whose slices `obj` shows: its cache's manifold, subdivided as its
    Smooth settings say. Each subdivision is computed once per loaded manifold and
    kept; a failure (or a result that would not fit in memory) raises SmoothingError
    and is remembered until a setting changes."""
    base = manifold_for(obj)
    settings = obj.animanifold
    levels = int(settings.subdivision_levels)
    if levels <= 0:
        return base
    path = cache_abspath(obj)
    entry = _SUBDIVIDED.get(path)
    if entry is None or entry.base is not base:  # a new file version: older subdivisions are stale
        entry = _SUBDIVIDED[path] = _Subdivided(base, {}, {})
    key = (levels, bool(settings.keep_keyframe_times))
    manifold = entry.manifolds.get(key)
    if manifold is not None:
        return manifold
    if key in entry.failed:
        raise SmoothingError(entry.failed[key])
    tets = subdivided_tets(base, levels)
    available = _available_memory()
    try:
        if available is not None and tets * BYTES_PER_TET > available // 2:
            raise SmoothingError(
                f"{levels} subdivision levels of '{obj.name}' would make {tets:,} tets "
                f"(~{tets * BYTES_PER_TET / 2**30:.1f} GiB; {available / 2**30:.1f} GiB free): use fewer levels")
        try:
            manifold = base.welded().subdivide(levels=levels, scheme="schaefer",
                                                       keep_keyframe_times=key[1])
        except MemoryError:
            raise SmoothingError(f"out of memory subdividing '{obj.name}' {levels} levels ({tets:,} tets): "
                                 "use fewer levels") from None
        except (ValueError, RuntimeError) as e:
            raise SmoothingError(f"cannot subdivide '{obj.name}': {e}") from e
    except SmoothingError as e:
        entry.failed[key] = str(e)
        raise
    entry.manifolds[key] = manifold
    return manifold


def prune_subdivided() -> None:
    """Drops the subdivisions no manifold object asks for any more (their memory) and
    the remembered failures (a settings change may retry them)."""
    wanted = set()
    for obj in bpy.data.objects:
        settings = getattr(obj, "animanifold", None)
        if settings is None or not settings.is_manifold or settings.subdivision_levels <= 0:
            continue
        try:
            path = cache_abspath(obj)
        except am.CacheError:  # no cache path yet: nothing of its to keep
            continue
        wanted.add((path, int(settings.subdivision_levels), bool(settings.keep_keyframe_times)))
    for path, entry in list(_SUBDIVIDED.items()):
        entry.failed.clear()
        for key in list(entry.manifolds):
            if (path,) + key not in wanted:
                del entry.manifolds[key]
        if not entry.manifolds:
            del _SUBDIVIDED[path]


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
    return am.smooth.smooth_slice(s, int(settings.smooth_levels), math.degrees(settings.crease_angle))


def frame_normals(s, smoothed: bool) -> np.ndarray | None:
    """Custom normals for a frame: None for flat-shaded sources; for smooth-shaded
    ones the source's normals carried along the manifold (slice_normals) or, on a
    frame refined by OpenSubdiv, the normals of its limit surface."""
    if smoothed:
        return s.normals if s.vertex_attributes.get("normal") is not None and len(s.normals) else None
    return slice_normals(s)


_NEEDS_LOOP_TOTAL = bpy.app.version < (3, 6, 0)
_NEEDS_AUTO_SMOOTH = bpy.app.version < (4, 1, 0)
# Blender 4.0+: positions, corner vertices, material indices, sharp faces and UV maps
# are generic attributes with raw (memcpy) foreach access: ~10x faster than the
# MeshVertex/MeshLoop/MeshPolygon RNA paths, which convert item by item.
_ATTRIBUTES = bpy.app.version >= (4, 0, 0)


def write_mesh(mesh, vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray | None = None,
               uv_name: str = "UVMap", material_index: np.ndarray | None = None,
               smooth: np.ndarray | None = None, normals: np.ndarray | None = None,
               edges: tuple | None = None, vectors: dict | None = None,
               corner_uv: np.ndarray | None = None) -> None:
    """Replaces the geometry of `mesh` by triangles (in place, no new data blocks).
    `normals` (P, 3): smooth normals set as custom normals (slices between
    keyframes have thin triangles that shade unevenly with computed normals).
    `edges`: (edge vertices (2E,), corner edges (3F,)) that Blender computed for
    these faces before (mesh_edges), set instead of computing them again.
    `vectors`: name -> (P, 3) float32 point attributes (float vectors) to add (4.0+).
    `corner_uv` (2 * 3F,) float32: the UV map per corner, instead of `uv` per vertex."""
    P, F = len(vertices), len(faces)
    corner_vertex = np.ascontiguousarray(faces, dtype=np.int32).reshape(-1)
    mesh.clear_geometry()
    mesh.vertices.add(P)
    mesh.loops.add(3 * F)
    mesh.polygons.add(F)
    co = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1)
    # loop_start is unsigned in 4.0+: an unsigned array is copied raw (~100x faster
    # than the per-item path a signed one takes).
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * F, 3, dtype=np.uint32 if _ATTRIBUTES else np.int32))
    if _ATTRIBUTES:
        attributes = mesh.attributes
        attributes["position"].data.foreach_set("vector", co)
        attributes[".corner_vert"].data.foreach_set("value", corner_vertex)
        if material_index is not None and F:
            attributes.new("material_index", "INT", "FACE").data.foreach_set(
                "value", np.ascontiguousarray(material_index, dtype=np.int32))
        if smooth is not None and F:
            attributes.new("sharp_face", "BOOLEAN", "FACE").data.foreach_set(
                "value", np.ascontiguousarray(smooth, dtype=np.int32) == 0)
        if uv is not None and corner_uv is None:
            corner_uv = live_cuts.corner_values(uv, corner_vertex)
        if corner_uv is not None:
            attributes.new(uv_name or "UVMap", "FLOAT2", "CORNER").data.foreach_set("vector", corner_uv)
        for name, values in (vectors or {}).items():
            attributes.new(name, "FLOAT_VECTOR", "POINT").data.foreach_set(
                "vector", np.ascontiguousarray(values, dtype=np.float32).reshape(-1))
        if edges is not None and F:
            edge_verts, corner_edge = edges
            mesh.edges.add(len(edge_verts) // 2)
            attributes[".edge_verts"].data.foreach_set("value", edge_verts)
            attributes[".corner_edge"].data.foreach_set("value", corner_edge)
    else:
        mesh.vertices.foreach_set("co", co)
        mesh.loops.foreach_set("vertex_index", corner_vertex)
        if _NEEDS_LOOP_TOTAL:
            mesh.polygons.foreach_set("loop_total", np.full(F, 3, dtype=np.int32))
        if material_index is not None and F:
            mesh.polygons.foreach_set("material_index", np.ascontiguousarray(material_index, dtype=np.int32))
        if smooth is not None and F:
            mesh.polygons.foreach_set("use_smooth", np.ascontiguousarray(smooth, dtype=bool))
        if uv is not None:
            layer = mesh.uv_layers.new(name=uv_name or "UVMap")
            if layer is not None and F:
                corner = np.ascontiguousarray(uv, dtype=np.float32)[corner_vertex]
                layer.data.foreach_set("uv", corner.reshape(-1))
    # With edges given (4.0+), the mesh has them: only tag it.
    mesh.update(calc_edges=not (_ATTRIBUTES and edges is not None))
    if normals is not None and F:
        if _NEEDS_AUTO_SMOOTH:
            mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(normals, dtype=np.float32))


def mesh_edges(mesh) -> tuple[np.ndarray, np.ndarray] | None:
    """The edges Blender computed for `mesh` (for write_mesh's `edges`); None before 4.0."""
    if not _ATTRIBUTES:
        return None
    edge_verts = np.empty(2 * len(mesh.edges), dtype=np.int32)
    corner_edge = np.empty(len(mesh.loops), dtype=np.int32)
    if len(edge_verts):
        mesh.attributes[".edge_verts"].data.foreach_get("value", edge_verts)
    if len(corner_edge):
        mesh.attributes[".corner_edge"].data.foreach_get("value", corner_edge)
    return edge_verts, corner_edge


def slice_for(obj, frame: float):
    """The Slice the object shows at scene frame `frame` (axis t), or at its sweep value."""
    manifold = manifold_for(obj)
    return manifold, manifold.slice(_slice_value(obj, manifold, frame), obj.animanifold.axis)


def display_vertices(manifold, s, axis: str, time_scale: float) -> np.ndarray:
    """Object-space positions of a slice: (x, y, z) for a time slice; for a sweep
    slice along x, y or z, time (from the start, times `time_scale`) takes the
    place of the sliced axis (the sweep view of Figure 2.7)."""
    if axis == "t" or len(s.vertices) == 0:
        return s.vertices
    i = AXES.index(axis) - 1
    t0 = manifold.time_range[0]
    others = [c for c in range(3) if c != i]
    out = np.empty((len(s.vertices), 3), dtype=np.float64)
    out[:, others] = s.vertices[:, :2]
    out[:, i] = (s.vertices[:, 2] - t0) * time_scale
    return out


@dataclass
class _Shown:
    """What an object's mesh holds after a full write: the frame `value`, and for
    a cut of a topology interval either the mover that slides its vertices on
    later frames (written by the handler) or, when `driven`, nothing to do: the
    live modifier moves them."""

    key: tuple
    interval: tuple | None
    mover: object  # am.SliceMover of the written cut (handler-moved intervals)
    corner_vertex: np.ndarray | None  # the corners as written (for the UV layer)
    counts: tuple  # (vertices, faces) of the mesh as written
    value: float = math.nan
    driven: bool = False
    cut: live_cuts.Cut | None = None  # driven: the cut written
    mesh_value: float = math.nan  # driven: the frame the mesh's positions and UV map hold


_SHOWN: dict[str, _Shown] = {}
# Object -> (scene, frame) last shown by update_scene without error: after the
# evaluation of that frame only animated objects need another look.
_CHECKED: dict[str, tuple] = {}
_CUTS = live_cuts.CutCache()


def _slice_value(obj, manifold, frame: float) -> float:
    settings = obj.animanifold
    if settings.axis == "t":
        # Before the first and after the last sample the shape holds, like an action's
        # constant extrapolation (the baked node group does the same).
        t0, t1 = manifold.time_range
        return min(max(frame, t0), t1)
    return settings.sweep_value


def _counts(mesh) -> tuple[int, int]:
    return len(mesh.vertices), len(mesh.polygons)


def can_drive(obj, scene=None) -> bool:
    """Whether the live modifier can play `obj`: Blender 4.2+, the time axis, frames
    that are plain slices (no frame smoothing, no custom normals to carry), the
    modifier not switched off by the user, and a scene whose Scene Time is its
    frame (no Time Stretching)."""
    settings = obj.animanifold
    if not (live_nodes.SUPPORTED and settings.axis == "t" and settings.smooth_levels <= 0
            and not settings.live_normals and live_nodes.usable(obj)):
        return False
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
    edges (AnimationManifold.move_slice), rewriting positions, UVs and normals.
    Frames refined by OpenSubdiv (smooth_levels > 0) are not on manifold
    edges: each is cut, refined and written in full.

    `force=False` (frame changes) skips the write when the mesh already shows
    this frame; other callers (settings, operators) always rewrite, since they
    may have changed the mesh or the manifold."""
    settings = obj.animanifold
    manifold = shown_manifold(obj)
    value = _slice_value(obj, manifold, frame)
    mesh = obj.data
    smoothed = settings.smooth_levels > 0
    normals_wanted = settings.axis == "t" and settings.live_normals
    key = (id(manifold), mesh.as_pointer(), settings.axis, settings.time_scale, normals_wanted, settings.uv_name,
           settings.subdivision_levels, settings.keep_keyframe_times, settings.smooth_levels, settings.crease_angle)
    shown = _SHOWN.get(obj.name_full)
    if shown is not None and (shown.key != key or shown.counts != _counts(mesh)):
        shown = None  # another mesh, manifold or setting, or the mesh was edited
    if can_drive(obj, scene):
        _update_driven(obj, manifold, value, key, None if force else shown)
        return

    if not force and shown is not None and shown.value == value and not shown.driven:
        return  # a sweep view (or a vertex time) on a frame change: nothing moved
    live_nodes.release(obj)
    interval = None if smoothed else manifold.topology_interval(value, settings.axis)
    if shown is not None and interval is not None and shown.interval == interval and shown.mover is not None:
        s = shown.mover.at(value)
        write_positions(mesh, display_vertices(manifold, s, settings.axis, settings.time_scale),
                        shown.corner_vertex, uv=s.vertex_attributes.get("uv"), uv_name=settings.uv_name or "UVMap",
                        normals=slice_normals(s) if normals_wanted else None)
        shown.value = value
        return

    _SHOWN.pop(obj.name_full, None)  # until the write is done, the mesh shows nothing known
    s = frame_slice(obj, manifold, value, settings.axis)
    uv = s.vertex_attributes.get("uv")
    faces = s.faces
    if settings.axis == "y":  # (x, z, t) shown as (x, t, z): an odd permutation, keep faces outward
        faces = faces[:, ::-1]
    write_mesh(
        mesh,
        display_vertices(manifold, s, settings.axis, settings.time_scale),
        faces,
        uv=uv,
        uv_name=settings.uv_name or "UVMap",
        material_index=s.face_attributes.get("material_index"),
        smooth=s.face_attributes.get("smooth"),
        normals=frame_normals(s, smoothed) if normals_wanted else None,
    )
    mover = None
    if interval is not None:
        carried = ["uv"] + (["normal"] if normals_wanted else [])
        mover = am.SliceMover(manifold, s, attributes=carried, normals=False)
    _SHOWN[obj.name_full] = _Shown(key, interval, mover, np.ascontiguousarray(faces, dtype=np.int32).reshape(-1),
                                   _counts(mesh), value)


def _update_driven(obj, manifold, value: float, key: tuple, shown: _Shown | None) -> None:
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
    _SHOWN.pop(obj.name_full, None)  # until the write is done, the mesh shows nothing known
    if interval is None:  # a vertex time (a keyframe): the frame as sliced, the modifier off
        cut_key = ("at", value)
        cut = _cut(manifold, cut_key, lambda: live_cuts.vertex_time_cut(manifold.slice(value, "t")))
        vectors = None
        vertices, corner_uv, mesh_value = cut.vertices, cut.corner_uv, value
    else:
        cut_key = interval
        cut = _cut(manifold, cut_key, lambda: live_cuts.interval_cut(manifold, manifold.slice(value, "t"), interval))
        vectors = {live_nodes.RATE: cut.rate}
        if cut.uv_rate is not None:
            vectors[live_nodes.UV] = cut.uv
            vectors[live_nodes.UV_RATE] = cut.uv_rate
        # The mesh holds this frame if it is kept (the modifier passes it through), else
        # the cut's frame (the modifier moves it).
        frame = _frame(manifold, cut_key, cut, value) or live_cuts.interval_frame(cut, cut.value)
        vertices, corner_uv, mesh_value = frame.positions.reshape(-1, 3), frame.corner_uv, frame.value
    uv_name = obj.animanifold.uv_name or "UVMap"
    write_mesh(mesh, vertices, cut.faces, uv_name=uv_name, corner_uv=corner_uv,
               material_index=cut.material_index, smooth=cut.smooth, edges=cut.edges, vectors=vectors)
    if cut.edges is None:
        cut.edges = mesh_edges(mesh)
        _CUTS.resized(manifold, cut_key)
    if interval is None:
        live_nodes.release(obj)
    else:
        live_nodes.drive(obj, mesh_value, cut.value, interval[0], interval[1],
                         uv_name if cut.uv_rate is not None else None)
    _SHOWN[obj.name_full] = _Shown(key, interval, None, None, _counts(mesh), value, driven=interval is not None,
                                   cut=cut if interval is not None else None, mesh_value=mesh_value)


def _has_rates(mesh) -> bool:
    """Whether the mesh holds an interval cut's rates. By name among the keys: `name in
    mesh.attributes` looks the layer up for writing, which copies it when the
    evaluated mesh shares it (every frame after a copied frame: ~70 us, against ~12)."""
    return live_nodes.RATE in mesh.attributes.keys()


def _frame(manifold, key, cut: live_cuts.Cut, value: float) -> live_cuts.Frame | None:
    """Interval cut `cut` (kept as `key`) at integer frame `value`: kept from an
    earlier visit, or computed now and kept if the frame budget has room; None for
    other frames, or when it has none (the modifier moves those)."""
    if value != math.floor(value):
        return None
    if value == cut.value:
        return live_cuts.interval_frame(cut, value)  # the cut's own arrays: nothing to keep
    frame = _CUTS.frame(manifold, key, value)
    if frame is not None:
        return frame
    # Computed only to be kept: one that could not be would cost a gather over every
    # corner on each visit, more than the modifier's work.
    if _CUTS.get(manifold, key) is not cut or not _CUTS.frame_room(manifold, key, live_cuts.frame_nbytes(cut)):
        return None
    frame = live_cuts.interval_frame(cut, value)
    return frame if _CUTS.keep_frame(manifold, key, frame) else None


def _show_frame(obj, manifold, shown: _Shown, value: float) -> bool:
    """On a frame change inside the driven interval: copies the kept frame of an
    integer frame into the mesh (and tells the modifier); other frames write
    nothing (the modifier moves the mesh to them). False if the mesh is not as
    written (the caller writes the cut again)."""
    if shown.mesh_value == value:
        return True  # shown (the post-frame handler, a repeated frame)
    frame = _frame(manifold, shown.interval, shown.cut, value)
    if frame is None:
        return True  # the modifier moves the mesh from the frame it holds
    if not write_frame(obj.data, obj.animanifold.uv_name or "UVMap", frame):
        return False
    live_nodes.set_frame(obj, value)
    shown.mesh_value = value
    return True


def write_frame(mesh, uv_name: str, frame: live_cuts.Frame) -> bool:
    """Copies a frame's positions and UV map into a mesh holding its cut (one raw copy
    each, after Blender unshares each buffer from the evaluated mesh). False, and
    nothing written, if the mesh's sizes or UV map do not match (Blender 4.0+)."""
    # The UV map through uv_layers: mesh.attributes[name] looks the layer up for
    # writing, ~0.4 ms on the bench object's UV map after each evaluation (uv_layers':
    # ~4 us); copying UV maps only, a frame measured 2.05 ms that way, 1.42 this way.
    layer = mesh.uv_layers.get(uv_name) if frame.corner_uv is not None else None
    if (3 * len(mesh.vertices) != len(frame.positions)
            or (frame.corner_uv is not None and (layer is None or 2 * len(mesh.loops) != len(frame.corner_uv)))):
        return False
    # (mesh.vertices.foreach_set("co") is no raw copy: a frame measured 14 ms that way.)
    mesh.attributes["position"].data.foreach_set("vector", frame.positions)
    if layer is not None:
        layer.uv.foreach_set("vector", frame.corner_uv)
    tag_positions_changed(mesh)
    return True


def tag_positions_changed(mesh) -> None:
    """After foreach_set of a mesh's positions: its normals, bounds and BVH are stale
    and the depsgraph must copy it again. mesh.update() marks only the normals (4.5:
    the evaluated object kept its old bounding box, measured); setting one vertex's
    co through RNA runs Blender's positions-changed tag and tags the depsgraph."""
    if len(mesh.vertices):
        vertex = mesh.vertices[0]
        vertex.co = vertex.co
    mesh.update_tag()


def _cut(manifold, key, make) -> live_cuts.Cut:
    cut = _CUTS.get(manifold, key)
    if cut is None:
        cut = make()
        _CUTS.put(manifold, key, cut)
    return cut


def write_positions(mesh, vertices: np.ndarray, corner_vertex: np.ndarray, uv: np.ndarray | None = None,
                    uv_name: str = "UVMap", normals: np.ndarray | None = None) -> None:
    """Moves the vertices of a mesh that write_mesh filled (same vertices and
    faces): positions, the UV map and custom normals only."""
    co = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1)
    if _ATTRIBUTES:
        mesh.attributes["position"].data.foreach_set("vector", co)
    else:
        mesh.vertices.foreach_set("co", co)
    if uv is not None and len(corner_vertex):
        corner = live_cuts.corner_values(uv, corner_vertex)
        if _ATTRIBUTES and uv_name in mesh.attributes:
            mesh.attributes[uv_name].data.foreach_set("vector", corner)
        elif uv_name in mesh.uv_layers:
            mesh.uv_layers[uv_name].data.foreach_set("uv", corner)
    mesh.update()
    tag_positions_changed(mesh)  # bounds too
    if normals is not None and len(corner_vertex):
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(normals, dtype=np.float32))


def slice_normals(s) -> np.ndarray | None:
    """Smooth normals of a time slice: the source's keyframe vertex normals (the
    'normal' vertex attribute of smooth-shaded sources), interpolated along the
    manifold edges and normalised; None for flat-shaded sources."""
    n = s.vertex_attributes.get("normal")
    if n is None or len(n) == 0:
        return None
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0, length, 1.0)


def scene_frame(scene) -> float:
    return scene.frame_current + scene.frame_subframe


def is_live(obj) -> bool:
    settings = getattr(obj, "animanifold", None)
    return (settings is not None and settings.is_manifold and settings.mode == "LIVE"
            and obj.type == "MESH" and obj.data is not None and obj.library is None)


def update_scene(scene, force: bool = False, after_evaluation: bool = False) -> int:
    """Shows every live manifold object of `scene` at its frame (update_object; on
    a frame change nothing is written for objects whose mesh shows it already);
    never raises (errors are kept per object, printed once, and shown in the
    panel). Returns the count.

    `after_evaluation` (the post-frame handler): objects shown at this frame before
    the evaluation are skipped unless animated (an animated setting, a keyframed
    sweep value say, has its new value only now): ~0.1 ms a frame on the bench
    object, as much as its frame's other checks."""
    frame = scene_frame(scene)
    checked = (scene.as_pointer(), frame)
    count = 0
    for obj in scene.objects:
        if not is_live(obj):
            continue
        if after_evaluation and not force and _CHECKED.get(obj.name_full) == checked and obj.animation_data is None:
            count += 1
            continue
        _CHECKED.pop(obj.name_full, None)
        try:
            # A morph frame that its shared hole space cannot cut is shown uncut: Morph
            # Selected said so once; a warning per frame (an error where warnings are
            # errors) would stop playback for nothing.
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", am.HoleSpaceWarning)
                update_object(obj, frame, force=force, scene=scene)
            _ERRORS.pop(obj.name_full, None)
            _CHECKED[obj.name_full] = checked
            count += 1
        except Exception as e:  # a broken cache must not break playback
            message = f"{type(e).__name__}: {e}"
            if _ERRORS.get(obj.name_full) != message:
                print(f"animanifold: cannot slice '{obj.name}': {message}")
            _ERRORS[obj.name_full] = message
    return count
