"""The command line: ``python3 -m animanifold stitch|slice|frames|info|demo|morph|subdivide|deform|skeleton|farm``.

stitch, slice, frames, info and demo read and write animation manifolds; morph makes one
between two closed meshes; subdivide (cli_subdivide.py) and deform (cli_deform.py) reshape
one, printing the core's steps on stderr; skeleton (cli_skeleton.py) writes a mesh's Voronoi
skeleton; farm (cli_farm.py) runs the render-farm steps that need no Blender.

Each sub-command is a small function from parsed arguments to an exit code, whose docstring
is the command's help (cli_common.add_command).
Anything the user can get wrong — a missing or unreadable file, a damaged
cache, keyframes that do not correspond, times that do not increase, a value
outside the manifold, a count beyond MAX_FRAMES, an output that cannot be written
completely (a full disk; every file is written through atomic_file.py and checked)
— ends as one line ``animanifold: error: ...`` on stderr and exit code 2
(argparse's own convention for usage errors), never a traceback. An input the
geometry cannot handle (any other animanifold.Error: CGAL refuses a shape's
hole space, a mesher fails) ends the same way with exit code 3. Programming
errors still raise, so bugs are not disguised as user mistakes.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Sequence

import numpy as np

from ._core import Error, MemoryLimitError
from . import cli_deform, cli_farm, cli_skeleton, cli_subdivide
from .cli_common import PROG, StepPrinter, UserError, add_command, check_count
from .cache import load, save
from .demo import run_demo as build_demo
from .manifold import AXES, AnimationManifold, axis_index
from .meshio import read_mesh, write_mesh
from .morph_noise import noise_on_frames, noise_summary
from .morph_pipeline import METHODS, cut_frame_warnings, default_method, morph
from .stitching import stitch

EXIT_USER_ERROR = 2
EXIT_GEOMETRY_ERROR = 3
MESH_FORMATS = ("obj", "ply", "off", "stl")  # what the core's CGAL IO writes, by extension
FRAME_FORMATS = ("obj", "ply", "off")


def refuse_stl(path: str) -> None:
    """Keyframes must keep their vertex order; STL stores triangles only, and the reader numbers
    the merged corners by position, so two keyframes of one mesh need not match vertex for vertex."""
    with open(path, "rb") as f:
        start = f.read(84)
    text_stl = start.lstrip().lower().startswith(b"solid")
    if path.lower().endswith(".stl") or text_stl:
        raise UserError(f"keyframe {path} is an STL file: STL keeps no vertex order, so keyframes cannot be matched "
                        "vertex for vertex; export them as OBJ, PLY or OFF")


# -- stitch --------------------------------------------------------------------


def keyframe_times(count: int, times: Sequence[float] | None, fps: float | None, files: Sequence[str]) -> np.ndarray:
    """The time of each of `count` keyframes: given, from a frame rate, or evenly spaced over 0..1."""
    if times is not None:
        if len(times) != count:
            raise UserError(f"{count} keyframe files but {len(times)} times")
        values = np.asarray(times, dtype=np.float64)
    elif fps is not None:
        if not (math.isfinite(fps) and fps > 0):
            raise UserError(f"--fps must be a positive number, got {fps}")
        values = np.arange(count, dtype=np.float64) / fps
    else:
        values = np.linspace(0.0, 1.0, count)
    for i, t in enumerate(values):
        if not math.isfinite(t):
            raise UserError(f"time of keyframe {i} ({files[i]}) is not finite: {t}")
        if i and t <= values[i - 1]:
            raise UserError(
                f"keyframe times must increase strictly: keyframe {i} ({files[i]}) at t={t:g} "
                f"follows keyframe {i - 1} ({files[i - 1]}) at t={values[i - 1]:g}"
            )
    return values


def first_differing_face(reference: np.ndarray, faces: np.ndarray) -> int | None:
    """Index of the first face that differs between two face tables (or is missing from one); None if equal."""
    common = min(len(reference), len(faces))
    differing = np.flatnonzero((reference[:common] != faces[:common]).any(axis=1))
    if differing.size:
        return int(differing[0])
    return None if len(reference) == len(faces) else common


def describe_face(faces: np.ndarray, index: int) -> str:
    return f"({' '.join(str(v) for v in faces[index])})" if index < len(faces) else "missing"


def read_keyframes(files: Sequence[str]) -> tuple[list[np.ndarray], np.ndarray]:
    """Reads keyframe meshes and checks they correspond: same vertex count, identical faces.

    Returns (vertices of each keyframe, the shared faces).
    """
    for path in files:
        refuse_stl(path)
    meshes = [read_mesh(path) for path in files]
    ref_vertices, ref_faces = meshes[0]
    for i, (path, (vertices, faces)) in enumerate(zip(files[1:], meshes[1:]), start=1):
        if len(vertices) != len(ref_vertices):
            raise UserError(
                f"keyframe {i} ({path}) has {len(vertices)} vertices but keyframe 0 ({files[0]}) has "
                f"{len(ref_vertices)}: keyframes must correspond vertex for vertex"
            )
        face = first_differing_face(ref_faces, faces)
        if face is not None:
            raise UserError(
                f"keyframe {i} ({path}) has different faces from keyframe 0 ({files[0]}): face {face} is "
                f"{describe_face(faces, face)} there but {describe_face(ref_faces, face)} in keyframe 0 "
                f"({len(faces)} and {len(ref_faces)} faces); keyframes must share their connectivity"
            )
    return [vertices for vertices, _ in meshes], ref_faces


def run_stitch(args: argparse.Namespace) -> int:
    """keyframe meshes -> animation manifold (.amf)

    Reads keyframe meshes (OBJ/PLY/OFF; not STL, which keeps no vertex order) with the same vertices
    and faces in the same order, stitches them into an animation manifold of 3·faces·(keyframes-1)
    tets and saves it.
    """
    files = list(args.keyframes)
    if len(files) < 2:
        raise UserError(f"an animation manifold needs at least two keyframe files, got {len(files)}")
    times = keyframe_times(len(files), args.times, args.fps, files)
    frames, faces = read_keyframes(files)
    manifold = stitch(frames, faces, times)
    manifold.metadata["keyframe_files"] = [os.path.basename(f) for f in files]
    save(manifold, args.output)
    print(
        f"stitched {len(files)} keyframes ({len(frames[0])} vertices, {len(faces)} faces each, "
        f"t = {', '.join(f'{t:g}' for t in times)}) into {len(manifold.simplices)} tets: {args.output}"
    )
    return 0


# -- slice and frames ------------------------------------------------------------


def load_manifold(path: str) -> AnimationManifold:
    manifold = load(path)
    if manifold.dimension != 4:
        raise UserError(
            f"{path} is a 2D animation (contours in (x, y, t)); its slices are polylines, "
            "which mesh files cannot hold — use the Python API"
        )
    return manifold


def axis_range(manifold: AnimationManifold, axis: str) -> tuple[float, float]:
    column = axis_index(axis, manifold.dimension)
    low, high = manifold.bounding_box
    return float(low[column]), float(high[column])


def check_mesh_extension(path: str, formats: Sequence[str]) -> None:
    extension = Path(path).suffix.lower().lstrip(".")
    if extension not in formats:
        raise UserError(f"cannot write {path}: the extension must be one of {', '.join('.' + f for f in formats)}")


def run_slice(args: argparse.Namespace) -> int:
    """one frame (or sweep view) -> mesh file

    Slices a manifold at a value along t (a frame) or x/y/z (a sweep view, whose vertices are the
    remaining coordinates, e.g. (y, z, t) for --axis x) and writes the mesh.
    """
    check_mesh_extension(args.output, MESH_FORMATS)
    manifold = load_manifold(args.manifold)
    low, high = axis_range(manifold, args.axis)
    if not (math.isfinite(args.value) and low <= args.value <= high):
        raise UserError(f"{args.axis}={args.value:g} is outside the manifold's range along {args.axis}: [{low:g}, {high:g}]")
    frame = manifold.slice(args.value, axis=args.axis)
    if len(frame.faces) == 0:
        # Legitimate (the plane only touches the manifold, e.g. at the end of a sweep), but rarely wanted.
        print(f"{PROG}: warning: the slice at {args.axis}={args.value:g} has no faces", file=sys.stderr)
    write_mesh(args.output, frame.vertices, frame.faces)
    others = "".join(a for a in "xyzt" if a != args.axis)
    print(
        f"{args.axis}={args.value:g}: {len(frame.vertices)} vertices, {len(frame.faces)} faces "
        f"(coordinates {', '.join(others)}): {args.output}"
    )
    return 0


def frame_path(folder: Path, number: int, count: int, extension: str) -> Path:
    """folder/frame_0007.obj: zero-padded so names sort in frame order."""
    width = max(4, len(str(count - 1)))
    return folder / f"frame_{number:0{width}d}.{extension}"


def run_frames(args: argparse.Namespace) -> int:
    """N evenly spaced frames -> folder of meshes

    Slices N frames evenly spaced from the first to the last time (both included) and writes them as
    frame_0000.obj, frame_0001.obj, ... Progress goes to stderr.
    """
    check_count("-n", args.count, 1)
    manifold = load_manifold(args.manifold)
    folder = Path(args.output)
    if folder.exists() and not folder.is_dir():
        raise UserError(f"output {folder} exists and is not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    times = np.linspace(*manifold.time_range, args.count)
    for number, (t, frame) in enumerate(zip(times, manifold.slices(times))):
        path = frame_path(folder, number, args.count, args.format)
        write_mesh(path, frame.vertices, frame.faces)
        if not args.quiet:
            print(f"[{number + 1}/{args.count}] t={t:.6g}: {len(frame.faces)} faces -> {path}", file=sys.stderr)
    print(f"wrote {args.count} frames, t = {times[0]:g} .. {times[-1]:g}, to {folder}")
    return 0


# -- info ------------------------------------------------------------------------


def manifold_info(path: str, manifold: AnimationManifold) -> dict:
    """Everything `info` reports, as plain JSON-ready values."""
    low, high = manifold.bounding_box
    axes = "xyzt" if manifold.dimension == 4 else "xyt"
    validity = {key: (bool(v) if isinstance(v, bool) else int(v)) for key, v in manifold.check().to_dict().items()}
    return {
        "file": path,
        "file_bytes": os.path.getsize(path),
        "dimension": manifold.dimension,
        "points": len(manifold.points),
        "simplices": len(manifold.simplices),
        "simplex_kind": "tets" if manifold.dimension == 4 else "triangles",
        "time_range": list(manifold.time_range),
        "bounding_box": {axis: [float(low[c]), float(high[c])] for c, axis in enumerate(axes)},
        "validity": validity,
        "vertex_attributes": {name: int(table.shape[1]) for name, table in manifold.vertex_attributes.items()},
        "simplex_attributes": {name: int(table.shape[1]) for name, table in manifold.simplex_attributes.items()},
        "metadata": manifold.metadata,
    }


def format_info(info: dict) -> str:
    v = info["validity"]
    verdict = "oriented manifold" if v["is_oriented_manifold"] else "NOT an oriented manifold"
    lines = [
        f"file            {info['file']} ({info['file_bytes']:,} bytes)",
        f"manifold        {info['points']:,} points, {info['simplices']:,} {info['simplex_kind']} in R^{info['dimension']}",
        f"time range      [{info['time_range'][0]:g}, {info['time_range'][1]:g}]",
        "bounding box    " + ", ".join(f"{a} [{lo:g}, {hi:g}]" for a, (lo, hi) in info["bounding_box"].items()),
        f"validity        {verdict}: {v['interior_facets']:,} interior facets, {v['boundary_facets']:,} boundary, "
        f"{v['nonmanifold_facets']:,} non-manifold, {v['misoriented_facets']:,} misoriented, "
        f"{v['degenerate_simplices']:,} degenerate simplices",
    ]
    meta = info["metadata"]
    if "keyframe_times" in meta:
        times = meta["keyframe_times"]
        lines.append(
            f"keyframes       {len(times)} at t = {', '.join(f'{t:g}' for t in times)}; "
            f"{meta.get('keyframe_vertices', '?')} vertices, {meta.get('keyframe_faces', '?')} faces each"
        )
    if "keyframe_files" in meta:
        lines.append(f"keyframe files  {', '.join(meta['keyframe_files'])}")
    for kind in ("vertex", "simplex"):
        attributes = info[f"{kind}_attributes"]
        if attributes:
            lines.append(f"{kind} attributes".ljust(16) + ", ".join(f"{n} ({w})" for n, w in attributes.items()))
    shown = {"keyframe_times", "keyframe_vertices", "keyframe_faces", "keyframe_files"}
    for key, value in meta.items():
        if key not in shown:
            lines.append(f"{key}".ljust(16) + f"{value}")
    return "\n".join(lines)


def run_info(args: argparse.Namespace) -> int:
    """counts, time range, bounding box, validity

    Describes a cache file: point and simplex counts, time range, bounding box, manifold validity
    (interior, boundary, non-manifold and misoriented facets), keyframes and attributes.
    """
    info = manifold_info(args.manifold, load(args.manifold))
    print(json.dumps(info, indent=2) if args.json else format_info(info))
    return 0


# -- demo ------------------------------------------------------------------------


def run_demo(args: argparse.Namespace) -> int:
    """the built-in main job: procedural keyframes -> manifold -> frames + picture

    Stitches a procedural keyframe animation (a lobed icosphere that squashes, stretches, twists and
    travels through 6 keyframes at non-uniform times), saves OUTPUT/demo.amf, writes frames to
    OUTPUT/frames/*.obj and a contact sheet of several frames to OUTPUT/contact_sheet.png.
    """
    check_count("--frames", args.frames, 1)
    if not args.no_picture:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise UserError("the contact sheet needs matplotlib (pip install matplotlib), or pass --no-picture") from None
    start = time.perf_counter()
    result = build_demo(args.output, frame_count=args.frames, small=args.small, picture=not args.no_picture)
    keyframes = ", ".join(f"{t:g}" for t in result.keyframe_times)
    print(f"keyframes   {len(result.keyframe_times)} at t = {keyframes} ({result.keyframe_faces} faces each)")
    print(f"manifold    {result.tets:,} tets, stitched in {result.seconds['stitch'] * 1e3:.1f} ms: {result.cache}")
    print(
        f"frames      {len(result.slice_times)} at t = {', '.join(f'{t:.3f}' for t in result.slice_times)}, "
        f"sliced in {result.seconds['slice'] * 1e3:.1f} ms: {result.frame_files[0].parent}/"
    )
    print(f"faces       {min(result.slice_faces):,} .. {max(result.slice_faces):,} per frame")
    if result.contact_sheet is not None:
        print(f"picture     {result.contact_sheet} (rendered in {result.seconds['render']:.1f} s)")
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


# -- parser and entry point ----------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Animation manifolds: stitch keyframes into tets in R^4 and slice frames back out.",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = add_command(commands, "stitch", run_stitch)
    p.add_argument("keyframes", nargs="+", metavar="KEYFRAME", help="keyframe mesh files, in time order")
    when = p.add_mutually_exclusive_group()
    when.add_argument("--times", nargs="+", type=float, metavar="T", help="strictly increasing keyframe times")
    when.add_argument("--fps", type=float, help="keyframe i at time i/FPS (default: evenly spaced over 0..1)")
    p.add_argument("-o", "--output", required=True, help="the cache file to write (.amf)")

    p = add_command(commands, "slice", run_slice)
    p.add_argument("manifold", help="cache file (.amf)")
    p.add_argument("-t", "--t", "--value", dest="value", type=float, required=True, help="where to slice")
    p.add_argument("--axis", choices=list(AXES), default="t", help="slicing axis (default t)")
    p.add_argument("-o", "--output", required=True, help=f"mesh file: {', '.join('.' + f for f in MESH_FORMATS)}")

    p = add_command(commands, "frames", run_frames)
    p.add_argument("manifold", help="cache file (.amf)")
    p.add_argument("-n", "--count", type=int, required=True, help="number of frames")
    p.add_argument("-o", "--output", required=True, help="output folder (created if needed)")
    p.add_argument("--format", choices=FRAME_FORMATS, default="obj", help="mesh format (default obj)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")

    p = add_command(commands, "info", run_info)
    p.add_argument("manifold", help="cache file (.amf)")
    p.add_argument("--json", action="store_true", help="machine-readable output")

    p = add_command(commands, "demo", run_demo)
    p.add_argument("-o", "--output", default="out", help="output folder (default out)")
    p.add_argument("--frames", type=int, default=12, help="number of frames (default 12)")
    p.add_argument("--small", action="store_true", help="a coarse sphere (320 faces) for a quick check")
    p.add_argument("--no-picture", action="store_true", help="skip the contact sheet (no matplotlib needed)")

    p = add_command(commands, "morph", run_morph)
    p.add_argument("source", help="closed, outward-oriented triangle mesh at t0")
    p.add_argument("target", help="closed, outward-oriented triangle mesh at t1")
    p.add_argument("-o", "--output", required=True, help="output folder: morph.amf, frames/ (created if needed)")
    p.add_argument("--frames", type=int, default=0, help="also write this many frames (default 0)")
    p.add_argument("--t0", type=float, default=0.0, help="time of the source (default 0)")
    p.add_argument("--t1", type=float, default=1.0, help="time of the target (default 1)")
    p.add_argument("--format", choices=FRAME_FORMATS, default="obj", help="frame format (default obj)")
    p.add_argument("--method", choices=METHODS, default=None,
                   help=f"morph method (default {default_method(3)}; {default_method(2)} for 2D polygons)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    p.add_argument("--max-push", type=float, default=0.45,
                   help="skeleton method: how far into the morph holes close and open, as a fraction of t1 - t0 "
                        "(default 0.45)")
    p.add_argument("--field-resolution", type=float, default=None,
                   help="field method: lattice cells across the shapes' size (default 24); finer resolves thinner "
                        "parts and smaller holes in between, in more time and memory")

    cli_subdivide.add_parser(commands)
    cli_deform.add_parser(commands)
    sub = cli_skeleton.add_parser(commands)
    sub.set_defaults(run=cli_skeleton.run)
    cli_farm.add_parser(commands)
    return parser


def run_morph(args: argparse.Namespace) -> int:
    """two closed meshes -> a morph manifold (and frames)

    Builds an animation manifold that is SOURCE at t0 and TARGET at t1 by filling the space between
    them: 'field' (the default) takes the zero set of a blended signed-distance field over
    space-time (smooth in-betweens, ends exact); with the skeleton method the shapes' external
    skeletons are pushed into a Delaunay fill (chapters 5 and 8), so shapes of any genus morph
    through closed surfaces; 'strip' only removes what lies outside them. Saves it, and with
    --frames writes N frames. Prints the validity report of §8.3.
    """
    check_count("--frames", args.frames, 0)
    source, target = read_mesh(args.source), read_mesh(args.target)
    if not 0 < args.max_push < 0.5:
        raise UserError(f"--max-push must lie between 0 and 0.5, got {args.max_push}")
    field = {}
    if args.field_resolution is not None:
        if (args.method or default_method(source[0].shape[1])) != "field":
            raise UserError("--field-resolution applies to the field method only (--method field)")
        if not args.field_resolution >= 2:
            raise UserError(f"--field-resolution must be at least 2 lattice cells, got {args.field_resolution}")
        field["field_resolution"] = args.field_resolution
    manifold = morph(source, target, t0=args.t0, t1=args.t1, method=args.method, max_push=args.max_push,
                     progress=StepPrinter(args.quiet, ended=True), **field)
    folder = Path(args.output)
    folder.mkdir(parents=True, exist_ok=True)
    save(manifold, folder / "morph.amf")
    report = manifold.validity
    method = manifold.metadata["morph"]["method"]
    print(f"morph: {method} method, {len(manifold.simplices)} tets; ends reproduced: {report['ends_reproduced']} "
          f"(distances {report['source_distance']:.2e}, {report['target_distance']:.2e} of the size); "
          f"inverted simplices: {report['inverted_simplices']} "
          f"({report['degenerate_simplices']} flat at the exact coordinates); " + _method_summary(method, report))
    if not report["ends_reproduced"]:
        print(f"{PROG}: warning: the end frames are not the inputs (see the distances above)", file=sys.stderr)
    if report.get("inputs_apart"):
        print(f"{PROG}: warning: the source and the target do not overlap where they are: the {method} morph "
              "shrinks one away and grows the other in its place, nothing travels between them; move one onto "
              "the other to morph it into the other", file=sys.stderr)
    if report.get("middle_widening"):
        print(f"the inputs barely meet: the blend is widened at the middle by {100 * report['middle_widening']:.2g} % "
              "of the size, so the shape passes through the space between them instead of vanishing there")
    if manifold.hole_space is not None:
        print(f"shared holes (§8.6.5): volume {report['shared_hole_volume']:.6g}; raw frames fill up to "
              f"{report['hole_overlap_volume']:.3g} of it, cut away; kept in the checked frames: "
              f"{report['holes_preserved']}")
        for error in report["hole_errors"]:
            print(f"{PROG}: warning: {error}", file=sys.stderr)
        for line in cut_frame_warnings(report):
            print(f"{PROG}: warning: {line}", file=sys.stderr)
    if report.get("frames_cross_themselves"):
        print(f"{PROG}: warning: in-between frames run through themselves at times "
              f"{', '.join(f'{t:.3g}' for t in report['crossing_frames'])}", file=sys.stderr)
    if report.get("bubble_frames"):
        print(f"{PROG}: warning: in-between frames hold bubbles enclosed in the solid (time: count "
              f"{', '.join(f'{t:.3g}: {n}' for t, n in report['bubble_frames'])}; up to "
              f"{100 * report['largest_bubble_fraction']:.2g} % of the volume)", file=sys.stderr)
    if not manifold.check().is_oriented_manifold:
        print(f"{PROG}: warning: some in-between frames pinch (not a clean surface)" +
              ("; the skeleton method (--method skeleton) avoids that" if method == "strip" else ""),
              file=sys.stderr)
    if args.frames and report.get("noise_frames"):
        # the checks also look between the frames written: say which of those show the noise
        found = noise_on_frames(manifold, report["noise_frames"], np.linspace(args.t0, args.t1, args.frames),
                                source, target)
        print(f"{PROG}: warning: {noise_summary(report['noise_frames'], found, 'written frame')}", file=sys.stderr)
    if args.frames:
        frames = folder / "frames"
        frames.mkdir(exist_ok=True)
        for i, s in enumerate(manifold.slices(np.linspace(args.t0, args.t1, args.frames))):
            write_mesh(frame_path(frames, i, args.frames, args.format), s.vertices, s.faces)
    return 0


def _method_summary(method: str, report: dict) -> str:
    """What the method itself reports, and the core's frame checks (3D), on one line."""
    parts = []
    if method == "strip":
        parts.append(f"stripped {report['stripped_simplices']} of {report['fill_simplices']}")
    elif method == "skeleton":
        parts.append(f"{report['source_free_vertices']} + {report['target_free_vertices']} free vertices pushed "
                     f"(mean {report['source_push'][1]:.3f}, {report['target_push'][1]:.3f} of the span)")
    if "frames_checked" in report:
        capped = " (changes left unbisected at the frame limit)" if report["frames_capped"] else ""
        parts.append(f"{report['frames_checked']} frames checked{capped}, the topology changes "
                     f"{report['topology_changes']} times between them; topological noise at "
                     f"{len(report['noise_frames'])} of them")
        parts.append(_crossing_summary(report))
    return "; ".join(parts)


def _crossing_summary(report: dict) -> str:
    """How the frames were checked for crossings: certified for every time (the field method's
    embedded space-time triangulation), or on some frames only."""
    checked = report.get("crossing_frames_checked", 0)
    if report.get("crossings_certified"):
        confirmed = "1 frame confirms it" if checked == 1 else f"{checked} frames confirm it"
        return f"no frame at any time can cross itself (space-time triangulation certified; {confirmed})"
    failure = report.get("certificate_failure")
    why = f" (not certified: {failure})" if failure else ""
    return f"crossings checked on {checked} frames{why}"


def one_line(error: BaseException) -> str:
    """An exception's message on one line (core messages may span several)."""
    return " ".join(str(error).split()) or type(error).__name__


def main(argv: Sequence[str] | None = None) -> int:
    """Runs the command line on `argv` (default sys.argv[1:]); returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:  # argparse has printed usage or help already
        return exit_.code if isinstance(exit_.code, int) else EXIT_USER_ERROR
    try:
        code = args.run(args)
        sys.stdout.flush()  # a report that cannot be written (stdout on a full disk) is a failure too
        return code
    # ValueError covers the core's input errors and CacheError; OSError covers
    # missing, unreadable or malformed files (the core's IO errors) and unwritable outputs.
    except (UserError, ValueError, OSError) as error:
        return report(error, EXIT_USER_ERROR)
    except MemoryLimitError as error:  # refused before allocating: the message names the estimate and the limit
        return report(error, EXIT_USER_ERROR)
    except MemoryError:
        return report("not enough memory for this input", EXIT_USER_ERROR)
    except Error as error:  # the core's other refusals: BooleanError, MeshingError, Cancelled
        return report(error, EXIT_GEOMETRY_ERROR)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


def report(error: BaseException | str, code: int) -> int:
    print(f"{PROG}: error: {error if isinstance(error, str) else one_line(error)}", file=sys.stderr)
    return code
