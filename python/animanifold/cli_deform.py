"""`python3 -m animanifold deform walk.amf -o moved.amf --anchors t::0 --handles t:1: --translate 0 0 1 0`:
a Laplacian deformation of an animation manifold (chapter 4, deformation.py) from the command
line, with the core's steps on stderr.

Anchors and handles are chosen by coordinate ranges: ``AXIS:LOW:HIGH`` takes the vertices
with LOW <= AXIS <= HIGH (an empty bound is open), and ranges joined by commas must all
hold, so ``t::0,z:0.5:`` is the vertices at t <= 0 with z >= 0.5.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from .cache import load, save
from .cli_common import StepPrinter, UserError, add_manifold_command
from .deformation import DeformOptions, deform
from .laplacian import BOUNDARY_RULES, METHODS, LaplacianOptions, handle_transform, rotation_matrix
from .manifold import AnimationManifold, axis_index
from .regularisation import RegulariseOptions


def add_parser(commands) -> argparse.ArgumentParser:
    p = add_manifold_command(commands, "deform", run)
    p.add_argument("--anchors", required=True, metavar="RANGES", help="vertices that stay, e.g. t::0")
    p.add_argument("--handles", required=True, metavar="RANGES", help="vertices that move, e.g. t:1:")
    p.add_argument("--translate", type=float, nargs="+", metavar="D",
                   help="the handles' motion, one number per coordinate: x y z t (x y t for a 2D animation)")
    p.add_argument("--rotate", type=float, nargs=4, metavar=("AX", "AY", "AZ", "DEGREES"),
                   help="turn the handles about the axis (AX, AY, AZ) through their centre, time kept "
                        "(animated surfaces only)")
    p.add_argument("--method", choices=METHODS, default="dual", help="Laplacian (default dual)")
    p.add_argument("--boundary", choices=BOUNDARY_RULES, default="grow",
                   help="what the dual method does when constraints are too few (default grow)")
    p.add_argument("--no-restore", action="store_true", help="skip the dual method's feature restore")
    p.add_argument("--regularise", action="store_true",
                   help="split the edges the motion stretched (§4.5.1): more vertices and simplices")
    return p


def parse_ranges(option: str, text: str, manifold: AnimationManifold) -> np.ndarray:
    """The vertices of `manifold` inside every AXIS:LOW:HIGH range of `text` (joined by commas)."""
    inside = np.ones(len(manifold.points), dtype=bool)
    for part in text.split(","):
        fields = part.strip().split(":")
        if len(fields) != 3:
            raise UserError(f"{option} {text!r}: {part!r} is not AXIS:LOW:HIGH (e.g. t::0 or z:0.5:)")
        try:
            column = axis_index(fields[0].strip(), manifold.dimension)
        except ValueError as e:
            raise UserError(f"{option} {text!r}: {e}") from None
        low, high = (_bound(option, text, value, default) for value, default in
                     ((fields[1], -math.inf), (fields[2], math.inf)))
        inside &= (manifold.points[:, column] >= low) & (manifold.points[:, column] <= high)
    chosen = np.flatnonzero(inside)
    if chosen.size == 0:
        low, high = manifold.bounding_box
        box = ", ".join(f"{a} [{lo:g}, {hi:g}]" for a, lo, hi in zip(_axes(manifold), low, high))
        raise UserError(f"{option} {text!r} selects no vertex; the manifold spans {box}")
    return chosen


def _bound(option: str, text: str, value: str, default: float) -> float:
    if not value.strip():
        return default
    try:
        bound = float(value)
    except ValueError:
        raise UserError(f"{option} {text!r}: {value!r} is not a number") from None
    if math.isnan(bound):
        raise UserError(f"{option} {text!r}: a bound cannot be NaN")
    return bound


def _axes(manifold: AnimationManifold) -> str:
    return "xyzt" if manifold.dimension == 4 else "xyt"


def motion(args: argparse.Namespace, manifold: AnimationManifold, handles: np.ndarray) -> np.ndarray:
    """The handles' (D+1)x(D+1) affine transform from --translate and --rotate (rotation first)."""
    D = manifold.dimension
    if args.translate is None and args.rotate is None:
        raise UserError("give the handles' motion: --translate and/or --rotate")
    translation = np.zeros(D)
    if args.translate is not None:
        if len(args.translate) != D or not np.isfinite(args.translate).all():
            raise UserError(f"--translate takes {D} finite numbers ({' '.join(_axes(manifold))}), "
                            f"got {' '.join(f'{v:g}' for v in args.translate)}")
        translation = np.asarray(args.translate)
    rotation, centre = None, None
    if args.rotate is not None:
        if D != 4:
            raise UserError("--rotate turns animated surfaces (x, y, z, t); this is a 2D animation (x, y, t)")
        axis, degrees = np.asarray(args.rotate[:3]), args.rotate[3]
        if not (np.isfinite(args.rotate).all() and np.linalg.norm(axis) > 0):
            raise UserError(f"--rotate needs a non-zero axis and finite numbers, got "
                            f"{' '.join(f'{v:g}' for v in args.rotate)}")
        rotation = rotation_matrix(axis, math.radians(degrees))
        centre = manifold.points[handles].mean(axis=0)
    return handle_transform(rotation=rotation, translation=translation, center=centre, dimension=D)


def _lengths(vectors: np.ndarray) -> np.ndarray:
    """Each row's length, scaled first so that huge finite motions do not overflow to inf."""
    scale = float(np.abs(vectors).max(initial=0.0)) or 1.0
    return scale * np.linalg.norm(vectors / scale, axis=1)


def run(args: argparse.Namespace) -> int:
    """Laplacian deformation: anchors stay, handles move -> .amf

    Deforms an animation manifold through space and time (chapter 4): the anchor vertices stay, the
    handle vertices move by --translate and/or --rotate, and the rest follows smoothly. Vertices are
    chosen by coordinate ranges AXIS:LOW:HIGH (an empty bound is open; ranges joined by commas must
    all hold), e.g. --anchors t::0 --handles t:1:,z:0.5: . The core's steps go to stderr; Ctrl-C
    stops it, writing nothing.
    """
    manifold = load(args.manifold)
    anchors = parse_ranges("--anchors", args.anchors, manifold)
    handles = parse_ranges("--handles", args.handles, manifold)
    both = np.intersect1d(anchors, handles)
    if both.size:
        raise UserError(f"vertex {both[0]} (at {', '.join(f'{c:g}' for c in manifold.points[both[0]])}) is chosen by "
                        f"both --anchors {args.anchors!r} and --handles {args.handles!r}")
    transform = motion(args, manifold, handles)
    options = DeformOptions(laplacian=LaplacianOptions(method=args.method, boundary=args.boundary,
                                                       restore=not args.no_restore),
                            regularise=RegulariseOptions() if args.regularise else None)
    moved = deform(manifold, anchors, handles, transform, options=options, progress=StepPrinter(args.quiet))
    save(moved, args.output)
    shift = _lengths(moved.points[: len(manifold.points)] - manifold.points)
    added = len(moved.simplices) - len(manifold.simplices)
    print(f"deformed {len(manifold.points):,} vertices ({anchors.size:,} anchors, {handles.size:,} handles; "
          f"{args.method}): largest motion {shift.max():.6g}, {np.count_nonzero(shift):,} vertices moved"
          + (f"; regularised: {added:,} simplices added" if args.regularise else "") + f": {args.output}")
    return 0
