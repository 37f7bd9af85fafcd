"""Offline regularisation of a Laplacian deformation (§4.5.1).

A large handle motion stretches the simplices between anchors and handles
into long slivers, and the Laplacian then behaves badly on them. After the
deformation, every edge whose Manhattan length in the *deformed* complex
exceeds ε is split at its midpoint in the *undeformed* complex (barycentric
refinement, :func:`animanifold.refine_complex`); the new vertices get uniform weights
and δ = 0 (the Deformer's ``zero_detail_vertices``: their deformed position is
the centroid of their neighbours), and the deformation is applied again to
the refined complex, until no edge splits or the iteration cap::

    points, simplices, maps = am.regularise(P, S, anchors, handles, T,
                                            options=am.RegulariseOptions(max_iterations=5))
    maps.converged, maps.iterations, maps.splits   # how it ended
    maps.rest_points                               # the refined undeformed complex

Error measure (§4.5.1): the Manhattan length Σ_k w_k |Δx_k| of an edge
(``axis_weights`` w, all ones by default, so time counts like space for an
animation manifold), compared with ε = 2 × the mean Manhattan edge length of
the undeformed input (``epsilon`` overrides it). Only edges the deformation
stretched are split: an edge longer than ε already in the input (a long
time edge between two keyframes, say) is split only when the deformation
made it longer still, so a zero motion changes nothing.

Constraints are inherited: a vertex split on an edge between two anchors is
an anchor, between two handles a handle (moved by the same transform, or, for
explicit ``handle_positions``, to the midpoint of its parents' targets);
anything else is free.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, NamedTuple

import numpy as np

from .interrupting import InterruptedCallback, ProgressCallback, Span
from .laplacian import Deformer, LaplacianOptions, _is_count, _vertex_list, solve
from .refinement import refine_complex
from ._core import InputError


@dataclass(frozen=True)
class RegulariseOptions:
    """When the offline regularisation of §4.5.1 splits an edge, and how long it goes on.

    epsilon: the Manhattan edge-length threshold; None (default) takes
      2 × the undeformed complex's mean Manhattan edge length.
    axis_weights: per-axis weights w of the Manhattan length, one per
      coordinate of the points (D numbers, finite, non-negative, not all zero);
      None (default) weighs every axis 1, so time counts like space.
    max_iterations: cap on the refinement rounds (default 10; 0 deforms once
      and reports whether edges would split).
    """

    epsilon: float | None = None
    axis_weights: tuple[float, ...] | None = None
    max_iterations: int = 10

    def __post_init__(self):
        if self.epsilon is not None and (isinstance(self.epsilon, bool) or not np.isfinite(self.epsilon)
                                         or self.epsilon <= 0):
            raise InputError(f"epsilon must be a positive number, got {self.epsilon!r}")
        if not _is_count(self.max_iterations):
            raise InputError(f"max_iterations must be a non-negative integer, got {self.max_iterations!r}")
        if self.axis_weights is not None:
            weights = np.asarray(self.axis_weights, dtype=np.float64).reshape(-1)
            if (weights < 0).any() or not np.isfinite(weights).all() or not weights.any():
                raise InputError(f"axis_weights must be finite non-negative numbers, not all zero, "
                                 f"got {self.axis_weights!r}")
            # A tuple keeps the options immutable and comparable.
            object.__setattr__(self, "axis_weights", tuple(float(w) for w in weights))


@dataclass(frozen=True)
class RegularisationMaps:
    """How the regularised complex relates to the input, and how it ended.

    rest_points (N', D): the refined undeformed complex (input points first,
    then the split vertices in the order made). anchors, handles: vertex
    indices in it, inherited ones included. new_vertices: the vertices the
    regularisation added (N..N'-1; zero detail). parent_simplex (M',): the
    input simplex each output simplex descends from. epsilon: the threshold
    used. splits: edges split in each round; iterations = len(splits);
    converged: the last deformation left no edge to split (False: the cap
    ``max_iterations`` stopped it). max_edge_length / mean_edge_length: of
    the final deformed complex (Manhattan, weighted). vertex_attributes /
    simplex_attributes: the input's, interpolated / inherited.
    """

    rest_points: np.ndarray
    anchors: np.ndarray
    handles: np.ndarray
    new_vertices: np.ndarray
    parent_simplex: np.ndarray
    epsilon: float
    splits: tuple[int, ...]
    converged: bool
    max_edge_length: float
    mean_edge_length: float
    vertex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)
    simplex_attributes: Mapping[str, np.ndarray] = field(default_factory=dict)

    @property
    def iterations(self) -> int:
        return len(self.splits)

    def summary(self) -> dict:
        """JSON-friendly status (for reports and manifold metadata)."""
        return {
            "epsilon": float(self.epsilon),
            "iterations": self.iterations,
            "splits": [int(s) for s in self.splits],
            "added_vertices": int(len(self.new_vertices)),
            "converged": bool(self.converged),
            "max_edge_length": float(self.max_edge_length),
            "mean_edge_length": float(self.mean_edge_length),
        }


class Regularisation(NamedTuple):
    """``points, simplices, maps = am.regularise(...)``: the deformed, refined
    points (N', D), its simplices (M', D) and the :class:`RegularisationMaps`."""

    points: np.ndarray
    simplices: np.ndarray
    maps: RegularisationMaps


def edges_of(simplices: np.ndarray, vertex_count: int) -> np.ndarray:
    """(E, 2) unique edges (sorted pairs) of the simplices."""
    S = np.asarray(simplices, dtype=np.int64)
    k = S.shape[1]
    pairs = [np.sort(S[:, [i, j]], axis=1) for i in range(k) for j in range(i + 1, k)]
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    E = np.concatenate(pairs)
    keys = np.unique(E[:, 0] * np.int64(vertex_count) + E[:, 1])
    return np.stack([keys // vertex_count, keys % vertex_count], axis=1)


def manhattan_lengths(points: np.ndarray, edges: np.ndarray, axis_weights: np.ndarray | None = None) -> np.ndarray:
    """Σ_k w_k |p_b − p_a|_k for each edge (a, b)."""
    d = np.abs(points[edges[:, 1]] - points[edges[:, 0]])
    return d.sum(axis=1) if axis_weights is None else d @ axis_weights


def _inherit(flags: np.ndarray, parents: np.ndarray, created: np.ndarray) -> None:
    """flags[created[t]] = all(flags[parents[t]]) (parents padded with -1), in place.
    A parent may itself be created earlier in the batch: repeat until stable."""
    valid = parents >= 0
    safe = np.where(valid, parents, 0)
    for _ in range(len(created) + 1):
        new = np.where(valid, flags[safe], True).all(axis=1)
        if np.array_equal(flags[created], new):
            return
        flags[created] = new


def regularise(
    points: np.ndarray,
    simplices: np.ndarray,
    anchors,
    handles,
    transform: np.ndarray | None = None,
    *,
    handle_positions: np.ndarray | None = None,
    laplacian: LaplacianOptions = LaplacianOptions(),
    options: RegulariseOptions = RegulariseOptions(),
    vertex_attributes: Mapping[str, np.ndarray] | None = None,
    simplex_attributes: Mapping[str, np.ndarray] | None = None,
    progress: ProgressCallback | None = None,
    interrupted: InterruptedCallback | None = None,
) -> Regularisation:
    """Deforms (like :func:`animanifold.laplacian_deform`) and regularises the
    result by the offline scheme of §4.5.1; see the module docstring.

    transform: (D+1)x(D+1) affine handle motion, or handle_positions (H, D)
    in the order of `handles`. laplacian: how each :class:`Deformer` solves
    (:class:`LaplacianOptions`); options: the threshold, axis weights and
    round cap (:class:`RegulariseOptions`). vertex_attributes /
    simplex_attributes are carried through the refinement (interpolated /
    inherited) into ``maps``.

    ``progress(step, fraction)`` follows each round's factorisation and solve
    (round k of at most ``max_iterations + 1`` fills the k-th equal part of
    [0, 1]; "done" at 1), ``interrupted()`` is polled with it; False from the
    one or True from the other raises :class:`animanifold.Cancelled`.
    """
    rest, S = _checked_complex(points, simplices)
    if (transform is None) == (handle_positions is None):
        raise InputError("give exactly one of transform ((D+1)x(D+1)) or handle_positions ((H, D))")
    n, D = rest.shape
    weights = None
    if options.axis_weights is not None:
        weights = np.asarray(options.axis_weights, dtype=np.float64)
        if weights.shape != (D,):
            raise InputError(f"axis_weights must be {D} finite non-negative numbers, not all zero, "
                             f"got {options.axis_weights!r}")
    state = _ConstraintState.of(n, D, anchors, handles, handle_positions)
    epsilon = _threshold(rest, S, weights, options.epsilon)

    span = Span(progress, interrupted)
    rounds = options.max_iterations + 1

    def deformed_by_solve(rest_points, simplices_, zero):
        part = span.part(len(splits) / rounds, (len(splits) + 1) / rounds)
        hs = np.flatnonzero(state.is_handle)
        d = Deformer.from_options(rest_points, simplices_, np.flatnonzero(state.is_anchor), hs, laplacian,
                                  zero_detail_vertices=zero, progress=part.part(0.0, 0.6).core_progress(),
                                  interrupted=interrupted)
        positions = None if state.targets is None else state.targets[hs]
        return np.array(solve(d, transform if positions is None else None, positions, laplacian, part.part(0.6, 1.0)))

    va = {k: np.asarray(v) for k, v in (vertex_attributes or {}).items()}
    sa = {k: np.asarray(v) for k, v in (simplex_attributes or {}).items()}
    parent = np.arange(len(S), dtype=np.int64)
    splits: list[int] = []
    deformed = deformed_by_solve(rest, S, np.zeros(0, dtype=np.int64))
    converged = False
    while True:
        long = _stretched_edges(rest, deformed, S, weights, epsilon)
        if not len(long):
            converged = True
            break
        if len(splits) >= options.max_iterations:
            break
        r = refine_complex(rest, S, (long.astype(np.int32), np.full(long.shape, 0.5)), order="degeneracy",
                           vertex_attributes=va, simplex_attributes=sa)
        created = state.inherit(r, len(rest))
        if not len(created):  # every split snapped to an existing vertex: nothing can change
            break
        rest, S = r.points, r.simplices
        parent = parent[r.parent_simplex]
        va, sa = dict(r.vertex_attributes), dict(r.simplex_attributes)
        splits.append(int(len(created)))
        deformed = deformed_by_solve(rest, S, np.arange(n, len(rest), dtype=np.int64))

    span.step("done", 1.0)
    final = manhattan_lengths(deformed, edges_of(S, len(rest)), weights)
    maps = RegularisationMaps(
        rest_points=rest,
        anchors=np.flatnonzero(state.is_anchor),
        handles=np.flatnonzero(state.is_handle),
        new_vertices=np.arange(n, len(rest)),
        parent_simplex=parent,
        epsilon=epsilon,
        splits=tuple(splits),
        converged=converged,
        max_edge_length=float(final.max()) if len(final) else 0.0,
        mean_edge_length=float(final.mean()) if len(final) else 0.0,
        vertex_attributes=va,
        simplex_attributes=sa,
    )
    return Regularisation(deformed, np.ascontiguousarray(S, dtype=np.int32), maps)


def _checked_complex(points, simplices) -> tuple[np.ndarray, np.ndarray]:
    """(points float64, simplices int32), checked to be n-simplices in R^(n+1) with n = 2 or 3."""
    rest = np.ascontiguousarray(points, dtype=np.float64)
    S = np.asarray(simplices)
    if rest.ndim != 2 or rest.shape[1] not in (3, 4):
        raise InputError(f"points must be (N, 3) or (N, 4), got shape {rest.shape}")
    if S.ndim != 2 or S.shape[1] != rest.shape[1]:
        raise InputError(f"simplices must be (M, {rest.shape[1]}) for {rest.shape[1]}D points, got shape {S.shape}")
    if S.size and not np.issubdtype(S.dtype, np.integer):
        raise InputError(f"simplices must be integer vertex indices, got {S.dtype}")
    return rest, np.ascontiguousarray(S, dtype=np.int32)


def _threshold(rest: np.ndarray, S: np.ndarray, weights: np.ndarray | None, epsilon: float | None) -> float:
    """The given epsilon, or 2 × the mean Manhattan edge length of the undeformed complex."""
    if epsilon is not None:
        return float(epsilon)
    lengths = manhattan_lengths(rest, edges_of(S, len(rest)), weights)
    if not len(lengths) or lengths.mean() <= 0:
        raise InputError("the complex has no edges of positive length: no default epsilon")
    return 2.0 * float(lengths.mean())


def _stretched_edges(rest, deformed, S, weights, epsilon: float) -> np.ndarray:
    """(E', 2) the edges longer than epsilon after the deformation that it stretched."""
    edges = edges_of(S, len(rest))
    after = manhattan_lengths(deformed, edges, weights)
    before = manhattan_lengths(rest, edges, weights)
    # Relative slack for round-off: an edge the motion left as long as it was is not split.
    long = (after > epsilon) & (after > before * (1 + 1e-9) + 1e-12 * epsilon)
    return edges[long]


@dataclass
class _ConstraintState:
    """Which vertices of the growing complex are anchors and handles, and where
    explicit handle positions send them (None for a transform)."""

    is_anchor: np.ndarray
    is_handle: np.ndarray
    targets: np.ndarray | None

    @classmethod
    def of(cls, n: int, D: int, anchors, handles, handle_positions) -> "_ConstraintState":
        anchor_ids = _vertex_list(anchors, "anchors", n)
        handle_ids = _vertex_list(handles, "handles", n)
        is_anchor = np.zeros(n, dtype=bool)
        is_anchor[anchor_ids] = True
        is_handle = np.zeros(n, dtype=bool)
        is_handle[handle_ids] = True
        targets = None
        if handle_positions is not None:
            P = np.asarray(handle_positions, dtype=np.float64)
            if P.shape != (len(handle_ids), D):
                raise InputError(f"handle_positions must be ({len(handle_ids)}, {D}), one row per handle, got {P.shape}")
            targets = np.zeros((n, D))
            targets[handle_ids] = P
        return cls(is_anchor, is_handle, targets)

    def inherit(self, r, vertex_count: int) -> np.ndarray:
        """Extends the state over the refinement `r` of a complex of `vertex_count`
        vertices (split vertices inherit from their parents); returns the created vertices."""
        applied = r.new_vertex_of_split >= 0
        created = r.new_vertex_of_split[applied].astype(np.int64)
        if not len(created):
            return created
        parents = r.applied_simplex[applied]
        coords = r.applied_barycentric[applied]
        grow = len(r.points) - vertex_count
        self.is_anchor = np.concatenate([self.is_anchor, np.zeros(grow, dtype=bool)])
        self.is_handle = np.concatenate([self.is_handle, np.zeros(grow, dtype=bool)])
        _inherit(self.is_anchor, parents, created)
        _inherit(self.is_handle, parents, created)
        if self.targets is not None:
            self.targets = np.concatenate([self.targets, np.zeros((grow, self.targets.shape[1]))])
            safe = np.where(parents >= 0, parents, 0)
            self.targets[created] = np.einsum("tk,tkd->td", np.where(parents >= 0, coords, 0.0), self.targets[safe])
        return created


__all__ = ["Regularisation", "RegularisationMaps", "RegulariseOptions", "edges_of", "manhattan_lengths", "regularise"]
