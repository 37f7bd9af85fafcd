"""`python3 -m animanifold subdivide walk.amf -o smooth.amf --levels 1`: shape and motion
smoothed together (§4.3, subdivision.py), with the core's steps on stderr."""

from __future__ import annotations

import argparse

from .cache import load, save
from .cli_common import StepPrinter, add_manifold_command, check_count
from .subdivision import MANIFOLD_SCHEMES, SubdivideOptions, subdivide

MAX_LEVELS = 8  # each level multiplies the tets by 8; the memory limit refuses most inputs long before


def add_parser(commands) -> argparse.ArgumentParser:
    p = add_manifold_command(commands, "subdivide", run)
    p.add_argument("--levels", type=int, default=1, help=f"levels of subdivision, 1 to {MAX_LEVELS} (default 1)")
    p.add_argument("--scheme", choices=MANIFOLD_SCHEMES, default="schaefer",
                   help="schaefer (split and average: smooth; default) or linear (split only)")
    p.add_argument("--keep-keyframe-times", action="store_true",
                   help="keep every keyframe's points at its time (default: the first and last only)")
    return p


def run(args: argparse.Namespace) -> int:
    """smooth shape and motion together: LEVELS of subdivision -> .amf

    Subdivides an animation manifold with the tetrahedral scheme of Schaefer, Hakenberg and Warren
    (2004): each level multiplies the tets by 8 (a 2D animation's triangles by 4) and smooths shape
    and motion paths together. The first and last keyframe stay on their time hyperplanes. The
    core's steps go to stderr; Ctrl-C stops it, writing nothing.
    """
    check_count("--levels", args.levels, 1, MAX_LEVELS)
    manifold = load(args.manifold)
    options = SubdivideOptions(scheme=args.scheme, keep_keyframe_times=args.keep_keyframe_times)
    smooth = subdivide(manifold, args.levels, options=options, progress=StepPrinter(args.quiet))
    save(smooth, args.output)
    kind = "tets" if manifold.dimension == 4 else "triangles"
    print(f"subdivided {len(manifold.simplices):,} {kind} {args.levels} time{'s' if args.levels > 1 else ''} "
          f"({args.scheme}) into {len(smooth.simplices):,} {kind}, {len(smooth.points):,} points: {args.output}")
    return 0
