"""Error-driven sampling: the keyframes, plus the frames where the manifold strays from
the source, until every frame and half frame of the range lies within a tolerance of the
source's evaluated mesh.

Why measure rather than predict: a manifold frame between two samples is not the source's
frame there. Easing and rotations are lost between linear samples, and the slice's
vertices slide along the diagonal edges of each prism's three tets (the staircase), so a
frame is not even the linear blend of its samples. Both errors shrink where samples are
added, and only slicing shows how large they are.

The measure is the two-sided vertex-to-surface distance: the source's evaluated vertices
to the frame's surface and the frame's vertices to the source's surface, both through the
core's CGAL AABB tree (`distances_to_surface`: any triangle soup, so open source meshes
too). The tolerance is a fraction of the object's size: the largest bounding-box diagonal
of its evaluated mesh over the candidate frames, in its own local space (so a rotating or
travelling object's size does not change).

Each round stitches the samples, slices the candidate frames whose interval changed (an
interval's tets depend only on its two samples), and adds, in every interval that has
one, its worst candidate above the tolerance. A sample reproduces the source at its frame,
so the refinement ends; the sample cap bounds it sooner, and the result says the largest
deviation reached and where.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from . import sampling
from ._lib import am

TOLERANCE_PERCENT = 0.2  # of the object's bounding-box diagonal
MAX_SAMPLES = 120


@dataclass
class Surface:
    """The source's evaluated mesh at a candidate frame (what the manifold must match)."""

    positions: np.ndarray  # (n, 3) float32, the object's local space at that frame
    faces: np.ndarray  # (T, 3) int32 loop triangles
    matrix_world: np.ndarray  # (4, 4)

    @property
    def diagonal(self) -> float:
        return float(np.linalg.norm(self.positions.max(axis=0) - self.positions.min(axis=0)))


@dataclass
class Fidelity:
    """How close the manifold's frames are to the source's evaluated mesh."""

    tolerance: float  # distance, the object's local units
    size: float  # the bounding-box diagonal the tolerance is a fraction of
    deviation: float  # the largest two-sided distance over the candidate frames
    frame: float  # where it is
    samples: int
    candidates: int
    sample_cap: int

    @property
    def reached(self) -> bool:
        return self.deviation <= self.tolerance

    def percent(self, distance: float) -> float:
        return 100.0 * distance / self.size if self.size > 0 else 0.0

    def warning(self, name: str) -> str | None:
        """The report's warning when the tolerance was not reached, else None."""
        if self.reached:
            return None
        why = (f"the cap of {self.sample_cap} samples was reached (raise the cap or the tolerance)"
               if self.samples >= self.sample_cap else
               "it is a sample, so its faces differ: the source's polygons are triangulated there unlike at the "
               "first frame, whose triangulation every sample shares")
        return (f"'{name}': frame {self.frame:g} is {self.percent(self.deviation):.3g} % of the object's size "
                f"({self.deviation:.4g}) from the source, above the tolerance of "
                f"{self.percent(self.tolerance):.3g} % ({self.tolerance:.4g}): {why}")


def candidate_frames(start: float, end: float, keys: np.ndarray) -> np.ndarray:
    """Every frame and half frame of [start, end], and the keyframes inside it."""
    halves = np.arange(2 * start, 2 * end + 1, dtype=np.float64) / 2.0
    inside = keys[(keys >= start) & (keys <= end)]
    return np.union1d(halves, inside)


def read_surfaces(context, obj, frames: np.ndarray, progress=None) -> list[Surface]:
    """The source's evaluated mesh at each frame, kept small: positions and loop triangles
    (shared with the previous frame's when equal)."""
    previous = [None]

    def keep(s: sampling.MeshSample) -> Surface:
        faces = s.tri_vertices
        if previous[0] is not None and np.array_equal(previous[0], faces):
            faces = previous[0]
        previous[0] = faces
        return Surface(s.positions.astype(np.float32), faces, s.matrix_world)

    return sampling.evaluate(context, obj, frames, progress, triangulate_all=True, keep=keep)


