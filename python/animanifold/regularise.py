"""Offline regularisation of a Laplacian deformation (§4.5.1).

A large handle motion stretches the simplices between anchors and handles
into long slivers, and the Laplacian then behaves badly on them. After the
deformation, every edge whose Manhattan length in the *deformed* complex
exceeds ε is split at its midpoint in the *undeformed* complex (barycentric
refinement, :func:`animanifold.refine`); the new vertices get uniform weights
and δ = 0 (the Deformer's ``zero_detail_vertices``: their deformed position is
the centroid of their neighbours), and the deformation is applied again to
the refined complex, until no edge splits or the iteration cap::

    points, simplices, maps = am.regularise(P, S, anchors, handles, T)
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

from .deform import Deformer, _vertex_list
from .refine import refine


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
    epsilon: float | None = None,
    axis_weights=None,
    method: str = "dual",
    boundary: str = "grow",
    restore: bool = True,
    restore_iterations: int = 50,
    tolerance: float = 1e-6,
    steps: int | str = "auto",
    max_iterations: int = 10,
    vertex_attributes: Mapping[str, np.ndarray] | None = None,
    simplex_attributes: Mapping[str, np.ndarray] | None = None,
    **options,
) -> Regularisation:
    """Deforms (like :func:`animanifold.laplacian_deform`) and regularises the
    result by the offline scheme of §4.5.1; see the module docstring.

    transform: (D+1)x(D+1) affine handle motion, or handle_positions (H, D)
    in the order of `handles`. epsilon: the Manhattan edge-length threshold
    (default 2 × the undeformed complex's mean). axis_weights (D,): per-axis
    weights of the Manhattan length (default ones). max_iterations: cap on
    the refinement rounds. method, boundary, restore, restore_iterations,
    tolerance, steps and the other options go to each :class:`Deformer`.
    vertex_attributes / simplex_attributes are carried through the
    refinement (interpolated / inherited) into ``maps``.
    """
    rest = np.ascontiguousarray(points, dtype=np.float64)
    S = np.asarray(simplices)
    if rest.ndim != 2 or rest.shape[1] not in (3, 4):
        raise ValueError(f"points must be (N, 3) or (N, 4), got shape {rest.shape}")
    if S.ndim != 2 or S.shape[1] != rest.shape[1]:
        raise ValueError(f"simplices must be (M, {rest.shape[1]}) for {rest.shape[1]}D points, got shape {S.shape}")
    if S.size and not np.issubdtype(S.dtype, np.integer):
        raise ValueError(f"simplices must be integer vertex indices, got {S.dtype}")
    S = np.ascontiguousarray(S, dtype=np.int32)
    if (transform is None) == (handle_positions is None):
        raise ValueError("give exactly one of transform ((D+1)x(D+1)) or handle_positions ((H, D))")
    if isinstance(max_iterations, bool) or int(max_iterations) != max_iterations or max_iterations < 0:
        raise ValueError(f"max_iterations must be a non-negative integer, got {max_iterations!r}")
    n, D = rest.shape
    weights = None
    if axis_weights is not None:
        weights = np.asarray(axis_weights, dtype=np.float64).reshape(-1)
        if weights.shape != (D,) or (weights < 0).any() or not np.isfinite(weights).all() or not weights.any():
            raise ValueError(f"axis_weights must be {D} finite non-negative numbers, not all zero, got {axis_weights!r}")

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
            raise ValueError(f"handle_positions must be ({len(handle_ids)}, {D}), one row per handle, got {P.shape}")
        targets = np.zeros((n, D))
        targets[handle_ids] = P

    if epsilon is None:
        lengths = manhattan_lengths(rest, edges_of(S, n), weights)
        if not len(lengths) or lengths.mean() <= 0:
            raise ValueError("the complex has no edges of positive length: no default epsilon")
        epsilon = 2.0 * float(lengths.mean())
    elif not np.isfinite(epsilon) or epsilon <= 0:
        raise ValueError(f"epsilon must be a positive number, got {epsilon!r}")
    epsilon = float(epsilon)

    def solve(rest_points, simplices_, zero):
        hs = np.flatnonzero(is_handle)
        d = Deformer(rest_points, simplices_, np.flatnonzero(is_anchor), hs, method, boundary,
                     zero_detail_vertices=zero, **options)
        if targets is None:
            out = d.deform(transform, steps=steps)
        else:
            out = d.deform(handle_positions=targets[hs], steps=steps)
        if restore and method == "dual":
            out = d.restore(restore_iterations, tolerance)
        return np.array(out)

    va = {k: np.asarray(v) for k, v in (vertex_attributes or {}).items()}
    sa = {k: np.asarray(v) for k, v in (simplex_attributes or {}).items()}
    parent = np.arange(len(S), dtype=np.int64)
    zero = np.zeros(0, dtype=np.int64)
    deformed = solve(rest, S, zero)
    splits: list[int] = []
    converged = False
    while True:
        m = len(rest)
        edges = edges_of(S, m)
        after = manhattan_lengths(deformed, edges, weights)
        before = manhattan_lengths(rest, edges, weights)
        # Split what is too long and was stretched (relative slack for round-off).
        long = (after > epsilon) & (after > before * (1 + 1e-9) + 1e-12 * epsilon)
        if not long.any():
            converged = True
            break
        if len(splits) >= max_iterations:
            break
        chosen = edges[long]
        r = refine(rest, S, (chosen.astype(np.int32), np.full(chosen.shape, 0.5)), order="degeneracy",
                   vertex_attributes=va, simplex_attributes=sa)
        applied = r.new_vertex_of_split >= 0
        created = r.new_vertex_of_split[applied].astype(np.int64)
        if not len(created):  # every split snapped to an existing vertex: nothing can change
            break
        parents = r.applied_simplex[applied]
        coords = r.applied_barycentric[applied]
        m2 = len(r.points)
        grow = m2 - m
        is_anchor = np.concatenate([is_anchor, np.zeros(grow, dtype=bool)])
        is_handle = np.concatenate([is_handle, np.zeros(grow, dtype=bool)])
        _inherit(is_anchor, parents, created)
        _inherit(is_handle, parents, created)
        if targets is not None:
            targets = np.concatenate([targets, np.zeros((grow, D))])
            safe = np.where(parents >= 0, parents, 0)
            targets[created] = np.einsum("tk,tkd->td", np.where(parents >= 0, coords, 0.0), targets[safe])
        rest, S = r.points, r.simplices
        parent = parent[r.parent_simplex]
        va, sa = dict(r.vertex_attributes), dict(r.simplex_attributes)
        zero = np.arange(n, m2, dtype=np.int64)
        splits.append(int(len(created)))
        deformed = solve(rest, S, zero)

    final = manhattan_lengths(deformed, edges_of(S, len(rest)), weights)
    maps = RegularisationMaps(
        rest_points=rest,
        anchors=np.flatnonzero(is_anchor),
        handles=np.flatnonzero(is_handle),
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


__all__ = ["Regularisation", "RegularisationMaps", "edges_of", "manhattan_lengths", "regularise"]
