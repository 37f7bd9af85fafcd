"""Sampling an object's evaluated mesh over a frame range into keyframes.

Everything is numpy + foreach_get: no geometry in Python loops. The result is
what :func:`animanifold.stitch` takes: positions (m, k, 3), triangles (l, 3),
times (m,), per-vertex UVs and per-face material indices. The mesh is split at
UV seams so every keyframe vertex carries one UV; the split is the same for
every sample (corners are welded by (vertex, uv at every sample)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import animation_sources, extra_layers, messages
from ._lib import am
from .reporting import ReportedError


class SamplingError(ReportedError):
    """The object cannot be sampled into keyframes (the message says why and where)."""


# -- which frames --------------------------------------------------------------

def sample_frames(obj, frame_start: float, frame_end: float, mode: str = "KEYFRAMES",
                  step: int = 1) -> tuple[np.ndarray, list[str]]:
    """The sample frames in [frame_start, frame_end], the first and last frame always, and
    notes for the report. 'KEYFRAMES': the keyframes of every action and driver source
    driving `obj` (every frame where a driver's times are unknown, with a note saying
    which); 'ADAPTIVE': the same keyframes without the fallback, where error-driven
    sampling starts (it finds a driver's frames by measuring); 'EVERY_N': every `step`
    frames."""
    if not frame_end > frame_start:
        raise SamplingError(f"the frame range {frame_start:g}–{frame_end:g} is empty: the end must be after the start")
    notes: list[str] = []
    if mode == "EVERY_N":
        if step < 1:
            raise SamplingError(f"'every N frames' needs N ≥ 1, got {step}")
        inner = np.arange(frame_start, frame_end, step, dtype=np.float64)
    elif mode in ("KEYFRAMES", "ADAPTIVE"):
        drivers = animation_sources.driver_frames(obj)
        if mode == "KEYFRAMES" and not animation_sources.driving_animation(obj) and not drivers.driven:
            raise SamplingError(
                f"'{obj.name}' has no animation: no object, shape-key or armature action and no driver drives it "
                "(for procedural animation use 'within tolerance' or 'every N frames' sampling)"
            )
        keys = np.union1d(animation_sources.keyframe_frames(obj), drivers.frames)
        if mode == "KEYFRAMES" and drivers.unknown:
            keys = np.union1d(keys, np.arange(math.ceil(frame_start), frame_end, dtype=np.float64))
            notes.append(f"'{obj.name}' sampled at every frame: {drivers.unknown[0]}"
                         + (f" (and {len(drivers.unknown) - 1} more drivers)" if len(drivers.unknown) > 1 else ""))
        inner = keys[(keys > frame_start) & (keys < frame_end)]
    else:
        raise SamplingError(f"unknown sampling mode {mode!r}")
    return np.unique(np.concatenate([[float(frame_start)], inner, [float(frame_end)]])), notes


# -- the evaluated mesh ----------------------------------------------------------

@dataclass
class MeshSample:
    positions: np.ndarray  # (n, 3) float64, local space
    normals: np.ndarray  # (n, 3) float32 vertex normals
    loop_vertex: np.ndarray  # (L,) int32: the connectivity that must not change
    poly_start: np.ndarray  # (P,) int32
    loop_uv: np.ndarray | None  # (L, 2) float32 or None
    uv_name: str | None
    matrix_world: np.ndarray  # (4, 4)
    # triangulation (the first sample, or every one asked for: n-gon triangulation depends on the shape)
    tri_vertices: np.ndarray | None = None  # (T, 3) int32
    tri_loops: np.ndarray | None = None  # (T, 3) int32
    material_index: np.ndarray | None = None  # (T,) int32
    smooth: np.ndarray | None = None  # (T,) int32 (0 flat, 1 smooth)
    extra: dict = field(default_factory=dict)  # extra_layers: name -> (L, c) float32 per corner


def read_mesh(mesh, matrix_world, triangulate: bool) -> MeshSample:
    """Arrays of an (evaluated) mesh; with `triangulate`, its loop triangles too."""
    n, L, P = len(mesh.vertices), len(mesh.loops), len(mesh.polygons)
    co = np.empty(3 * n, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    normals = np.empty(3 * n, dtype=np.float32)
    mesh.vertices.foreach_get("normal", normals)
    loop_vertex = np.empty(L, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    poly_start = np.empty(P, dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", poly_start)
    loop_uv, uv_name = None, None
    layer = mesh.uv_layers.active
    if layer is not None:
        loop_uv = np.empty(2 * L, dtype=np.float32)
        layer.data.foreach_get("uv", loop_uv)
        loop_uv = loop_uv.reshape(L, 2) + np.float32(0.0)  # + 0 turns -0.0 into 0.0
        uv_name = layer.name
    sample = MeshSample(co.reshape(n, 3).astype(np.float64), normals.reshape(n, 3), loop_vertex, poly_start, loop_uv, uv_name,
                        np.array(matrix_world, dtype=np.float64), extra=extra_layers.read_corner_layers(mesh, loop_vertex))
    if triangulate:
        mesh.calc_loop_triangles()
        tris = mesh.loop_triangles
        T = len(tris)
        tv = np.empty(3 * T, dtype=np.int32)
        tl = np.empty(3 * T, dtype=np.int32)
        mi = np.empty(T, dtype=np.int32)
        poly = np.empty(T, dtype=np.int32)
        tris.foreach_get("vertices", tv)
        tris.foreach_get("loops", tl)
        tris.foreach_get("material_index", mi)
        tris.foreach_get("polygon_index", poly)
        smooth_poly = np.empty(P, dtype=bool)
        mesh.polygons.foreach_get("use_smooth", smooth_poly)
        sample.tri_vertices = tv.reshape(T, 3)
        sample.tri_loops = tl.reshape(T, 3)
        sample.material_index = mi
        sample.smooth = smooth_poly[poly].astype(np.int32)
    return sample


@dataclass
class Keyframes:
    """Keyframes ready for animanifold.stitch."""

    times: np.ndarray  # (m,)
    positions: np.ndarray  # (m, k, 3) in the local space of the object at the first sample
    normals: np.ndarray  # (m, k, 3) vertex normals (same space)
    faces: np.ndarray  # (l, 3)
    uv: np.ndarray | None  # (k, 2) or (m, k, 2)
    uv_name: str | None
    material_index: np.ndarray  # (l,)
    smooth: np.ndarray  # (l,)
    source_vertex: np.ndarray  # (k,) index of the source mesh vertex
    matrix_world: np.ndarray  # (4, 4) world matrix of the object at the first sample
    moves: bool = False  # object-level motion was baked into the positions
    notes: list = field(default_factory=list)
    extra: dict = field(default_factory=dict)  # extra_layers: name -> (k, c) or (m, k, c)


def weld_corners(tri_vertices: np.ndarray, corner_uvs: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Splits vertices at UV seams, consistently for every sample.

    tri_vertices (T, 3); corner_uvs: per sample and layer (T*3, c) float32 arrays (UVs,
    colours). Corners are grouped by vertex, then refined by their values in each
    array, so two corners share a new vertex only if they share the vertex and the
    value of every layer at every sample (a seam of any UV map splits). Returns faces (T, 3) over the new vertices, new → source vertex
    (k,), and the first corner of each new vertex (k,).
    """
    key = tri_vertices.reshape(-1).astype(np.int64)
    previous = None
    for uv in corner_uvs:
        if previous is not None and np.array_equal(uv, previous):
            continue
        previous = uv
        bits = np.ascontiguousarray(uv).view(np.uint32).astype(np.int64)
        rows = np.column_stack([key, bits.reshape(len(key), -1)])
        _, key = np.unique(rows, axis=0, return_inverse=True)
        key = key.reshape(-1)
    _, first_corner, inverse = np.unique(key, return_index=True, return_inverse=True)
    faces = inverse.reshape(-1, 3).astype(np.int32)
    return faces, tri_vertices.reshape(-1)[first_corner].astype(np.int32), first_corner


def evaluate(context, obj, frames, progress=None, triangulate_all: bool = False, keep=None) -> list:
    """Evaluates `obj` at each frame: what `keep` (default: the MeshSample itself) makes of
    each sample. The first sample is always triangulated, the others with `triangulate_all`.

    Restores the scene's current frame. Raises SamplingError when the mesh's connectivity
    changes between samples (naming the frame).
    """
    scene = context.scene
    frame0, subframe0 = scene.frame_current, scene.frame_subframe
    kept: list = []
    first = None
    try:
        for i, frame in enumerate(frames):
            whole = math.floor(frame)
            scene.frame_set(int(whole), subframe=float(frame - whole))
            depsgraph = context.evaluated_depsgraph_get()
            ob_eval = obj.evaluated_get(depsgraph)
            mesh = ob_eval.to_mesh()
            try:
                sample = read_mesh(mesh, ob_eval.matrix_world, triangulate=(i == 0 or triangulate_all))
            finally:
                ob_eval.to_mesh_clear()
            if i == 0:
                if len(sample.tri_vertices) == 0:
                    raise SamplingError(f"'{obj.name}' has no faces at frame {frame:g}")
                first = sample
            else:
                _check_topology(obj, sample, first, frame, frames[0])
            kept.append(sample if keep is None else keep(sample))
            if progress is not None:
                progress(i + 1)
    finally:
        scene.frame_set(frame0, subframe=subframe0)
    return kept


def _check_topology(obj, sample: MeshSample, ref: MeshSample, frame: float, frame0: float) -> None:
    if (len(sample.positions) != len(ref.positions) or not np.array_equal(sample.poly_start, ref.poly_start)
            or not np.array_equal(sample.loop_vertex, ref.loop_vertex)):
        raise SamplingError(
            f"the topology of '{obj.name}' changes at frame {frame:g} "
            f"({_topology_change(sample, ref, frame0)}): "
            "a keyframed action must keep the mesh's connectivity"
        )


def _topology_change(sample: MeshSample, ref: MeshSample, ref_frame: float) -> str:
    counts = f"{len(sample.positions)} vertices, {len(sample.poly_start)} faces"
    if len(sample.positions) != len(ref.positions) or len(sample.poly_start) != len(ref.poly_start):
        return f"{counts}; frame {ref_frame:g} has {len(ref.positions)} vertices, {len(ref.poly_start)} faces"
    change = messages.connectivity_change(sample.poly_start, sample.loop_vertex, ref.poly_start, ref.loop_vertex)
    return f"{counts} as at frame {ref_frame:g}, but {change} there"


def sample_object(context, obj, frames: np.ndarray, progress=None) -> Keyframes:
    """Evaluates `obj` at each frame and returns corresponding keyframes.

    Restores the scene's current frame. Raises SamplingError when the mesh's
    connectivity changes between samples (naming the frame) or nothing moves.
    """
    return keyframes_from(obj, evaluate(context, obj, frames, progress), frames)


def keyframes_from(obj, samples: list[MeshSample], frames, check_motion: bool = True) -> Keyframes:
    """Keyframes from the samples `evaluate` made at `frames` (the first one triangulated):
    split at UV seams, object motion baked into the first sample's local space. With
    `check_motion`, raises SamplingError when nothing moves."""
    ref = samples[0]
    corners = ref.tri_loops.reshape(-1)
    uvs = []
    if ref.loop_uv is not None:
        uvs = [s.loop_uv[corners] if s.loop_uv is not None and s.loop_uv.shape == ref.loop_uv.shape
               else ref.loop_uv[corners] for s in samples]
    extra = {name: [s.extra[name][corners] if s.extra.get(name) is not None and s.extra[name].shape == layer.shape
                    else layer[corners] for s in samples] for name, layer in ref.extra.items()}
    faces, source_vertex, first_corner = weld_corners(ref.tri_vertices, uvs + [a for v in extra.values() for a in v])

    m0 = ref.matrix_world
    moves = any(not np.array_equal(s.matrix_world, m0) for s in samples)
    if moves:
        inv0 = np.linalg.inv(m0)
        rel = [inv0 @ s.matrix_world for s in samples]
        positions = np.stack([s.positions[source_vertex] @ r[:3, :3].T + r[:3, 3] for s, r in zip(samples, rel)])
        normals = np.stack([s.normals[source_vertex] @ np.linalg.inv(r[:3, :3]) for s, r in zip(samples, rel)])
    else:
        positions = np.stack([s.positions[source_vertex] for s in samples])
        normals = np.stack([s.normals[source_vertex] for s in samples]).astype(np.float64)

    if check_motion and np.all(positions == positions[0]):
        raise SamplingError(
            f"'{obj.name}' does not move in frames {frames[0]:g}–{frames[-1]:g}: no animation in the range"
        )

    uv = _per_vertex(uvs, first_corner) if uvs else None
    return Keyframes(
        times=np.asarray(frames, dtype=np.float64),
        positions=positions,
        normals=normals,
        faces=faces,
        uv=uv,
        uv_name=ref.uv_name,
        material_index=ref.material_index,
        smooth=ref.smooth,
        source_vertex=source_vertex,
        matrix_world=m0,
        moves=moves,
        extra={name: _per_vertex(values, first_corner) for name, values in extra.items()},
    )


def _per_vertex(corner_values: list, first_corner: np.ndarray) -> np.ndarray:
    """A layer's per-sample corner values as per-vertex values: (k, c) if the same at every
    sample, else (m, k, c)."""
    if all(np.array_equal(u, corner_values[0]) for u in corner_values[1:]):
        return corner_values[0][first_corner].astype(np.float64)
    return np.stack([u[first_corner] for u in corner_values]).astype(np.float64)


def stitch_keyframes(keys: Keyframes, progress=None, interrupted=None):
    """The animation manifold of `keys` (animanifold.stitch), carrying the source vertex,
    the smooth normals of a smooth-shaded source, UVs, materials and shading; `progress`
    (step, fraction) hears the stitch's steps and `interrupted()` can stop it (the core's
    interrupter). Reads no Blender data: a worker thread may run it."""
    vertex_attributes = {"source_vertex": keys.source_vertex.astype(np.float64)}
    if keys.smooth.all():  # smooth-shaded: carry the source's vertex normals
        vertex_attributes["normal"] = keys.normals
    if keys.uv is not None:
        vertex_attributes["uv"] = keys.uv
    vertex_attributes.update(keys.extra)
    return am.stitch(
        keys.positions, keys.faces, keys.times, vertex_attributes=vertex_attributes,
        face_attributes={"material_index": keys.material_index, "smooth": keys.smooth},
        progress=progress, interrupted=interrupted,
    )
