"""In-between frames of stitched keyframes: the keyframes' faces, every vertex on its vertical edge.

A stitched manifold (:func:`animanifold.stitch`) sweeps each keyframe face to
the next keyframe as a prism, cut into tets. The tets' slice between two keys
is a staircase: about four triangles per face, with vertices on the prisms'
diagonal edges too, so a frame is not even the linear blend of its keys. The
prism's own slice at t is the face with each corner moved linearly along its
vertical edge (the keyframes' blend): the exact slice of the bilinear prism the
tets approximate, with the source's faces and face count.

:class:`Prisms` records that structure: which manifold vertex is source vertex
v at key i, the keys' times, the faces, and per gap between two keys whether it
is played as prisms (a gap whose keys differ in connectivity, or that a morph
or fill joined, is not). :class:`PrismGap` is one gap's frames: at a value
strictly inside the gap the frame is::

    s        = (t - t_i) / (t_{i+1} - t_i)
    vertices = (1 - s) * P[key_vertices[i]] + s * P[key_vertices[i + 1]]

with the same arithmetic the core's slice uses for a point on an edge, so the
prism frame's vertices are bit for bit the staircase frame's points on the
vertical edges. Vertex attributes blend the same way; face attributes are the
prism's tets' (one face, one prism). At a key the frame is the key exactly, over
the same faces (:meth:`Prisms.key_frame`; the tets' slice has the same triangles):
all frames of an animation that keeps its faces share one face list, so playback
moves vertices and never rewrites the mesh's topology.

The structure holds only for the points and simplices it was made with:
operations that make a new manifold drop it unless it provably still holds
(:meth:`Prisms.holds_for`: every layer still at its one time, same simplices).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Mapping

import numpy as np

from .interval_frame import IntervalFrame
from .slices import Slice, squeezed
from ._core import InputError

# Named arrays of the cache file (cache.py) holding a Prisms, in this order.
CACHE_ARRAYS = ("prism_times", "prism_key_vertices", "prism_faces", "prism_face_simplices", "prism_gaps")


@dataclass(frozen=True, eq=False)
class Prisms:
    """The prism structure of a manifold whose every simplex lies in one prism.

    times (m,) float64 strictly increasing: the keys; key_vertices (m, k) int32:
    the manifold vertex that is source vertex v at key i (every manifold vertex
    exactly once); faces (l, n) int32 source-vertex faces, oriented like the
    keys (triangles for surfaces, segments for contours); face_simplices
    (m-1, l) int32: a manifold simplex of face f's prism in gap i (its face
    attributes are the face's); gaps (m-1,) bool: whether gap i is played as
    prisms.
    """

    times: np.ndarray
    key_vertices: np.ndarray
    faces: np.ndarray
    face_simplices: np.ndarray
    gaps: np.ndarray

    @classmethod
    def stitched(cls, times: np.ndarray, vertices: int, faces: np.ndarray) -> "Prisms | None":
        """The structure of the core's stitch (stitch.hpp): vertex j of key i is manifold
        vertex i*k + j, and face f's prism in gap i starts at simplex (i*l + f)*n. None
        for keys without faces (nothing to play)."""
        times = np.asarray(times, dtype=np.float64)
        faces = np.asarray(faces, dtype=np.int32)
        m, (l, n) = len(times), faces.shape
        if l == 0 or vertices == 0 or m < 2:
            return None
        key_vertices = np.arange(m * vertices, dtype=np.int32).reshape(m, vertices)
        face_simplices = ((np.arange(m - 1, dtype=np.int64)[:, None] * l + np.arange(l)) * n).astype(np.int32)
        return cls(times, key_vertices, faces, face_simplices, np.ones(m - 1, dtype=bool))

    def checked(self, points: np.ndarray, simplex_count: int) -> "Prisms":
        """`self` with read-only arrays of the right types, after checking it fits a manifold
        of `points` and `simplex_count` simplices; ValueError naming the element at fault."""
        times = np.array(self.times, dtype=np.float64).reshape(-1)
        key_vertices = _int_table(self.key_vertices, "prism key_vertices")
        faces = _int_table(self.faces, "prism faces")
        face_simplices = _int_table(self.face_simplices, "prism face_simplices")
        gaps = np.asarray(self.gaps).reshape(-1)
        m, k = key_vertices.shape
        if len(times) != m or m < 2:
            raise InputError(f"prism times hold {len(times)} keys, key_vertices {m} (at least 2)")
        if not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
            raise InputError("prism times must be finite and strictly increasing")
        if face_simplices.shape != (m - 1, len(faces)) or len(gaps) != m - 1:
            raise InputError(f"prism face_simplices {face_simplices.shape} and gaps ({len(gaps)},) must be "
                             f"({m - 1}, {len(faces)}) and ({m - 1},)")
        if gaps.dtype != bool and not np.isin(gaps, (0, 1)).all():
            raise InputError("prism gaps must be 0 or 1")
        _check_range(key_vertices, len(points), "prism key vertex")
        _check_range(faces, k, "prism face corner")
        _check_range(face_simplices, simplex_count, "prism face simplex")
        if key_vertices.size != len(points) or np.any(np.bincount(key_vertices.reshape(-1), minlength=len(points)) != 1):
            raise InputError(f"prism key_vertices must name each of the {len(points)} manifold vertices once")
        if faces.shape[1] != points.shape[1] - 1:
            raise InputError(f"prism faces have {faces.shape[1]} corners; frames of this manifold have "
                             f"{points.shape[1] - 1}")
        gaps = gaps.astype(bool)
        broken = np.flatnonzero(gaps & ~_holding_gaps(points[key_vertices, -1], times))
        if len(broken):
            raise InputError(f"prism gap {broken[0]} ({times[broken[0]]:g} to {times[broken[0] + 1]:g}) does not hold: "
                             "a key's vertices are not all at its time, or another key's reach into the gap")
        arrays = [times, *(table.astype(np.int32, copy=False) for table in (key_vertices, faces, face_simplices)), gaps]
        for a in arrays:
            a.flags.writeable = False
        return Prisms(*arrays)

    def holds_for(self, points: np.ndarray, simplex_count: int) -> "Prisms | None":
        """This structure for a manifold with new `points` (and `simplex_count` simplices,
        the same ones): the gaps that still hold (both keys' vertices at their times, no
        other key's vertex inside the gap) still played as prisms; None when none does."""
        try:
            times = np.asarray(self.times, dtype=np.float64)
            holding = np.asarray(self.gaps, dtype=bool) & _holding_gaps(points[self.key_vertices, -1], times)
            return None if not holding.any() else Prisms(self.times, self.key_vertices, self.faces,
                                                        self.face_simplices, holding).checked(points, simplex_count)
        except (ValueError, IndexError):
            return None

    def gap(self, interval: tuple[float, float] | None) -> int | None:
        """The gap played as prisms whose open interval is `interval` (a topology interval
        of the time axis), or None."""
        if interval is None:
            return None
        i = int(np.searchsorted(self.times, interval[0]))
        if i + 1 < len(self.times) and self.times[i] == interval[0] and self.times[i + 1] == interval[1] \
                and self.gaps[i]:
            return i
        return None

    @cached_property
    def _frame_vertices(self) -> tuple[np.ndarray, np.ndarray]:
        """(the source vertices the faces use, ascending; the faces over them): a frame keeps
        only vertices its faces use, as the tets' slice does."""
        used, faces = np.unique(self.faces, return_inverse=True)
        faces = faces.reshape(self.faces.shape).astype(np.int32)
        faces.flags.writeable = False  # shared by every frame (and kept by playback uncopied)
        return used.astype(np.int64), faces

    @cached_property
    def _same_at_every_key(self) -> dict:
        """(name, the table's memory) -> (the table, kept so that its memory is not reused,
        and its frame rows at key 0, read-only, or None when they differ between keys):
        filled by :meth:`_key_rows`. By memory: the manifold hands out a new view of
        the same table on every read."""
        return {}

    def _key_rows(self, name: str, table, key: int) -> np.ndarray:
        """Vertex attribute `table`'s rows of key `key`'s frame vertices. An attribute the
        same at every key (a UV map that does not animate) gives one shared read-only
        array for all keys, so playback can reuse what it made of it (its corner UVs)."""
        used = self._frame_vertices[0]
        table = np.asarray(table)
        memory = (name, table.__array_interface__["data"][0], table.shape, table.strides, table.dtype.str)
        entry = self._same_at_every_key.get(memory)
        if entry is None:
            first = _rows(table, self.key_vertices[0][used])
            same = all(np.array_equal(first, _rows(table, self.key_vertices[i][used]))
                       for i in range(1, len(self.times)))
            first.flags.writeable = False
            entry = self._same_at_every_key[memory] = (table, first if same else None)
        return entry[1] if entry[1] is not None else _rows(table, self.key_vertices[key][used])

    def cut(self, points: np.ndarray, vertex_attributes: Mapping[str, np.ndarray],
            simplex_attributes: Mapping[str, np.ndarray], gap: int) -> "PrismGap":
        """Gap `gap`'s frames, gathered once from the manifold's arrays."""
        used, faces = self._frame_vertices
        a, b = self.key_vertices[gap][used], self.key_vertices[gap + 1][used]
        simplices = self.face_simplices[gap]
        return PrismGap(
            interval=(float(self.times[gap]), float(self.times[gap + 1])),
            faces=faces, edges=np.stack([a, b], axis=1).astype(np.int32),
            low=_space(points, a), high=_space(points, b),
            attributes={name: (_rows(t, a), _rows(t, b)) for name, t in vertex_attributes.items()},
            face_attributes={name: squeezed(_rows(t, simplices)) for name, t in simplex_attributes.items()},
            face_simplex=np.array(simplices, dtype=np.int32))

    def key_frame(self, points: np.ndarray, vertex_attributes: Mapping[str, np.ndarray],
                  simplex_attributes: Mapping[str, np.ndarray], value: float, axis: int) -> Slice | None:
        """The frame at `value`, a key's time (or within the core's snap of one: the
        caller saw no topology interval there), as the key itself: the faces over the
        key's vertices, so a key and the frames around it share the source's faces.
        None unless the gap whose tets give the key's faces (the one above it; the last
        key's, below) is played as prisms, and the gap `value` lies in holds (no other
        vertex near it, so the key is what the core snapped to)."""
        times, m = self.times, len(self.times)
        i = int(np.argmin(np.abs(times - value)))
        layer_gap = min(i, m - 2)
        containing = i if value >= times[i] else i - 1
        if not self.gaps[layer_gap] or (value != times[i] and not (0 <= containing < m - 1 and self.gaps[containing])):
            return None
        used, faces = self._frame_vertices
        key = self.key_vertices[i][used]
        simplices = self.face_simplices[layer_gap]
        return Slice(axis=axis, value=float(value), vertices=_space(points, key), faces=faces, normals=None,
                     vertex_attributes={k: squeezed(self._key_rows(k, t, i)) for k, t in vertex_attributes.items()},
                     face_attributes={k: squeezed(_rows(t, simplices)) for k, t in simplex_attributes.items()},
                     vertex_edges=np.stack([key, key], axis=1).astype(np.int32),
                     edge_parameter=np.zeros(len(key)), face_simplex=np.array(simplices, dtype=np.int32))

    def arrays(self) -> dict[str, np.ndarray]:
        """The named 2D arrays the cache file stores (CACHE_ARRAYS)."""
        m = len(self.times)
        return dict(zip(CACHE_ARRAYS, (self.times.reshape(m, 1), self.key_vertices, self.faces,
                                       self.face_simplices.reshape(m - 1, -1), self.gaps.astype(np.int32)[:, None])))

    @classmethod
    def from_arrays(cls, arrays: Mapping[str, np.ndarray]) -> "Prisms | None":
        """The structure from the cache's named arrays: None when none of them is there;
        ValueError when only some are (check it with :meth:`checked`)."""
        present = [name for name in CACHE_ARRAYS if name in arrays]
        if not present:
            return None
        if len(present) != len(CACHE_ARRAYS):
            missing = sorted(set(CACHE_ARRAYS) - set(present))
            raise InputError(f"the prism structure is incomplete: {', '.join(missing)} missing")
        times, key_vertices, faces, face_simplices, gaps = (arrays[name] for name in CACHE_ARRAYS)
        return cls(np.asarray(times).reshape(-1), key_vertices, faces, face_simplices, np.asarray(gaps).reshape(-1))


@dataclass(frozen=True, eq=False)
class PrismGap:
    """One gap's frames: the faces, each frame vertex's vertical edge (a at the lower key,
    b at the upper), its positions and vertex attributes at both keys, the face attributes."""

    interval: tuple[float, float]
    faces: np.ndarray
    edges: np.ndarray  # (P, 2) int32 manifold vertices
    low: np.ndarray  # (P, D-1)
    high: np.ndarray
    attributes: Mapping[str, tuple[np.ndarray, np.ndarray]]
    face_attributes: Mapping[str, np.ndarray]
    face_simplex: np.ndarray

    def parameter(self, value: float) -> float:
        """How far `value` is along the gap, as the core computes it for a point on an edge."""
        lo, hi = self.interval
        return (value - lo) / (hi - lo)

    def slice(self, value: float, axis: int) -> Slice:
        """The frame at `value` (strictly inside the interval)."""
        s = self.parameter(float(value))
        vertices = (1.0 - s) * self.low + s * self.high
        return Slice(axis=axis, value=float(value), vertices=vertices, faces=self.faces,
                     normals=None,
                     vertex_attributes={k: squeezed((1.0 - s) * a + s * b) for k, (a, b) in self.attributes.items()},
                     face_attributes=dict(self.face_attributes), vertex_edges=self.edges,
                     edge_parameter=np.full(len(vertices), s), face_simplex=self.face_simplex)

    def interval_frame(self, value: float, axis: int) -> IntervalFrame:
        """The frame at `value` with the gap as its interval and every vertex's rate along its edge."""
        lo, hi = self.interval
        inverse = 1.0 / (hi - lo)
        return IntervalFrame(self.slice(value, axis), self.interval, (self.high - self.low) * inverse,
                             {k: squeezed((b - a) * inverse) for k, (a, b) in self.attributes.items()},
                             np.full(len(self.low), inverse))


def _holding_gaps(layer_times: np.ndarray, times: np.ndarray) -> np.ndarray:
    """(m-1,) bool: per gap, whether its frames are its prisms' alone. Both keys' vertices
    (rows of `layer_times`, (m, k)) are at their times, the keys below stay at or below the
    gap and those above at or above it: every other prism's simplices then lie outside."""
    at_time = np.all(layer_times == times[:, None], axis=1)
    below = np.maximum.accumulate(layer_times.max(axis=1))  # below[j]: the latest time of keys 0..j
    above = np.minimum.accumulate(layer_times.min(axis=1)[::-1])[::-1]  # above[j]: the earliest of keys j..
    m = len(times)
    fits_below = np.r_[True, below[:m - 2] <= times[1:m - 1]]  # keys 0..i-1 at or below t_i
    fits_above = np.r_[above[2:] >= times[1:m - 1], True]  # keys i+2.. at or above t_{i+1}
    return at_time[:-1] & at_time[1:] & fits_below & fits_above


def _rows(table, rows: np.ndarray) -> np.ndarray:
    """table[rows] for a table of rows: np.take, several times faster than fancy indexing
    of a 2D array (a frame's gathers are most of a cold playback frame's cost)."""
    return np.take(np.asarray(table), rows, axis=0)


def _space(points: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The rows' coordinates but the last (time), contiguous: copied column by column,
    since numpy copies a (P, 3) view of (P, 4) rows row by row, ~5x slower (and callers
    convert the frame to float32 for Blender, as slowly again from a strided view)."""
    taken = _rows(points, rows)
    space = np.empty((len(rows), taken.shape[1] - 1), dtype=taken.dtype)
    for c in range(space.shape[1]):
        space[:, c] = taken[:, c]
    return space


def _int_table(values, what: str) -> np.ndarray:
    table = np.asarray(values)
    if table.ndim != 2:
        raise InputError(f"{what} must be a 2D table, got shape {table.shape}")
    if table.size and not np.issubdtype(table.dtype, np.integer):
        raise InputError(f"{what} must be integers, got {table.dtype}")
    # A copy the caller cannot change; int32 (what Prisms keeps, and what a stitch gives) stays
    # int32, any other integer type is widened so its range check sees its values.
    return np.array(table, dtype=np.int32 if table.dtype == np.int32 else np.int64)


def _check_range(table: np.ndarray, count: int, what: str) -> None:
    bad = np.flatnonzero((table < 0) | (table >= count))
    if len(bad):
        raise InputError(f"{what} {table.reshape(-1)[bad[0]]} (entry {bad[0]}) is outside 0..{count - 1}")

