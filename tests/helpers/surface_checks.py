"""Comparing a frame with the mesh it should reproduce (numpy only: imported by the
in-process tests and by the scripts run under Debian's blender binary)."""

from __future__ import annotations

import numpy as np


def closest_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Closest points of triangles (a, b, c) to points p, all (..., 3) broadcast
    (Ericson, Real-Time Collision Detection, 5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
    bp = p - b
    d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
    cp = p - c
    d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v_in, w_in = vb / denom, vc / denom
        v_ab = d1 / (d1 - d3)
        w_ac = d2 / (d2 - d6)
        w_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    out = a + v_in[..., None] * ab + w_in[..., None] * ac  # inside the face
    cases = [  # later cases win: from the face region out to the vertex regions
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + w_bc[..., None] * (c - b)),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + w_ac[..., None] * ac),
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + v_ab[..., None] * ab),
        ((d6 >= 0) & (d5 <= d6), c),
        ((d3 >= 0) & (d4 <= d3), b),
        ((d1 <= 0) & (d2 <= 0), a),
    ]
    for mask, point in cases:
        out = np.where(mask[..., None], np.broadcast_to(point, out.shape), out)
    return out


def distance_to_surface(points: np.ndarray, corners: np.ndarray, chunk: int = 256) -> np.ndarray:
    """Distance of each point (N, 3) to the triangles `corners` (T, 3, 3)."""
    a, b, c = (corners[None, :, i] for i in range(3))
    out = np.empty(len(points))
    for i in range(0, len(points), chunk):
        p = points[i:i + chunk, None, :]
        q = closest_on_triangles(p, a, b, c)
        out[i:i + chunk] = np.linalg.norm(q - p, axis=-1).min(axis=1)
    return out


def nearest_point_distance(points: np.ndarray, others: np.ndarray, chunk: int = 512) -> np.ndarray:
    """Distance of each point (N, 3) to the nearest of `others` (M, 3)."""
    out = np.empty(len(points))
    for i in range(0, len(points), chunk):
        out[i:i + chunk] = np.linalg.norm(points[i:i + chunk, None, :] - others[None], axis=-1).min(axis=1)
    return out


def area(corners: np.ndarray) -> float:
    return float(0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1).sum())


def signed_volume(corners: np.ndarray) -> float:
    return float(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() / 6.0)


def compare_frame(frame_vertices: np.ndarray, frame_corners: np.ndarray, vertices: np.ndarray,
                  corners: np.ndarray) -> dict:
    """How far a frame (its vertices and triangles) is from a mesh, relative to the
    mesh's bounding-box diagonal: 'frame_to_mesh' (every frame vertex on the mesh's
    surface), 'mesh_to_frame' (every mesh vertex among the frame's: the frame may
    add vertices on the surface, never lose one), 'area' (relative difference of the
    area sums) and 'volume' (relative difference of the enclosed volumes: an
    inside-out frame has the opposite sign)."""
    size = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))
    mesh_area, mesh_volume = area(corners), signed_volume(corners)
    return {
        "frame_to_mesh": float(distance_to_surface(frame_vertices, corners).max()) / size,
        "mesh_to_frame": float(nearest_point_distance(vertices, frame_vertices).max()) / size,
        "area": abs(area(frame_corners) - mesh_area) / mesh_area,
        "volume": abs(signed_volume(frame_corners) - mesh_volume) / abs(mesh_volume),
    }


def frame_matches(report: dict, tolerance: float = 1e-6) -> bool:
    return all(value <= tolerance for value in report.values())


def triangles(s, face_attribute: str | None = None) -> list:
    """A frame's triangles as corner coordinates, each started at its least corner (its
    orientation kept), with `face_attribute` if named, sorted: the same surface, bit for
    bit, whatever the order of its vertices and faces."""
    values = s.face_attributes[face_attribute].tolist() if face_attribute else [None] * len(s.faces)
    out = []
    for corners, value in zip(s.vertices[s.faces].tolist(), values):
        first = corners.index(min(corners))
        out.append((tuple(map(tuple, corners[first:] + corners[:first])), value))
    return sorted(out)
