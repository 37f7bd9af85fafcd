"""The main job on the built-in default: keyframes → manifold → frames → pictures.

A procedural keyframe animation (a lobed icosphere that squashes, leaps with
a stretch and a twist, travels and lands) is stitched into an animation
manifold, saved as a cache, sliced into evenly spaced frames (most of them
between keyframes) written as OBJ files, and a contact sheet of several
frames is rendered to a PNG.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .cache import save
from .contact_sheet import render_contact_sheet
from .stitching import stitch
from .meshio import write_mesh
from .procedural import demo_keyframes
from ._core import InputError

# Icosphere subdivision levels: 5,120 faces for the real demo, 320 for a quick check.
FULL_SUBDIVISIONS = 4
SMALL_SUBDIVISIONS = 2
SHEET_PANELS = 8


@dataclass
class DemoResult:
    keyframe_times: list[float]
    keyframe_faces: int
    tets: int
    slice_times: list[float]
    slice_faces: list[int]
    cache: Path
    frame_files: list[Path]
    contact_sheet: Path | None
    seconds: dict[str, float]


def sheet_selection(count: int, panels: int) -> list[int]:
    """`panels` frame numbers spread evenly over 0..count-1, first and last included."""
    return sorted(set(np.linspace(0, count - 1, min(panels, count)).round().astype(int).tolist()))


def run_demo(output: str | Path, frame_count: int = 12, small: bool = False, picture: bool = True) -> DemoResult:
    """Runs the demo into `output` (created if needed): demo.amf, frames/*.obj, contact_sheet.png."""
    if frame_count < 1:
        raise InputError(f"the demo needs at least one frame, got {frame_count}")
    output = Path(output)
    frames_dir = output / "frames"
    frames_dir.mkdir(parents=True, exist_ok=True)
    seconds: dict[str, float] = {}

    keyframes, faces, times = demo_keyframes(SMALL_SUBDIVISIONS if small else FULL_SUBDIVISIONS)
    start = time.perf_counter()
    manifold = stitch(keyframes, faces, times)
    seconds["stitch"] = time.perf_counter() - start
    manifold.metadata["source"] = "animanifold demo (procedural lobed icosphere)"
    cache = save(manifold, output / "demo.amf")

    start = time.perf_counter()
    slice_times = np.linspace(*manifold.time_range, frame_count)
    slices = [manifold.slice(t) for t in slice_times]
    seconds["slice"] = time.perf_counter() - start

    width = max(2, len(str(frame_count - 1)))
    frame_files = []
    for number, frame in enumerate(slices):
        path = frames_dir / f"frame_{number:0{width}d}.obj"
        write_mesh(path, frame.vertices, frame.faces)
        frame_files.append(path)

    sheet = None
    if picture:
        start = time.perf_counter()
        sheet = output / "contact_sheet.png"
        chosen = [slices[i] for i in sheet_selection(frame_count, SHEET_PANELS)]
        render_contact_sheet(chosen, sheet, manifold.bounding_box, columns=4)
        seconds["render"] = time.perf_counter() - start

    return DemoResult(
        keyframe_times=times.tolist(),
        keyframe_faces=len(faces),
        tets=len(manifold.simplices),
        slice_times=slice_times.tolist(),
        slice_faces=[len(s.faces) for s in slices],
        cache=cache,
        frame_files=frame_files,
        contact_sheet=sheet,
        seconds=seconds,
    )
