"""Barycentric refinement (chapter 6): insert vertices into a simplicial complex of any dimension.

:func:`refine_complex` refines raw arrays; :func:`refine` refines an
:class:`~animanifold.AnimationManifold` and returns a new one.

A split is ``(vertex_ids, barycentric)``: a simplex of the complex (an edge, a
triangle, a tet, ... given by vertex indices) and coordinates over its
vertices. Each applied split adds one vertex and splits every simplex around
that face, so the result stays a conforming, consistently oriented complex::

    import animanifold as am
    r = am.refine_complex(points, simplices, [([0, 1], [0.5, 0.5]), ([1, 2, 3], [0.2, 0.3, 0.5])])
    r.points, r.simplices, r.new_vertex_of_split, r.parent_simplex
    refined, r = am.refine(manifold, splits)      # the same on an animation manifold

Pending splits that a split destroys are re-homed by eq. 6.1; coordinates
below ``epsilon`` are dropped (the split moves to the lower face) and a split
left within ``epsilon`` of an existing vertex is removed (§6.3). The work is
done by the native core (``animanifold/refine.hpp``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from . import _core
from .choices import checked, names
from .manifold import AnimationManifold
from .option_keywords import options_from
from ._core import InputError

ORDERS = names(_core.RefineOrder)


@dataclass(frozen=True)
class Refinement:
    """The refined complex and its relation to the input.

    points (N', D): the input points first, then one per applied split in
    the order applied. simplices (M', k), oriented like their parents.
    new_vertex_of_split (T,): the vertex each split created, -1 when the
    sliver control removed it; snapped_vertex_of_split (T,): for a removed
    split the existing vertex it coincided with (-1 for applied splits).
    split_of_vertex (N',): the split that created each vertex, -1 for input
    vertices. parent_simplex (M',): the input simplex each simplex comes from.
    applied_simplex (T, k) / applied_barycentric (T, k): the face (sorted ids,
    -1 padded) and coordinates each split was finally applied with, after
    re-homing and downgrading. Vertex attributes are interpolated with those
    coordinates; simplex attributes are copied from the parent.
    """

    points: np.ndarray
    simplices: np.ndarray
    new_vertex_of_split: np.ndarray
    snapped_vertex_of_split: np.ndarray
    split_of_vertex: np.ndarray
    parent_simplex: np.ndarray
    applied_simplex: np.ndarray
    applied_barycentric: np.ndarray
    vertex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)
    simplex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)

    @property
    def removed(self) -> np.ndarray:
        """(T,) bool: the splits removed by the sliver control."""
        return self.new_vertex_of_split < 0


@dataclass(frozen=True)
class RefineOptions:
    """How :func:`refine` and :func:`refine_complex` apply their splits.

    epsilon: the barycentric sliver tolerance in [0, 0.5) (default 1e-3):
      coordinates below it are dropped, and a split within it of an
      existing vertex is removed (§6.3).
    order: "degeneracy" (default; least degenerate split first, §6.3) or
      "given" (input order).
    """

    epsilon: float = 1e-3
    order: str = "degeneracy"

    def __post_init__(self):
        # Frozen: the checked name replaces an enum member given for the order.
        object.__setattr__(self, "order", checked(self.order, _core.RefineOrder, "order"))
        if isinstance(self.epsilon, bool) or not isinstance(self.epsilon, (int, float, np.number)) \
                or not 0.0 <= self.epsilon < 0.5:
            raise InputError(f"epsilon must be a number in [0, 0.5), got {self.epsilon!r}")


def refine(
    manifold: AnimationManifold,
    splits,
    *,
    options: RefineOptions | None = None,
    epsilon: float | None = None,
    order: str | None = None,
) -> tuple[AnimationManifold, Refinement]:
    """Barycentric refinement of an animation manifold (chapter 6).

    splits as in :func:`refine_complex`; options a :class:`RefineOptions`,
    or its epsilon and order as keywords (not both: ValueError). Returns a new
    manifold (vertex attributes interpolated, simplex attributes inherited,
    metadata and hole space kept: the shape does not change) and the
    :class:`Refinement` with new_vertex_of_split, parent_simplex and the
    other maps.
    """
    r = refine_complex(manifold.points, manifold.simplices, splits,
                       options=options_from(RefineOptions, options, epsilon=epsilon, order=order),
                       vertex_attributes=manifold.vertex_attributes,
                       simplex_attributes=manifold.simplex_attributes)
    refined = AnimationManifold.from_arrays(r.points, r.simplices, r.vertex_attributes, r.simplex_attributes,
                                            manifold.metadata, manifold.hole_space)
    return refined, r


def refine_complex(
    points: np.ndarray,
    simplices: np.ndarray,
    splits,
    *,
    options: RefineOptions | None = None,
    epsilon: float | None = None,
    order: str | None = None,
    vertex_attributes: Mapping[str, np.ndarray] | None = None,
    simplex_attributes: Mapping[str, np.ndarray] | None = None,
) -> Refinement:
    """Applies barycentric split tuples to a simplicial complex (chapter 6).

    points (N, D) float; simplices (M, k) int vertex indices, k <= 8, any D
    (triangles in R^3, tets in R^4, tets in R^3, ...). splits: a sequence of
    ``(vertex_ids, barycentric)`` pairs — ids of a face of the complex
    (1..k distinct vertices) and as many coordinates >= 0 summing to 1 — or,
    for large batches, a pair of (T, m) arrays ``(ids, barycentric)`` with
    rows padded by -1 ids. options: a :class:`RefineOptions` (the sliver
    tolerance epsilon and the order), or its fields as keywords (not both:
    ValueError). vertex_attributes: name -> (N,) or (N, c) floats,
    interpolated; simplex_attributes: name -> (M,) or (M, c) ints, inherited.

    Raises ValueError naming the split (and vertex) at fault.
    """
    options = options_from(RefineOptions, options, epsilon=epsilon, order=order)
    points = np.ascontiguousarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] < 1:
        raise InputError(f"points must be (N, D), got shape {points.shape}")
    simplices = np.asarray(simplices)
    if simplices.ndim != 2:
        raise InputError(f"simplices must be (M, k), got shape {simplices.shape}")
    if simplices.size and not np.issubdtype(simplices.dtype, np.integer):
        raise InputError(f"simplices must be integer vertex indices, got {simplices.dtype}")
    simplices = np.ascontiguousarray(simplices, dtype=np.int32)
    k = simplices.shape[1]
    ids, coords = _split_arrays(splits, k)

    squeeze_vertex, va = _tables(vertex_attributes, np.float64, "vertex attribute")
    squeeze_simplex, sa = _tables(simplex_attributes, np.int32, "simplex attribute")
    out = _core.refine(points, simplices, va, sa, ids, coords, float(options.epsilon), options.order)

    def restore(tables: Mapping[str, np.ndarray], squeezed: set[str]) -> dict[str, np.ndarray]:
        return {name: table[:, 0] if name in squeezed else table for name, table in tables.items()}

    return Refinement(
        points=out.points,
        simplices=out.simplices,
        new_vertex_of_split=out.new_vertex_of_split,
        snapped_vertex_of_split=out.snapped_vertex_of_split,
        split_of_vertex=out.split_of_vertex,
        parent_simplex=out.parent_simplex,
        applied_simplex=out.applied_simplex,
        applied_barycentric=out.applied_barycentric,
        vertex_attributes=restore(out.vertex_attributes, squeeze_vertex),
        simplex_attributes=restore(out.simplex_attributes, squeeze_simplex),
    )


def _split_arrays(splits, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(ids, barycentric) as (T, k) int32 / float64 arrays, ids padded with -1."""
    if (
        isinstance(splits, tuple)
        and len(splits) == 2
        and all(isinstance(a, np.ndarray) and a.ndim == 2 for a in splits)
    ):
        ids, coords = splits
        if ids.shape != coords.shape:
            raise InputError(f"split ids are {ids.shape} but barycentric coordinates are {coords.shape}")
        if ids.shape[1] > k:
            raise InputError(f"splits name up to {ids.shape[1]} vertices but the simplices have {k}")
        if ids.size and not np.issubdtype(ids.dtype, np.integer):
            raise InputError(f"split ids must be integers, got {ids.dtype}")
        padded_ids = np.full((len(ids), k), -1, dtype=np.int32)
        padded_coords = np.zeros((len(ids), k), dtype=np.float64)
        padded_ids[:, : ids.shape[1]] = ids
        padded_coords[:, : ids.shape[1]] = coords
        return padded_ids, padded_coords

    splits = list(splits)
    padded_ids = np.full((len(splits), k), -1, dtype=np.int32)
    padded_coords = np.zeros((len(splits), k), dtype=np.float64)
    for t, split in enumerate(splits):
        try:
            vertex_ids, barycentric = split
        except (TypeError, ValueError):
            raise InputError(f"split {t} must be a pair (vertex_ids, barycentric), got {split!r}") from None
        vertex_ids = np.asarray(vertex_ids).reshape(-1)
        barycentric = np.asarray(barycentric, dtype=np.float64).reshape(-1)
        if vertex_ids.size and not np.issubdtype(vertex_ids.dtype, np.integer):
            raise InputError(f"split {t}: vertex ids must be integers, got {vertex_ids.dtype}")
        if not 1 <= len(vertex_ids) <= k:
            raise InputError(f"split {t} names {len(vertex_ids)} vertices; a face of these simplices has 1..{k}")
        if len(barycentric) != len(vertex_ids):
            raise InputError(
                f"split {t} has {len(vertex_ids)} vertex ids but {len(barycentric)} barycentric coordinates"
            )
        if np.any(vertex_ids < 0) or np.any(vertex_ids >= 2**31):
            bad = int(vertex_ids[(vertex_ids < 0) | (vertex_ids >= 2**31)][0])
            raise InputError(f"split {t}: vertex {bad} is not a vertex index")
        padded_ids[t, : len(vertex_ids)] = vertex_ids
        padded_coords[t, : len(vertex_ids)] = barycentric
    return padded_ids, padded_coords


def _tables(tables: Mapping[str, np.ndarray] | None, dtype, what: str) -> tuple[set[str], dict[str, np.ndarray]]:
    """2D C-contiguous copies of attribute tables, and the names given as 1D (to squeeze back)."""
    squeezed: set[str] = set()
    out: dict[str, np.ndarray] = {}
    for name, values in (tables or {}).items():
        table = np.asarray(values)
        if table.ndim == 1:
            squeezed.add(name)
            table = table[:, None]
        if table.ndim != 2:
            raise InputError(f"{what} {name!r} must be 1D or 2D, got shape {table.shape}")
        if dtype is np.int32 and table.size and not np.issubdtype(table.dtype, np.integer):
            raise InputError(f"{what} {name!r} must be integers, got {table.dtype}")
        out[name] = np.ascontiguousarray(table, dtype=dtype)
    return squeezed, out


__all__ = ["Refinement", "refine", "refine_complex"]
