"""The Voronoi skeleton (chapter 7): internal/external medial skeletons of
closed oriented polygons (R^2) and triangle meshes (R^3).

::

    import animanifold as am
    sk = am.voronoi_skeleton(vertices, faces, side="both")
    sk.vertices, sk.faces, sk.side, sk.sites          # the skeleton
    sk.refined_vertices, sk.refined_faces             # the Voronoi-separable mesh
    sk.separable, sk.iterations                       # how separation ended

The mesh is first made Voronoi separable (§7.5-7.6): every simplex encroached
by a vertex is split at the closest point to its closest encroacher, for at
most ``max_iterations`` rounds. A skeleton face lies on the bisector b_ij of
two vertices of the refined mesh (``sk.sites``); the bisectors that intersect
the mesh are discarded and the rest is classified internal or external
(external parts clipped to the convex hull, §7.4).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from . import _core
from .choices import checked, names
from ._core import InputError

__all__ = [
    "EmptySkeletonWarning",
    "SeparabilityWarning",
    "VoronoiSkeleton",
    "dihedral_test",
    "empty_skeleton_reason",
    "encroachments",
    "faces_intersecting_mesh",
    "is_convex",
    "make_voronoi_separable",
    "voronoi_skeleton",
    "wrap",
]

INTERNAL = "internal"
EXTERNAL = "external"
SIDES = names(_core.SkeletonSide)
WRAP_SHAPES = names(_core.WrapShape)


class SeparabilityWarning(RuntimeWarning):
    """The iteration cap was hit before the mesh became Voronoi separable."""


class EmptySkeletonWarning(RuntimeWarning):
    """The skeleton came out empty although the shape has one: its sampling is too regular."""


@dataclass(frozen=True)
class VoronoiSkeleton:
    """A Voronoi skeleton and the separable mesh it was extracted from.

    ``faces`` are triangles (R^3) or segments (R^2, also as ``segments``) into
    ``vertices``; ``side[k]`` is ``"internal"`` or ``"external"``; ``sites[k]``
    are the two refined-mesh vertices whose bisector holds face k (triangles
    are oriented with their normal from ``sites[k, 0]`` towards
    ``sites[k, 1]``); ``polygon[k]`` says which bisector polygon face k
    triangulates. ``on_mesh`` flags skeleton vertices lying on the mesh
    (Figure 7.10). ``attachment`` (with ``attach=True``, §8.6.2) are simplices
    over ``np.vstack([refined_vertices, vertices])`` connecting mesh vertices to
    the skeleton.
    """

    vertices: np.ndarray
    faces: np.ndarray
    side: np.ndarray
    sites: np.ndarray
    polygon: np.ndarray
    on_mesh: np.ndarray
    refined_vertices: np.ndarray
    refined_faces: np.ndarray
    separable: bool
    iterations: int
    splits: int
    dihedral: "_core.DihedralReport"
    attachment: np.ndarray
    stats: dict = field(default_factory=dict)

    @property
    def dimension(self) -> int:
        return int(self.refined_vertices.shape[1])

    @property
    def segments(self) -> np.ndarray | None:
        """The skeleton's segments in R^2 (None in R^3)."""
        return self.faces if self.dimension == 2 else None

    def select(self, side: str) -> tuple[np.ndarray, np.ndarray]:
        """(vertices, faces) of one side, re-indexed compactly."""
        if side not in (INTERNAL, EXTERNAL):
            raise InputError(f"side must be 'internal' or 'external', got {side!r}")
        faces = self.faces[self.side == side]
        used, inverse = np.unique(faces, return_inverse=True)
        return self.vertices[used], inverse.reshape(faces.shape).astype(np.int32)


def _points(vertices, name: str = "vertices") -> np.ndarray:
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] not in (2, 3):
        raise InputError(f"{name} must be (k, 2) or (k, 3), got shape {v.shape}")
    return v


def _simplices(faces, name: str = "faces") -> np.ndarray:
    f = np.asarray(faces)
    if f.ndim != 2 or (f.size and not np.issubdtype(f.dtype, np.integer)):
        raise InputError(f"{name} must be a 2D integer array, got shape {f.shape} and dtype {f.dtype}")
    return np.ascontiguousarray(f, dtype=np.int32)


MAX_WRAP_DENSITY = 32  # 6,146 wrap sites; the wrap grows with the square of the density


