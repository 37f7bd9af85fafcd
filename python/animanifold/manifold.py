"""The animation manifold data type: numpy in, numpy out, backed by the native core.

An :class:`AnimationManifold` holds points (N, D) — (x, y, z, t) or (x, y, t) —
and oriented simplices (M, D) in the core's own memory; the arrays it returns
are read-only views, not copies. :meth:`AnimationManifold.slice` cuts a frame
(or a sweep view along x, y or z) through a cached interval index, so a frame
costs what it cuts. Operations that make a new manifold are free functions in
their own modules: :func:`animanifold.refine`, :func:`animanifold.deform`,
:func:`animanifold.subdivide`, :func:`animanifold.weld`.
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import Iterable, Iterator, Mapping

import numpy as np

from . import _core
from .frame_smoothing import smooth_slice
from .hole_cut import cut_frame
from .indices import as_indices
from .interval_frame import IntervalFrame
from .prism_frames import PrismGap, Prisms
from .slices import Slice, squeezed
from ._core import InputError

AXES = {"x": 0, "y": 1, "z": 2, "t": -1}


class HoleSpaceWarning(UserWarning):
    """A frame could not be cut by its manifold's hole space and is shown uncut."""


def axis_index(axis: str | int, dimension: int) -> int:
    """Column of `axis` ('x', 'y', 'z', 't' or an int) in points of `dimension` columns."""
    if isinstance(axis, str):
        key = axis.lower()
        if key not in AXES:
            raise InputError(f"unknown axis {axis!r}: use 't', 'x', 'y' or 'z'")
        if key == "z" and dimension < 4:
            raise InputError("a 2D animation manifold (x, y, t) has no z axis")
        index = AXES[key]
        return dimension - 1 if index < 0 else index
    index = int(axis)
    if not -dimension <= index < dimension:
        raise InputError(f"axis {axis} is outside 0..{dimension - 1}")
    return index % dimension


