"""Laplacian deformation of animation manifolds and meshes (chapter 4).

::

    d = am.Deformer(points, simplices, anchors, handles, method="dual", boundary="grow")
    moved = d.deform(am.handle_transform(rotation=R, center=c, dimension=4))
    moved = d.deform(handle_positions=P)          # (H, D), one row per handle
    moved = d.deform(T, steps="auto")              # large rotations: one increment per π/4
    restored = d.restore(max_iterations=50, tolerance=1e-6)
    d.status                                       # RestoreStatus(iterations, motion, converged)
    moved = am.laplacian_deform(points, simplices, anchors, handles, T,
                                options=am.LaplacianOptions(method="graph"))   # one-off

points are (N, D) with D = 3 (triangles in R^3: surfaces, animated contours)
or D = 4 (tets in R^4: animated surfaces); the last column is time for an
animation manifold, but any mesh of n-simplices in R^(n+1) works.

Methods: ``"dual"`` (Au et al. 2006, generalised; restores features, best),
``"graph"`` (per-vertex QP of eq. 4.2), ``"uniform"`` (Taubin) and
``"cotangent"`` (triangle meshes in R^3 only). Boundary vertices of the primal
methods use the eq. 4.3 weights. The dual method completes boundary simplices
with ghost dual vertices, which can leave too few constraints; ``boundary``
says what then happens: ``"grow"`` grows the anchors/handles ring by ring
(only when needed), ``"ghost_anchors"`` keeps every ghost at its input position
(boundaries stay put), ``"error"`` raises a ValueError saying how many more
constraints are needed. A rank-deficient system is never solved.

Anchors and handles are hard constraints by default (anchors stay exactly,
handles land exactly where the transform puts them); ``constraint_weight > 0``
makes them soft rows of that weight instead, as in the dissertation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from . import _core
from .indices import as_indices
from .choices import checked, names
from .interrupting import InterruptedCallback, ProgressCallback, Span
from ._core import InputError

METHODS = names(_core.LaplacianMethod)
BOUNDARY_RULES = names(_core.BoundaryRule)


@dataclass(frozen=True)
class RestoreStatus:
    """How a restore ended: iterations run, the last max vertex motion (relative
    to the input's bounding-box diagonal) and whether it fell below the tolerance."""

    iterations: int
    motion: float
    converged: bool


def _vertex_list(values, name: str, vertex_count: int) -> np.ndarray:
    """Vertex indices (or a boolean mask) → int32 indices, checked."""
    if values is None:
        return np.zeros(0, dtype=np.int32)
    raw = np.asarray(values)
    if raw.dtype == bool:
        if raw.shape != (vertex_count,):
            raise InputError(f"{name} mask has shape {raw.shape} for {vertex_count} vertices")
        array = np.flatnonzero(raw)
    else:
        if raw.size and not np.issubdtype(raw.dtype, np.integer):
            raise InputError(f"{name} must be integer vertex indices or a boolean mask, got {raw.dtype}")
        array = raw.astype(np.int64).reshape(-1)
    if array.size:
        bad = np.flatnonzero((array < 0) | (array >= vertex_count))
        if bad.size:
            raise InputError(f"{name}[{bad[0]}] is vertex {array[bad[0]]}, outside 0..{vertex_count - 1}")
        unique, counts = np.unique(array, return_counts=True)
        if (counts > 1).any():
            raise InputError(f"vertex {unique[counts > 1][0]} is listed more than once in {name}")
    return np.ascontiguousarray(array, dtype=np.int32)


def handle_transform(
    rotation: np.ndarray | None = None,
    translation: Sequence[float] | np.ndarray | None = None,
    scale: float | Sequence[float] | None = None,
    center: Sequence[float] | np.ndarray | None = None,
    dimension: int = 4,
) -> np.ndarray:
    """The (D+1)x(D+1) affine matrix x ↦ R·S·(x − c) + c + t.

    rotation: (D, D), or (3, 3) applied to x, y, z of 4D points (time kept);
    scale: a number or D numbers; center: the pivot c (default origin).
    """
    D = int(dimension)
    if D not in (3, 4):
        raise InputError(f"dimension must be 3 or 4, got {dimension}")
    linear = np.eye(D)
    if scale is not None:
        s = np.broadcast_to(np.asarray(scale, dtype=float), (D,))
        linear = np.diag(s) @ linear
    if rotation is not None:
        R = np.asarray(rotation, dtype=float)
        if R.shape == (3, 3) and D == 4:
            R = np.block([[R, np.zeros((3, 1))], [np.zeros((1, 3)), np.ones((1, 1))]])
        if R.shape != (D, D):
            raise InputError(f"rotation must be ({D}, {D}) (or (3, 3) for 4D points), got {R.shape}")
        linear = R @ linear
    c = np.zeros(D) if center is None else np.asarray(center, dtype=float).reshape(D)
    t = np.zeros(D) if translation is None else np.asarray(translation, dtype=float).reshape(D)
    T = np.eye(D + 1)
    T[:D, :D] = linear
    T[:D, D] = c + t - linear @ c
    return T


def rotation_matrix(axis: Sequence[float], angle: float) -> np.ndarray:
    """3x3 rotation by `angle` radians about `axis` (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def rotation_angle(linear: np.ndarray) -> float:
    """The largest rotation angle (radians) of the rotation factor of a linear map."""
    U, _, Vt = np.linalg.svd(np.asarray(linear, dtype=float))
    R = U @ Vt
    if np.linalg.det(R) < 0:
        raise InputError("the handle motion reflects: a rotation angle is undefined")
    return float(np.abs(np.angle(np.linalg.eigvals(R))).max())


def best_fit_linear(rest: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """The rotation best mapping the centred rest handle positions onto the moved ones (Kabsch)."""
    a = rest - rest.mean(0)
    b = moved - moved.mean(0)
    U, _, Vt = np.linalg.svd(b.T @ a)
    R = U @ Vt
    if np.linalg.det(R) < 0:
        U[:, -1] *= -1
        R = U @ Vt
    return R


def steps_for_rotation(angle: float, per_step: float = np.pi / 4) -> int:
    """One increment per `per_step` radians of rotation (at least one)."""
    return max(1, int(np.ceil(angle / per_step - 1e-9)))


def _check_steps(steps) -> int:
    if isinstance(steps, str) or int(steps) < 1:
        raise InputError(f"steps must be 'auto' or an integer >= 1, got {steps!r}")
    return int(steps)


@dataclass(frozen=True)
class LaplacianOptions:
    """How a one-off Laplacian deformation builds and runs its :class:`Deformer`.

    method: "dual" (default), "graph", "uniform" or "cotangent" (see the module doc).
    boundary: "grow" (default), "ghost_anchors" or "error": what the dual
      method does when ghost dual vertices leave too few constraints.
    restore: restore features after the solve (dual method only; default True).
    restore_iterations: cap on the restore's rounds (default 50).
    tolerance: the restore stops when the largest vertex motion, relative to
      the bounding-box diagonal, falls below it (default 1e-6).
    steps: handle motion increments, an integer >= 1 or "auto" (default: one
      per π/4 of the handles' rotation for the dual method, else 1).
    lam, xi, ridge: graph-Laplacian λ of eq. 4.2, weight floor ξ, and ridge
      (defaults 0.1, 1e-3, 1e-8).
    constraint_weight: 0 (default) makes anchors and handles hard
      constraints; > 0 makes them soft rows of that weight.
    """

    method: str = "dual"
    boundary: str = "grow"
    restore: bool = True
    restore_iterations: int = 50
    tolerance: float = 1e-6
    steps: int | str = "auto"
    lam: float = 0.1
    xi: float = 1e-3
    ridge: float = 1e-8
    constraint_weight: float = 0.0

    def __post_init__(self):
        # Frozen: the checked names replace an enum member given for either.
        object.__setattr__(self, "method", checked(self.method, _core.LaplacianMethod, "method"))
        object.__setattr__(self, "boundary", checked(self.boundary, _core.BoundaryRule, "boundary rule"))
        if not isinstance(self.restore, (bool, np.bool_)):
            raise InputError(f"restore must be True or False, got {self.restore!r}")
        if not _is_count(self.restore_iterations):
            raise InputError(f"restore_iterations must be a non-negative integer, got {self.restore_iterations!r}")
        if self.steps != "auto" and not (_is_count(self.steps) and self.steps >= 1):
            raise InputError(f"steps must be 'auto' or an integer >= 1, got {self.steps!r}")
        for name in ("tolerance", "lam", "xi", "ridge", "constraint_weight"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) or not np.isfinite(value) \
                    or value < 0:
                raise InputError(f"{name} must be a finite non-negative number, got {value!r}")


def _is_count(value) -> bool:
    """Whether `value` is a non-negative integer (bools are not counts)."""
    return not isinstance(value, bool) and isinstance(value, (int, np.integer)) and value >= 0


class Deformer:
    """Laplacian editing of a mesh or animation manifold, factored once.

    points (N, D), simplices (M, D) with D = 3 or 4; anchors and handles are
    vertex indices (or boolean masks), disjoint, not both empty. Graph-Laplacian
    parameters: ``lam`` (λ of eq. 4.2), ``xi`` (ξ, the weight floor), ``ridge``.
    ``zero_detail_vertices`` get uniform weights and δ = 0 (for the offline
    regularisation of §4.5.1: vertices added by refinement). ``progress(step,
    fraction)`` and ``interrupted()`` follow the factorisation's steps; False
    from the one or True from the other raises :class:`animanifold.Cancelled`.
    """

    def __init__(
        self,
        points: np.ndarray,
        simplices: np.ndarray,
        anchors,
        handles,
        method: str = "dual",
        boundary: str = "grow",
        *,
        lam: float = 0.1,
        xi: float = 1e-3,
        ridge: float = 1e-8,
        constraint_weight: float = 0.0,
        zero_detail_vertices=None,
        progress: Callable[[str, float], bool] | None = None,
        interrupted: Callable[[], bool] | None = None,
    ):
        points = np.ascontiguousarray(points, dtype=np.float64)
        simplices = np.asarray(simplices)
        if points.ndim != 2 or points.shape[1] not in (3, 4):
            raise InputError(f"points must be (N, 3) or (N, 4), got shape {points.shape}")
        if simplices.ndim != 2 or simplices.shape[1] != points.shape[1]:
            raise InputError(
                f"simplices must be (M, {points.shape[1]}) for {points.shape[1]}D points "
                f"(n-simplices in R^(n+1)), got shape {simplices.shape}"
            )
        if simplices.size and not np.issubdtype(simplices.dtype, np.integer):
            raise InputError(f"simplices must be integer vertex indices, got {simplices.dtype}")
        method = checked(method, _core.LaplacianMethod, "method")
        boundary = checked(boundary, _core.BoundaryRule, "boundary rule")
        n = len(points)
        anchors = _vertex_list(anchors, "anchors", n)
        handles = _vertex_list(handles, "handles", n)
        if anchors.size + handles.size == 0:
            raise InputError("no anchors and no handles: the deformation needs at least one constrained vertex")
        both = np.intersect1d(anchors, handles)
        if both.size:
            raise InputError(f"vertex {both[0]} is both an anchor and a handle ({both.size} such vertices)")
        zero = _vertex_list(zero_detail_vertices, "zero_detail_vertices", n)
        self.method = method
        self.boundary = boundary
        self._dimension = points.shape[1]
        self._handle_count = handles.size
        self._rest_handles = points[handles].copy()
        self._core = _core.Deformer(
            points,
            as_indices(simplices, "simplices"),
            anchors,
            handles,
            method=method,
            boundary=boundary,
            lam=float(lam),
            xi=float(xi),
            ridge=float(ridge),
            constraint_weight=float(constraint_weight),
            zero_detail_vertices=zero.tolist(),
            progress=progress,
            interrupted=interrupted,
        )
        self.status: RestoreStatus | None = None

    @classmethod
    def from_options(cls, points, simplices, anchors, handles, options: LaplacianOptions,
                     zero_detail_vertices=None, progress=None, interrupted=None) -> "Deformer":
        """A Deformer with the method, boundary rule and Laplacian parameters of `options`."""
        return cls(points, simplices, anchors, handles, options.method, options.boundary, lam=options.lam,
                   xi=options.xi, ridge=options.ridge, constraint_weight=options.constraint_weight,
                   zero_detail_vertices=zero_detail_vertices, progress=progress, interrupted=interrupted)

    # -- solving ------------------------------------------------------------
    def deform(
        self,
        handle_transform: np.ndarray | None = None,
        *,
        handle_positions: np.ndarray | None = None,
        steps: int | str = 1,
        progress: ProgressCallback | None = None,
        interrupted: InterruptedCallback | None = None,
    ) -> np.ndarray:
        """Moves the handles — by a (D+1)x(D+1) affine matrix, or to explicit
        (H, D) positions in the order the handles were given — and returns the
        new (N, D) points.

        ``steps > 1`` (dual method) drags the handles there in that many equal
        increments, restoring features after each but the last, like an artist
        dragging: large rotations (Figure 4.11's 3π/4) then restore without
        folding. ``steps="auto"`` uses one increment per π/4 of the handles'
        rotation (the transform's, or the best-fit one of the positions).
        Call :meth:`restore` afterwards as usual. ``progress(step, fraction)``
        is told "deforming" before each increment and ``interrupted()`` polled
        with it (and in the intermediate restores); False from the one or True
        from the other raises :class:`animanifold.Cancelled`."""
        if (handle_transform is None) == (handle_positions is None):
            raise InputError("give exactly one of handle_transform ((D+1)x(D+1)) or handle_positions ((H, D))")
        self.status = None
        D = self._dimension
        if handle_transform is not None:
            T = np.asarray(handle_transform, dtype=np.float64)
            if T.shape != (D + 1, D + 1):
                raise InputError(f"handle_transform must be ({D + 1}, {D + 1}) for {D}D points, got {T.shape}")
            if steps == "auto":
                steps = steps_for_rotation(rotation_angle(T[:D, :D])) if self.method == "dual" else 1
            return self._core.deform(T, _check_steps(steps), progress=progress, interrupted=interrupted)
        P = np.ascontiguousarray(handle_positions, dtype=np.float64)
        if P.shape != (self._handle_count, D):
            raise InputError(f"handle_positions must be ({self._handle_count}, {D}), one row per handle, got {P.shape}")
        if steps == "auto":
            rest = self._rest_handles
            steps = steps_for_rotation(rotation_angle(best_fit_linear(rest, P))) if self.method == "dual" else 1
        return self._core.deform_to(P, _check_steps(steps), progress=progress, interrupted=interrupted)

    def restore(self, max_iterations: int = 50, tolerance: float = 1e-6, *,
                progress: ProgressCallback | None = None, interrupted: InterruptedCallback | None = None) -> np.ndarray:
        """Dual method: rotates the differential coordinates onto the deformed
        normals and re-solves until the largest vertex motion (relative to the
        bounding-box diagonal) is below `tolerance`; sets :attr:`status`.
        ``progress`` is told "restoring" before each round, as for :meth:`deform`."""
        if self.method != "dual":
            raise InputError(f"restore applies to method='dual' only, this Deformer uses {self.method!r}")
        s = self._core.restore(int(max_iterations), float(tolerance), progress=progress, interrupted=interrupted)
        self.status = RestoreStatus(int(s.iterations), float(s.motion), bool(s.converged))
        return self._core.points

    # -- state --------------------------------------------------------------
    @property
    def points(self) -> np.ndarray:
        """The latest result (the input before any deform)."""
        return self._core.points

    @property
    def anchors(self) -> np.ndarray:
        """Anchor vertices, including any grown by boundary='grow'."""
        return self._core.anchors

    @property
    def handles(self) -> np.ndarray:
        """Handle vertices (given ones first), including any grown."""
        return self._core.handles

    @property
    def info(self) -> "_core.DeformerInfo":
        """System size, ghosts, grown constraints, CHOLMOD's rcond and factor size."""
        return self._core.info


def laplacian_deform(
    points: np.ndarray,
    simplices: np.ndarray,
    anchors,
    handles,
    handle_transform: np.ndarray | None = None,
    *,
    handle_positions: np.ndarray | None = None,
    options: LaplacianOptions = LaplacianOptions(),
    progress: ProgressCallback | None = None,
    interrupted: InterruptedCallback | None = None,
) -> np.ndarray:
    """One-off deformation: builds a :class:`Deformer` as `options` say, moves
    the handles (by `handle_transform` or to `handle_positions`) and, for the
    dual method with ``options.restore``, restores features. Returns (N, D)
    points. ``progress(step, fraction)`` follows the factorisation's steps,
    then each increment ("deforming"), each restore round ("restoring") and
    "done", with fractions growing in [0, 1]; ``interrupted()`` is polled with
    it; False from the one or True from the other raises
    :class:`animanifold.Cancelled`."""
    span = Span(progress, interrupted)
    factorising = span.part(0.0, _FACTORISING)
    d = Deformer.from_options(points, simplices, anchors, handles, options, progress=factorising.core_progress(),
                              interrupted=interrupted)
    out = solve(d, handle_transform, handle_positions, options, span.part(_FACTORISING, 1.0))
    span.step("done", 1.0)
    return out


# The share of a one-off solve's progress given to building and factoring the system:
# it is what takes time, unless the restore runs many rounds.
_FACTORISING = 0.6


def solve(deformer: Deformer, handle_transform, handle_positions, options: LaplacianOptions,
          span: Span = Span()) -> np.ndarray:
    """Moves `deformer`'s handles in ``options.steps`` increments and restores
    features when ``options.restore`` asks for it and the method has a restore
    (dual only). Returns the deformer's new (N, D) points. The increments
    ("deforming") fill the first part of `span`, the restore's rounds
    ("restoring") the rest (Cancelled when its caller says stop)."""
    restoring = options.restore and deformer.method == "dual"
    deforming = span.part(0.0, 0.5 if restoring else 1.0)
    out = deformer.deform(handle_transform, handle_positions=handle_positions, steps=options.steps,
                          progress=deforming.core_progress(), interrupted=span.interrupted)
    if restoring:
        out = deformer.restore(options.restore_iterations, options.tolerance,
                               progress=span.part(0.5, 1.0).core_progress(), interrupted=span.interrupted)
    return out
