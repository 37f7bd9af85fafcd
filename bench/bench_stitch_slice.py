"""Benchmark: stitch a mesh over many keyframes, then slice frames with and without the index.

    python3 bench/bench_stitch_slice.py [--case meshes|character] [--keyframes N] [--frames 20] [--bandwidth-gib 1]

Cases:
  meshes     (default, 100 keyframes: 16.8 M tets) bunny.off + 3holes.off from
             <repo>/../shared/data/meshes, each midpoint-subdivided once (≈ 56.7k
             faces together). Without the data folder it falls back to three
             procedural icospheres (61,440 faces) and says so.
  character  (default 20 keyframes: 4.97 M tets) a 43.6k-vertex, 87k-face geodesic
             sphere with a UV map (vertex attribute "uv"), the size of a game character.
Both are animated by a smooth travelling-wave deformation (animanifold.procedural.wobble).

Prints: stitch time and tets/s; the interval index's build time and size (bytes a tet);
the first slice (cold caches); per-frame slice time with the index and without it (every
tet tested), through the package, and its normals' share; a sequence of frames (a bake:
several per keyframe gap) sliced one by one and through AnimationManifold.slices, which
reuses each topology interval's cut; the OpenMP thread count; and the bytes a slice touches per second against this machine's
memory bandwidth (a numpy copy of a large array, measured in the same run).

Bytes touched per slice, a lower bound: for each cut tet its 4 int32 indices
and its 4 points of 4 doubles (144 B), plus the output arrays. It leaves out
the index nodes visited and the welding hash table.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "python"))

import animanifold as am  # noqa: E402
from animanifold import _core  # noqa: E402
from animanifold.procedural import geodesic_sphere, icosphere, subdivide_midpoint, wobble  # noqa: E402

DATA = REPO.parent / "shared" / "data" / "meshes"
TIME_AXIS = 3
BYTES_PER_CUT_TET = 4 * 4 + 4 * 4 * 8  # 4 int32 indices + 4 points of (x, y, z, t) doubles


def normalised(vertices: np.ndarray, offset_x: float) -> np.ndarray:
    """`vertices` scaled to unit size, centred, moved along x (so several meshes sit side by side)."""
    centred = vertices - (vertices.min(axis=0) + vertices.max(axis=0)) / 2.0
    return centred / np.ptp(vertices, axis=0).max() + np.array([offset_x, 0.0, 0.0])


def combine(meshes: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """One mesh (vertices, faces) from several, with face indices offset."""
    offsets = np.cumsum([0] + [len(v) for v, _ in meshes[:-1]])
    vertices = np.concatenate([normalised(v, 1.2 * i) for i, (v, _) in enumerate(meshes)])
    faces = np.concatenate([f + o for (_, f), o in zip(meshes, offsets)]).astype(np.int32)
    return vertices, faces


def benchmark_mesh() -> tuple[np.ndarray, np.ndarray, str]:
    names = ("bunny.off", "3holes.off")
    if all((DATA / n).is_file() for n in names):
        meshes = [subdivide_midpoint(*am.read_mesh(DATA / n)) for n in names]
        return (*combine(meshes), " + ".join(names) + ", each midpoint-subdivided once")
    print(f"note: {DATA} not found; using three procedural icospheres instead of bunny + 3holes")
    sphere = icosphere(5)
    return (*combine([sphere, sphere, sphere]), "3 icospheres (subdivision 5)")


def character_mesh() -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """A 43.6k-vertex sphere of 87k faces and its UV map (longitude, latitude)."""
    vertices, faces = geodesic_sphere(66)
    uv = np.stack([np.arctan2(vertices[:, 1], vertices[:, 0]) / (2 * np.pi) + 0.5,
                   np.arccos(np.clip(vertices[:, 2], -1.0, 1.0)) / np.pi], axis=1)
    return vertices, faces, uv, "geodesic sphere (frequency 66) with a UV map"


def memory_bandwidth(gib: float, repeats: int = 3) -> float:
    """Best GB/s of a numpy copy of `gib` GiB, counting bytes read plus bytes written (STREAM 'copy')."""
    source = np.ones(int(gib * 2**30) // 8)
    target = np.empty_like(source)
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        np.copyto(target, source)
        best = min(best, time.perf_counter() - start)
    return 2 * source.nbytes / best / 1e9


def bytes_touched(s: "_core.Slice") -> int:
    cut_tets = len(np.unique(s.face_simplex))
    outputs = (s.vertices, s.faces, s.normals, s.vertex_edges, s.edge_parameter, s.face_simplex)
    return cut_tets * BYTES_PER_CUT_TET + sum(np.asarray(a).nbytes for a in outputs)


def timed(function, *args):
    start = time.perf_counter()
    result = function(*args)
    return result, time.perf_counter() - start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", choices=("meshes", "character"), default="meshes")
    parser.add_argument("--keyframes", type=int, help="default: 100 (meshes), 20 (character)")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--frames-per-gap", type=int, default=6, help="frames per keyframe gap in the sequence")
    parser.add_argument("--sequence-gaps", type=int, default=10, help="keyframe gaps the sequence covers")
    parser.add_argument("--bandwidth-gib", type=float, default=1.0, help="size of the array copied to measure bandwidth")
    args = parser.parse_args()

    attributes = None
    if args.case == "character":
        rest, faces, uv, source = character_mesh()
        attributes = {"uv": uv}
        args.keyframes = args.keyframes or 20
    else:
        rest, faces, source = benchmark_mesh()
        args.keyframes = args.keyframes or 100
    phases = np.linspace(0.0, 2.0 * np.pi, args.keyframes)
    keyframes = np.stack([wobble(rest, phase, 0.03) for phase in phases])
    times = np.linspace(0.0, 1.0, args.keyframes)
    print(f"mesh        {source}: {len(rest):,} vertices, {len(faces):,} faces; {args.keyframes} keyframes")
    threads = _core._testing.set_omp_threads(1)  # reads the count (and puts it back below)
    _core._testing.set_omp_threads(threads)
    print(f"machine     {os.cpu_count()} cores; slicing on {threads} OpenMP threads")

    manifold, seconds = timed(am.stitch, keyframes, faces, times, attributes)
    tets = len(manifold.simplices)
    assert tets == 3 * len(faces) * (args.keyframes - 1)
    print(f"stitch      {tets:,} tets, {len(manifold.points):,} points in {seconds:.3f} s = {tets / seconds / 1e6:.1f} M tets/s")

    # The core Slicer that AnimationManifold.slice uses, driven directly so the
    # one-off cost of the index is timed apart from per-frame cost.
    slicer = _core.Slicer(manifold.core_complex)
    index_bytes, seconds = timed(slicer.index_memory_bytes, TIME_AXIS)
    print(f"index       built in {seconds:.3f} s, {index_bytes / 2**20:.0f} MiB = {index_bytes / 1e6:.0f} MB, "
          f"{index_bytes / tets:.1f} B a tet ({tets / seconds / 1e6:.1f} M tets/s)")
    first_t = 0.5 * (times[0] + times[1])
    _, seconds = timed(slicer.slice, TIME_AXIS, first_t, True)
    print(f"first slice {seconds:.3f} s (cold caches)")

    # Midpoints of `frames` equal steps: never a keyframe time (those are copies, not cuts).
    frame_times = times[0] + (np.arange(args.frames) + 0.5) / args.frames * (times[-1] - times[0])
    with_index, without_index, touched, faces_out = [], [], [], []
    for t in frame_times:
        s, seconds = timed(slicer.slice, TIME_AXIS, t, True)
        with_index.append(seconds)
        touched.append(bytes_touched(s))
        _, seconds = timed(slicer.slice, TIME_AXIS, t, False)
        without_index.append(seconds)
        faces_out.append(len(s.faces))
    with_index, without_index, touched = map(np.array, (with_index, without_index, touched))
    print(
        f"per frame   with index    median {np.median(with_index) * 1e3:7.2f} ms, "
        f"mean {with_index.mean() * 1e3:7.2f} ms  ({args.frames} frames, median {int(np.median(faces_out)):,} faces)"
    )
    print(
        f"            without index median {np.median(without_index) * 1e3:7.2f} ms, "
        f"mean {without_index.mean() * 1e3:7.2f} ms  (every tet tested; "
        f"{np.median(without_index) / np.median(with_index):.0f}x slower)"
    )
    manifold.slice(first_t)  # builds the package's own Slicer index, untimed
    package = np.array([timed(manifold.slice, float(t))[1] for t in frame_times])
    print(f"            package     median {np.median(package) * 1e3:7.2f} ms "
          f"(am.AnimationManifold.slice: the core slice wrapped as the package's Slice; "
          f"{1 / np.median(package):.0f} frames/s)")
    normals = np.array([timed(_core.frame_vertex_normals, s.vertices, s.faces)[1] for _ in range(5)])
    print(f"            normals     median {np.median(normals) * 1e3:7.2f} ms of it (frame_vertex_normals of the last frame)")

    # A bake or playback: --frames-per-gap frames in each of the first --sequence-gaps keyframe gaps.
    gaps = min(args.sequence_gaps, args.keyframes - 1)
    steps = (np.arange(args.frames_per_gap) + 0.5) / args.frames_per_gap
    sequence = np.concatenate([times[g] + steps * (times[g + 1] - times[g]) for g in range(gaps)])
    start = time.perf_counter()
    for t in sequence:
        manifold.slice(float(t))
    fresh = time.perf_counter() - start
    start = time.perf_counter()
    for _ in manifold.slices(sequence):
        pass
    reused = time.perf_counter() - start
    print(f"sequence    {len(sequence)} frames, {args.frames_per_gap} per keyframe gap: one by one "
          f"{fresh / len(sequence) * 1e3:7.2f} ms a frame ({len(sequence) / fresh:.0f} frames/s); "
          f"am.AnimationManifold.slices {reused / len(sequence) * 1e3:7.2f} ms a frame "
          f"({len(sequence) / reused:.0f} frames/s: each interval's first frame cut, the others a gather + lerp)")

    _, seconds = timed(_core._testing.slice, manifold.core_complex, TIME_AXIS, float(frame_times[len(frame_times) // 2]))
    print(f"            brute force {seconds:.3f} s (_core._testing.slice: no index)")

    rate = touched / with_index / 1e9
    print(
        f"touched     {np.median(touched) / 2**20:.1f} MiB per frame (cut tets x {BYTES_PER_CUT_TET} B + outputs): "
        f"median {np.median(rate):.2f} GB/s"
    )
    del manifold, slicer  # free ~1 GB before allocating the bandwidth arrays
    bandwidth = memory_bandwidth(args.bandwidth_gib)
    print(
        f"bandwidth   numpy copy of {args.bandwidth_gib:g} GiB: {bandwidth:.1f} GB/s (read + write); "
        f"slice reaches {np.median(rate) / bandwidth * 100:.1f}% of it"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