class AnimationManifold:
    """An n-manifold of n-simplices in R^(n+1) whose last coordinate is time.

    What it holds:

    * points (N, D) float64, D = 4 for animated surfaces (x, y, z, t), 3 for
      animated contours (x, y, t);
    * simplices (M, D) int32, oriented n-simplices (tets in R^4, triangles in R^3);
    * vertex_attributes: name -> (N, c) float64 (UVs, ...), interpolated by slices;
    * simplex_attributes: name -> (M, c) int32 (material index, ...), inherited;
    * metadata: a plain dict (keyframe_times, keyframe_vertices / _faces from
      :func:`stitch`, a morph's validity report, subdivisions, regularisation);
    * hole_space: for a morph, the holes its source and target share
      (§8.6.5), a solid in R^n as (vertices, faces) like a frame, or None;
    * prisms: for stitched keyframes, which vertex is which key's source
      vertex (:class:`~animanifold.prism_frames.Prisms`), or None. Time slices
      strictly between two keys of a gap it plays are the keys' faces with
      each vertex on its vertical edge (the keys' blend), not the tets'
      staircase; see :meth:`slice`.

    Invariants: points, simplices and attributes never change after
    construction (the arrays are read-only; the core checks indices are in
    range and points finite), so the slicer and time range are cached.
    Operations return new manifolds. Time slices strictly between the first
    and last time of a manifold with a hole space H are frame \\ H
    (validity 3 of §8.3); see :meth:`slice`. :func:`animanifold.weld` and
    :func:`animanifold.refine` keep H (the shape does not change);
    :func:`animanifold.deform` and :func:`animanifold.subdivide` return
    manifolds without it. Operations that make new points or simplices drop
    the prisms unless they provably still hold (:func:`animanifold.deform`
    without regularisation keeps them while every key stays at its time).
    """

    def __init__(
        self,
        complex_: "_core.Complex",
        metadata: Mapping[str, object] | None = None,
        hole_space: tuple[np.ndarray, np.ndarray] | None = None,
        prisms: Prisms | None = None,
    ):
        self._complex = complex_
        self._slicer: _core.Slicer | None = None
        self._time_range: tuple[float, float] | None = None
        self.metadata: dict = dict(metadata or {})
        self._hole_space = _checked_hole_space(hole_space, self.dimension)
        self._prisms = None if prisms is None else prisms.checked(self.points, len(self.simplices))
        self._prism_gap: PrismGap | None = None  # the last gap sliced, gathered

    @classmethod
    def from_arrays(
        cls,
        points: np.ndarray,
        simplices: np.ndarray,
        vertex_attributes: Mapping[str, np.ndarray] | None = None,
        simplex_attributes: Mapping[str, np.ndarray] | None = None,
        metadata: Mapping[str, object] | None = None,
        hole_space: tuple[np.ndarray, np.ndarray] | None = None,
        prisms: Prisms | None = None,
    ) -> "AnimationManifold":
        """Builds a manifold from raw arrays (validated: indices in range, finite
        points); `hole_space` (vertices (k, D-1), faces (l, D-1)) and `prisms`
        as in the class doc (ValueError naming the element when they do not fit)."""
        points = np.ascontiguousarray(points, dtype=np.float64)
        simplices = as_indices(simplices, "simplices")
        if points.ndim != 2 or points.shape[1] not in (3, 4):
            raise InputError(f"points must be (N, 3) or (N, 4), got shape {points.shape}")
        if simplices.ndim != 2 or simplices.shape[1] != points.shape[1]:
            raise InputError(
                f"simplices must be (M, {points.shape[1]}) for {points.shape[1]}D points, got shape {simplices.shape}"
            )
        va = {k: as_table(v, np.float64, f"vertex attribute {k!r}") for k, v in (vertex_attributes or {}).items()}
        sa = {k: as_table(v, np.int32, f"simplex attribute {k!r}") for k, v in (simplex_attributes or {}).items()}
        return cls(_core.Complex(points, simplices, va, sa), metadata, hole_space, prisms)

    # -- data ---------------------------------------------------------------
    @property
    def core_complex(self) -> "_core.Complex":
        """The native complex holding the arrays, for functions that hand it to the core
        (subdivision, benchmarks) without copying."""
        return self._complex

    @property
    def points(self) -> np.ndarray:
        """(N, D) float64, read-only: (x, y, z, t) or (x, y, t)."""
        return self._complex.points

    @property
    def simplices(self) -> np.ndarray:
        """(M, D) int32, read-only, oriented."""
        return self._complex.simplices

    @property
    def vertex_attributes(self) -> dict[str, np.ndarray]:
        return self._complex.vertex_attributes

    @property
    def simplex_attributes(self) -> dict[str, np.ndarray]:
        return self._complex.simplex_attributes

    @property
    def validity(self) -> dict | None:
        """For a morph, the validity report of §8.3 (None for other manifolds)."""
        return self.metadata.get("validity")

    @property
    def hole_space(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The solid subtracted from in-between time slices, (vertices (k, D-1),
        faces (l, D-1)) read-only; None when there is none (every manifold but
        a morph whose inputs share a hole)."""
        return self._hole_space

    @property
    def prisms(self) -> Prisms | None:
        """The prism structure of stitched keyframes (read-only arrays), or None."""
        return self._prisms

    @property
    def has_holes(self) -> bool:
        return self._hole_space is not None

    def _honours_holes(self, axis: int, value: float) -> bool:
        """Whether the slice at `value` along `axis` is cut by the hole space."""
        if self._hole_space is None or axis != self.dimension - 1:
            return False
        t0, t1 = self.time_range
        return t0 < value < t1

    @property
    def dimension(self) -> int:
        """Ambient dimension D (4 for animated surfaces, 3 for animated contours)."""
        return self.points.shape[1]

    @property
    def time_range(self) -> tuple[float, float]:
        if self._time_range is None:  # points never change: compute once
            t = self.points[:, -1]
            self._time_range = (float(t.min()), float(t.max())) if len(t) else (0.0, 0.0)
        return self._time_range

    @property
    def bounding_box(self) -> tuple[np.ndarray, np.ndarray]:
        return self.points.min(axis=0), self.points.max(axis=0)

    def __repr__(self) -> str:
        t0, t1 = self.time_range
        kind = "tets" if self.dimension == 4 else "triangles"
        return f"AnimationManifold({len(self.points)} points, {len(self.simplices)} {kind}, t in [{t0:g}, {t1:g}])"

    # -- queries ------------------------------------------------------------
    def slice(
        self,
        value: float,
        axis: str | int = "t",
        use_index: bool = True,
        smooth_levels: int = 0,
        crease_angle: float = 30.0,
        honour_holes: bool | str = True,
    ) -> Slice:
        """The frame at `value` along `axis` ('t' by default; 'x', 'y', 'z' for sweep views).

        smooth_levels > 0 refines the frame with Loop subdivision (OpenSubdiv),
        projected to the limit surface, with sharp creases where faces meet at
        more than `crease_angle` degrees (frames of 2D animations: cubic
        B-spline curves with corners); the smoothed slice has no
        vertex_edges / edge_parameter (its points are not on manifold edges).

        For a manifold with a hole space H (a morph whose inputs share holes),
        time slices strictly between the first and last time are frame \\ H
        (validity 3 of §8.3); `honour_holes=False` gives the raw slice. Where
        H cuts the frame, the result's new points are not on manifold edges:
        it has no vertex_edges / edge_parameter / face_simplex, its attributes
        are taken back from the raw frame (hole_cut.py: copies split at UV
        seams are welded for the cut and split again after it) and its normals
        are recomputed; where H does not touch the frame,
        the raw slice comes back as it is. A frame that cannot be cut (it
        pinches or intersects itself: the morph is not valid there) comes back
        raw with a :class:`HoleSpaceWarning`; `honour_holes="strict"` raises
        the animanifold.BooleanError instead.

        For stitched keyframes (:attr:`prisms`), a time slice strictly between
        two keys is the keys' faces with every vertex moved linearly along its
        vertical edge (prism_frames.py): the source's face count, its faces,
        the keys' blend. Its vertex_edges are those vertical edges. At a key
        (and within the core's snap of one) it is the key, over the same faces.
        """
        if honour_holes not in (True, False, "strict"):
            raise InputError(f"honour_holes must be True, False or 'strict', got {honour_holes!r}")
        a = axis_index(axis, self.dimension)
        s = self._prism_frame(a, float(value))
        if s is None:
            s = self._core_slicer().slice(a, float(value), use_index)
        if honour_holes and self._honours_holes(a, float(value)):
            try:
                s = _subtract_holes(s, self._hole_space, a, float(value))
            except _core.BooleanError as e:
                if honour_holes == "strict":
                    raise
                warnings.warn(f"the frame at {float(value):g} cannot be cut by the hole space, shown uncut: {e}",
                              HoleSpaceWarning, stacklevel=2)
        if smooth_levels:
            if isinstance(smooth_levels, bool) or int(smooth_levels) != smooth_levels or smooth_levels < 0:
                raise InputError(f"smooth_levels must be a non-negative integer, got {smooth_levels!r}")
            if isinstance(s, Slice):  # cut by the hole space
                return smooth_slice(s, int(smooth_levels), float(crease_angle))
            s = _core.smooth_slice(s, int(smooth_levels), float(crease_angle), True)
            smooth = Slice._from_core(a, float(value), s)
            return dataclasses.replace(smooth, vertex_edges=None, edge_parameter=None)
        return s if isinstance(s, Slice) else Slice._from_core(a, float(value), s)

    def slices(self, values: Iterable[float], axis: str | int = "t") -> Iterator[Slice]:
        """The frames at `values` along `axis`, one at a time: each is exactly
        ``slice(value, axis)`` (bit for bit), but a frame in the same topology
        interval as the frame before it reuses that frame's cut, so writing it
        is a gather and a lerp per vertex instead of a slice. Bakes and exports,
        which slice increasing times, several in each interval, use this.
        Frames the hole space cuts are sliced one by one; prism frames
        (:attr:`prisms`) are a lerp each."""
        a = axis_index(axis, self.dimension)
        slicer = self._core_slicer()
        cut = None  # the core IntervalFrame of the last frame's interval
        for value in values:
            v = float(value)
            prism = self._prism_frame(a, v)
            if prism is not None:
                yield self.slice(v, a) if self._honours_holes(a, v) else prism  # slice() gives `prism` itself
                continue
            interval = None if self._honours_holes(a, v) else slicer.topology_interval(a, v)
            if interval is None:
                cut = None
                yield self.slice(v, a)
                continue
            if cut is not None and cut.interval == interval:
                yield Slice._from_core(a, v, slicer.slice_in_interval(cut, v))
                continue
            cut = slicer.interval_frame(a, v)
            yield Slice._from_core(a, v, cut.slice)

    def topology_interval(self, value: float, axis: str | int = "t") -> tuple[float, float] | None:
        """The open interval (lo, hi) around `value` in which every slice has the
        same faces and cuts the same edges (no vertex lies between lo and hi
        along the axis): within it, :meth:`interval_frame` gives any frame from
        one cut. None when `value` is a vertex coordinate or outside the
        manifold, and for time slices of a manifold with a hole space strictly
        inside its time range: the hole space cuts those frames (:meth:`slice`),
        which changes their faces from frame to frame, so callers fall back to
        slicing every frame (as live playback in Blender does)."""
        a = axis_index(axis, self.dimension)
        return None if self._honours_holes(a, float(value)) else self._core_slicer().topology_interval(a, float(value))

    def interval_frame(self, value: float, axis: str | int = "t") -> IntervalFrame:
        """The frame at `value` along `axis` with its topology interval and every
        vertex's rate along its manifold edge (:class:`IntervalFrame`: its
        :meth:`~IntervalFrame.at` gives any frame of the interval). ValueError
        where :meth:`topology_interval` is None."""
        a = axis_index(axis, self.dimension)
        if self._honours_holes(a, float(value)):
            raise InputError(
                f"the frame at {value} of a manifold with a hole space is cut by it, and the cut changes from "
                "frame to frame: slice every frame (AnimationManifold.slice) instead of moving one")
        prism = self._prism_cut(a, float(value))
        if prism is not None:
            return prism.interval_frame(float(value), a)
        f = self._core_slicer().interval_frame(a, float(value))
        return IntervalFrame(Slice._from_core(a, float(value), f.slice), f.interval, f.rate,
                             {k: squeezed(v) for k, v in f.attribute_rates.items()}, f.parameter_rate)

    def _prism_frame(self, axis: int, value: float) -> Slice | None:
        """The time slice at `value` as the prisms give it (a gap's lerp, or a key), or None
        where the tets' slice is the frame (see :meth:`slice`)."""
        if not self._prism_times(axis, value):
            return None
        interval = self._core_slicer().topology_interval(axis, value)
        if interval is None:
            return self._prisms.key_frame(self.points, self.vertex_attributes, self.simplex_attributes, value, axis)
        gap = self._prism_cut(axis, value)
        return None if gap is None else gap.slice(value, axis)

    def _prism_times(self, axis: int, value: float) -> bool:
        """Whether the prisms may give the time slice at `value`: within the keys' times."""
        if self._prisms is None or axis != self.dimension - 1 or not np.isfinite(value):
            return False
        t0, t1 = self.time_range
        return t0 <= value <= t1

    def _prism_cut(self, axis: int, value: float) -> PrismGap | None:
        """The prism gap whose frames the time slice at `value` is (see :meth:`slice`), or None.
        Its interval is the core's topology interval there (every manifold vertex is a key
        vertex), so the core's snap to a key decides what is a key, as for the tets."""
        if not self._prism_times(axis, value):
            return None
        interval = self._core_slicer().topology_interval(axis, value)
        gap = self._prisms.gap(interval)
        if gap is None:
            return None
        cut = self._prism_gap
        if cut is None or cut.interval != interval:
            cut = self._prisms.cut(self.points, self.vertex_attributes, self.simplex_attributes, gap)
            self._prism_gap = cut
        return cut

    def _core_slicer(self) -> "_core.Slicer":
        if self._slicer is None:
            self._slicer = _core.Slicer(self._complex)
        return self._slicer

    def check(self) -> "_core.ManifoldReport":
        """Manifold validity: facet counts, non-manifold and misoriented facets
        (``.is_oriented_manifold``; ``.to_dict()`` for a JSON report)."""
        return _core.check_manifold(self.simplices)

    def boundary(self) -> np.ndarray:
        """Boundary facets, oriented outward (for a stitched manifold: first and last keyframe)."""
        return _core.boundary_facets(self.simplices)

    def vertex_normals(self) -> np.ndarray:
        """Area-weighted unit normals (N, D) from the wedge product (§2.3)."""
        return _core.vertex_normals(self.points, self.simplices)


def _checked_hole_space(hole_space, dimension: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The hole space as read-only (float64, int32) arrays, or None when absent or empty."""
    if hole_space is None:
        return None
    try:
        vertices, faces = hole_space
    except (TypeError, ValueError):
        raise InputError("hole_space must be a pair (vertices, faces)") from None
    d = dimension - 1
    v = np.array(vertices, dtype=np.float64, order="C")
    f = np.asarray(faces)
    if f.size == 0:
        f = f.reshape(0, d)
    if v.ndim != 2 or v.shape[1] != d or f.ndim != 2 or f.shape[1] != d:
        raise InputError(f"the hole space of a manifold in R^{dimension} must be vertices (k, {d}) and faces "
                         f"(l, {d}), got shapes {v.shape} and {f.shape}")
    if f.size and (not np.issubdtype(f.dtype, np.integer) or f.min() < 0 or f.max() >= len(v)):
        raise InputError(f"the hole space's faces must be integer indices into its {len(v)} vertices")
    if not np.isfinite(v).all():
        raise InputError("the hole space has a vertex that is not finite")
    if not len(f):
        return None
    f = np.array(f, dtype=np.int32, order="C")
    v.flags.writeable = False
    f.flags.writeable = False
    return v, f


def _subtract_holes(s: "_core.Slice", hole: tuple[np.ndarray, np.ndarray], axis: int, value: float):
    """frame \\ hole for a core slice `s`: `s` itself when the hole cannot touch it, else a Slice
    of the cut frame (no edge maps; attributes carried: hole_cut.py)."""
    cut = cut_frame(s.vertices, s.faces, s.vertex_attributes, s.face_attributes, hole)
    if cut is None:
        return s
    return Slice(axis=axis, value=value, vertices=cut.vertices, faces=cut.faces,
                 normals=_core.frame_vertex_normals(cut.vertices, cut.faces),
                 vertex_attributes={k: squeezed(v) for k, v in cut.vertex_attributes.items()},
                 face_attributes={k: squeezed(v) for k, v in cut.face_attributes.items()})


def as_table(values: np.ndarray, dtype, what: str) -> np.ndarray:
    """`values` as a C-contiguous 2D table of `dtype` (a 1D array becomes one column);
    ValueError naming `what` for another shape or non-integers where integers are due."""
    table = np.asarray(values)
    if table.ndim == 1:
        table = table[:, None]
    if table.ndim != 2:
        raise InputError(f"{what} must be 1D or 2D, got shape {table.shape}")
    if dtype is np.int32:
        return as_indices(table, what)
    return np.ascontiguousarray(table, dtype=dtype)
