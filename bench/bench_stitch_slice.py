"""Benchmark: stitch a ~50k-face mesh over 100 keyframes, then slice frames with and without the index.

    python3 bench/bench_stitch_slice.py [--keyframes 100] [--frames 20] [--bandwidth-gib 1]
                                        [--mesh default|production|character] [--repeat 3] [--json PATH]

Input: bunny.off + 3holes.off from <repo>/../shared/data/meshes, each
midpoint-subdivided once (≈ 56.7k faces together), animated by a smooth
travelling-wave deformation (animanifold.procedural.wobble). Without the
data folder it falls back to three procedural icospheres (61,440 faces) and
says so. --mesh production is issue 24's case, run with --keyframes 20:
homer.obj + 3holes.off + torus-800.off + torus.obj, each midpoint-subdivided
once (42,750 vertices, 85,504 faces: 4.87 M tets over 20 keyframes; the
fallback is icosphere(6), 40,962 vertices). --mesh character (default 20 keyframes: 4.97 M
tets) is a 43.6k-vertex, 87k-face geodesic sphere with a UV map (vertex attribute "uv"), the
size of a game character.

Prints: stitch time and tets/s end to end (am.stitch: the first call, on memory faulted in just
before (machine.fresh_memory_seconds, whose time is printed: this VM's host takes back memory the
guest leaves free, and faulting it in again is ~20x slower), then the best of --repeat) and the
C++ stitch alone (_core.stitch with the seam order
given), the stitch's peak memory (the process's resident high-water mark,
reset before the call) against the output's size; the interval index's build time and size
(bytes a tet); the first slice (cold caches); per-frame slice time (frames between keyframes) with the index
and without it (every tet tested), per stage (stab, cut, weld, output, normals), through the
package (a stitched manifold's frame between keys is its prism frame: the source's faces, a
lerp), and its normals' share; a sequence of
frames (a bake: several per keyframe gap) sliced one by one and through
AnimationManifold.slices, which reuses each topology interval's cut; the OpenMP thread count;
and the bytes a slice touches per second against this machine's
memory bandwidth (a numpy copy of a large array, measured in the same run).

Bytes touched per slice, a lower bound: for each cut tet its 4 int32 indices
and its 4 points of 4 doubles (144 B), plus the output arrays. It leaves out
the index nodes visited and the weld's per-vertex lists.
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
from animanifold import _core, stitching  # noqa: E402
from animanifold.procedural import geodesic_sphere, icosphere, subdivide_midpoint, wobble  # noqa: E402
from figures import add_json_option, write_json  # noqa: E402
from machine import fresh_memory_seconds  # noqa: E402

DATA = REPO.parent / "shared" / "data" / "meshes"
TIME_AXIS = 3
BYTES_PER_CUT_TET = 4 * 4 + 4 * 4 * 8  # 4 int32 indices + 4 points of (x, y, z, t) doubles
# Fresh memory faulted in before the first stitch: more than the 16.8 M-tet stitch's peak (~0.5 GiB).
WARM_GIB = 1.0
# Faulting WARM_GIB in takes about 0.1 s on warm pages and 2 s on pages the host took back.
COLD_SECONDS = 0.5


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


MESHES = {"default": ("bunny.off", "3holes.off"),
          "production": ("homer.obj", "3holes.off", "torus-800.off", "torus.obj")}


def benchmark_mesh(which: str = "default") -> tuple[np.ndarray, np.ndarray, str]:
    names = MESHES[which]
    if all((DATA / n).is_file() for n in names):
        meshes = [subdivide_midpoint(*am.read_mesh(DATA / n)) for n in names]
        return (*combine(meshes), " + ".join(names) + ", each midpoint-subdivided once")
    if which == "production":
        print(f"note: {DATA} not found; using icosphere(6) instead of {' + '.join(names)}")
        return (*combine([icosphere(6)]), "icosphere (subdivision 6)")
    print(f"note: {DATA} not found; using three procedural icospheres instead of bunny + 3holes")
    sphere = icosphere(5)
    return (*combine([sphere, sphere, sphere]), "3 icospheres (subdivision 5)")


def character_mesh() -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """A 43.6k-vertex sphere of 87k faces and its UV map (longitude, latitude)."""
    vertices, faces = geodesic_sphere(66)
    uv = np.stack([np.arctan2(vertices[:, 1], vertices[:, 0]) / (2 * np.pi) + 0.5,
                   np.arccos(np.clip(vertices[:, 2], -1.0, 1.0)) / np.pi], axis=1)
    return vertices, faces, uv, "geodesic sphere (frequency 66) with a UV map"


def resident_kib(field: str) -> int:
    """A /proc/self/status memory field (VmRSS, VmHWM) in KiB."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1])
    raise KeyError(field)


