"""Benchmark for issue 8 (smoothing): prints figures, asserts nothing.

1. Schaefer et al. subdivision of a ~1M-tet manifold, one level: time and
   peak resident memory (the process's high-water mark before and after).
2. OpenSubdiv Loop refinement of a ~50k-face frame to level 2 (limit
   positions, creases by dihedral angle): time per frame, topology built anew
   each frame as live playback must (slices change topology).
3. Live playback path: slice + smooth_levels=2 per frame on the 1M-tet manifold.

Run:  PYTHONPATH=python:tests python3 bench/bench_subdivide.py
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import animanifold as am  # noqa: E402
from helpers.shapes import icosphere  # noqa: E402


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: KiB


def torus(n: int, m: int, R: float = 1.0, r: float = 0.35) -> tuple[np.ndarray, np.ndarray]:
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n, endpoint=False), np.linspace(0, 2 * np.pi, m, endpoint=False))
    pts = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(m))
    a = j * n + i
    b = j * n + (i + 1) % n
    c = ((j + 1) % m) * n + (i + 1) % n
    d = ((j + 1) % m) * n + i
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return pts, faces.astype(np.int32)


def main() -> None:
    # --- 1. manifold subdivision
    v, f = icosphere(5)  # 10242 vertices, 20480 faces
    keyframes = 17
    times = np.linspace(0.0, 4.0, keyframes)
    path = np.stack([times, 0.5 * np.sin(2 * times), np.zeros_like(times)], 1)
    m = am.stitch([v * (1 + 0.1 * np.sin(3 * t)) + p for t, p in zip(times, path)], f, times)
    print(f"input: {len(m.points):,} points, {len(m.simplices):,} tets; peak RSS so far {peak_mb():.0f} MB")
    for keep in (False, True):
        before = peak_mb()
        t0 = time.perf_counter()
        m1 = am.subdivide(m, levels=1, keep_keyframe_times=keep)
        dt = time.perf_counter() - t0
        after = peak_mb()
        out_mb = (m1.points.nbytes + m1.simplices.nbytes) / 2**20
        print(
            f"subdivide 1 level (keep_keyframe_times={keep}): {dt:.2f} s -> {len(m1.points):,} points, "
            f"{len(m1.simplices):,} tets ({out_mb:.0f} MB of arrays); peak RSS {before:.0f} -> {after:.0f} MB"
        )
    t0 = time.perf_counter()
    report = m1.check()
    print(f"check_manifold of the result: {time.perf_counter() - t0:.2f} s, oriented={report.is_oriented_manifold}")

    # --- 2. OpenSubdiv on a ~50k-face frame
    tv, tf = torus(160, 160)
    print(f"frame: {len(tv):,} vertices, {len(tf):,} triangles")
    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        r = am.subdivide_frame(tv, tf, levels=2, scheme="loop", crease_angle=30.0)
        runs.append(time.perf_counter() - t0)
    print(
        f"Loop level 2 + limit: {1000 * np.median(runs):.0f} ms per frame (median of 5) -> "
        f"{len(r.vertices):,} vertices, {len(r.faces):,} triangles"
    )
    quads = np.concatenate([tf[: len(tf) // 2], tf[len(tf) // 2 :, 2:3]], 1)  # (a, b, c, d) per grid cell
    runs = []
    for _ in range(5):
        t0 = time.perf_counter()
        r = am.subdivide_frame(tv, quads, levels=2, scheme="catmull_clark", crease_angle=30.0)
        runs.append(time.perf_counter() - t0)
    print(
        f"Catmull-Clark level 2 + limit on {len(quads):,} quads: {1000 * np.median(runs):.0f} ms per frame -> "
        f"{len(r.faces):,} quads"
    )

    # --- 3. live path: slice the 1M-tet manifold and smooth the frame
    m.slice(0.1)  # build the interval index once
    runs, plain = [], []
    for t in np.linspace(0.13, 3.9, 8):
        t0 = time.perf_counter()
        s = m.slice(t)
        plain.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        s2 = m.slice(t, smooth_levels=2)
        runs.append(time.perf_counter() - t0)
    print(
        f"slice of the 1M-tet manifold: {1000 * np.median(plain):.0f} ms ({len(s.faces):,} faces); "
        f"slice + smooth_levels=2: {1000 * np.median(runs):.0f} ms ({len(s2.faces):,} faces) per frame"
    )
    print(f"peak RSS of the whole run: {peak_mb():.0f} MB")


if __name__ == "__main__":
    main()
