"""Keyframes with vertex correspondence → an animation manifold (§2.2): :func:`stitch`.

Each keyframe face sweeps a prism to the next keyframe, split into tets by a
global vertex order (the core's ``stitch``). The order puts copies of one point
(a vertex split at a UV seam) next to each other, so the prisms on both sides
of a seam split alike and :func:`animanifold.weld` closes the seam.
"""

from __future__ import annotations

from typing import Callable, Mapping, Sequence

import numpy as np

from . import _core
from .indices import as_indices
from .manifold import AnimationManifold, as_table
from .prism_frames import Prisms
from ._core import InputError


_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX_1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX_2 = np.uint64(0x94D049BB133111EB)


def _mixed(words: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser on each uint64: every input bit moves every output
    bit, so positions differing only in a few mantissa bits hash apart."""
    words = (words ^ (words >> np.uint64(30))) * _MIX_1
    words = (words ^ (words >> np.uint64(27))) * _MIX_2
    return words ^ (words >> np.uint64(31))


def _track_hashes(flat: np.ndarray, keyframes: Sequence[int] | None = None) -> np.ndarray:
    """(k,) uint64: a hash of each vertex's positions in `keyframes` of `flat`
    (m, k, d) float64 (default: the first, middle and last, enough to tell a
    seamless mesh's vertices apart at a fraction of the cost of all). Equal
    tracks hash alike (−0.0 counts as 0.0, as it compares equal); vertices
    apart in any of the keyframes rarely do."""
    m, k, d = flat.shape
    if keyframes is None:
        keyframes = sorted({0, m // 2, m - 1}) if m else []
    hashes = np.zeros(k, dtype=np.uint64)
    with np.errstate(over="ignore"):
        for i in keyframes:
            words = _mixed((flat[i] + 0.0).view(np.uint64) + _GOLDEN * np.uint64(i * d + 1))
            for c in range(d):
                hashes = (hashes ^ words[:, c]) * _GOLDEN + np.uint64(c + 1)
    return hashes


def _first_copies(stacked: np.ndarray, flat: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """For each of `candidates` (ascending vertex indices), the first vertex whose
    track equals its own, as np.unique over their tracks would group them. Groups
    by a hash of whole tracks and checks each member equals its group's first
    (== in the input's dtype); on any mismatch (a collision, or NaN, which
    equals nothing) it asks np.unique."""
    m, _, d = stacked.shape
    hashes = _track_hashes(flat[:, candidates], range(m))
    by_hash = np.argsort(hashes, kind="stable")
    starts = np.r_[True, hashes[by_hash][1:] != hashes[by_hash][:-1]]
    first = np.empty(len(candidates), dtype=np.int64)
    first[by_hash] = by_hash[np.flatnonzero(starts)[np.cumsum(starts) - 1]]
    if np.array_equal(stacked[:, candidates], stacked[:, candidates[first]]):
        return candidates[first]
    tracks = np.ascontiguousarray(stacked[:, candidates, :].transpose(1, 0, 2).reshape(len(candidates), m * d))
    _, first, group = np.unique(tracks, axis=0, return_index=True, return_inverse=True)
    return candidates[first[np.asarray(group).reshape(-1)]]


def _seam_order(stacked: np.ndarray, flat: np.ndarray | None = None) -> np.ndarray:
    """The keyframe vertices ordered by index, except that copies of one point
    (same position in every keyframe: a vertex split at a UV seam) follow the
    first copy. Stitching in this order splits the prisms on both sides of a
    seam alike, so animanifold.weld() closes the seam completely.

    stacked: (m, k, d) keyframes; flat: the same as float64 (m, k, d), when the
    caller already has it. Copies are looked for only among the vertices whose
    hash is shared: equal tracks hash alike, so every group of copies lies in
    that set, and a mesh without seams is settled by the hashes alone."""
    m, k, d = stacked.shape
    if flat is None:
        flat = np.asarray(stacked, dtype=np.float64)
    hashes = _track_hashes(flat)
    ordered = np.sort(hashes)
    shared = ordered[1:][ordered[1:] == ordered[:-1]]
    if shared.size == 0:
        return np.arange(k, dtype=np.int32)
    candidates = np.flatnonzero(np.isin(hashes, shared))
    first_copy = np.arange(k)
    first_copy[candidates] = _first_copies(stacked, flat, candidates)
    return np.argsort(first_copy, kind="stable").astype(np.int32)


def _seam_order_by_unique(stacked: np.ndarray) -> np.ndarray:
    """_seam_order's definition, np.unique over every track: the reference the tests compare with."""
    m, k, d = stacked.shape
    tracks = np.ascontiguousarray(stacked.transpose(1, 0, 2).reshape(k, m * d))
    _, first, group = np.unique(tracks, axis=0, return_index=True, return_inverse=True)
    if len(first) == k:
        return np.arange(k, dtype=np.int32)
    return np.lexsort((np.arange(k), first[np.asarray(group).reshape(-1)])).astype(np.int32)


def stitch(
    frames: np.ndarray | Sequence[np.ndarray],
    faces: np.ndarray,
    times: Sequence[float] | np.ndarray,
    vertex_attributes: Mapping[str, np.ndarray] | None = None,
    face_attributes: Mapping[str, np.ndarray] | None = None,
    *,
    progress: Callable[[str, float], bool] | None = None,
    interrupted: Callable[[], bool] | None = None,
) -> AnimationManifold:
    """Keyframes with vertex correspondence → animation manifold (§2.2).

    frames: (m, k, 3) or a list of m (k, 3) arrays — (m, k, 2) for contours;
    faces: (l, 3) triangles — (l, 2) edges for contours — shared by all
    keyframes; times: (m,) strictly increasing. vertex_attributes: name →
    (k,) / (k, c) constant over time, or (m, k) / (m, k, c) per keyframe.
    face_attributes: name → (l,) / (l, c) integers (material index, ...).
    The result has exactly 3·l·(m−1) tets (2·l·(m−1) triangles for contours)
    and records its prisms (``.prisms``): its frames between two keys are the
    keys' faces, each vertex on its vertical edge (AnimationManifold.slice).
    progress(step, fraction) and interrupted() follow the core's steps (once per
    keyframe gap); False from the one or True from the other raises
    :class:`animanifold.Cancelled`.
    """
    if isinstance(frames, np.ndarray):
        stacked = frames
        if stacked.ndim != 3:
            raise InputError(f"frames must be (m, k, d), got shape {stacked.shape}")
    else:
        frames = [np.asarray(f) for f in frames]
        if not frames:
            raise InputError("an animation manifold needs at least two keyframes, got 0")
        for i, f in enumerate(frames):
            if f.ndim != 2:
                raise InputError(f"keyframe {i} must be (k, d), got shape {f.shape}")
            if f.shape != frames[0].shape:
                raise InputError(
                    f"keyframe {i} has {f.shape[0]} vertices of {f.shape[1]}D; keyframe 0 has "
                    f"{frames[0].shape[0]} of {frames[0].shape[1]}D: keyframes must correspond vertex for vertex"
                )
        stacked = np.stack(frames)
    m, k, d = stacked.shape
    times = np.ascontiguousarray(times, dtype=np.float64).reshape(-1)
    if len(times) != m:
        raise InputError(f"{m} keyframes but {len(times)} times")
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] != d:
        raise InputError(f"faces must be (l, {d}) for {d}D keyframes, got shape {faces.shape}")
    if faces.size and not np.issubdtype(faces.dtype, np.integer):
        raise InputError(f"faces must be integer vertex indices, got {faces.dtype}")
    if faces.size and (faces.max() >= 2**31 or faces.min() < -(2**31)):
        raise InputError("face indices do not fit in 32 bits")

    va = {}
    for name, values in (vertex_attributes or {}).items():
        table = np.asarray(values, dtype=np.float64)
        if table.ndim == 3:  # (m, k, c): per keyframe
            if table.shape[:2] != (m, k):
                raise InputError(f"vertex attribute {name!r} has shape {table.shape}; expected ({m}, {k}, c)")
            table = table.reshape(m * k, -1)
        elif table.ndim == 2 and table.shape == (m, k) and m != k:  # (m, k): per keyframe, one channel
            table = table.reshape(m * k, 1)
        va[name] = as_table(table, np.float64, f"vertex attribute {name!r}")
    fa = {name: as_table(values, np.int32, f"face attribute {name!r}") for name, values in (face_attributes or {}).items()}

    flat = np.ascontiguousarray(stacked.reshape(m * k, d), dtype=np.float64)
    return AnimationManifold(
        _core.stitch(flat, as_indices(faces, "faces"), times, va, fa, _seam_order(stacked, flat.reshape(m, k, d)),
                     progress=progress, interrupted=interrupted),
        metadata={"keyframe_times": times.tolist(), "keyframe_vertices": int(k), "keyframe_faces": int(len(faces))},
        prisms=Prisms.stitched(times, k, faces),
    )
