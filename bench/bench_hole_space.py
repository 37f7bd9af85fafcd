"""Benchmark of the hole space (§8.6.5) on the shared genus-1 torus-800.off (800 vertices),
the figure tests/test_hole_space.py::test_torus_800_volume used to assert (under 5 s).

    PYTHONPATH=python python3 bench/bench_hole_space.py [--repeat 3] [--data ../shared/data] [--json PATH]
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import animanifold as am
from figures import bench_parser, write_json

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    parser = bench_parser(__doc__, repeat=3)
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    args = parser.parse_args()
    path = args.data / "meshes" / "torus-800.off"
    if not path.is_file():
        print(f"bench_hole_space: {path} is missing (the shared test data)", file=sys.stderr)
        return 2
    v, f = am.read_mesh(path)
    seconds = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        hole = am.hole_space(v, f)
        seconds.append(time.perf_counter() - start)
    print(f"torus-800: hole space of {len(hole[1])} faces, volume {am.solid_measure(*hole):.6g}; "
          f"median {statistics.median(seconds):.3f} s over {args.repeat} runs (was asserted < 5 s)")
    write_json(args.json, {"vertices": len(v), "hole_faces": len(hole[1]), "seconds": statistics.median(seconds)})
    return 0


if __name__ == "__main__":
    sys.exit(main())