def peak_bytes_of(function, *args):
    """(result, bytes): `function(*args)` and how far the process's resident set rose
    above its size before the call (the high-water mark is reset first: Linux's clear_refs)."""
    Path("/proc/self/clear_refs").write_text("5")
    before = resident_kib("VmRSS")
    result = function(*args)
    return result, (resident_kib("VmHWM") - before) * 1024


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


def stitch_figures(keyframes: np.ndarray, faces: np.ndarray, times: np.ndarray, repeat: int, attributes=None):
    """(manifold, figures): am.stitch timed end to end (first call, best of `repeat`), its
    peak memory against the output's size, and the C++ stitch alone on the same input. Fresh
    memory is faulted in first (machine.fresh_memory_seconds): the first call is timed on
    warm pages, and the time the warming took is printed with it."""
    warming = fresh_memory_seconds(WARM_GIB)
    (manifold, first), peak = peak_bytes_of(timed, am.stitch, keyframes, faces, times, attributes)
    tets, points = len(manifold.simplices), len(manifold.points)
    assert tets == 3 * len(faces) * (len(keyframes) - 1)
    output = tets * 4 * 4 + points * 4 * 8  # int32 tets + (x, y, z, t) doubles
    best = first
    for _ in range(repeat - 1):
        del manifold
        manifold, seconds = timed(am.stitch, keyframes, faces, times, attributes)
        best = min(best, seconds)
    m, k, d = keyframes.shape
    flat = np.ascontiguousarray(keyframes.reshape(m * k, d))
    order = stitching._seam_order(keyframes, keyframes)
    indices = faces.astype(np.int32)
    core = min(timed(_core.stitch, flat, indices, times, {}, {}, order)[1] for _ in range(repeat))
    # The memory-bound reference: numpy copying the output into fresh arrays (allocation,
    # page faults, read + write), as the stitch must write it.
    simplices, points_array = np.asarray(manifold.simplices), np.asarray(manifold.points)
    copy = min(timed(lambda: (simplices.copy(), points_array.copy()))[1] for _ in range(repeat))
    print(f"stitch      {tets:,} tets, {points:,} points: end to end first call {first:.3f} s "
          f"= {tets / first / 1e6:.1f} M tets/s, best of {repeat} {best:.3f} s = {tets / best / 1e6:.1f} M tets/s; "
          f"C++ stitch alone {core:.3f} s = {tets / core / 1e6:.1f} M tets/s; "
          f"numpy copy of the output {copy:.3f} s = {tets / copy / 1e6:.1f} M tets/s")
    print(f"            peak memory {peak / 2**20:.0f} MiB for an output of {output / 2**20:.0f} MiB "
          f"({peak / output:.2f}x)")
    state = "cold: the host had taken the guest's free memory back" if warming > COLD_SECONDS else "warm"
    print(f"            fresh memory: {WARM_GIB:g} GiB faulted in {warming:.3f} s just before the first call ({state})")
    figures = {"tets": tets, "points": points, "stitch_first_s": first, "stitch_best_s": best, "stitch_core_s": core,
               "stitch_mtets_per_s": tets / best / 1e6, "stitch_first_mtets_per_s": tets / first / 1e6,
               "stitch_core_mtets_per_s": tets / core / 1e6,
               "output_copy_s": copy, "output_copy_mtets_per_s": tets / copy / 1e6, "stitch_peak_bytes": peak, "output_bytes": output,
               "stitch_peak_over_output": peak / output, "fresh_memory_s": warming}
    return manifold, figures


STAGES = ("stab", "cut", "weld", "output", "normals")


