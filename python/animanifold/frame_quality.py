"""Measures of a morph's in-between frames, the same for every method and for a peer's meshes:
topology (Euler characteristic, connected pieces), creases, and the steps between frames.

These are the bar a morph is held to (see the morph issue and bench/bench_morph.py): frames keep
their topology between the ends' (no noise), their creases near the inputs' own, and move
steadily (no pop, no standstill).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _core
from .cavities import surface_components


def unique_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(edges (E, 2) sorted, inverse (3F,)): every triangle side once, and which edge each side
    is (side k of face f, from corner k to corner k+1, is entry 3f + k)."""
    faces = np.asarray(faces, dtype=np.int64)
    sides = np.sort(np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    span = int(faces.max()) + 1 if len(faces) else 1
    keys, inverse = np.unique(sides[:, 0] * span + sides[:, 1], return_inverse=True)  # one integer per edge
    return np.stack([keys // span, keys % span], axis=1), inverse.ravel()


def euler_characteristic(vertices: np.ndarray, faces: np.ndarray) -> int:
    """V - E + F of a triangle mesh, counting only vertices that faces use."""
    faces = np.asarray(faces)
    if len(faces) == 0:
        return 0
    used = len(np.unique(faces))
    return int(used - len(unique_edges(faces)[0]) + len(faces))


def pieces(vertices: np.ndarray, faces: np.ndarray) -> int:
    """Connected pieces (faces sharing a vertex are connected)."""
    faces = np.asarray(faces)
    if len(faces) == 0:
        return 0
    return int(len(np.unique(surface_components(len(vertices), faces))))


def crease_share(vertices: np.ndarray, faces: np.ndarray, degrees: float = 60.0) -> float:
    """The share of the mesh's edge length on edges where the two faces' normals differ by more
    than `degrees` (a crease sharper than that). Edges with one face (open) or more than two are
    left out; faces of zero area count as creased (their normal is undefined)."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return 0.0
    edges, inverse = unique_edges(faces)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    norm = np.linalg.norm(normals, axis=1)
    unit = normals / np.maximum(norm, 1e-300)[:, None]
    face_of_side = np.repeat(np.arange(len(faces)), 3)
    order = np.argsort(inverse, kind="stable")
    counts = np.bincount(inverse, minlength=len(edges))
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    two = counts == 2
    first = face_of_side[order[starts[two]]]
    second = face_of_side[order[starts[two] + 1]]
    cosine = np.einsum("ij,ij->i", unit[first], unit[second])
    degenerate = (norm[first] <= 0) | (norm[second] <= 0)
    creased = (cosine < np.cos(np.radians(degrees))) | degenerate
    lengths = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    total = lengths.sum()
    return float(lengths[two][creased].sum() / total) if total > 0 else 0.0


# At most this many samples per surface for a two-sided distance (every k-th, deterministically):
# frames of a morph carry 50k-100k faces, and a step between frames is far larger than their spacing.
MAX_SAMPLES = 20000


def surface_samples(vertices: np.ndarray, faces: np.ndarray, limit: int = MAX_SAMPLES) -> np.ndarray:
    """Points a two-sided distance is measured on: the vertices and the face centres, every k-th
    where there are more than `limit`."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    points = np.concatenate([vertices[np.unique(faces)], vertices[faces].mean(axis=1)]) if len(faces) else vertices
    stride = max(1, -(-len(points) // limit))
    return np.ascontiguousarray(points[::stride])


def hausdorff(first: tuple[np.ndarray, np.ndarray], second: tuple[np.ndarray, np.ndarray]) -> float:
    """Two-sided Hausdorff distance between two triangle meshes, on samples (vertices and face
    centres) of each against the other's surface. Infinite when exactly one is empty."""
    (va, fa), (vb, fb) = first, second
    if len(fa) == 0 and len(fb) == 0:
        return 0.0
    if len(fa) == 0 or len(fb) == 0:
        return float("inf")
    one = _core.distances_to_surface(surface_samples(va, fa), np.asarray(vb, np.float64), np.asarray(fb, np.int32))
    two = _core.distances_to_surface(surface_samples(vb, fb), np.asarray(va, np.float64), np.asarray(fa, np.int32))
    return float(max(one.max(), two.max()))


@dataclass
class FrameMeasures:
    """The bar's measures over a sequence of frames (the ends first and last)."""

    times: list[float]
    euler: list[int]
    pieces: list[int]
    creases: list[float]
    steps: list[float]             # Hausdorff distance between consecutive frames
    from_source: float             # Hausdorff distance of the frame at 1/4 of the range from the source
    source_target: float           # Hausdorff distance between the two ends

    @property
    def topology_noise(self) -> list[int]:
        """Indices of frames whose Euler characteristic leaves the ends' range or that have more
        pieces than the ends."""
        low, high = sorted((self.euler[0], self.euler[-1]))
        most = max(self.pieces[0], self.pieces[-1])
        return [i for i, (e, p) in enumerate(zip(self.euler, self.pieces)) if not low <= e <= high or p > most]

    @property
    def excess_creases(self) -> float:
        """The largest share of creased edge length over the inputs' own (the larger end's)."""
        own = max(self.creases[0], self.creases[-1])
        return max(c - own for c in self.creases)

    @property
    def pop_ratio(self) -> float:
        """The largest step between consecutive frames over the mean step."""
        mean = float(np.mean(self.steps))
        return float(max(self.steps) / mean) if mean > 0 else float("inf")

    @property
    def quarter_motion(self) -> float:
        """How far the frame at a quarter of the range is from the source, of the source-target
        distance."""
        return self.from_source / self.source_target if self.source_target > 0 else float("inf")

    def as_dict(self) -> dict:
        return {"frames": len(self.times), "euler": self.euler, "pieces": self.pieces,
                "topology_noise_frames": len(self.topology_noise), "excess_creases": self.excess_creases,
                "pop_ratio": self.pop_ratio, "quarter_motion": self.quarter_motion}


def measure_frames(frames: list[tuple[np.ndarray, np.ndarray]], times: list[float],
                   quarter: tuple[np.ndarray, np.ndarray]) -> FrameMeasures:
    """The measures of `frames` ((vertices, faces) at `times`, ends included) and of the frame at a
    quarter of the range (`quarter`)."""
    steps = [hausdorff(frames[i], frames[i + 1]) for i in range(len(frames) - 1)]
    return FrameMeasures(
        times=list(map(float, times)),
        euler=[euler_characteristic(v, f) for v, f in frames],
        pieces=[pieces(v, f) for v, f in frames],
        creases=[crease_share(v, f) for v, f in frames],
        steps=steps,
        from_source=hausdorff(frames[0], quarter),
        source_target=hausdorff(frames[0], frames[-1]),
    )