def two_sided_distance(a_vertices, a_faces, b_vertices, b_faces) -> float:
    """The larger of: the farthest vertex of a from b's surface, and of b from a's
    (infinite when either has no faces)."""
    core = am._core
    a_v, b_v = np.ascontiguousarray(a_vertices, np.float64), np.ascontiguousarray(b_vertices, np.float64)
    a_f, b_f = np.ascontiguousarray(a_faces, np.int32), np.ascontiguousarray(b_faces, np.int32)
    if len(a_f) == 0 or len(b_f) == 0:
        return float("inf")
    return float(max(core.distances_to_surface(a_v, b_v, b_f).max(), core.distances_to_surface(b_v, a_v, a_f).max()))


def surface_in(surface: Surface, matrix0: np.ndarray) -> np.ndarray:
    """`surface`'s positions in the local space of the object at the first sample (the
    manifold's space: object motion is baked into it)."""
    positions = surface.positions.astype(np.float64)
    if np.array_equal(surface.matrix_world, matrix0):
        return positions
    rel = np.linalg.inv(matrix0) @ surface.matrix_world
    return positions @ rel[:3, :3].T + rel[:3, 3]


def frame_deviation(manifold, frame: float, surface: Surface, matrix0: np.ndarray) -> float:
    """Two-sided distance between the manifold's frame and the source's mesh at `frame`."""
    s = manifold.slice(frame)
    return two_sided_distance(s.vertices, s.faces, surface_in(surface, matrix0), surface.faces)


def worst_per_interval(candidates: np.ndarray, deviation: np.ndarray, samples: np.ndarray,
                       tolerance: float) -> np.ndarray:
    """In each interval between two samples, the candidate frame farthest from the source,
    if it is above the tolerance; ordered worst first."""
    interval = np.searchsorted(samples, candidates, side="right")  # candidates in (s[i-1], s[i])
    over = (deviation > tolerance) & ~np.isin(candidates, samples)
    picks = []
    for i in np.unique(interval[over]):
        mine = np.flatnonzero(over & (interval == i))
        picks.append(mine[np.argmax(deviation[mine])])
    picks = np.array(picks, dtype=np.int64)
    return picks[np.argsort(-deviation[picks], kind="stable")]


class _Refinement:
    """The state of one error-driven sampling: the candidates' source surfaces and their
    deviations, the samples (evaluated in full) and the latest manifold."""

    def __init__(self, context, obj, candidates, surfaces, initial, tolerance, progress):
        self.context, self.obj, self.progress, self.tolerance = context, obj, progress, tolerance
        self.candidates, self.surfaces = candidates, surfaces
        self.matrix0 = surfaces[0].matrix_world
        self.deviation = np.full(len(candidates), np.inf)
        self.samples: dict[float, sampling.MeshSample] = {}
        self.add(initial)
        self.dirty = np.ones(len(candidates), dtype=bool)
        self.keys = self.manifold = None

    def add(self, frames) -> None:
        """Evaluates the source in full at new sample frames (connectivity was checked on
        every candidate already; the start's triangulation is the one keyframes share)."""
        frames = [float(f) for f in frames if float(f) not in self.samples]
        if frames:
            self.samples.update(zip(frames, sampling.evaluate(self.context, self.obj, frames, triangulate_all=True)))

    def stitch_and_measure(self):
        """Steps (am.core_job.Steps): the round's stitch and measure as one long call."""
        times = np.array(sorted(self.samples))
        self.keys = sampling.keyframes_from(self.obj, [self.samples[t] for t in times], times, check_motion=False)
        # A slice at a sample's time is that sample exactly (the slicer reproduces keyframes):
        # nothing to measure there.
        sampled = np.isin(self.candidates, times)
        self.deviation[sampled] = 0.0
        dirty = np.flatnonzero(self.dirty & ~sampled)
        self.manifold, self.deviation[dirty] = yield am.core_job.CoreCall(
            stitch_and_measure, (self.keys, [(self.candidates[i], self.surfaces[i]) for i in dirty], self.matrix0))
        self.dirty[:] = False
        within = int(np.count_nonzero(self.deviation <= self.tolerance))
        self.progress.counter(2 * len(self.candidates) + 2)(len(self.candidates) + within)

    def refine_once(self, cap: int) -> bool:
        """Adds the worst candidates (one an interval, at most up to the cap); False when
        nothing was added (all within the tolerance, or the cap reached)."""
        times = np.array(sorted(self.samples))
        picks = worst_per_interval(self.candidates, self.deviation, times, self.tolerance)
        picks = picks[:max(cap - len(times), 0)]
        if len(picks) == 0:
            return False
        new = np.sort(self.candidates[picks])
        self.add(new)
        # The intervals that got a sample changed; the others keep their tets.
        where = np.searchsorted(times, new, side="right")
        lo, hi = times[where - 1], times[where]
        for a, b in zip(lo, hi):
            self.dirty |= (self.candidates > a) & (self.candidates < b)
        return True


