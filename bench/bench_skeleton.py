"""Benchmark of the Voronoi skeleton (chapter 7, §7.6.6) on ~5000-vertex genus > 0 models.

    python3 bench/bench_skeleton.py [--repeat 3] [--build build]

For each model: separability time and rounds, extraction time, total, next to the
dissertation's figures for its 5000-vertex fertility model (80.5 s over 2 rounds to
make it separable, 4 minutes in all, peers 10 s), and in the same run CGAL's
Mean_curvature_flow_skeletonization on the same mesh (bench/bench_mcf_skeleton.cpp,
built by CMake next to the tests).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

import animanifold as am  # noqa: E402
from figures import add_json_option, write_json  # noqa: E402

SEED_SEPARABILITY_S = 80.5
SEED_TOTAL_S = 240.0
PEERS_S = 10.0


def irregular_torus(n_major: int = 100, n_minor: int = 50, R: float = 2.0, r: float = 0.7, seed: int = 7):
    """A genus-1 torus of n_major*n_minor vertices with jittered parameters (no
    cocircular UV quads), triangulated along the shorter quad diagonal."""
    rng = np.random.default_rng(seed)
    u = (np.arange(n_major)[:, None] + 0.3 * rng.uniform(-1, 1, (n_major, n_minor))) * 2 * np.pi / n_major
    v = (np.arange(n_minor)[None, :] + 0.3 * rng.uniform(-1, 1, (n_major, n_minor))) * 2 * np.pi / n_minor
    x = np.stack([(R + r * np.cos(v)) * np.cos(u), r * np.sin(v), (R + r * np.cos(v)) * np.sin(u)], -1)
    pts = x.reshape(-1, 3)
    idx = np.arange(n_major * n_minor).reshape(n_major, n_minor)
    faces = []
    for i in range(n_major):
        for j in range(n_minor):
            a, b = idx[i, j], idx[(i + 1) % n_major, j]
            c, d = idx[(i + 1) % n_major, (j + 1) % n_minor], idx[i, (j + 1) % n_minor]
            if np.linalg.norm(pts[a] - pts[c]) < np.linalg.norm(pts[b] - pts[d]):
                faces += [[a, b, c], [a, c, d]]
            else:
                faces += [[a, b, d], [b, c, d]]
    f = np.array(faces, np.int32)
    # Outward orientation: flip everything if the enclosed volume is negative.
    t = pts[f]
    if np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() < 0:
        f = f[:, ::-1].copy()
    return pts, f


def run_ours(vertices, faces, repeat: int):
    rows = []
    for _ in range(repeat):
        start = time.perf_counter()
        sk = am.voronoi_skeleton(vertices, faces, side="both", warn=False)
        total = time.perf_counter() - start
        rows.append((sk.stats["seconds_separability"], sk.stats["seconds_extraction"], total))
    sep, ext, total = (statistics.median(c) for c in zip(*rows))
    return sk, sep, ext, total


def run_mcf(exe: Path, mesh_path: Path):
    if not exe.exists() and (exe.parent / "CMakeCache.txt").exists():  # benches are built when asked for
        subprocess.run(["cmake", "--build", str(exe.parent), "--target", exe.name], capture_output=True, check=False)
    if not exe.exists():
        return None, f"{exe} not built (cmake --build build --target bench_mcf_skeleton)"
    out = subprocess.run([str(exe), str(mesh_path)], capture_output=True, text=True, timeout=600)
    if out.returncode != 0:
        return None, out.stderr.strip()
    return json.loads(out.stdout), None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--build", type=Path, default=ROOT / "build",
                        help="the CMake build holding bench_mcf_skeleton (the CGAL peer)")
    parser.add_argument("--cases", default=None,
                        help="comma-separated file names of the cases to run (3holes.off, bunny.off, torus-5000.off)")
    add_json_option(parser)
    args = parser.parse_args()

    data = ROOT.parent / "shared" / "data" / "meshes"
    cases = []
    if (data / "3holes.off").exists():
        cases.append(("3holes.off (AIM@SHAPE three-holed torus, genus 3)", data / "3holes.off", None))
        cases.append(("bunny.off (genus 0; needs splitting rounds, as in §7.6.5)", data / "bunny.off", None))
    else:
        print(f"note: {data} is absent; benchmarking the generated torus only")
    tmp = Path(tempfile.mkdtemp(prefix="bench_skeleton_"))
    tv, tf = irregular_torus()
    torus_path = tmp / "torus-5000.off"
    am.write_mesh(torus_path, tv, tf)
    cases.append(("irregular torus, 5000 vertices (genus 1)", torus_path, None))
    if args.cases:
        wanted = {name.strip() for name in args.cases.split(",")}
        cases = [case for case in cases if case[1].name in wanted]
    figures = {}

    print(f"Voronoi skeleton benchmark (median of {args.repeat}); dissertation's seed on its 5000-vertex "
          f"fertility model: separability {SEED_SEPARABILITY_S} s (2 rounds), total {SEED_TOTAL_S:.0f} s; "
          f"peers {PEERS_S:.0f} s")
    for label, path, _ in cases:
        v, f = am.read_mesh(path)
        sk, sep, ext, total = run_ours(v, f, args.repeat)
        mcf, why = run_mcf(args.build / "bench_mcf_skeleton", path)
        internal = int(np.count_nonzero(sk.side == "internal"))
        print(f"\n{label}: {len(v)} vertices, {len(f)} faces")
        print(f"  separability : {sep:8.3f} s  ({sk.iterations} rounds, {sk.splits} splits, "
              f"{'separable' if sk.separable else 'NOT separable (cap hit)'})")
        print(f"  extraction   : {ext:8.3f} s  ({len(sk.faces)} triangles: {internal} internal, "
              f"{len(sk.faces) - internal} external; {sk.stats['bisectors']} bisector polygons tested)")
        print(f"  total        : {total:8.3f} s  (seed: {SEED_TOTAL_S:.0f} s -> {SEED_TOTAL_S / total:,.0f}x faster; "
              f"separability vs seed's {SEED_SEPARABILITY_S} s: {SEED_SEPARABILITY_S / max(sep, 1e-9):,.0f}x)")
        if mcf is None:
            print(f"  CGAL MCF     :      n/a  ({why})")
            figures[path.name] = {"vertices": len(v), "ours_s": total, "separability_s": sep, "mcf_unavailable": why}
        else:
            print(f"  CGAL MCF     : {mcf['mcf_seconds']:8.3f} s  (Mean_curvature_flow_skeletonization: "
                  f"{mcf['skeleton_vertices']} curve vertices, {mcf['skeleton_edges']} edges)")
            figures[path.name] = {"vertices": len(v), "ours_s": total, "separability_s": sep,
                                  "mcf_s": mcf["mcf_seconds"]}
    write_json(args.json, figures)
    return 0


if __name__ == "__main__":
    sys.exit(main())
