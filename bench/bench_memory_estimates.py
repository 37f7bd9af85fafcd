"""Benchmark for issue 23 (memory limits): prints figures, asserts nothing.

For each call the memory limit judges (stitch, subdivide, subdivide_frame, subdivide_polyline,
smoothed slices, refine), on an input whose output is tens to hundreds of megabytes: the
core's estimate (read from the MemoryLimitError a limit of 1 byte gives) beside the peak the
call really took (the rise of the process's resident high-water mark, each case in its own
process so that earlier cases do not hide it). The estimates' peak factors in
cpp/src/memory_estimates.cpp come from these figures: a ratio estimate/measured of 1 to 3
means the limit refuses in time without refusing what fits.

Run:  python3 bench/bench_memory_estimates.py [case ...]
"""

from __future__ import annotations

import re
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests"))

import animanifold as am  # noqa: E402
from animanifold import _core  # noqa: E402
from helpers.shapes import icosphere  # noqa: E402


def keyframes(subdivisions: int, count: int):
    v, f = icosphere(subdivisions)
    times = np.linspace(0.0, 1.0, count)
    frames = np.stack([v * (1 + 0.2 * np.sin(3 * t)) + [t, 0, 0] for t in times])
    return frames, f, times


def stitch_case():
    frames, f, times = keyframes(4, 200)  # 5,120 faces, 200 keyframes: 3.1 million tets
    return lambda: am.stitch(frames, f, times)


def subdivide_case():
    frames, f, times = keyframes(2, 5)  # 3,840 tets, three levels: 2 million
    m = am.stitch(frames, f, times)
    return lambda: am.subdivide(m, levels=3)


def frame_case():
    v, f = icosphere(3)  # 1,280 faces, five levels: 1.3 million
    return lambda: am.subdivide_frame(v, f, levels=5)


def polyline_case():
    n = 1000
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    points = np.c_[np.cos(angles), np.sin(angles)]
    segments = np.array([[i, (i + 1) % n] for i in range(n)], np.int32)
    return lambda: _core.subdivide_polyline(points, segments, levels=10)


def smooth_slice_case():
    frames, f, times = keyframes(4, 3)
    m = am.stitch(frames, f, times)
    return lambda: m.slice(0.5, smooth_levels=4)


def refine_case():
    frames, f, times = keyframes(3, 10)  # 34,560 tets; every edge of every tet's first two vertices split
    m = am.stitch(frames, f, times)
    edges = np.unique(np.sort(m.simplices[:, [0, 1]], axis=1), axis=0).astype(np.int32)
    splits = (edges, np.full(edges.shape, 0.5))
    return lambda: am.refine(m, splits)


CASES = {"stitch": stitch_case, "subdivide": subdivide_case, "subdivide_frame": frame_case,
         "subdivide_polyline": polyline_case, "smooth_slice": smooth_slice_case, "refine": refine_case}


def peak_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB


def measure(name: str) -> None:
    """In a child: the estimate and the measured peak of one case, printed as 'estimate peak doing'."""
    call = CASES[name]()
    am.set_memory_limit(1)
    try:
        call()
        raise SystemExit(f"{name}: a limit of 1 byte did not refuse it")
    except am.MemoryLimitError as e:
        message = str(e)
    am.set_memory_limit(None)
    estimate = int(re.search(r"needs about ([\d,]+) bytes", message).group(1).replace(",", ""))
    before = peak_bytes()
    result = call()
    del result
    print(estimate, peak_bytes() - before, message.split(" needs about")[0])


def main(names: list[str]) -> None:
    print(f"{'call':<20} {'estimate MB':>12} {'measured MB':>12} {'ratio':>6}  what")
    for name in names or list(CASES):
        out = subprocess.run([sys.executable, __file__, "--child", name], capture_output=True, text=True)
        if out.returncode:
            print(f"{name:<20} failed: {out.stderr.strip()[-300:]}")
            continue
        estimate, peak, doing = out.stdout.split(maxsplit=2)
        ratio = int(estimate) / max(int(peak), 1)
        print(f"{name:<20} {int(estimate) / 1e6:>12.1f} {int(peak) / 1e6:>12.1f} {ratio:>6.2f}  {doing.strip()}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        measure(sys.argv[2])
    else:
        main(sys.argv[1:])
