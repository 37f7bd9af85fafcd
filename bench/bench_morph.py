"""Benchmark of morphing, two modes.

--bar (the default): the morph issue's bar, one table per pair of shapes with a row per morph
method and one for OpenVDB's level-set morph, all measured the same way (bench/morph_bar.py
says what is compared and how):

    python3 bench/bench_morph.py [--bar] [--methods field,skeleton] [--pairs spot->3holes,...]
                                 [--frames 24] [--vdb-resolution 128] [--no-peer]
                                 [--field-resolution 24]

--seed-report: chapter 8, §8.7.1: sphere -> a genus-3 model, next to the dissertation's seed
figures and, in the same run, OpenVDB's level-set morph (what follows describes this mode):

    python3 bench/bench_morph.py --seed-report [--method skeleton|strip] [--vdb-resolutions 128,192]
                                 [--no-peer] [--target path.off|procedural]

The target is ../shared/data/meshes/3holes.off (libigl's genus-3 model, 3,596 vertices) when the
shared data has it, else (or with --target procedural) animanifold.procedural.smooth_genus3(): a
curved genus-3 slab of 1,596 vertices, a stand-in whose figures are not the 3holes figures.

What is compared
----------------
* Ours: ``am.morph(sphere, genus3, method=...)`` (the seed's skeleton method
  unless --method names another). Every stage the core
  reports in ``validity["stage_seconds"]`` is printed under its own name, with
  the total (the stages' sum and the wall time of the call), the size of the
  4D fill (vertices, simplices, stripped simplices), and:
    - end-shape exactness: the two-sided Hausdorff distance between the
      slices at t0 / t1 and the inputs, relative to the genus-3 model's
      bounding-box diagonal (one yardstick for everything; the core's own
      report divides by the larger diagonal of the two inputs, the
      sphere's here). Distances are exact point-to-triangle distances from
      samples of each surface (vertices, edge midpoints, face centres) to
      the other surface; both directions are shown, H = the larger.
    - topology of the frames at t0, 1/4, 1/2, 3/4 and t1: closed (every
      edge on two faces)? Euler characteristic, components, genus.
* Seed (§8.7.1, fertility model of ~3,000 vertices, a 2 GB commodity PC):
  conforming fill (Tetgen) 6.6 s; find M' in the filled volume 559.5 s (and
  "a similar time" for the skeleton, not counted here; our conforming stage
  keeps track of the conforming surface, so it has no such step); Qhull fill
  of 19,006 4D vertices 12.24 s; strip 227.1 s (of which grow 39.9 s) of
  6,010 simplices out of 170,039. No figures for push and bound. The seed's
  total below is the sum of the figures given (805.4 s), a lower bound.
* Peer: OpenVDB's level-set morph (bench/bench_vdb_morph.cpp, C++: Debian's
  pyopenvdb has no LevelSetMorphing or advection, only level sets from
  polygons and meshing). Both meshes become narrow-band level sets
  (meshToLevelSet, half width 3 voxels) with a voxel of 1/N of the genus-3
  model's diagonal for each N in --vdb-resolutions; LevelSetMorphing
  (HJWENO5 + TVD-RK2, its defaults) advects the sphere toward the target
  until the front is within 0.05 voxel of the target's or stops getting
  closer; volumeToMesh gives the frames at 0, half the time taken, and the
  end. Its exactness and topology are measured exactly as ours, plus the
  target's own level set meshed (the voxelisation alone: the best the peer
  can reach at that voxel size). The peer is built once in build-bench/
  (CMake option ANIMANIFOLD_BUILD_VDB_BENCH, off in the normal build); the
  script installs libopenvdb-dev with apt when its headers are missing and
  it runs as root.

Times are wall seconds on whatever machine runs this (the peer uses TBB on
all cores, ours is single-threaded); the seed's are from 2008 hardware. The
seed report takes about five minutes on two cores, most of it in the peer at
1/192 (it grows about as N^3).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

sys.path.insert(0, str(ROOT / "bench"))

import animanifold as am  # noqa: E402
import morph_bar  # noqa: E402  (the --bar mode)
from figures import write_json  # noqa: E402
from animanifold.morph_pipeline import METHODS  # noqa: E402
from animanifold.procedural import icosphere, smooth_genus3  # noqa: E402

# §8.7.1, keyed by our stage names where there is a counterpart.
SEED_SECONDS = {"conforming": 6.6, "find": 559.5, "fill": 12.24, "strip": 227.1}
SEED_NOTES = {
    "conforming": "Tetgen fill of the fertility model",
    "find": "find M' in the filled volume (+ a similar time for the skeleton)",
    "fill": "Qhull, 19,006 4D vertices",
    "strip": "of which grow 39.9 s",
    "push": "push the skeleton (no time given)",
    "boundary": "bound (no time given)",
}
SEED_ORDER = ("conforming", "find", "fill", "push", "strip", "boundary")
SEED_FILL_VERTICES, SEED_FILL_SIMPLICES, SEED_STRIPPED = 19006, 170039, 6010
PEER_STAGES = (("levelset_seconds", "level sets"), ("morph_seconds", "advect"), ("mesh_seconds", "meshing"))
VDB_SOURCE = ROOT / "bench" / "bench_vdb_morph.cpp"
VDB_HEADER = Path("/usr/include/openvdb/tools/LevelSetMorph.h")
SHARED_TARGET = ROOT.parent / "shared" / "data" / "meshes" / "3holes.off"


# -- geometry helpers (also used by tests/test_bench_morph.py) -----------------
def covering_sphere(vertices: np.ndarray, subdivisions: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """An icosphere (20·4^s faces) centred on the bounding box of `vertices`, of
    radius half its diagonal: it encloses the whole box."""
    lo, hi = vertices.min(0), vertices.max(0)
    v, f = icosphere(subdivisions)
    return v * (0.5 * np.linalg.norm(hi - lo)) + 0.5 * (lo + hi), f


def closest_points_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Row-wise closest point of triangle (a, b, c) to p (Ericson, Real-Time
    Collision Detection §5.1.5), vectorised; all arguments (n, 3)."""
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    ab, ac, ap, bp, cp = b - a, c - a, p - a, p - b, p - c
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        out = a + ab * (vb / denom)[:, None] + ac * (vc / denom)[:, None]  # inside the face
        # Voronoi regions of the edges and corners, the earlier ones of
        # Ericson's order winning (assigned last).
        m = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        out[m] = (b + (c - b) * w[:, None])[m]
        m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        out[m] = (a + ac * (d2 / (d2 - d6))[:, None])[m]
        m = (d6 >= 0) & (d5 <= d6)
        out[m] = c[m]
        m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        out[m] = (a + ab * (d1 / (d1 - d3))[:, None])[m]
        m = (d3 >= 0) & (d4 <= d3)
        out[m] = b[m]
        m = (d1 <= 0) & (d2 <= 0)
        out[m] = a[m]
    bad = ~np.isfinite(out).all(1)  # degenerate (zero-area) triangles: nearest corner
    if bad.any():
        corners = np.stack([a[bad], b[bad], c[bad]], 1)
        nearest = np.argmin(np.linalg.norm(corners - p[bad, None], axis=2), 1)
        out[bad] = corners[np.arange(len(nearest)), nearest]
    return out


