"""Timeline playback speed (frames/s of a scene.frame_set loop, depsgraph evaluated)
for (a) the original shape-key object, (b) the live manifold object (sliced by the
add-on's frame_change_post handler) and (c) the baked object (node group over the
frames collection), on the demo blob at ~50k triangles. Prints figures and ratios.

    python3 bench/bench_playback.py [--segments 180] [--rings 140] [--loops 2]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for p in (str(ROOT / "python"), str(ROOT / "addon"), str(ROOT / "blender_scenes")):
    if p not in sys.path:
        sys.path.insert(0, p)

import bpy  # noqa: E402

from build_demo_scene import build_demo_scene  # noqa: E402


def playback_fps(scene, frames, loops, probe=None) -> float:
    scene.frame_set(frames[0])  # warm up (loads caches)
    start = time.perf_counter()
    n = 0
    for _ in range(loops):
        for f in frames:
            scene.frame_set(f)
            if probe is not None:
                probe()
            n += 1
    return n / (time.perf_counter() - start)


def only_visible(obj, objects):
    for o in objects:
        o.hide_viewport = o != obj


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--segments", type=int, default=180)
    parser.add_argument("--rings", type=int, default=140)
    parser.add_argument("--loops", type=int, default=2)
    args = parser.parse_args()
    import animanifold_blender

    bpy.ops.wm.read_factory_settings(use_empty=True)
    animanifold_blender.register()
    try:
        src = build_demo_scene(segments=args.segments, rings=args.rings)
        scene = bpy.context.scene
        frames = list(range(scene.frame_start, scene.frame_end + 1))
        src.data.calc_loop_triangles()
        tris = len(src.data.loop_triangles)

        def evaluated_faces(obj):
            return lambda: len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)

        fps_source = playback_fps(scene, frames, args.loops, evaluated_faces(src))

        t = time.perf_counter()
        assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
        convert_s = time.perf_counter() - t
        man = bpy.data.objects[src.name + "_manifold"]
        src.hide_set(False)
        only_visible(man, [src, man])
        fps_live = playback_fps(scene, frames, args.loops, evaluated_faces(man))

        t = time.perf_counter()
        assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
        bake_s = time.perf_counter() - t
        fps_baked = playback_fps(scene, frames, args.loops, evaluated_faces(man))

        # Where the time of a live frame goes: slicing vs writing the mesh.
        from animanifold_blender import live

        manifold = live.manifold_for(man)
        t = time.perf_counter()
        for f in frames:
            manifold.slice(f + 0.5)
        slice_ms = 1000 * (time.perf_counter() - t) / len(frames)

        result = {
            "blender": bpy.app.version_string,
            "source_faces": len(src.data.polygons),
            "source_triangles": tris,
            "manifold_tets": int(len(manifold.simplices)),
            "frames": len(frames) * args.loops,
            "fps": {"a_source_shape_keys": round(fps_source, 1), "b_live_manifold": round(fps_live, 1),
                    "c_baked_node_group": round(fps_baked, 1)},
            "ratios": {"live/source": float(f"{fps_live / fps_source:.3g}"),
                       "baked/source": float(f"{fps_baked / fps_source:.3g}"),
                       "live/baked": float(f"{fps_live / fps_baked:.3g}")},
            "live_ms_per_frame": round(1000 / fps_live, 1),
            "slice_ms_per_frame": round(slice_ms, 2),
            "convert_s": round(convert_s, 2),
            "bake_s": round(bake_s, 2),
        }
        print(json.dumps(result, indent=2))
    finally:
        animanifold_blender.unregister()  # bpy as a module hangs at exit with classes registered
    return 0


if __name__ == "__main__":
    sys.exit(main())