def voronoi_skeleton(
    vertices,
    faces,
    side: str = "both",
    max_iterations: int = 4,
    wrap: str | None = "box",
    *,
    wrap_density: int = 4,
    wrap_margin: float = 1.0,
    dihedral_limit: float = math.pi / 4,
    attach: bool = False,
    neighbourhood: int = 2,
    in_plane_angle: float = 0.3,
    warn: bool = True,
    progress: Callable[[str, float], bool] | None = None,
    interrupted: Callable[[], bool] | None = None,
) -> VoronoiSkeleton:
    """The Voronoi skeleton of a closed, oriented polygon (R^2) or triangle mesh (R^3).

    ``side`` is ``"internal"``, ``"external"`` or ``"both"``. ``wrap``
    (``"box"``, ``"sphere"`` or None) adds Voronoi sites around the input so
    every mesh vertex has a bounded cell (§7.6.4); without it, bisectors that
    reach infinity are dropped. ``neighbourhood`` and ``in_plane_angle`` set
    which edge encroachments count in R^3 (see the core's
    ``EncroachmentRule``; ``neighbourhood=1, in_plane_angle=0`` is the
    dissertation's literal rule). Open, non-manifold or inward-oriented
    input raises ValueError. When ``max_iterations`` rounds do not make the
    mesh separable, the skeleton is still returned with ``separable=False``
    and a :class:`SeparabilityWarning` is issued (``warn=False`` silences it).
    ``progress(step, fraction)`` and ``interrupted()`` follow the core's steps;
    False from the one or True from the other raises :class:`animanifold.Cancelled`.
    """
    side = checked(side, _core.SkeletonSide, "skeleton side")
    wrap = "none" if wrap is None else checked(wrap, _core.WrapShape, "wrap shape")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)) or max_iterations < 0:
        raise InputError(f"max_iterations must be an integer >= 0, got {max_iterations!r}")
    if isinstance(wrap_density, bool) or not isinstance(wrap_density, (int, np.integer)) or not (
            1 <= wrap_density <= MAX_WRAP_DENSITY):
        raise InputError(f"wrap_density must be an integer from 1 to {MAX_WRAP_DENSITY}, got {wrap_density!r} "
                         "(a box wrap has 6·density² + 2 sites)")
    v = _points(vertices)
    f = _simplices(faces)
    raw = _core.voronoi_skeleton(
        v, f, side=side, max_iterations=int(max_iterations), wrap=wrap, wrap_density=int(wrap_density),
        wrap_margin=float(wrap_margin), dihedral_limit=float(dihedral_limit), attach=bool(attach),
        neighbourhood=int(neighbourhood), in_plane_angle=float(in_plane_angle), progress=progress,
        interrupted=interrupted)
    sides = np.where(np.asarray(raw.side) == 0, INTERNAL, EXTERNAL)
    sk = VoronoiSkeleton(
        vertices=np.asarray(raw.vertices),
        faces=np.asarray(raw.faces),
        side=sides,
        sites=np.asarray(raw.sites),
        polygon=np.asarray(raw.polygon),
        on_mesh=np.asarray(raw.on_mesh).astype(bool),
        refined_vertices=np.asarray(raw.refined_vertices),
        refined_faces=np.asarray(raw.refined_faces),
        separable=bool(raw.separable),
        iterations=int(raw.iterations),
        splits=int(raw.splits),
        dihedral=raw.dihedral,
        attachment=np.asarray(raw.attachment),
        stats={
            "bisectors": int(raw.bisectors),
            "discarded": int(raw.discarded),
            "discarded_nonlocal": int(raw.discarded_nonlocal),
            "discarded_far": int(raw.discarded_far),
            "seconds_separability": float(raw.seconds_separability),
            "seconds_extraction": float(raw.seconds_extraction),
        },
    )
    if warn and not sk.separable:
        warnings.warn(separability_warning(sk, max_iterations), SeparabilityWarning, stacklevel=2)
    if warn and len(sk.faces) == 0 and (reason := empty_skeleton_reason(side, v, f)):
        warnings.warn(f"the {_side_name(side)} {reason}", EmptySkeletonWarning, stacklevel=2)
    return sk


def _side_name(side: str) -> str:
    return "skeleton" if side == "both" else f"{side} skeleton"