def distance_to_mesh(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray, chunk: int = 20000,
                     pairs: int = 2_000_000) -> np.ndarray:
    """Exact distance from each point to the triangle mesh (not a sampling of it).

    Candidates are pruned with a k-d tree of face centres: a face at distance
    < d from p has its centre within d + (its radius about the centre), and d
    is first bounded by the 8 faces with the nearest centres. Faces much larger
    than the rest (a slice's spurious face across a hole, say) would make that
    reach cover everything; they are measured against every point instead."""
    points, vertices = np.asarray(points, float), np.asarray(vertices, float)
    tri = vertices[faces]
    centres = tri.mean(1)
    radius = np.linalg.norm(tri - centres[:, None], axis=2).max(1)
    large = radius > 4 * np.median(radius)
    small = np.flatnonzero(~large)
    result = np.full(len(points), np.inf)

    def measure(p, rows, cand, best):  # best[rows] = min(best[rows], distance(p[rows], tri[cand]))
        for s in range(0, len(rows), pairs):
            r, t = rows[s : s + pairs], tri[cand[s : s + pairs]]
            d = np.linalg.norm(closest_points_on_triangles(p[r], t[:, 0], t[:, 1], t[:, 2]) - p[r], axis=1)
            np.minimum.at(best, r, d)

    if large.any():
        big = np.flatnonzero(large)
        for s in range(0, len(points), max(1, pairs // len(big))):
            p = points[s : s + max(1, pairs // len(big))]
            best = np.full(len(p), np.inf)
            measure(p, np.repeat(np.arange(len(p)), len(big)), np.tile(big, len(p)), best)
            result[s : s + len(p)] = best
    if len(small) == 0:
        return result
    tree = cKDTree(centres[small])
    reach = radius[small].max()
    k = min(8, len(small))
    for s in range(0, len(points), chunk):
        p = points[s : s + chunk]
        best = result[s : s + chunk].copy()
        _, near = tree.query(p, k=k)
        measure(p, np.repeat(np.arange(len(p)), k), small[near.reshape(len(p), k).ravel()], best)
        balls = tree.query_ball_point(p, best + reach + 1e-12 * (1 + np.abs(p).max()))
        counts = np.fromiter((len(b) for b in balls), int, len(balls))
        cand = small[np.fromiter((i for b in balls for i in b), int, counts.sum())]
        measure(p, np.repeat(np.arange(len(p)), counts), cand, best)
        result[s : s + chunk] = best
    return result


def surface_samples(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The used vertices, edge midpoints and face centres of a triangle mesh."""
    edges = np.unique(np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    return np.concatenate([vertices[np.unique(faces)], vertices[edges].mean(1), vertices[faces].mean(1)])


def hausdorff(va, fa, vb, fb) -> tuple[float, float]:
    """(max distance from A's samples to B, max from B's samples to A): the
    two one-sided Hausdorff distances; the two-sided one is the larger."""
    return (float(distance_to_mesh(surface_samples(va, fa), vb, fb).max()),
            float(distance_to_mesh(surface_samples(vb, fb), va, fa).max()))


def topology(vertices: np.ndarray, faces: np.ndarray) -> dict:
    """Closedness, Euler characteristic, components and genus of a triangle mesh
    (unused vertices ignored; genus = (2·components - χ)/2 summed over
    components, meaningful when closed and oriented)."""
    faces = np.asarray(faces)
    used = np.unique(faces)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    edges, uses = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    chi = len(used) - len(edges) + len(faces)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(vertices),) * 2)
    _, label = connected_components(graph, directed=False)
    components = len(np.unique(label[used]))
    # Oriented: each directed edge once (a closed, consistently oriented surface).
    oriented = len(np.unique(directed, axis=0)) == len(directed)
    closed = bool((uses == 2).all())
    return {"faces": len(faces), "closed": closed, "oriented": oriented, "boundary_edges": int((uses == 1).sum()),
            "nonmanifold_edges": int((uses > 2).sum()), "chi": int(chi), "components": components,
            "genus": (2 * components - chi) / 2 if closed else None}


def describe(topo: dict) -> str:
    if topo["faces"] == 0:
        return "empty"
    shape = "closed" if topo["closed"] else (f"OPEN ({topo['boundary_edges']} boundary, "
                                             f"{topo['nonmanifold_edges']} non-manifold edges)")
    genus = "" if topo["genus"] is None else f", genus {topo['genus']:g}"
    return f"{shape}, χ = {topo['chi']}, {topo['components']} component(s){genus}, {topo['faces']} triangles"


# -- ours ----------------------------------------------------------------------
def run_ours(sphere, target, method: str, diagonal: float) -> dict:
    start = time.perf_counter()
    try:
        m = am.morph(sphere, target, method=method)
    except Exception as error:  # noqa: BLE001  (the bench goes on with the peer)
        return {"error": f"{type(error).__name__}: {error}", "wall": time.perf_counter() - start}
    wall = time.perf_counter() - start
    report = m.validity
    t0, t1 = m.time_range
    frames = {}
    for label, t in (("t0", t0), ("1/4", t0 + 0.25 * (t1 - t0)), ("1/2", 0.5 * (t0 + t1)),
                     ("3/4", t0 + 0.75 * (t1 - t0)), ("t1", t1)):
        s = m.slice(t)
        frames[label] = (s.vertices, s.faces)
    ends = {}
    for label, (v, f), (vi, fi) in (("t0", frames["t0"], sphere), ("t1", frames["t1"], target)):
        ends[label] = np.array(hausdorff(v, f, vi, fi)) / diagonal if len(f) else np.array([np.inf, np.inf])
    return {"wall": wall, "report": report, "stages": [(str(n), float(s)) for n, s in report["stage_seconds"]],
            "fill_vertices": len(m.points), "manifold_simplices": len(m.simplices), "ends": ends,
            "check": m.check().to_dict(),
            "inner_vertices": int(np.count_nonzero((m.points[:, -1] > t0) & (m.points[:, -1] < t1))),
            "topology": {k: topology(*vf) for k, vf in frames.items()}}


# -- the OpenVDB peer ------------------------------------------------------------
def vdb_executable(build: Path) -> tuple[Path | None, str | None]:
    """The peer program: from the main build when configured with
    ANIMANIFOLD_BUILD_VDB_BENCH=ON, else built (incrementally) in build-bench/."""
    if (build / "bench_vdb_morph").exists() and (build / "bench_vdb_morph").stat().st_mtime >= VDB_SOURCE.stat().st_mtime:
        return build / "bench_vdb_morph", None
    if not VDB_HEADER.exists():
        if os.geteuid() != 0 or not shutil.which("apt-get"):
            return None, "libopenvdb-dev is not installed (scripts/install-deps.sh installs it)"
        print("bench_morph: OpenVDB headers missing; installing libopenvdb-dev with apt-get (once) ...", flush=True)
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        done = subprocess.run("apt-get update -qq && apt-get install -y -qq --no-install-recommends libopenvdb-dev",
                              shell=True, capture_output=True, text=True, env=env)
        if done.returncode != 0:
            return None, f"apt-get install libopenvdb-dev failed: {done.stderr.strip()[-300:]}"
    out = ROOT / "build-bench"
    exe = out / "bench_vdb_morph"
    if not exe.exists() or exe.stat().st_mtime < VDB_SOURCE.stat().st_mtime:
        print(f"bench_morph: building the OpenVDB peer in {out.relative_to(ROOT)}/ (once, ~40 s) ...", flush=True)
    if not (out / "CMakeCache.txt").exists():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        done = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(out), *generator, "-DCMAKE_BUILD_TYPE=Release",
                               "-DANIMANIFOLD_BUILD_VDB_BENCH=ON", "-DANIMANIFOLD_TESTS=OFF", "-DANIMANIFOLD_BENCH=OFF"],
                              capture_output=True, text=True)
        if done.returncode != 0:
            return None, "cmake configure failed:\n" + done.stdout[-1500:] + done.stderr[-1500:]
    done = subprocess.run(["cmake", "--build", str(out), "--target", "bench_vdb_morph"], capture_output=True, text=True)
    if done.returncode != 0:
        return None, "build failed:\n" + done.stdout[-2000:]
    return exe, None


def run_peer(exe: Path, sphere_path: Path, target_path: Path, resolution: float, sphere, target, diagonal: float,
             work: Path) -> dict:
    out = work / f"vdb-{resolution:g}"
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    done = subprocess.run([str(exe), str(sphere_path), str(target_path), str(out), str(resolution)],
                          capture_output=True, text=True, timeout=3600)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        return {"error": done.stderr.strip() or f"exit code {done.returncode}", "resolution": resolution}
    result = json.loads(done.stdout)
    result.update(resolution=resolution, wall=wall)
    meshes = {k: am.read_mesh(out / f"vdb_{k}.off") for k in ("t0", "mid", "t1", "target")}
    result["ends"] = {"t0": np.array(hausdorff(*meshes["t0"], *sphere)) / diagonal,
                      "t1": np.array(hausdorff(*meshes["t1"], *target)) / diagonal,
                      "target": np.array(hausdorff(*meshes["target"], *target)) / diagonal}
    result["topology"] = {k: topology(*meshes[k]) for k in ("t0", "mid", "t1", "target")}
    return result


# -- report ----------------------------------------------------------------------
def stage_rows(ours_stages: list[str]) -> list[str]:
    """Our stage names in our order, with the seed's other stages merged in at
    their place in the seed's order."""
    rows = list(ours_stages)
    for i, name in enumerate(SEED_ORDER):
        if name in rows:
            continue
        earlier = [rows.index(n) for n in SEED_ORDER[:i] if n in rows]
        rows.insert(earlier[-1] + 1 if earlier else 0, name)
    return rows


def fmt(value, width=10, digits=2) -> str:
    if value is None:
        return f"{'—':>{width}}"
    return f"{value:>{width},.{digits}f}"


def print_report(method: str, ours: dict, peers: list[dict], inputs: dict) -> None:
    print(f"\n=== sphere -> {inputs['name']}: ours (method {method!r}), seed (§8.7.1), OpenVDB peer ===")
    print(f"inputs: sphere {len(inputs['sphere'][0])} vertices / {len(inputs['sphere'][1])} faces; "
          f"{inputs['name']} {len(inputs['target'][0])} vertices / {len(inputs['target'][1])} faces; "
          f"yardstick = its bbox diagonal {inputs['diagonal']:.4g}")
    ok_peers = [p for p in peers if "error" not in p]
    ours_stages = dict(ours.get("stages", []))
    rows = stage_rows([n for n, _ in ours.get("stages", [])])
    peer_heads = "".join(f"{'VDB 1/' + format(p['resolution'], 'g') + ' (s)':>16}" for p in ok_peers)
    print(f"\n{'stage':<24}{'ours (s)':>10}{'seed (s)':>11}{peer_heads}   seed's stage")
    for name in rows:
        print(f"{name:<24}{fmt(ours_stages.get(name))} {fmt(SEED_SECONDS.get(name))}"
              f"{''.join(' ' * 6 + fmt(None) for _ in ok_peers)}   {SEED_NOTES.get(name, '')}")
    for key, name in PEER_STAGES:
        print(f"{'peer: ' + name:<24}{fmt(None)} {fmt(None)}{''.join(' ' * 6 + fmt(p[key]) for p in ok_peers)}")
    seed_total = sum(SEED_SECONDS.values())
    ours_total = sum(ours_stages.values()) if ours_stages else None
    print(f"{'total (sum of stages)':<24}{fmt(ours_total)} {fmt(seed_total)}"
          f"{''.join(' ' * 6 + fmt(sum(p[k] for k, _ in PEER_STAGES)) for p in ok_peers)}"
          f"   seed: lower bound (push, bound, the skeleton's find not given)")
    print(f"{'total (wall of the call)':<24}{fmt(ours.get('wall'))} {fmt(None)}"
          f"{''.join(' ' * 6 + fmt(p['wall']) for p in ok_peers)}")

    print("\nours:")
    if "error" in ours:
        print(f"  am.morph raised after {ours['wall']:.2f} s: {ours['error']}")
    else:
        r = ours["report"]
        extra = {k: v for k, v in r.items() if k not in ("stage_seconds", "source_distance", "target_distance",
                                                          "fill_simplices", "stripped_simplices")}
        print(f"  fill: {ours['fill_vertices']:,} 4D vertices (seed {SEED_FILL_VERTICES:,}), "
              f"{r.get('fill_simplices', 0):,} simplices (seed's A {SEED_FILL_SIMPLICES:,}), "
              f"{r.get('stripped_simplices', 0):,} stripped (seed {SEED_STRIPPED:,}); "
              f"manifold: {ours['manifold_simplices']:,} tets")
        print(f"  report: {', '.join(f'{k}={v}' for k, v in extra.items())}")
        c = ours["check"]
        print(f"  manifold check: {'oriented manifold' if c['is_oriented_manifold'] else 'NOT an oriented manifold'} "
              f"({c['nonmanifold_facets']} non-manifold, {c['misoriented_facets']} misoriented of "
              f"{c['interior_facets'] + c['boundary_facets']} facets)")
        for label, name in (("t0", "sphere"), ("t1", inputs["name"])):
            a, b = ours["ends"][label]
            core = r.get("source_distance" if label == "t0" else "target_distance")
            print(f"  end {label} vs {name:<12}: H = {max(a, b):.3g} of the diagonal (slice->input {a:.3g}, "
                  f"input->slice {b:.3g}; core's report {core:.3g} of the larger diagonal)")
        for label, topo in ours["topology"].items():
            print(f"  frame {label:<4}: {describe(topo)}")
        if ours["inner_vertices"] == 0:
            print("  (no vertex lies strictly between t0 and t1, so every in-between frame has the same combinatorics)")
        else:
            print(f"  ({ours['inner_vertices']} vertices lie strictly between t0 and t1: pushed in time)")

    for p in peers:
        if "error" in p:
            print(f"\nOpenVDB peer 1/{p['resolution']:g}: n/a ({p['error']})")
            continue
        voxel = p["voxel_size"] / inputs["diagonal"]
        print(f"\nOpenVDB peer, voxel 1/{p['resolution']:g} of the diagonal ({p['voxel_size']:.4g}; "
              f"{p['threads']} threads): {p['cfl_steps']} CFL steps to time {p['morph_time']:g} "
              f"({'converged' if p['converged'] else 'NOT converged (max time)'}: front within "
              f"{p['residual_voxels']:.3f} voxel of the target's), {p['active_voxels']:,} active voxels at the end")
        for label, name in (("t0", "sphere"), ("t1", inputs["name"]), ("target", inputs["name"])):
            a, b = p["ends"][label]
            what = "target's own level set, meshed" if label == "target" else f"end {label}"
            print(f"  {what:<31} vs {name:<10}: H = {max(a, b):.3g} of the diagonal = "
                  f"{max(a, b) / voxel:.2f} voxels (mesh->input {a:.3g}, input->mesh {b:.3g})")
        for label in ("t0", "mid", "t1", "target"):
            name = {"mid": f"mid (time {p['mid_time']:g})", "target": "target LS"}.get(label, label)
            print(f"  frame {name:<16}: {describe(p['topology'][label])}")
    if not peers:
        print("\nOpenVDB peer: skipped")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--bar", action="store_true", help="the bar table per pair (the default)")
    mode.add_argument("--seed-report", action="store_true", help="the §8.7.1 sphere -> genus-3 report")
    bar = parser.add_argument_group("--bar")
    bar.add_argument("--methods", default="field,skeleton",
                     help=f"comma-separated am.morph methods (default field,skeleton; available: {', '.join(METHODS)})")
    bar.add_argument("--pairs", default=None, help=f"comma-separated pairs (default all: {', '.join(morph_bar.PAIRS)})")
    bar.add_argument("--frames", type=int, default=24, help="in-between frames, spread over the range (default 24)")
    bar.add_argument("--vdb-resolution", type=float, default=128, help="the peer's voxels per diagonal (default 128)")
    bar.add_argument("--field-resolution", type=float, default=None,
                     help="the field method's lattice cells across the shapes' size (default: am.morph's, 24)")
    seed = parser.add_argument_group("--seed-report")
    default_method = "skeleton" if "skeleton" in METHODS else "strip"
    seed.add_argument("--method", default=default_method,
                      help=f"am.morph method (default here: {default_method}; available: {', '.join(METHODS)})")
    seed.add_argument("--target", default=None,
                      help=f"an OFF/OBJ genus-3 model, or 'procedural' (default: {SHARED_TARGET} when present, "
                           "else procedural)")
    seed.add_argument("--sphere-subdivisions", type=int, default=4, help="icosphere level (4: 2,562 vertices)")
    seed.add_argument("--vdb-resolutions", default="128,192",
                      help="voxels per bbox diagonal of the target, comma separated (peer cost ~ N^3)")
    parser.add_argument("--no-peer", action="store_true", help="skip the OpenVDB peer")
    parser.add_argument("--build", type=Path, default=ROOT / "build")
    parser.add_argument("--json", type=Path, default=None, metavar="PATH",
                        help="--bar: also write every pair's rows as JSON to PATH (bench/run_all.py reads it)")
    return parser


def bar_mode(args) -> int:
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    unknown = [m for m in methods if m not in METHODS]
    if unknown or not methods:
        print(f"bench_morph: unknown method(s) {', '.join(unknown) or '(none given)'}; available: {', '.join(METHODS)}")
        return 1
    pairs = [p.strip() for p in args.pairs.split(",") if p.strip()] if args.pairs else None
    exe = why = None
    if not args.no_peer:
        exe, why = vdb_executable(args.build)
    work = Path(tempfile.mkdtemp(prefix="bench_morph_bar_"))
    try:
        options = {} if args.field_resolution is None else {"field": {"field_resolution": args.field_resolution}}
        results = morph_bar.run_bar(pairs, methods, args.frames, work, exe, why,
                                    None if args.no_peer else args.vdb_resolution, options)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    write_json(args.json, {"frames": args.frames, "peer_unavailable": why, "field_resolution": args.field_resolution,
                           "pairs": {pair.name: [dataclasses.asdict(row) for row in rows] for pair, rows in results}})
    return 0


def seed_report(args) -> int:
    work = Path(tempfile.mkdtemp(prefix="bench_morph_"))
    if args.target is None and not SHARED_TARGET.exists():
        print(f"bench_morph: {SHARED_TARGET} is absent (it comes with the project's shared/ folder): "
              "the procedural stand-in instead (figures not comparable with 3holes')", flush=True)
    if args.target == "procedural" or (args.target is None and not SHARED_TARGET.exists()):
        target = smooth_genus3()
        args.target = work / "smooth_genus3.off"
        am.write_mesh(args.target, *target)
    else:
        args.target = Path(args.target) if args.target else SHARED_TARGET
        if not args.target.exists():
            print(f"bench_morph: {args.target} does not exist")
            shutil.rmtree(work, ignore_errors=True)
            return 1
        target = am.read_mesh(args.target)
    lo, hi = target[0].min(0), target[0].max(0)
    diagonal = float(np.linalg.norm(hi - lo))
    sphere = covering_sphere(target[0], args.sphere_subdivisions)
    inputs = {"name": args.target.name, "sphere": sphere, "target": target, "diagonal": diagonal}
    topo = topology(*target)
    print(f"bench_morph: {args.target.name}: {describe(topo)}; sphere: {describe(topology(*sphere))}", flush=True)

    print(f"bench_morph: ours, am.morph(method={args.method!r}) ...", flush=True)
    ours = run_ours(sphere, target, args.method, diagonal)
    print(f"bench_morph: ours done in {ours['wall']:.1f} s{' (raised)' if 'error' in ours else ''}", flush=True)

    peers = []
    if not args.no_peer:
        sphere_path = work / "sphere.off"
        am.write_mesh(sphere_path, *sphere)
        exe, why = vdb_executable(args.build)
        for resolution in (float(r) for r in args.vdb_resolutions.split(",") if r.strip()):
            if exe is None:
                peers.append({"error": why, "resolution": resolution})
                continue
            print(f"bench_morph: OpenVDB peer at 1/{resolution:g} ...", flush=True)
            peers.append(run_peer(exe, sphere_path, args.target, resolution, sphere, target, diagonal, work))
            if "wall" in peers[-1]:
                print(f"bench_morph: peer done in {peers[-1]['wall']:.1f} s", flush=True)
    print_report(args.method, ours, peers, inputs)
    shutil.rmtree(work, ignore_errors=True)
    return 0


def main() -> int:
    args = build_parser().parse_args()
    return seed_report(args) if args.seed_report else bar_mode(args)


if __name__ == "__main__":
    sys.exit(main())
