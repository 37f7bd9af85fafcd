"""Meshes for the Laplacian tests and benchmark: the block of Figure 4.11 as a
triangulated box surface (outward-oriented, welded), and helpers to measure
deformations (folded edges, local feature size)."""

from __future__ import annotations

import numpy as np


def block(nx: int = 12, ny: int = 12, nz: int = 45, size=(1.0, 1.0, 3.75)) -> tuple[np.ndarray, np.ndarray]:
    """Surface of the box [-sx/2, sx/2] x [-sy/2, sy/2] x [0, sz] with an
    (nx, ny, nz) grid of cells, each quad split into two triangles; closed,
    outward. The default has 2,432 vertices (the dissertation's block has ~2500)."""
    sx, sy, sz = size
    xs, ys, zs = np.linspace(-sx / 2, sx / 2, nx + 1), np.linspace(-sy / 2, sy / 2, ny + 1), np.linspace(0, sz, nz + 1)
    points, faces = [], []
    offset = 0

    def grid(a, b, embed):
        nonlocal offset
        A, B = np.meshgrid(a, b, indexing="ij")
        p = embed(A.ravel(), B.ravel())
        na, nb = len(a), len(b)
        idx = np.arange(na * nb).reshape(na, nb) + offset
        q0, q1, q2, q3 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
        tri = np.concatenate([np.stack([q0, q1, q2], -1).reshape(-1, 3), np.stack([q0, q2, q3], -1).reshape(-1, 3)])
        points.append(p)
        faces.append(tri)
        offset += na * nb

    one = np.ones
    grid(xs, ys, lambda a, b: np.stack([a, b, 0 * one(a.shape)], 1))
    grid(xs, ys, lambda a, b: np.stack([a, b, sz * one(a.shape)], 1))
    grid(xs, zs, lambda a, b: np.stack([a, -sy / 2 * one(a.shape), b], 1))
    grid(xs, zs, lambda a, b: np.stack([a, sy / 2 * one(a.shape), b], 1))
    grid(ys, zs, lambda a, b: np.stack([-sx / 2 * one(a.shape), a, b], 1))
    grid(ys, zs, lambda a, b: np.stack([sx / 2 * one(a.shape), a, b], 1))
    P = np.concatenate(points)
    F = np.concatenate(faces)
    _, first, inverse = np.unique(np.round(P, 9), axis=0, return_index=True, return_inverse=True)
    V = P[first]
    F = inverse.reshape(-1)[F]
    # Orient outward (the box is convex): flip faces whose normal points inward.
    centre = np.array([0.0, 0.0, sz / 2])
    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = np.einsum("ij,ij->i", n, tri.mean(1) - centre) < 0
    F[inward] = F[inward][:, [0, 2, 1]]
    return V, F.astype(np.int32)


def face_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def interior_edges(F: np.ndarray) -> np.ndarray:
    """(E, 2) pairs of faces sharing an edge."""
    k = F.shape[1]
    edges = np.concatenate([np.sort(F[:, [a, (a + 1) % k]], axis=1) for a in range(k)])
    owner = np.tile(np.arange(len(F)), k)
    order = np.lexsort(edges.T[::-1])
    e, o = edges[order], owner[order]
    same = (e[1:] == e[:-1]).all(1)
    return np.stack([o[:-1][same], o[1:][same]], 1)


def folded_edges(V0: np.ndarray, V: np.ndarray, F: np.ndarray, threshold: float = np.pi / 2) -> int:
    """Edges whose dihedral (angle between the two face normals) grew by more
    than `threshold` compared with the input: creases, folds and inverted faces."""
    pairs = interior_edges(F)
    def angles(X):
        n = face_normals(X, F)
        return np.arccos(np.clip(np.einsum("ij,ij->i", n[pairs[:, 0]], n[pairs[:, 1]]), -1, 1))
    return int(np.count_nonzero(angles(V) - angles(V0) > threshold))


def uniform_delta(V: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """|v_i − mean of its 1-ring| per vertex: a rigid-motion-invariant local feature size."""
    k = simplices.shape[1]
    pairs = np.concatenate([simplices[:, [a, b]] for a in range(k) for b in range(k) if a != b])
    pairs = np.unique(pairs, axis=0)
    count = np.bincount(pairs[:, 0], minlength=len(V)).astype(float)
    mean = np.zeros_like(V)
    np.add.at(mean, pairs[:, 0], V[pairs[:, 1]])
    mean /= np.maximum(count, 1)[:, None]
    return np.linalg.norm(V - mean, axis=1)
