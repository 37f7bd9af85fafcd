"""The array entry points' fuzz target (stitch, slice and interval frames, refine, Deformer,
voronoi_skeleton, morph's input check, hole_space, subdivide_frame, the morph with each method,
manifold subdivision), shared by fuzz_arrays.py and the pytest replay.

An input is decoded with atheris.FuzzedDataProvider: its first byte picks the entry point, the rest
builds small arrays from a closed shape (a tetrahedron or an octahedron) — vertices moved by fuzzed
amounts (any double, NaN and infinities included, now and then), face indices now and then replaced
by fuzzed ones (negative, out of range, beyond 32 bits) — so that most inputs get past the
argument checks. Sizes are capped, so one input costs milliseconds.

Allowed outcomes: a result, an animanifold.Error (InputError, MeshingError, BooleanError, ...), or a
ValueError/TypeError raised by our Python argument checks (they name the argument). Anything else
(another exception, a crash, an abort, a hang, a huge allocation) is a finding.
"""

from __future__ import annotations

import warnings

import numpy as np

import animanifold as am
from animanifold import _core
from animanifold.indices import as_indices

TETRAHEDRON = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
               np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
OCTAHEDRON = (np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float),
              np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]))
INDEX_VALUES = (-1, -(10**6), 6, 10**8, 2**31, 2**32)


def _double(fdp) -> float:
    """Mostly a modest number; one time in eight any double (NaN, infinities, 1e308 included)."""
    return fdp.ConsumeFloat() if fdp.ConsumeIntInRange(0, 7) == 0 else fdp.ConsumeFloatInRange(-2.0, 2.0)


def _doubles(fdp, shape) -> np.ndarray:
    return np.array([_double(fdp) for _ in range(int(np.prod(shape)))], float).reshape(shape)


