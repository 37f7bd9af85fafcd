"""Benchmark of barycentric refinement (issue 4): 100k random splits on a ~1M-tet
animation manifold. Prints splits per second and peak memory.

    PYTHONPATH=python python3 bench/bench_refine.py [--order degeneracy|given] [--check] [--json PATH]

The manifold is a torus of 2·u·v triangles (u=100, v=50: 10k faces) stitched
over 35 keyframes of a travelling wave: 3·10000·34 = 1,020,000 tets in R^4.
Splits pick a random tet, a random face of it with 2..4 vertices and random
(Dirichlet) coordinates, so edges, triangles and tets are all split.
"""

from __future__ import annotations

import resource
import time

import numpy as np

import animanifold as am
from animanifold import _core
from figures import bench_parser, write_json


def torus(u: int, v: int) -> tuple[np.ndarray, np.ndarray]:
    a, b = np.meshgrid(np.linspace(0, 2 * np.pi, u, endpoint=False), np.linspace(0, 2 * np.pi, v, endpoint=False),
                       indexing="ij")
    V = np.c_[((2 + np.cos(b)) * np.cos(a)).ravel(), ((2 + np.cos(b)) * np.sin(a)).ravel(), np.sin(b).ravel()]
    i, j = np.meshgrid(np.arange(u), np.arange(v), indexing="ij")
    p00, p10 = i * v + j, ((i + 1) % u) * v + j
    p01, p11 = i * v + (j + 1) % v, ((i + 1) % u) * v + (j + 1) % v
    F = np.r_[np.c_[p00.ravel(), p10.ravel(), p11.ravel()], np.c_[p00.ravel(), p11.ravel(), p01.ravel()]]
    return V, F.astype(np.int32)


def peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux reports KiB


def main() -> None:
    parser = bench_parser(__doc__, splits=100_000, keyframes=35, u=100, v=50, seed=1)
    parser.add_argument("--order", choices=["degeneracy", "given"], default="degeneracy")
    parser.add_argument("--check", action="store_true", help="also verify the result is an oriented manifold")
    args = parser.parse_args()

    V, F = torus(args.u, args.v)
    times = np.linspace(0, 1, args.keyframes)
    radial = V / np.linalg.norm(V, axis=1)[:, None]
    angle = np.arctan2(V[:, 1], V[:, 0])
    frames = [V + 0.2 * np.sin(4 * angle - 6 * t)[:, None] * radial for t in times]
    start = time.perf_counter()
    m = am.stitch(frames, F, times)
    points, simplices = np.array(m.points), np.array(m.simplices)
    print(f"manifold: {len(points):,} vertices, {len(simplices):,} tets in R^{points.shape[1]} "
          f"(stitched in {time.perf_counter() - start:.2f} s); peak so far {peak_mib():.0f} MiB")

    rng = np.random.default_rng(args.seed)
    n = args.splits
    tets = simplices[rng.integers(0, len(simplices), n)]
    sizes = rng.integers(2, 5, n)
    order = np.argsort(rng.random((n, 4)), axis=1)
    ids = np.take_along_axis(tets, order, axis=1).astype(np.int32)
    coords = rng.gamma(1.0, size=(n, 4))  # normalised over each face below: Dirichlet(1, ..., 1)
    mask = np.arange(4)[None] < sizes[:, None]
    ids[~mask] = -1
    coords[~mask] = 0
    coords /= coords.sum(axis=1, keepdims=True)

    start = time.perf_counter()
    r = am.refine_complex(points, simplices, (ids, coords), epsilon=1e-3, order=args.order)
    elapsed = time.perf_counter() - start
    applied = int(np.count_nonzero(r.new_vertex_of_split >= 0))
    print(f"order={args.order}: {n:,} splits ({applied:,} applied, {n - applied:,} removed by epsilon) in "
          f"{elapsed:.2f} s = {n / elapsed:,.0f} splits/s")
    print(f"result: {len(r.points):,} vertices, {len(r.simplices):,} tets; "
          f"peak memory (ru_maxrss) {peak_mib():.0f} MiB")
    write_json(args.json, {"tets": len(simplices), "splits": n, "applied": applied, "seconds": elapsed,
                           "splits_per_s": n / elapsed, "peak_mib": peak_mib(), "order": args.order})
    if args.check:
        report = _core.check_manifold(r.simplices)
        volume = (_core._testing.simplex_volumes(r.points, r.simplices).sum(), _core._testing.simplex_volumes(points, simplices).sum())
        print(f"check: oriented manifold {report.is_oriented_manifold}, volume {volume[0]:.9g} vs {volume[1]:.9g}")


if __name__ == "__main__":
    main()
