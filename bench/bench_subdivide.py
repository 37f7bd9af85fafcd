"""Benchmark for issue 8 (smoothing): prints figures, asserts nothing.

1. Schaefer et al. subdivision of a ~1M-tet manifold, one level: time and
   peak resident memory (the process's high-water mark before and after).
2. OpenSubdiv Loop refinement of a ~50k-face frame to level 2 (limit
   positions, creases by dihedral angle): time per frame, topology built anew
   each frame as live playback must (slices change topology). Catmull-Clark on
   the same frame's quads, next to Blender's Subdivision Surface modifier
   (bpy, level 2, limit surface) on the same quads when bpy imports: the mesh
   tagged changed and the evaluated mesh read every time.
3. Live playback path: slice + smooth_levels=2 per frame on the 1M-tet manifold.

Run:  PYTHONPATH=python:tests python3 bench/bench_subdivide.py [--json PATH]
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
from figures import bench_parser, write_json  # noqa: E402


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


def blender_subsurf_ms(vertices: np.ndarray, quads: np.ndarray, levels: int = 2, runs: int = 5) -> dict:
    """Median ms of Blender's Subdivision Surface modifier re-evaluating `quads` at `levels`
    (the mesh tagged changed each time, so the topology is refined anew, and the evaluated mesh
    read); {"blender_unavailable": why} without bpy."""
    try:
        import bpy
    except ImportError as error:
        return {"blender_unavailable": f"bpy is not importable ({error})"}
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh = bpy.data.meshes.new("frame")
    mesh.from_pydata(vertices.tolist(), [], quads.tolist())
    mesh.update()
    obj = bpy.data.objects.new("frame", mesh)
    bpy.context.scene.collection.objects.link(obj)
    modifier = obj.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = levels
    seconds, faces = [], 0
    for _ in range(runs):
        t0 = time.perf_counter()
        mesh.update()
        depsgraph = bpy.context.evaluated_depsgraph_get()
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        faces = len(evaluated.to_mesh().polygons)
        evaluated.to_mesh_clear()
        seconds.append(time.perf_counter() - t0)
    return {"blender_ms": 1000 * float(np.median(seconds)), "blender_faces": faces,
            "blender_peer": f"Blender {bpy.app.version_string} Subdivision Surface modifier"}



def median_ms(call, runs: int = 5):
    """(the last result of `call`, the median of `runs` calls in milliseconds)."""
    seconds = []
    for _ in range(runs):
        t0 = time.perf_counter()
        result = call()
        seconds.append(time.perf_counter() - t0)
    return result, 1000 * float(np.median(seconds))

def main() -> None:
    parser = bench_parser(__doc__)
    args = parser.parse_args()
    figures = {}
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
        figures[f"manifold_keep_keyframe_times_{keep}"] = {"input_tets": len(m.simplices), "seconds": dt,
                                                          "output_tets": len(m1.simplices),
                                                          "input_mtets_per_s": len(m.simplices) / dt / 1e6}
    t0 = time.perf_counter()
    report = m1.check()
    print(f"check_manifold of the result: {time.perf_counter() - t0:.2f} s, oriented={report.is_oriented_manifold}")

    # --- 2. OpenSubdiv on a ~50k-face frame
    tv, tf = torus(160, 160)
    print(f"frame: {len(tv):,} vertices, {len(tf):,} triangles")
    r, loop_ms = median_ms(lambda: am.subdivide_frame(tv, tf, levels=2, scheme="loop", crease_angle=30.0))
    print(
        f"Loop level 2 + limit: {loop_ms:.0f} ms per frame (median of 5) -> "
        f"{len(r.vertices):,} vertices, {len(r.faces):,} triangles"
    )
    figures["loop_frame"] = {"triangles": len(tf), "ms_per_frame": loop_ms}
    quads = np.concatenate([tf[: len(tf) // 2], tf[len(tf) // 2 :, 2:3]], 1)  # (a, b, c, d) per grid cell
    r, cc_ms = median_ms(lambda: am.subdivide_frame(tv, quads, levels=2, scheme="catmull_clark", crease_angle=30.0))
    print(
        f"Catmull-Clark level 2 + limit on {len(quads):,} quads: {cc_ms:.0f} ms per frame -> "
        f"{len(r.faces):,} quads"
    )
    figures["catmull_clark_frame"] = {"quads": len(quads), "ms_per_frame": cc_ms,
                                      **blender_subsurf_ms(tv, quads)}
    peer = figures["catmull_clark_frame"]
    if "blender_ms" in peer:
        print(f"{peer['blender_peer']}, level 2: {peer['blender_ms']:.0f} ms per frame -> {peer['blender_faces']:,} quads")
    else:
        print(f"Blender peer: {peer['blender_unavailable']}")

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
    figures["live_slice_smooth"] = {"slice_ms": 1000 * float(np.median(plain)), "slice_smooth2_ms": 1000 * float(np.median(runs))}
    write_json(args.json, figures)


if __name__ == "__main__":
    main()
