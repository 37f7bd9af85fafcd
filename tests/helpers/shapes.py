"""Small procedural meshes for tests: closed, outward-oriented, exactly known."""

from __future__ import annotations

import numpy as np

from animanifold.procedural import voxel_surface  # noqa: F401  (the tests' voxel models)


def icosahedron() -> tuple[np.ndarray, np.ndarray]:
    p = (1 + 5**0.5) / 2
    v = np.array(
        [[-1, p, 0], [1, p, 0], [-1, -p, 0], [1, -p, 0], [0, -1, p], [0, 1, p],
         [0, -1, -p], [0, 1, -p], [p, 0, -1], [p, 0, 1], [-p, 0, -1], [-p, 0, 1]], float)
    f = np.array(
        [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], np.int32)
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def icosphere(subdivisions: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Unit icosphere with outward faces (20·4^s faces)."""
    v, f = icosahedron()
    for _ in range(subdivisions):
        edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        mids = v[unique].mean(axis=1)
        mid_ids = len(v) + inverse.reshape(3, -1).T  # (F, 3): mid of edge 01, 12, 20
        v = np.concatenate([v, mids])
        a, b, c = f.T
        ab, bc, ca = mid_ids.T
        f = np.concatenate([np.stack(x, 1) for x in ([a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca])])
        v = v / np.linalg.norm(v, axis=1, keepdims=True)
    return v, f.astype(np.int32)


def cube() -> tuple[np.ndarray, np.ndarray]:
    """The cube [-1, 1]^3 as 12 outward triangles."""
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    f = np.array([t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])], np.int32)
    return v, f


def cylinder(n: int = 32, radius: float = 1.0, depth: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """Blender's cylinder primitive: n points on each cap's circle (all 2n cospherical), the caps
    triangulated as fans, outward."""
    a = 2 * np.pi * np.arange(n) / n
    ring = np.stack([radius * np.cos(a), radius * np.sin(a)], 1)
    v = np.concatenate([np.c_[ring, np.full(n, -depth / 2)], np.c_[ring, np.full(n, depth / 2)]])
    i = np.arange(n)
    j = (i + 1) % n
    sides = np.concatenate([np.stack([i, j, j + n], 1), np.stack([i, j + n, i + n], 1)])
    k = np.arange(1, n - 1)
    bottom = np.stack([np.zeros_like(k), k + 1, k], 1)
    top = np.stack([np.full_like(k, n), k + n, k + 1 + n], 1)
    return v, np.concatenate([sides, bottom, top]).astype(np.int32)


def strip_capped_cylinder(n: int = 64, radius: float = 1.0, depth: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """A cylinder whose n-gon caps are split into triangles between rim points only, as Blender's
    "N-Gon" cap fill is once triangulated (Blender's own split differs in detail): a zigzag strip
    across each cap (ears at the two ends), outward."""
    v, f = cylinder(n, radius, depth)
    sides = f[:2 * n]
    strip = [[0, n - 1, 1]]
    low, high, turn = 1, n - 1, 0
    while high - low > 1:
        strip.append([low, high, low + 1] if turn == 0 else [low, high, high - 1])
        low, high = (low + 1, high) if turn == 0 else (low, high - 1)
        turn ^= 1
    bottom = np.array(strip)  # facing down: clockwise seen from above
    top = bottom[:, ::-1] + n
    return v, np.concatenate([sides, bottom, top]).astype(np.int32)


def cone(n: int = 32, radius: float = 1.0, depth: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """Blender's cone primitive: n cocircular points at the base (a fan), one at the tip, outward."""
    a = 2 * np.pi * np.arange(n) / n
    v = np.concatenate([np.c_[radius * np.cos(a), radius * np.sin(a), np.full(n, -depth / 2)], [[0, 0, depth / 2]]])
    i = np.arange(n)
    k = np.arange(1, n - 1)
    sides = np.stack([i, (i + 1) % n, np.full(n, n)], 1)
    base = np.stack([np.zeros_like(k), k + 1, k], 1)
    return v, np.concatenate([sides, base]).astype(np.int32)


def uv_sphere(segments: int = 32, rings: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Blender's UV sphere as Blender hands it over: float32 coordinates, every quad between two
    rings split along the same diagonal. Exactly, each quad is a planar trapezoid; rounded, most
    of them bend along that diagonal by ~1e-8 of the size, half of them inwards."""
    lat = np.pi * np.arange(1, rings) / rings
    lon = 2 * np.pi * np.arange(segments) / segments
    ring_points = [[np.sin(a) * np.cos(b), np.sin(a) * np.sin(b), np.cos(a)] for a in lat for b in lon]
    v = np.array([[0, 0, 1]] + ring_points + [[0, 0, -1]], np.float32).astype(np.float64)

    def at(r, s):
        return 1 + r * segments + s % segments

    f = []
    for s in range(segments):
        f += [[0, at(0, s), at(0, s + 1)], [len(v) - 1, at(rings - 2, s + 1), at(rings - 2, s)]]
        for r in range(rings - 2):
            a, b, c, d = at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)
            f += [[a, b, c], [a, c, d]]
    return v, np.array(f, np.int32)


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


def polygon(n: int, radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Counter-clockwise regular n-gon and its edges."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = radius * np.stack([np.cos(a), np.sin(a)], 1)
    e = np.stack([np.arange(n), (np.arange(n) + 1) % n], 1).astype(np.int32)
    return v, e


def torus(major_radius: float = 1.0, minor_radius: float = 0.3, major: int = 24, minor: int = 12,
          centre=(0.0, 0.0, 0.0), wobble: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Torus around the z axis with outward faces (2·major·minor triangles).

    Vertex (i, j) sits at angle 2πi/major around the axis and 2πj/minor
    around the tube. With wobble = 0 each grid quad is an isosceles trapezoid
    (planar, its corners cocircular) and, with `minor` a multiple of 4, rings
    lie at the top and bottom of the tube, where the flat caps of the convex
    hull meet it. wobble > 0 breaks those symmetries smoothly (the tube's
    radius and the rings' phase vary around the axis), keeping the outer half
    convex. Each quad is split along its convex diagonal, so that where the
    torus lies on its hull, its faces are the hull's facets.
    """
    u = 2 * np.pi * np.arange(major) / major
    w = 2 * np.pi * np.arange(minor) / minor
    U, W = np.meshgrid(u, w, indexing="ij")
    r = minor_radius * (1 + wobble * np.sin(3 * U + 0.5))
    W = W + wobble * (np.sin(2 * U) + 0.5 * np.cos(5 * U + 1.0))
    rho = major_radius + r * np.cos(W)
    v = np.stack([rho * np.cos(U), rho * np.sin(U), r * np.sin(W)], -1).reshape(-1, 3) + np.asarray(centre, float)
    i, j = np.meshgrid(np.arange(major), np.arange(minor), indexing="ij")
    a = (i * minor + j).reshape(-1)
    b = (((i + 1) % major) * minor + j).reshape(-1)
    c = (((i + 1) % major) * minor + (j + 1) % minor).reshape(-1)
    d = (i * minor + (j + 1) % minor).reshape(-1)
    # Diagonal ac is convex when d lies below the plane of (a, b, c).
    convex_ac = np.einsum("ij,ij->i", np.cross(v[b] - v[a], v[c] - v[a]), v[d] - v[a]) <= 0
    f = np.concatenate([
        np.where(convex_ac[:, None], np.stack([a, b, c], 1), np.stack([a, b, d], 1)),
        np.where(convex_ac[:, None], np.stack([a, c, d], 1), np.stack([b, c, d], 1)),
    ])
    return v, f.astype(np.int32)


def genus3_plate() -> tuple[np.ndarray, np.ndarray]:
    """A 7 x 3 x 1 voxel plate with three square holes: genus 3 (Euler characteristic -4)."""
    filled = np.ones((7, 3, 1), bool)
    filled[[1, 3, 5], 1, 0] = False
    v, f = voxel_surface(filled, 0.5)
    return v - v.mean(0), f
