"""Procedural meshes and keyframe animations: the built-in demo and benchmark inputs.

Everything here is whole-array numpy; the meshes are closed and outward
oriented, so stitched manifolds and their slices are closed too.
"""

from __future__ import annotations

import numpy as np


def icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """The regular icosahedron on the unit sphere: (12, 3) vertices, (20, 3) outward faces."""
    phi = (1.0 + 5.0**0.5) / 2.0
    vertices = np.array(
        [
            [-1, phi, 0], [1, phi, 0], [-1, -phi, 0], [1, -phi, 0],
            [0, -1, phi], [0, 1, phi], [0, -1, -phi], [0, 1, -phi],
            [phi, 0, -1], [phi, 0, 1], [-phi, 0, -1], [-phi, 0, 1],
        ],
        dtype=np.float64,
    )  # fmt: skip
    faces = np.array(
        [
            [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
            [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
            [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
            [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
        ],
        dtype=np.int32,
    )  # fmt: skip
    return vertices / np.linalg.norm(vertices, axis=1, keepdims=True), faces


def subdivide_midpoint(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One 1-to-4 midpoint subdivision: each triangle (a, b, c) becomes four.

    New vertices are the edge midpoints, appended after the old vertices in the
    order of their sorted edge keys, so the same connectivity always gives the
    same numbering (keyframes subdivided separately still correspond).
    Orientation is kept.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    # The three edges of every face, (a, b), (b, c), (c, a), as undirected keys.
    directed = np.stack([faces, np.roll(faces, -1, axis=1)], axis=-1).reshape(-1, 2)
    keys = np.sort(directed, axis=1)
    edges, edge_of = np.unique(keys, axis=0, return_inverse=True)
    midpoints = 0.5 * (vertices[edges[:, 0]] + vertices[edges[:, 1]])
    mid = (len(vertices) + edge_of.reshape(-1)).reshape(-1, 3)  # mid[:, 0] is the midpoint of (a, b)
    a, b, c = faces.T
    ab, bc, ca = mid.T
    children = np.concatenate(
        [
            np.stack([a, ab, ca], axis=1),
            np.stack([ab, b, bc], axis=1),
            np.stack([ca, bc, c], axis=1),
            np.stack([ab, bc, ca], axis=1),
        ]
    )
    return np.concatenate([vertices, midpoints]), children.astype(np.int32)


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """A unit sphere of 20·4^subdivisions faces (subdivided icosahedron, projected)."""
    if subdivisions < 0:
        raise ValueError(f"subdivisions must be >= 0, got {subdivisions}")
    vertices, faces = icosahedron()
    for _ in range(subdivisions):
        vertices, faces = subdivide_midpoint(vertices, faces)
        vertices /= np.linalg.norm(vertices, axis=1, keepdims=True)
    return vertices, faces


# -- keyframe poses ------------------------------------------------------------
# A pose is (squash, twist, offset): vertical scale (volume kept by scaling
# x and y by 1/sqrt), twist angle in radians from bottom to top, translation.
# Times are deliberately non-uniform: a quick squash before the take-off, a
# slow hang at the top, a fast fall.
DEMO_POSES = (
    # time   squash  twist   offset (x, y, z)
    (0.00, 1.00, 0.0, (0.0, 0.0, 0.0)),
    (0.12, 0.55, 0.0, (0.0, 0.0, -0.45)),
    (0.30, 1.60, 0.9, (0.6, 0.0, 0.8)),
    (0.55, 1.00, 2.2, (1.5, 0.3, 1.6)),
    (0.80, 1.35, 0.4, (2.4, 0.2, 0.7)),
    (1.00, 0.70, 0.0, (3.0, 0.0, -0.3)),
)


def pose(vertices: np.ndarray, squash: float, twist: float, offset) -> np.ndarray:
    """`vertices` squashed along z (volume-preserving), twisted about z, then moved."""
    lateral = 1.0 / np.sqrt(squash)
    x, y, z = vertices[:, 0] * lateral, vertices[:, 1] * lateral, vertices[:, 2] * squash
    # The twist grows linearly with height, so the top turns by `twist` relative to the bottom.
    extent = max(float(np.ptp(z)), 1e-12)
    angle = twist * (z - z.min()) / extent
    cos, sin = np.cos(angle), np.sin(angle)
    posed = np.stack([cos * x - sin * y, sin * x + cos * y, z], axis=1)
    return posed + np.asarray(offset, dtype=np.float64)


def bump(vertices: np.ndarray, amplitude: float) -> np.ndarray:
    """A radial ripple (three lobes around z), so the twist is visible on a sphere."""
    azimuth = np.arctan2(vertices[:, 1], vertices[:, 0])
    radial = 1.0 + amplitude * np.cos(3.0 * azimuth) * (1.0 - vertices[:, 2] ** 2)
    return vertices * radial[:, None]


def demo_keyframes(subdivisions: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The demo animation: (frames (m, k, 3), faces (l, 3), times (m,)).

    An icosphere with three lobes squashes, leaps with a stretch and a twist,
    travels along x and lands squashed — 6 keyframes at non-uniform times.
    subdivisions=4 gives 5,120 faces; 2 gives 320 (a fast variant for tests).
    """
    rest, faces = icosphere(subdivisions)
    lobed = bump(rest, 0.3)
    times = np.array([p[0] for p in DEMO_POSES])
    frames = np.stack([pose(lobed, squash, twist, offset) for _, squash, twist, offset in DEMO_POSES])
    return frames, faces, times


def wobble(vertices: np.ndarray, phase: float, amplitude: float) -> np.ndarray:
    """A smooth travelling-wave deformation of `vertices` at `phase` (radians).

    Used by the benchmark to animate a real mesh over many keyframes: every
    vertex moves by a sum of sines of its rest position, so neighbouring
    keyframes stay close and the mesh stays unfolded for small amplitudes.
    """
    centre = vertices.mean(axis=0)
    size = float(np.ptp(vertices, axis=0).max())
    p = (vertices - centre) / size
    displacement = np.stack(
        [
            np.sin(2 * np.pi * p[:, 1] + phase),
            np.sin(2 * np.pi * p[:, 2] + 1.3 * phase),
            np.sin(2 * np.pi * p[:, 0] + 0.7 * phase),
        ],
        axis=1,
    )
    return vertices + amplitude * size * displacement


def voxel_surface(filled: np.ndarray, size: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Boundary of a union of unit voxels (`filled`: a 3D bool array) as outward triangles.

    The caller keeps voxels from touching along an edge or a corner only (the
    surface would not be a manifold there)."""
    filled = np.pad(np.asarray(filled, bool), 1)
    ids: dict[tuple[int, int, int], int] = {}
    faces = []

    def vertex(p):
        return ids.setdefault(tuple(int(x) for x in p), len(ids))

    for axis in range(3):
        step = np.eye(3, dtype=int)[axis]
        u, w = np.eye(3, dtype=int)[(axis + 1) % 3], np.eye(3, dtype=int)[(axis + 2) % 3]
        for cell in np.argwhere(filled):
            for sign in (1, -1):
                if filled[tuple(cell + sign * step)]:
                    continue
                base = cell + (step if sign > 0 else 0)
                quad = [base, base + u, base + u + w, base + w]  # counter-clockwise seen from +axis
                if sign < 0:
                    quad = quad[::-1]
                q = [vertex(p) for p in quad]
                faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    v = np.array(sorted(ids, key=ids.get), float) * size
    return v, np.array(faces, np.int32)


def smooth_genus3(levels: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """A curved genus-3 model without flat sides: a 7 x 3 x 2 voxel slab with three square holes
    through it (size 3.5 x 1.5 x 1), Loop-subdivided `levels` times onto its limit surface
    (OpenSubdiv, no creases). levels=2: 1,596 vertices, 3,200 triangles. The benchmark's stand-in
    when the shared genus-3 model (libigl's 3holes.off) is absent."""
    from .smooth import subdivide_frame  # local: the other builders here need numpy only

    filled = np.ones((7, 3, 2), bool)
    filled[[1, 3, 5], 1, :] = False
    v, f = voxel_surface(filled, 0.5)
    s = subdivide_frame(v - v.mean(0), f, levels=levels, crease_angle=180.0)
    return np.asarray(s.vertices, np.float64), np.asarray(s.faces, np.int32)
