"""Topological noise of the field morph at many times, not only at the bar's 24 frames.

    python3 bench/bench_noise_scan.py [--pairs "icosphere->ring_of_holes,flat_box_3->icosphere"]
                                      [--times 401] [--middle 81] [--field-resolution 24]

The bar (bench_morph.py) looks at 24 frames spread over the range; the morph's own checks add
the fill slab's and the bisections'. Noise that lives between those frames (the fill slab
joining the halves, 0.5 +- 0.0147 of the range at the default 17 layers; transients inside a layer's slab) shows
only in a denser scan. Per pair of bench/morph_bar.py (all by default), one field morph, then
`--times` even times over the range and `--middle` times across the middle (0.5 +- 0.02 of the
range). A frame is noisy by the bar's rule (animanifold.morph_noise): an Euler characteristic
outside the ends' or more outer shells than the ends have.

Prints, per pair: the morph's seconds, its own checks' noise and bubble frames, the noisy times
near the middle (of those scanned there) and elsewhere, the largest excess (of the Euler
characteristic beyond the ends' range, plus 2 per extra piece), the topology the two halves meet
the fill slab with (the frames just inside its ends), and the first noisy times.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "bench"))

import animanifold as am  # noqa: E402
from animanifold.frame_quality import euler_characteristic  # noqa: E402
from animanifold.morph_noise import outer_shells  # noqa: E402
import morph_bar  # noqa: E402

MIDDLE = 0.02  # share of the range each side of its middle scanned densely (the fill slab: 0.0147 at 17 layers)


def scan_times(t0: float, t1: float, count: int, middle: int) -> np.ndarray:
    """`count` even times over [t0, t1] and `middle` across the middle, sorted, without repeats."""
    centre, reach = 0.5 * (t0 + t1), MIDDLE * (t1 - t0)
    times = np.concatenate([np.linspace(t0, t1, count), np.linspace(centre - reach, centre + reach, middle)])
    return np.unique(np.round(times, 12))


def noise_excess(chi: int, pieces: int, chi_range: tuple[int, int], most_pieces: int) -> int:
    """How far a frame is from the ends' topology: 0 when it is within it."""
    low, high = chi_range
    return max(low - chi, chi - high, 0) + 2 * max(pieces - most_pieces, 0)


def fill_ends(t0: float, t1: float, slabs: int) -> list[float]:
    """Times just inside the two ends of the field morph's fill slab (morph_field.cpp's kFillSlab: half
    a layer of the `slabs` about the middle), where its frames are the halves' last layers' zero
    sets; none for another method."""
    if slabs <= 0:
        return []
    centre, half, inside = 0.5 * (t0 + t1), 0.25 / slabs * (t1 - t0), 1e-9 * (t1 - t0)
    return [centre - half + inside, centre + half - inside]


def frame_topology(frame) -> tuple[int, int]:
    """A frame's Euler characteristic and outer shells."""
    return euler_characteristic(frame.vertices, frame.faces), outer_shells(frame.vertices, frame.faces)


def scan_pair(pair: morph_bar.Pair, count: int, middle: int, options: dict) -> str:
    start = time.perf_counter()
    manifold = am.morph(pair.source, pair.target, method="field", **options)
    seconds = time.perf_counter() - start
    ends = [(euler_characteristic(*mesh), outer_shells(*mesh)) for mesh in (pair.source, pair.target)]
    chi_range = (min(e for e, _ in ends), max(e for e, _ in ends))
    most_pieces = max(p for _, p in ends)
    t0, t1 = manifold.time_range
    centre, reach = 0.5 * (t0 + t1), MIDDLE * (t1 - t0)
    near, elsewhere, worst, near_count = [], [], 0, 0
    for t in scan_times(t0, t1, count, middle):
        frame = manifold.slice(float(t))
        excess = noise_excess(euler_characteristic(frame.vertices, frame.faces),
                              outer_shells(frame.vertices, frame.faces), chi_range, most_pieces)
        in_middle = abs(t - centre) <= reach
        near_count += in_middle
        if excess:
            (near if in_middle else elsewhere).append(float(t))
            worst = max(worst, excess)
    report = manifold.validity
    ends_of_fill = [frame_topology(manifold.slice(float(t))) for t in fill_ends(t0, t1, report.get("field_layers", 0))]
    shown = lambda times: ", ".join(f"{t:.4g}" for t in times[:6]) + (", ..." if len(times) > 6 else "")  # noqa: E731
    return (f"{pair.name}: {seconds:.1f} s; own checks: noise at {len(report.get('noise_frames', []))}, "
            f"bubbles at {len(report.get('bubble_frames', []))}; scan: noisy at {len(near)} of {near_count} "
            f"times near the middle, {len(elsewhere)} elsewhere; largest excess {worst}"
            + (f"; the halves meet the fill at (chi, shells) {ends_of_fill[0]} and {ends_of_fill[1]}"
               if ends_of_fill else "")
            + (f"; near the middle t = {shown(near)}" if near else "")
            + (f"; elsewhere t = {shown(elsewhere)}" if elsewhere else ""))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pairs", default="", help="comma-separated pair names (bench_morph.py's); all by default")
    parser.add_argument("--times", type=int, default=401, help="even times over the range")
    parser.add_argument("--middle", type=int, default=81, help="times across the middle, 0.5 +- 0.02 of the range")
    parser.add_argument("--field-resolution", type=float, default=None, help="the morph's field_resolution")
    args = parser.parse_args()
    options = {} if args.field_resolution is None else {"field_resolution": args.field_resolution}
    names = [name for name in args.pairs.split(",") if name] or None
    for pair in morph_bar.load_pairs(names):
        print(scan_pair(pair, args.times, args.middle, options), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
