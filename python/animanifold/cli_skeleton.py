"""`python3 -m animanifold skeleton in.obj -o skel.obj`: the Voronoi skeleton of a
closed triangle mesh file (chapter 7).

Self-contained sub-command: the main CLI calls ``add_parser(subparsers)`` and
dispatches to ``run(args)`` (also set as the parser's ``func`` default).
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from .cli_common import StepPrinter
from .holes import solid_measure
from .meshio import read_mesh, write_mesh
from .skeleton import SIDES, WRAP_SHAPES, empty_skeleton_reason, voronoi_skeleton

PROG = "animanifold"


def add_parser(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "skeleton",
        help="internal/external Voronoi skeleton of a closed mesh (chapter 7)",
        description="Makes a closed, oriented triangle mesh Voronoi separable and writes its Voronoi "
                    "skeleton: the bisectors of the Voronoi diagram of its vertices that do not "
                    "intersect it, internal and/or external (clipped to the convex hull). The core's steps "
                    "go to stderr; Ctrl-C stops it, writing nothing.")
    p.add_argument("input", help="closed triangle mesh (.obj, .off, .ply, .stl)")
    p.add_argument("-o", "--output", required=True, help="skeleton triangles (format from the extension)")
    p.add_argument("--side", choices=SIDES, default="both",
                   help="which skeleton to write (default: both)")
    p.add_argument("--max-iterations", type=int, default=4, metavar="N",
                   help="cap on the splitting rounds that make the mesh separable (default: 4)")
    p.add_argument("--wrap", choices=WRAP_SHAPES, default=WRAP_SHAPES[0],
                   help=f"sites around the mesh so every cell is bounded (default: {WRAP_SHAPES[0]})")
    p.add_argument("--wrap-density", type=int, default=4, metavar="N", help="wrap subdivisions (default: 4)")
    p.add_argument("--dihedral-limit", type=float, default=45.0, metavar="DEGREES",
                   help="warn about surface angles sharper than this (default: 45)")
    p.add_argument("--refined", metavar="PATH", help="also write the Voronoi-separable (refined) mesh")
    p.add_argument("--attach", action="store_true",
                   help="write the refined mesh, the skeleton and the triangles attaching them (§8.6.2) "
                        "as one mesh to --output")
    p.add_argument("--literal-rule", action="store_true",
                   help="the dissertation's literal encroachment rule (one-ring edges skipped only); "
                        "may cascade on obtuse triangles")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)
    return p


def _error(message: str) -> int:
    print(f"{PROG}: error: {message}", file=sys.stderr)
    return 2


def empty_skeleton_message(path: str, side: str, vertices: np.ndarray, faces: np.ndarray) -> str:
    """What the command says of an empty skeleton, naming the file (skeleton.empty_skeleton_reason)."""
    which = "skeleton" if side == "both" else f"{side} skeleton"
    reason = empty_skeleton_reason(side, vertices, faces)
    if reason is None:
        return f"the {which} of '{path}' is empty: the shape is convex, so it has no external skeleton"
    return f"the {which} of '{path}' {reason}"


def run(args: argparse.Namespace) -> int:
    if args.max_iterations < 0:
        return _error(f"--max-iterations must be >= 0, got {args.max_iterations}")
    if args.wrap_density < 1:
        return _error(f"--wrap-density must be >= 1, got {args.wrap_density}")
    try:
        vertices, faces = read_mesh(args.input)
        sk = voronoi_skeleton(
            vertices, faces, side=args.side, max_iterations=args.max_iterations,
            wrap=args.wrap, wrap_density=args.wrap_density,
            dihedral_limit=math.radians(args.dihedral_limit), attach=args.attach,
            neighbourhood=1 if args.literal_rule else 2, in_plane_angle=0.0 if args.literal_rule else 0.3,
            warn=False, progress=StepPrinter(args.quiet))
        if len(sk.faces) == 0:
            return _error(empty_skeleton_message(args.input, args.side, vertices, faces))
        if args.attach:
            n = len(sk.refined_vertices)
            out_v = np.vstack([sk.refined_vertices, sk.vertices])
            out_f = np.vstack([sk.refined_faces, sk.faces + n, sk.attachment]).astype(np.int32)
        else:
            out_v, out_f = sk.vertices, sk.faces
        write_mesh(args.output, out_v, out_f)
        if args.refined:
            write_mesh(args.refined, sk.refined_vertices, sk.refined_faces)
    except (ValueError, OSError, RuntimeError) as e:
        return _error(str(e))

    internal = int(np.count_nonzero(sk.side == "internal"))
    external = len(sk.faces) - internal
    rounds = f"{sk.iterations} splitting round{'s' if sk.iterations != 1 else ''} ({sk.splits} splits)"
    print(f"skeleton: {len(sk.faces)} triangles (internal {internal}, external {external}) from "
          f"{len(vertices)} vertices; {'separable after' if sk.separable else 'NOT separable after'} {rounds}; "
          f"{sk.stats['seconds_separability'] + sk.stats['seconds_extraction']:.3f} s -> {args.output}")
    if not sk.separable:
        print(f"{PROG}: warning: the mesh is not Voronoi separable after --max-iterations {args.max_iterations}; "
              "the skeleton may miss faces where the shape is thin or sharp", file=sys.stderr)
    if not sk.dihedral.passes:
        print(f"{PROG}: warning: {len(sk.dihedral.angles)} edges are sharper than {args.dihedral_limit:g}° "
              f"(sharpest {math.degrees(sk.dihedral.sharpest):.1f}°, first at vertices "
              f"{tuple(int(i) for i in sk.dihedral.sharp[0])}); the skeleton may miss faces there",
              file=sys.stderr)
    return 0


def main(argv: list[str] | None = None) -> int:
    """Stand-alone entry (``python3 -m animanifold.cli_skeleton in.obj -o out.obj``)."""
    parser = argparse.ArgumentParser(prog=PROG)
    sub = parser.add_subparsers(dest="command", required=True)
    add_parser(sub)
    args = parser.parse_args(["skeleton", *(sys.argv[1:] if argv is None else argv)])
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
