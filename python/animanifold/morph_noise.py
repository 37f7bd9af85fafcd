"""Which of the frames a user renders show the topological noise a morph's checks found.

The core's frame checks (morph_validity.hpp) report `noise_frames`: times where a frame's Euler
characteristic leaves the range of the ends' or it has more pieces than the ends. They look between
whole frames too (bisections towards changes of topology, the field method's fill slab), where noise
may last less than the spacing of the frames an artist renders. So the reports say which of the
rendered frames next to those times show it (Blender's whole frames, the CLI's written frames), each
checked here by the same rule.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .cavities import shell_volumes
from .frame_quality import euler_characteristic


@dataclass(frozen=True)
class NoiseOnFrames:
    """The rendered frames next to the noise (the one before and the one after each noisy time, or
    the frame at it), and those of them that show noise."""

    near: list[float]
    noisy: list[float]


def frames_next_to(times: Sequence[float], frame_times: Sequence[float]) -> list[float]:
    """Of `frame_times` (increasing), the one at or before and the one after each of `times`."""
    frames = np.asarray(frame_times, dtype=np.float64)
    near = set()
    for t in times:
        after = int(np.searchsorted(frames, t, side="right"))
        near.update(float(frames[i]) for i in (after - 1, after) if 0 <= i < len(frames))
    return sorted(near)


def outer_shells(vertices: np.ndarray, faces: np.ndarray) -> int:
    """The pieces of a closed surface as the core's checks count them: shells enclosing positive
    volume (a bubble's shell encloses negative volume and is a cavity, not a piece)."""
    return int((shell_volumes(vertices, faces) > 0).sum())


def noise_on_frames(manifold, noise_times: Sequence[float], frame_times: Sequence[float], source_mesh,
                    target_mesh) -> NoiseOnFrames:
    """Which of the rendered `frame_times` next to `noise_times` show topological noise: an Euler
    characteristic outside the ends' (`source_mesh`, `target_mesh`: (vertices, faces)) or more
    pieces (outer shells) than the ends have."""
    ends = [(euler_characteristic(*mesh), outer_shells(*mesh)) for mesh in (source_mesh, target_mesh)]
    least, most = min(e for e, _ in ends), max(e for e, _ in ends)
    most_pieces = max(p for _, p in ends)
    near = frames_next_to(noise_times, frame_times)
    noisy = []
    for t in near:
        frame = manifold.slice(t)
        chi, parts = euler_characteristic(frame.vertices, frame.faces), outer_shells(frame.vertices, frame.faces)
        if not least <= chi <= most or parts > most_pieces:
            noisy.append(t)
    return NoiseOnFrames(near, noisy)


def noise_summary(noise_times: Sequence[float], found: NoiseOnFrames, frame_word: str = "frame") -> str:
    """One line for a report: where the checks found noise and which rendered frames show it."""
    if not noise_times:
        return "no topological noise in the frames checked"
    span = (f"at {noise_times[0]:.4g}" if len(noise_times) == 1
            else f"at {len(noise_times)} checked times from {min(noise_times):.4g} to {max(noise_times):.4g}")
    listed = ", ".join(f"{t:g}" for t in found.near)
    if not found.noisy:
        return (f"topological noise {span}, lasting less than a {frame_word}: the {frame_word}s next to it "
                f"({listed}) do not show it")
    shown = ", ".join(f"{t:g}" for t in found.noisy)
    verb = "shows" if len(found.noisy) == 1 else "show"
    return f"topological noise {span}; of the {frame_word}s next to it ({listed}), {shown} {verb} it"
