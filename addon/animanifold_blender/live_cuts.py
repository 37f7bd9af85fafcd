"""Cuts of a manifold kept between frames, so that playback coming back to a
topology interval (or a vertex time: a keyframe) neither slices again nor makes
Blender compute the mesh's edges again.

A cut is what one topology interval (lo, hi) of the time axis looks like: its
faces, and its frame at the middle of the interval with, per vertex, the rate
at which it slides along its manifold edge (position and UV are affine in the
frame inside the interval): the arrays the mesh and the live modifier take,
ready to copy. A vertex-time cut is the one frame at that time. Both remember
the edges Blender computed the first time the cut was written (edge vertices,
corner edges): later writes set them directly (the edge hash of a 200k-face
frame is most of the cost of writing it).

Kept least recently used first out, within a budget (the add-on's Frame Cache Budget
preference; BUDGET_BYTES by default), per loaded manifold
(a reloaded or subdivided manifold is another object and gets its own cuts).

Beside an interval's cut, each of its integer frames (interval_frame: the
positions and the UV map per corner, as the mesh takes them): the live modifier
moves every vertex and rebuilds the UV map on every corner (600k corners for
a 50k-triangle source) on every frame, where copying a kept frame into the mesh
is two raw copies, several times cheaper (bench/bench_playback.py compares them). Computed
on a frame's first visit and kept within a budget of their own (the same preference;
FRAME_BUDGET_BYTES by default); when that is full,
no more are kept (a loop longer than the budget would otherwise evict every frame
before it comes back) and the modifier moves the others. They go with their cut.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from dataclasses import dataclass
from typing import Callable

import numpy as np

# Defaults (preferences.DEFAULT_BUDGET_MB in the add-on). ~12 intervals of a 200k-face frame (a 50k-triangle source): a typical action's
# keyframes fit, and scrubbing back and forth over them slices nothing.
BUDGET_BYTES = 256 * 2**20
# ~44 integer frames of that frame (100k positions, 600k corners: 6 MB each): a loop
# of 40 frames fits whole.
FRAME_BUDGET_BYTES = 256 * 2**20


@dataclass
class Cut:
    """One cut, as write_mesh takes it (float32, contiguous: nothing to convert
    when it is written again)."""

    value: float  # the frame the arrays show: the vertex time, or the interval's middle
    faces: np.ndarray  # (F, 3) int32
    material_index: np.ndarray | None
    smooth: np.ndarray | None
    vertices: np.ndarray  # (P, 3) float32 at `value`
    corner_uv: np.ndarray | None  # (2 * 3F,) float32 at `value`: the UV map
    # Interval cuts: d/dframe of position and UV, and the UV at `value` per vertex
    # (u, v, 0), for the live modifier.
    rate: np.ndarray | None = None
    uv: np.ndarray | None = None
    uv_rate: np.ndarray | None = None
    edges: tuple | None = None  # (edge_verts (2E,), corner_edge (3F,)) int32, as Blender made them
    # The source's smooth normals carried along the manifold (None for flat-shaded
    # sources): at `value` (P, 3), not normalised, and, for interval cuts, their rate.
    normal: np.ndarray | None = None
    normal_rate: np.ndarray | None = None

    def nbytes(self) -> int:
        arrays = [self.faces, self.material_index, self.smooth, self.vertices, self.corner_uv, self.rate,
                  self.uv, self.uv_rate, self.normal, self.normal_rate] + list(self.edges or ())
        return sum(a.nbytes for a in arrays if a is not None)


def interval_cut(frame) -> Cut:
    """The cut of the topology interval of `frame`, an am.IntervalFrame of a time
    slice (the core's frame, edges and rates), shown at the interval's middle:
    every vertex at its place on its edge there, with the rate at which it slides
    along the edge."""
    middle = cut_value(frame.interval, frame.value)
    s = frame.slice
    dt = middle - frame.value
    faces = _faces(s)
    cut = Cut(middle, faces, _own(s.face_attributes.get("material_index")), _own(s.face_attributes.get("smooth")),
              _f32(s.vertices + dt * frame.rate), None, rate=_f32(frame.rate))
    uv_rate = frame.attribute_rates.get("uv")
    if uv_rate is not None:
        uv_rate = np.asarray(uv_rate)[:, :2]
        now = np.asarray(s.vertex_attributes["uv"])[:, :2] + dt * uv_rate
        cut.corner_uv = corner_values(now, faces)
        cut.uv = _padded(now)
        cut.uv_rate = _padded(uv_rate)
    normal_rate = frame.attribute_rates.get("normal")
    if normal_rate is not None and len(normal_rate):
        cut.normal = _f32(np.asarray(s.vertex_attributes["normal"]) + dt * np.asarray(normal_rate))
        cut.normal_rate = _f32(normal_rate)
    return cut


def cut_value(interval: tuple[float, float], value: float) -> float:
    """The frame an interval's cut shows: its middle as the modifier's float input holds
    it; `value` (a frame of it) for an interval too short for float32."""
    lo, hi = interval
    middle = float(np.float32((lo + hi) / 2))
    return middle if lo < middle < hi else float(value)


@dataclass
class Frame:
    """A frame of an interval cut as the handler copies it into the mesh."""

    value: float
    positions: np.ndarray  # (3P,) float32
    corner_uv: np.ndarray | None  # (2C,) float32: the UV map; None without UVs

    def nbytes(self) -> int:
        return self.positions.nbytes + (0 if self.corner_uv is None else self.corner_uv.nbytes)


def frame_nbytes(cut: Cut) -> int:
    """The size of one Frame of `cut`."""
    return cut.vertices.nbytes + (0 if cut.uv_rate is None else cut.corner_uv.nbytes)


def interval_frame(cut: Cut, frame: float) -> Frame:
    """An interval cut at `frame` (in the interval): every vertex (and its UV) moved
    along its edge from the cut's frame; the UVs per corner."""
    if frame == cut.value:
        return Frame(cut.value, cut.vertices.reshape(-1), cut.corner_uv)
    dt = frame - cut.value
    positions = _f32(cut.vertices + dt * cut.rate.astype(np.float64)).reshape(-1)
    corner_uv = None
    if cut.uv_rate is not None:
        corner_uv = corner_values(cut.uv[:, :2] + dt * cut.uv_rate[:, :2].astype(np.float64), cut.faces)
    return Frame(float(frame), positions, corner_uv)


def vertex_time_cut(s) -> Cut:
    """The cut at a vertex time: the slice itself."""
    faces = _faces(s)
    uv = s.vertex_attributes.get("uv")
    normal = s.vertex_attributes.get("normal")
    return Cut(float(s.value), faces, _own(s.face_attributes.get("material_index")),
               _own(s.face_attributes.get("smooth")), _f32(s.vertices), None if uv is None else _key_corner_uv(uv, faces),
               normal=None if normal is None or not len(normal) else _f32(normal))


_last_key_corner_uv: list = [None, None, None]  # [uv, faces, their corner values]


def _key_corner_uv(uv: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """corner_values(uv, faces) of a vertex-time cut; the last one's again when both are
    the same unchangeable arrays (the keys of an animation whose faces and UVs do not
    change share them: prism_frames), a gather of every corner saved per key."""
    last_uv, last_faces, values = _last_key_corner_uv
    if uv is last_uv and faces is last_faces:
        return values
    values = corner_values(uv, faces)
    if _immutable(uv) and _immutable(faces):
        values.flags.writeable = False
        _last_key_corner_uv[:] = [uv, faces, values]
    return values


def time_cut(manifold, value: float) -> tuple[object, Cut]:
    """(the key playback keeps it under, the cut) of the time slice at `value`: its
    topology interval's cut, or at a vertex time the frame itself ("at", value)."""
    interval = manifold.topology_interval(value, "t")
    if interval is None:
        return ("at", value), vertex_time_cut(manifold.slice(value, "t"))
    # Cut at the frame it shows, so a cut is the same bits whichever frame made it.
    return interval, interval_cut(manifold.interval_frame(cut_value(interval, value), "t"))


def corner_values(uv: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(2C,) float32: the UV of every corner's vertex. Gathered as one 8-byte word per
    corner (a row-wise fancy index of a (P, 2) table is ~5x slower)."""
    table = np.ascontiguousarray(uv, dtype=np.float32).reshape(-1, 2)
    return table.view(np.int64).reshape(-1)[np.asarray(faces).reshape(-1)].view(np.float32)


def _faces(s) -> np.ndarray:
    return _own(s.faces)


def _own(a) -> np.ndarray | None:
    """An int32 copy: the slice's arrays are views that keep the whole slice alive. An
    array nobody can change that keeps nothing else alive (the faces every prism frame
    shares) is kept as it is."""
    if a is None:
        return None
    if _immutable(a) and a.dtype == np.int32 and a.flags.c_contiguous:
        return a
    return np.array(a, dtype=np.int32, copy=True, order="C")


def _immutable(a) -> bool:
    """Whether `a` is a read-only array owning its memory: its values never change."""
    return isinstance(a, np.ndarray) and not a.flags.writeable and a.base is None


def _f32(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float32)


def _padded(a) -> np.ndarray:
    out = np.zeros((len(a), 3), dtype=np.float32)
    out[:, :2] = a
    return out


class CutCache:
    """Each budget is a byte count, or a function giving it that is asked each time the
    cache decides what to keep (the add-on's Frame Cache Budget preference)."""

    def __init__(self, budget: int | Callable[[], int] = BUDGET_BYTES,
                 frame_budget: int | Callable[[], int] = FRAME_BUDGET_BYTES):
        self._budget = budget
        self._frame_budget = frame_budget
        self._entries: OrderedDict = OrderedDict()  # (id(manifold), key) -> (weakref, Cut, nbytes)
        self._bytes = 0
        self._frames: dict = {}  # (id(manifold), key) -> {frame value: Frame}, for kept cuts only
        self._frame_bytes = 0

    @property
    def budget(self) -> int:
        return self._budget() if callable(self._budget) else self._budget

    @property
    def frame_budget(self) -> int:
        return self._frame_budget() if callable(self._frame_budget) else self._frame_budget

    def get(self, manifold, key) -> Cut | None:
        entry = self._entries.get((id(manifold), key))
        if entry is None:
            return None
        if entry[0]() is not manifold:  # an id reused by another manifold
            self._drop((id(manifold), key))
            return None
        self._entries.move_to_end((id(manifold), key))
        return entry[1]

    def put(self, manifold, key, cut: Cut) -> None:
        self._drop((id(manifold), key))
        size = cut.nbytes()
        if size > self.budget:
            return
        self._entries[(id(manifold), key)] = (weakref.ref(manifold), cut, size)
        self._bytes += size
        self._shrink()

    def resized(self, manifold, key) -> None:
        """A kept cut grew (its edges were added): account for it."""
        entry = self._entries.get((id(manifold), key))
        if entry is not None:
            ref, cut, size = entry
            self._bytes += cut.nbytes() - size
            self._entries[(id(manifold), key)] = (ref, cut, cut.nbytes())
            self._shrink()

    def _shrink(self) -> None:
        budget = self.budget
        while self._bytes > budget and len(self._entries) > 1:
            self._drop(next(iter(self._entries)))
        for k in [k for k, (ref, _, _) in self._entries.items() if ref() is None]:
            self._drop(k)

    def room(self, nbytes: int, share: float = 1.0) -> bool:
        """Whether a cut of `nbytes` fits within `share` of the budget beside those kept."""
        return self._bytes + nbytes <= share * self.budget

    def frame(self, manifold, key, value: float) -> Frame | None:
        """The kept frame `value` of the kept cut `key`, if any."""
        if self.get(manifold, key) is None:
            return None
        return self._frames.get((id(manifold), key), {}).get(value)

    def frame_room(self, manifold, key, nbytes: int) -> bool:
        """Whether a frame of `nbytes` for the kept cut `key` would be kept."""
        return (id(manifold), key) in self._entries and self._frame_bytes + nbytes <= self.frame_budget

    def keep_frame(self, manifold, key, frame: Frame) -> bool:
        """Keeps `frame` of the kept cut `key` if the frame budget has room (nothing is
        evicted for it); False if not kept."""
        if not self.frame_room(manifold, key, frame.nbytes()):
            return False
        frames = self._frames.setdefault((id(manifold), key), {})
        if frame.value not in frames:
            frames[frame.value] = frame
            self._frame_bytes += frame.nbytes()
        return True

    def _drop(self, k) -> None:
        entry = self._entries.pop(k, None)
        if entry is not None:
            self._bytes -= entry[2]
        for frame in self._frames.pop(k, {}).values():
            self._frame_bytes -= frame.nbytes()

    def clear(self) -> None:
        self._entries.clear()
        self._bytes = 0
        self._frames.clear()
        self._frame_bytes = 0

    def __len__(self) -> int:
        return len(self._entries)

    @property
    def nbytes(self) -> int:
        return self._bytes

    @property
    def frame_nbytes(self) -> int:
        return self._frame_bytes