def stitch_and_measure(keys, frames, matrix0, progress=None, interrupted=None):
    """(manifold, deviations): the manifold stitched from `keys` and its deviation from the source at
    each of `frames` ((frame, Surface) pairs). Reads no Blender data: a worker thread may run it."""
    manifold = sampling.stitch_keyframes(keys, progress, interrupted)
    deviation = np.zeros(len(frames))

    def measure(i):
        if interrupted is not None and interrupted():
            raise am.Cancelled("cancelled measuring the deviations")
        return frame_deviation(manifold, frames[i][0], frames[i][1], matrix0)

    if len(frames):
        deviation[0] = measure(0)  # the first slice makes the manifold's slicer
        # Slicing and distances run in the core without the GIL: one thread per core.
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
            deviation[1:] = list(pool.map(measure, range(1, len(frames))))
    return manifold, deviation


def adaptive_steps(context, obj, start: float, end: float, initial: np.ndarray,
                   tolerance_percent: float, max_samples: int, progress):
    """Keyframes of `obj` over [start, end]: the `initial` frames (start and end among them)
    and the frames refinement adds, with the manifold and the Fidelity reached, as
    am.core_job.Steps whose long calls are the rounds' stitches. The bar (`progress`,
    progress.Progress) has 2·candidates + 2 parts: the candidates read, then those within the
    tolerance, then Convert's saving and making; a stitch leaves it where it is. Raises
    SamplingError when the source changes connectivity or nothing moves, or the tolerance or
    cap is out of range."""
    if not tolerance_percent > 0:
        raise sampling.SamplingError(f"the tolerance must be above 0 % of the object's size, got {tolerance_percent:g} %")
    if max_samples < len(initial):
        raise sampling.SamplingError(f"'{obj.name}': the sample cap ({max_samples}) is below the {len(initial)} keyframes and range ends "
                         "that are always sampled")
    candidates = candidate_frames(start, end, initial)
    surfaces = read_surfaces(context, obj, candidates, progress.counter(2 * len(candidates) + 2))
    _check_motion(obj, candidates, surfaces)
    size = max(s.diagonal for s in surfaces)
    tolerance = tolerance_percent / 100.0 * size
    refinement = _Refinement(context, obj, candidates, surfaces, initial, tolerance, progress)
    while True:
        progress.span(progress.value, progress.value)
        yield from refinement.stitch_and_measure()
        if not refinement.refine_once(max_samples):
            break
    worst = int(np.argmax(refinement.deviation))
    fidelity = Fidelity(tolerance, size, float(refinement.deviation[worst]), float(candidates[worst]),
                        len(refinement.samples), len(candidates), int(max_samples))
    return refinement.keys, refinement.manifold, fidelity


def _check_motion(obj, candidates, surfaces) -> None:
    first = surfaces[0]
    for s in surfaces[1:]:
        if not np.array_equal(s.positions, first.positions) or not np.array_equal(s.matrix_world, first.matrix_world):
            return
    raise sampling.SamplingError(
        f"'{obj.name}' does not move in frames {candidates[0]:g}–{candidates[-1]:g}: no animation in the range")