def slice_stages(slicer, frame_times: np.ndarray, repeat: int = 3) -> dict:
    """Per stage of a slice (_core._testing.slice_stages): the median over the frames of the
    best of `repeat` runs, in ms; printed as one line."""
    best = {stage: [] for stage in STAGES}
    for t in frame_times:
        runs = [_core._testing.slice_stages(slicer, TIME_AXIS, float(t)) for _ in range(repeat)]
        for stage in STAGES:
            best[stage].append(min(run[stage] for run in runs))
    ms = {stage: float(np.median(best[stage])) * 1e3 for stage in STAGES}
    print("            stages      " + ", ".join(f"{stage} {ms[stage]:.2f}" for stage in STAGES)
          + f" ms (median over the frames of the best of {repeat}; sum {sum(ms.values()):.2f} ms)")
    return {f"slice_{stage}_ms": value for stage, value in ms.items()}


def slice_figures(manifold, times: np.ndarray, frames: int) -> dict:
    """The interval index's build, the first slice, and per-frame slices with and without the index."""
    tets = len(manifold.simplices)
    # The core Slicer that AnimationManifold.slice uses, driven directly so the
    # one-off cost of the index is timed apart from per-frame cost.
    slicer = _core.Slicer(manifold.core_complex)
    index_bytes, index_s = timed(slicer.index_memory_bytes, TIME_AXIS)
    print(f"index       built in {index_s:.3f} s, {index_bytes / 2**20:.0f} MiB = {index_bytes / 1e6:.0f} MB, "
          f"{index_bytes / tets:.1f} B a tet ({tets / index_s / 1e6:.1f} M tets/s)")
    first_t = 0.5 * (times[0] + times[1])
    _, first_s = timed(slicer.slice, TIME_AXIS, first_t, True)
    print(f"first slice {first_s:.3f} s (cold caches)")

    # Midpoints of `frames` equal steps: never a keyframe time (those are copies, not cuts).
    frame_times = times[0] + (np.arange(frames) + 0.5) / frames * (times[-1] - times[0])
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
        f"mean {with_index.mean() * 1e3:7.2f} ms  ({frames} frames, median {int(np.median(faces_out)):,} faces)"
    )
    print(
        f"            without index median {np.median(without_index) * 1e3:7.2f} ms, "
        f"mean {without_index.mean() * 1e3:7.2f} ms  (every tet tested; "
        f"{np.median(without_index) / np.median(with_index):.0f}x slower)"
    )
    stage_figures = slice_stages(slicer, frame_times)
    manifold.slice(first_t)  # builds the package's own Slicer index, untimed

    def package_frame(t: float):
        frame = manifold.slice(t)
        frame.normals  # computed on first read: timed, for a whole frame
        return frame

    package = np.array([timed(package_frame, float(t))[1] for t in frame_times])
    package_faces = len(manifold.slice(float(frame_times[0])).faces)
    what = ("its prism frame between keys: the keys' faces, each vertex on its vertical edge"
            if manifold.prisms is not None else "the core slice wrapped as the package's Slice")
    print(f"            package     median {np.median(package) * 1e3:7.2f} ms "
          f"(am.AnimationManifold.slice with its normals, {package_faces:,} faces: {what}; "
          f"{1 / np.median(package):.0f} frames/s)")
    normals = np.array([timed(_core.frame_vertex_normals, s.vertices, s.faces)[1] for _ in range(5)])
    print(f"            normals     median {np.median(normals) * 1e3:7.2f} ms of it (frame_vertex_normals of the last frame)")
    _, brute_s = timed(_core._testing.slice, manifold.core_complex, TIME_AXIS, float(frame_times[len(frame_times) // 2]))
    print(f"            brute force {brute_s:.3f} s (_core._testing.slice: no index)")
    rate = touched / with_index / 1e9
    print(
        f"touched     {np.median(touched) / 2**20:.1f} MiB per frame (cut tets x {BYTES_PER_CUT_TET} B + outputs): "
        f"median {np.median(rate):.2f} GB/s"
    )
    return {"index_s": index_s, "index_bytes": index_bytes, "first_slice_s": first_s,
            "slice_ms_per_frame": float(np.median(with_index)) * 1e3,
            "slice_frames_per_s": 1.0 / float(np.median(with_index)),
            "slice_without_index_ms": float(np.median(without_index)) * 1e3, "brute_force_slice_s": brute_s,
            "faces_per_frame": int(np.median(faces_out)), "touched_gb_per_s": float(np.median(rate)),
            "touched_bytes_per_frame": float(np.median(touched)),
            "package_slice_ms_per_frame": float(np.median(package)) * 1e3, "package_faces_per_frame": package_faces,
            "package_prism_frames": manifold.prisms is not None, **stage_figures}


def sequence_figures(manifold, times: np.ndarray, frames_per_gap: int, gaps: int) -> dict:
    """A bake or playback: `frames_per_gap` frames in each of the first `gaps` keyframe gaps,
    sliced one by one and through AnimationManifold.slices."""
    gaps = min(gaps, len(times) - 1)
    steps = (np.arange(frames_per_gap) + 0.5) / frames_per_gap
    sequence = np.concatenate([times[g] + steps * (times[g + 1] - times[g]) for g in range(gaps)])
    start = time.perf_counter()
    for t in sequence:
        manifold.slice(float(t))
    fresh = time.perf_counter() - start
    start = time.perf_counter()
    for _ in manifold.slices(sequence):
        pass
    reused = time.perf_counter() - start
    print(f"sequence    {len(sequence)} frames, {frames_per_gap} per keyframe gap: one by one "
          f"{fresh / len(sequence) * 1e3:7.2f} ms a frame ({len(sequence) / fresh:.0f} frames/s); "
          f"am.AnimationManifold.slices {reused / len(sequence) * 1e3:7.2f} ms a frame "
          f"({len(sequence) / reused:.0f} frames/s: each interval's first frame cut, the others a gather + lerp)")
    return {"sequence_one_by_one_ms_per_frame": fresh / len(sequence) * 1e3,
            "sequence_reused_ms_per_frame": reused / len(sequence) * 1e3}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--keyframes", type=int, help="default: 100 (20 for --mesh character)")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--bandwidth-gib", type=float, default=1.0, help="size of the array copied to measure bandwidth")
    parser.add_argument("--mesh", choices=sorted(MESHES) + ["character"], default="default",
                        help="production: issue 24's 42,750-vertex case (with --keyframes 20: 4.87 M tets); "
                             "character: a 43.6k-vertex sphere with a UV map")
    parser.add_argument("--frames-per-gap", type=int, default=6, help="frames per keyframe gap in the sequence")
    parser.add_argument("--sequence-gaps", type=int, default=10, help="keyframe gaps the sequence covers")
    parser.add_argument("--repeat", type=int, default=3, help="stitch calls timed (the first is reported apart)")
    add_json_option(parser)
    args = parser.parse_args()

    attributes = None
    if args.mesh == "character":
        rest, faces, uv, source = character_mesh()
        attributes = {"uv": uv}
        args.keyframes = args.keyframes or 20
    else:
        rest, faces, source = benchmark_mesh(args.mesh)
        args.keyframes = args.keyframes or 100
    phases = np.linspace(0.0, 2.0 * np.pi, args.keyframes)
    keyframes = np.stack([wobble(rest, phase, 0.03) for phase in phases])
    times = np.linspace(0.0, 1.0, args.keyframes)
    print(f"mesh        {source}: {len(rest):,} vertices, {len(faces):,} faces; {args.keyframes} keyframes")

    threads = am.threads()
    print(f"machine     {os.cpu_count()} cores; slicing on {threads} OpenMP threads")

    manifold, figures = stitch_figures(keyframes, faces, times, max(args.repeat, 1), attributes)
    figures.update(slice_figures(manifold, times, args.frames))
    figures.update(sequence_figures(manifold, times, args.frames_per_gap, args.sequence_gaps))
    figures["threads"] = threads
    figures.update(mesh=source, vertices=len(rest), faces=len(faces), keyframes=args.keyframes)
    del manifold  # free ~1 GB before allocating the bandwidth arrays
    bandwidth = memory_bandwidth(args.bandwidth_gib)
    print(
        f"bandwidth   numpy copy of {args.bandwidth_gib:g} GiB: {bandwidth:.1f} GB/s (read + write); "
        f"slice reaches {figures['touched_gb_per_s'] / bandwidth * 100:.1f}% of it"
    )
    figures["bandwidth_gb_per_s"] = bandwidth
    figures["memory_bound_slice_ms"] = figures["touched_bytes_per_frame"] / (bandwidth * 1e9) * 1e3
    write_json(args.json, figures)
    return 0


if __name__ == "__main__":
    sys.exit(main())
