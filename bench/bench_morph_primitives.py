"""Morph Selected's first test by an artist: Blender's default primitives morphed into each other.

    python3 bench/bench_morph_primitives.py [--turned N] [--seed S]

Every ordered pair of Blender's cube, UV sphere, ico sphere (2 subdivisions), cylinder, cone and
torus, each as Blender adds it at the origin, then N pairs of them turned, moved and scaled (a fixed
seed), morphed with the default method over frames 1-48 (Morph Selected's default range). Per pair:
the seconds, the changes of topology, what the morph's own checks found (topological noise and
bubbles at the checked times, crossings, flat tets, whether the space-time triangulation is
certified), and of the 48 frames those next to the noise that show it (am.morph_noise: the checks
look between frames too, where noise may last less than a frame). A pair whose morph fails is
listed with its error. bpy 4.5 makes the primitives, so the shapes are exactly Blender's (float32
coordinates, its triangulation of the caps).
"""

from __future__ import annotations

import argparse
import itertools
import random
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
import animanifold as am  # noqa: E402

FRAMES = (1.0, 48.0)
PRIMITIVES = {
    "cube": ("cube", {}),
    "uv_sphere": ("uv_sphere", {}),
    "ico_sphere": ("ico_sphere", {"subdivisions": 2}),
    "cylinder": ("cylinder", {}),
    "cone": ("cone", {}),
    "torus": ("torus", {}),
}


def primitive(name: str, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), scale=1.0):
    """The primitive's world-space vertices and triangles, as Morph Selected reads them."""
    import bpy

    kind, options = PRIMITIVES[name]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    getattr(bpy.ops.mesh, f"primitive_{kind}_add")(location=location, rotation=rotation, **options)
    obj = bpy.context.active_object
    obj.scale = (scale, scale, scale)
    bpy.context.view_layer.update()
    mesh = obj.data
    mesh.calc_loop_triangles()
    world = np.array(obj.matrix_world)
    vertices = np.array([v.co for v in mesh.vertices]) @ world[:3, :3].T + world[:3, 3]
    return np.ascontiguousarray(vertices), np.array([t.vertices for t in mesh.loop_triangles], np.int32)


def turned_pairs(count: int, seed: int):
    """`count` pairs of distinct primitives, each turned, moved and scaled at random (fixed seed)."""
    rng = random.Random(seed)
    for _ in range(count):
        names = rng.sample(sorted(PRIMITIVES), 2)
        placed = []
        for name in names:
            location = tuple(rng.choice([0.0, rng.uniform(-0.5, 0.5)]) for _ in range(3))
            rotation = tuple(rng.choice([0.0, rng.uniform(0.0, 3.14)]) for _ in range(3))
            scale = rng.choice([1.0, rng.uniform(0.6, 1.5)])
            placed.append((name, {"location": location, "rotation": rotation, "scale": scale}))
        yield placed


def survey_row(label: str, source, target) -> str:
    """One pair's line of the table (or its error), morphed over FRAMES with the default method."""
    start = time.perf_counter()
    try:
        manifold = am.morph(source, target, *FRAMES)
    except Exception as error:  # noqa: BLE001  (the survey goes on with the next pair)
        return f"{label:<34} ERROR {type(error).__name__}: {str(error).strip().splitlines()[0]}"
    seconds = time.perf_counter() - start
    r = manifold.validity
    noise = r["noise_frames"]
    shown = []
    if noise:
        found = am.morph_noise.noise_on_frames(manifold, noise, np.linspace(*FRAMES, 48), source, target)
        shown = [int(round(t)) for t in found.noisy]
    return (f"{label:<34} {seconds:5.1f} {r['topology_changes']:>7} {len(noise):>5} {len(r['bubble_frames']):>7} "
            f"{len(r['crossing_frames']):>5} {r['degenerate_simplices'] + r['inverted_simplices']:>4} "
            f"{'yes' if r['crossings_certified'] else 'no':>9}  {', '.join(map(str, shown)) or '-'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--turned", type=int, default=12, help="pairs turned, moved and scaled at random")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    print(f"{'pair':<34} {'s':>5} {'changes':>7} {'noise':>5} {'bubbles':>7} {'cross':>5} {'flat':>4} "
          f"{'certified':>9}  frames of 48 showing noise")
    rows = []
    for a, b in itertools.permutations(sorted(PRIMITIVES), 2):
        rows.append(survey_row(f"{a}->{b}", primitive(a), primitive(b)))
        print(rows[-1], flush=True)
    for (a, place_a), (b, place_b) in turned_pairs(args.turned, args.seed):
        rows.append(survey_row(f"{a}->{b} (turned)", primitive(a, **place_a), primitive(b, **place_b)))
        print(rows[-1], flush=True)
    failed = sum("ERROR" in row for row in rows)
    print(f"\n{len(rows)} pairs: {failed} failed; the columns count the morph's own checks (frames 1-48)")


if __name__ == "__main__":
    main()