def _faces(fdp, faces: np.ndarray) -> np.ndarray:
    """The faces, int64, with up to two entries replaced by hostile indices when the input asks."""
    out = faces.astype(np.int64)
    for _ in range(fdp.ConsumeIntInRange(0, 3) // 2 if fdp.ConsumeBool() else 0):
        row, col = fdp.ConsumeIntInRange(0, len(out) - 1), fdp.ConsumeIntInRange(0, out.shape[1] - 1)
        out[row, col] = INDEX_VALUES[fdp.ConsumeIntInRange(0, len(INDEX_VALUES) - 1)]
    return out


def _shape(fdp) -> tuple[np.ndarray, np.ndarray]:
    """A tetrahedron or octahedron, each vertex moved by up to ~0.1 (or by anything, rarely), hostile faces now and then."""
    vertices, faces = OCTAHEDRON if fdp.ConsumeBool() else TETRAHEDRON
    scale = 0.05 if fdp.ConsumeIntInRange(0, 3) else 1.0
    return vertices + scale * _doubles(fdp, vertices.shape), _faces(fdp, faces)


def _manifold(fdp) -> am.AnimationManifold:
    vertices, faces = _shape(fdp)
    keyframes = [vertices] + [vertices + 0.2 * _doubles(fdp, vertices.shape) for _ in range(fdp.ConsumeIntInRange(1, 2))]
    times = np.cumsum([_double(fdp) for _ in keyframes]) if fdp.ConsumeBool() else np.arange(len(keyframes), dtype=float)
    return am.stitch(np.stack(keyframes), faces, times)


def stitch_and_slice(fdp) -> None:
    manifold = _manifold(fdp)
    lo, hi = manifold.time_range
    t = lo + (hi - lo) * fdp.ConsumeFloatInRange(-0.1, 1.1) if fdp.ConsumeIntInRange(0, 3) else _double(fdp)
    manifold.slice(t)
    manifold.interval_frame(t)


def _split(fdp, simplices: np.ndarray, vertex_count: int) -> tuple[list[int], np.ndarray]:
    """Some corners of one simplex (a face of the complex) with fuzzed weights; rarely a hostile id."""
    simplex = simplices[fdp.ConsumeIntInRange(0, len(simplices) - 1)]
    ids = [int(i) for i in simplex[: fdp.ConsumeIntInRange(1, len(simplex))]]
    if fdp.ConsumeIntInRange(0, 7) == 0:
        ids[0] = fdp.ConsumeIntInRange(-2, vertex_count + 1)
    weights = np.abs(_doubles(fdp, (len(ids),)))
    total = weights.sum()
    return ids, (weights / total if fdp.ConsumeIntInRange(0, 3) and total > 0 else weights)


def refine(fdp) -> None:
    manifold = _manifold(fdp)
    splits = [_split(fdp, manifold.simplices, len(manifold.points)) for _ in range(fdp.ConsumeIntInRange(1, 3))]
    am.refine(manifold, splits, order="given" if fdp.ConsumeBool() else "degeneracy")


def deformer(fdp) -> None:
    vertices, faces = _shape(fdp)
    n = len(vertices)
    anchors = [fdp.ConsumeIntInRange(-1, n) for _ in range(fdp.ConsumeIntInRange(1, 2) - fdp.ConsumeIntInRange(0, 7) // 7)]
    handles = [fdp.ConsumeIntInRange(-1, n) for _ in range(fdp.ConsumeIntInRange(1, 2) - fdp.ConsumeIntInRange(0, 7) // 7)]
    method = "dual" if fdp.ConsumeBool() else "graph"
    d = am.Deformer(vertices, faces, anchors, handles, method=method)
    transform = np.eye(4)
    transform[:3] += 0.3 * _doubles(fdp, (3, 4))
    d.deform(transform)
    if method == "dual":
        d.restore(max_iterations=3)


def voronoi_skeleton(fdp) -> None:
    vertices, faces = _shape(fdp)
    am.voronoi_skeleton(vertices, faces, max_iterations=1, wrap=None, warn=False)


def morph_input(fdp) -> None:
    vertices, faces = _shape(fdp)
    _core.check_morph_input(vertices, as_indices(faces, "the faces"), "fuzzed shape")


def hole_space(fdp) -> None:
    am.hole_space(*_shape(fdp))


def subdivide_frame(fdp) -> None:
    vertices, faces = _shape(fdp)
    am.subdivide_frame(vertices, faces, levels=1, limit=fdp.ConsumeBool())


def morph(fdp) -> None:
    """The whole morph on two fuzzed shapes, every stage and its checks. The field method costs
    ~0.2 s a call on these shapes (the others ~20 ms), so it is picked one time in sixteen."""
    pick = fdp.ConsumeIntInRange(0, 15)
    method = "field" if pick == 0 else "skeleton" if pick <= 8 else "strip"
    source, target = _shape(fdp), _shape(fdp)
    am.morph(source, target, t0=_double(fdp) if fdp.ConsumeIntInRange(0, 7) == 0 else 0.0, method=method)


def subdivide_manifold(fdp) -> None:
    manifold = _manifold(fdp)
    scheme = "linear" if fdp.ConsumeBool() else "schaefer"
    am.subdivide(manifold, 1, scheme=scheme, keep_keyframe_times=fdp.ConsumeBool())


# Appended in this order: an input's first byte picks TARGETS[byte % len(TARGETS)], and the seeds'
# first bytes are the index of their entry point, so a new entry point goes at the end.
TARGETS = (stitch_and_slice, refine, deformer, voronoi_skeleton, morph_input, hole_space, subdivide_frame,
           morph, subdivide_manifold)
ALLOWED = (am.Error, ValueError, TypeError)


def run_input(data: bytes) -> str | None:
    """Runs the entry point the input picks; returns its name, or None for an empty input. An
    allowed refusal (ALLOWED) is swallowed; anything else propagates."""
    import atheris  # imported here so that the pytest replay needs atheris only when it replays

    if not data:
        return None
    target = TARGETS[data[0] % len(TARGETS)]
    fdp = atheris.FuzzedDataProvider(data[1:])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # warnings (separability, hole space) are results, not findings
        with np.errstate(all="ignore"):
            try:
                target(fdp)
            except ALLOWED:
                pass
    return target.__name__