def empty_skeleton_reason(side: str, vertices: np.ndarray, faces: np.ndarray) -> str | None:
    """Why a skeleton of `side` came out empty, as the end of a sentence, or None where empty
    is right: a convex shape has no external skeleton. Every solid has an internal one and any
    other shape an external one, so the sampling is to blame: sites on common spheres, as a
    regularly sampled torus or sphere has, give Voronoi cells the extraction cannot separate."""
    convex = is_convex(vertices, faces)
    if side != INTERNAL and convex:
        return None
    return (f"came out empty{'' if convex else ' although the shape is not convex'}: its vertices are probably "
            "sampled too regularly (many on one sphere, as on a primitive torus); move them by a little noise "
            "(1e-6 of the size) and try again")


def is_convex(vertices: np.ndarray, faces: np.ndarray) -> bool:
    """Every vertex lies on or behind every face's plane (to rounding): the closed, outward
    oriented mesh is convex. Without scipy, which the package does not need at runtime."""
    vertices = np.asarray(vertices, dtype=np.float64)
    corners = vertices[faces]
    chunk = max(1, (1 << 22) // max(len(vertices), 1))  # faces per pass: ~32 MB of heights
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    size = float(np.ptp(vertices, axis=0).max()) or 1.0
    for i in range(0, len(faces), chunk):
        n = normals[i:i + chunk]
        lengths = np.linalg.norm(n, axis=1)
        keep = lengths > 0
        offsets = np.einsum("ij,ij->i", n[keep], corners[i:i + chunk, 0][keep])
        heights = (vertices @ n[keep].T - offsets) / lengths[keep]
        if heights.size and heights.max() > 1e-9 * size:
            return False
    return True


def separability_warning(sk: VoronoiSkeleton, max_iterations: int) -> str | None:
    """What :func:`voronoi_skeleton` warns of when `sk` is not separable (None when it is)."""
    if sk.separable:
        return None
    return (f"the mesh is not Voronoi separable after {sk.iterations} splitting rounds (max_iterations="
            f"{max_iterations}); the skeleton may miss faces where the shape is thin or sharp")


def make_voronoi_separable(vertices, faces, max_iterations: int = 4, *, neighbourhood: int = 2,
                           in_plane_angle: float = 0.3) -> "_core.SeparabilityResult":
    """Splits encroached simplices (§7.5-7.6). Returns the ``vertices`` and
    ``faces`` of the refined mesh, ``separable``, ``iterations``, ``splits`` and
    ``remaining`` (encroached simplices left when the cap was hit)."""
    return _core.make_voronoi_separable(_points(vertices), _simplices(faces), int(max_iterations),
                                        neighbourhood=int(neighbourhood), in_plane_angle=float(in_plane_angle))


def encroachments(vertices, faces, *, neighbourhood: int = 2, in_plane_angle: float = 0.3):
    """(rows, distance): per encroached simplex, rows (vertex, a, b, c or -1,
    type) with the Figure 7.14 type (2 edge, 3 face, 4 both) of its closest
    encroacher, and that vertex's distance to the simplex."""
    return _core.encroachments(_points(vertices), _simplices(faces), neighbourhood=int(neighbourhood),
                               in_plane_angle=float(in_plane_angle))


def dihedral_test(vertices, faces, limit: float = math.pi / 4) -> "_core.DihedralReport":
    """§7.6.6: ``passes`` (no surface angle sharper than ``limit`` radians),
    ``sharpest``, and where: ``sharp`` (edges in R^3, corner vertices in R^2)
    with their ``angles``."""
    return _core.dihedral_test(_points(vertices), _simplices(faces), float(limit))


def wrap(vertices, faces, shape: str = "box", density: int = 4, margin: float = 1.0):
    """(vertices, faces, input_vertices, input_faces): the input followed by an
    inward-oriented box or sphere (rectangle or circle in R^2) ``margin``
    bounding-box diagonals away from it (§7.6.4)."""
    shape = checked(shape, _core.WrapShape, "wrap shape")
    return _core.wrap(_points(vertices), _simplices(faces), shape, int(density), float(margin))


def faces_intersecting_mesh(face_vertices, face_simplices, vertices, faces) -> np.ndarray:
    """Boolean per face (triangles in R^3, segments in R^2): does it intersect the
    mesh? Decided with CGAL's exact predicates; touching counts."""
    return np.asarray(_core.faces_intersecting_mesh(_points(face_vertices, "face_vertices"),
                                                    _simplices(face_simplices, "face_simplices"),
                                                    _points(vertices), _simplices(faces)))
