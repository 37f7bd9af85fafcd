"""`python3 -m animanifold farm ...`: the render-farm steps that need no Blender.

    farm count PAIRS                       how many pairs a list holds (a job's PairCount)
    farm morph PAIRS --index I -o OUT      pair I (from 1): morph, validity report, frames, contact sheet
    farm summary PAIRS -o OUT              OUT/summary.md: every pair's validity and timings
    farm frames CACHE --first F --last L -o DIR   integer frames F..L with UVs, normals, materials

PAIRS is a JSON or CSV list of (source, target, frames, method) pairs; what a pair's task
writes, and why a re-run skips it, is morph_batch.py's. A morph the geometry refuses is a
result, not a crash: its report says `failed` with the reason and the summary shows it.
farm/openjd/morph/template.yaml runs morph once per pair, then summary.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from ._core import Error
from .cache import load
from .morph_batch import REPORT, SUMMARY, PairListError, frame_bytes, morph_pair, read_pairs, summary_markdown, \
    summary_rows, write_atomic


class FrameRangeError(Error, ValueError):
    """Frames asked for that the manifold does not have (the message names the file and its frames)."""


def run_morph(args: argparse.Namespace) -> int:
    pairs = read_pairs(args.pairs)
    if not 1 <= args.index <= len(pairs):
        raise PairListError(f"--index {args.index} is outside the list's pairs 1..{len(pairs)} ({args.pairs})")
    pair = pairs[args.index - 1]
    report = morph_pair(pair, Path(args.output), args.format)
    if report is None:
        print(f"farm morph: {pair['name']}: complete already ({Path(args.output) / pair['name'] / REPORT}), skipped")
    else:
        print(f"farm morph: {pair['name']}: {report['status']}" + (f" ({report['error']})" if "error" in report else ""))
    return 0


def run_summary(args: argparse.Namespace) -> int:
    pairs = read_pairs(args.pairs)
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    rows = summary_rows(pairs, output)
    write_atomic(output / SUMMARY, summary_markdown(rows).encode())
    write_atomic(output / "summary.json", (json.dumps(rows, indent=1) + "\n").encode())
    print(f"farm summary: {sum(r['status'] == 'ok' for r in rows)} of {len(rows)} pairs morphed: {output / SUMMARY}")
    return 0


def run_count(args: argparse.Namespace) -> int:
    print(len(read_pairs(args.pairs)))
    return 0


def run_frames(args: argparse.Namespace) -> int:
    manifold = load(args.manifold)
    t0, t1 = manifold.time_range
    first, last = max(args.first, math.ceil(t0 - 1e-9)), min(args.last, math.floor(t1 + 1e-9))
    if last < first:
        raise FrameRangeError(f"frames {args.first}–{args.last} are outside {args.manifold}'s frames {t0:g}–{t1:g}")
    folder = Path(args.output)
    folder.mkdir(parents=True, exist_ok=True)
    paths = {frame: folder / f"{Path(args.manifold).stem}_{frame:06d}.{args.format}" for frame in range(first, last + 1)}
    missing = [frame for frame, path in paths.items() if not path.exists()]  # written atomically: there means complete
    for frame, s in zip(missing, manifold.slices(missing)):
        write_atomic(paths[frame], frame_bytes(s, args.format))
    print(f"farm frames: {last - first + 1} frames {first}–{last} in {folder}")
    return 0


def add_parser(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser("farm", help="render-farm steps that need no Blender (batch morphs, frames)",
                              description=__doc__.split("\n\n")[0])
    commands = p.add_subparsers(dest="farm_command", required=True, metavar="STEP")
    c = commands.add_parser("count", help="number of pairs in a list")
    c.add_argument("pairs")
    c.set_defaults(run=run_count)
    m = commands.add_parser("morph", help="morph one pair of a list")
    m.add_argument("pairs", help="JSON or CSV list of (source, target, frames, method)")
    m.add_argument("--index", type=int, required=True, help="which pair, from 1")
    m.add_argument("-o", "--output", required=True, help="output folder (the pair's results in OUTPUT/<name>/)")
    m.add_argument("--format", choices=("obj", "ply"), default="obj")
    m.set_defaults(run=run_morph)
    s = commands.add_parser("summary", help="Markdown table of every pair's report")
    s.add_argument("pairs")
    s.add_argument("-o", "--output", required=True)
    s.set_defaults(run=run_summary)
    f = commands.add_parser("frames", help="integer frames of a cache, with UVs, normals and materials")
    f.add_argument("manifold")
    f.add_argument("--first", type=int, required=True)
    f.add_argument("--last", type=int, required=True)
    f.add_argument("-o", "--output", required=True)
    f.add_argument("--format", choices=("obj", "ply"), default="obj")
    f.set_defaults(run=run_frames)
    return p

