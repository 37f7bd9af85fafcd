"""Timeline playback speed (frames/s of a scene.frame_set loop, depsgraph evaluated,
the evaluated mesh read after every frame) for (a) the original shape-key object,
(b) the live manifold object and (c) the baked object (node group over the frames
collection), on the demo blob at ~50k triangles. Prints figures and ratios.

(b) is the add-on's live playback: inside a topology interval, on every integer
frame the frame-change handler copies the frame (positions and UV map, kept per
frame by animanifold.cut_cache) into the mesh with two foreach_set and the "Animanifold Live"
geometry-nodes modifier passes it through (on other frames the modifier moves the
vertices and rebuilds the UV map); it writes a cut when playback enters an
interval or a keyframe (9 of the 48 frames of the demo). The first loop also
slices, lets Blender compute edges and computes the frames (cold); later loops
reuse the kept cuts and frames (warm): (b) is the warm figure, and the medians of
frames inside an interval and of frames that write a cut are printed too, with
the counts per loop. For comparison, in the same run:
"b_live_modifier_moves_every_frame", the previous path (the modifier moves the
vertices and rebuilds the UV map on every frame but the cut's own), and unless
--no-handler-path "b_live_handler_writes", the path before that (the handler
rewrites positions and UVs on every frame, computing them).

The machine's load matters: the modifier's work is multi-threaded, so figures
from a busy machine are lower and noisier than from an idle one.

    python3 bench/bench_playback.py [--segments 180] [--rings 140] [--loops 3] [--json PATH]
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for p in (str(ROOT / "python"), str(ROOT / "addon"), str(ROOT / "blender_scenes")):
    if p not in sys.path:
        sys.path.insert(0, p)

import bpy  # noqa: E402

from build_demo_scene import build_demo_scene  # noqa: E402
from figures import bench_parser, write_json  # noqa: E402


def playback_fps(scene, frames, loops, probe=None, per_frame=None, started=None) -> list[float]:
    """Frames per second of each loop over `frames`, after going to the first frame
    (then `started()` is called); `per_frame` (a list) gets the seconds of every frame."""
    scene.frame_set(frames[0])  # warm up (loads the manifold)
    if started is not None:
        started()
    fps = []
    for _ in range(loops):
        start = time.perf_counter()
        for f in frames:
            t = time.perf_counter()
            scene.frame_set(f)
            if probe is not None:
                probe()
            if per_frame is not None:
                per_frame.append(time.perf_counter() - t)
        fps.append(len(frames) / (time.perf_counter() - start))
    return fps


def warm(fps: list[float]) -> float:
    """Frames per second over the loops after the first (all of them when there is one)."""
    later = fps[1:] or fps
    return len(later) / sum(1.0 / f for f in later)


def count_calls(module, name: str) -> dict:
    """Counts the calls of module.name (replaced by a counting wrapper)."""
    counter = {"n": 0}
    fn = getattr(module, name)

    def counted(*args, **kwargs):
        counter["n"] += 1
        return fn(*args, **kwargs)

    setattr(module, name, counted)
    return counter


def only_visible(obj, objects):
    for o in objects:
        o.hide_viewport = o != obj


def main() -> int:
    parser = bench_parser(__doc__, segments=180, rings=140, loops=3)
    parser.add_argument("--no-handler-path", action="store_true", help="skip the handler-writes-every-frame path")
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

        def evaluated_faces(obj):  # the evaluated mesh: what is shown and rendered
            return lambda: len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)

        fps_source = warm(playback_fps(scene, frames, args.loops, evaluated_faces(src)))

        t = time.perf_counter()
        assert bpy.ops.animanifold.convert_action() == {"FINISHED"}
        convert_s = time.perf_counter() - t
        man = bpy.data.objects[src.name + "_manifold"]
        src.hide_set(False)
        only_visible(man, [src, man])
        from animanifold import interval_cuts
        from animanifold_blender import mesh_writer, object_manifold, playback
        from animanifold_blender.live_registry import registry

        writes = count_calls(mesh_writer, "write_mesh")
        copies = count_calls(mesh_writer, "write_frame")
        computed = {"n": 0}
        interval_frame = interval_cuts.interval_frame

        def counted_frame(cut, value):  # computed, not the cut's own
            computed["n"] += value != cut.value
            return interval_frame(cut, value)

        interval_cuts.interval_frame = counted_frame
        keyframes = set(object_manifold.manifold_for(man).metadata["keyframe_times"])
        # Frames that write a cut: the keyframes and the first frame of each interval.
        writing = {f for f in frames if f in keyframes or (f - 1) in keyframes}
        live_loops = playback_fps(scene, frames, 1, evaluated_faces(man))  # cold: slices, edges, frames
        cold = {"cut_writes": writes["n"], "frames_computed": computed["n"], "frames_copied": copies["n"]}

        def reset():
            for counter in (writes, copies, computed):
                counter["n"] = 0

        seconds = []
        warm_loops = max(args.loops - 1, 1)
        live_loops += playback_fps(scene, frames, warm_loops, evaluated_faces(man), seconds, started=reset)
        fps_live = warm(live_loops)
        warm_counts = {"cut_writes": writes["n"] / warm_loops, "frames_computed": computed["n"] / warm_loops,
                       "frames_copied": copies["n"] / warm_loops}
        per_frame = dict(zip(frames * warm_loops, seconds))  # the last loop's
        inside_ms = 1000 * statistics.median(per_frame[f] for f in frames if f not in writing)
        writing_ms = 1000 * statistics.median(per_frame[f] for f in writing)
        assert man.modifiers.get("Animanifold Live") is not None, "the live modifier did not play the object"
        assert warm_counts["frames_computed"] == 0, "warm loops computed frames"

        # The previous path: the modifier moves the mesh on every frame but the cut's own.
        frame = playback._frame
        playback._frame = lambda manifold, key, cut, value: interval_frame(cut, value) if value == cut.value else None
        try:
            registry.forget_shown()
            fps_modifier = warm(playback_fps(scene, frames, args.loops, evaluated_faces(man)))
        finally:
            playback._frame = frame
            registry.forget_shown()
            scene.frame_set(frames[0])

        fps_handler = None
        if not args.no_handler_path:  # the path before the modifier: the handler writes every frame
            can_drive = playback.can_drive
            playback.can_drive = lambda *a, **k: False
            try:
                fps_handler = warm(playback_fps(scene, frames, args.loops, evaluated_faces(man)))
            finally:
                playback.can_drive = can_drive
                registry.forget_shown()
                scene.frame_set(frames[0])

        t = time.perf_counter()
        assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
        bake_s = time.perf_counter() - t
        fps_baked = warm(playback_fps(scene, frames, args.loops, evaluated_faces(man)))

        manifold = object_manifold.manifold_for(man)
        t = time.perf_counter()
        for f in frames:
            manifold.slice(f + 0.5)
        slice_ms = 1000 * (time.perf_counter() - t) / len(frames)

        result = {
            "blender": bpy.app.version_string,
            "source_faces": len(src.data.polygons),
            "source_triangles": tris,
            "manifold_tets": int(len(manifold.simplices)),
            "frames_per_loop": len(frames),
            "loops": args.loops,
            "fps": {"a_source_shape_keys": round(fps_source, 1), "b_live_manifold": round(fps_live, 1),
                    "c_baked_node_group": round(fps_baked, 1),
                    "b_live_modifier_moves_every_frame": round(fps_modifier, 1)},
            "ratios": {"live/source": float(f"{fps_live / fps_source:.3g}"),
                       "baked/source": float(f"{fps_baked / fps_source:.3g}"),
                       "live/baked": float(f"{fps_live / fps_baked:.3g}"),
                       "live/modifier_moves_every_frame": float(f"{fps_live / fps_modifier:.3g}")},
            "live_fps_per_loop": [round(f, 1) for f in live_loops],
            "live_ms_per_frame": round(1000 / fps_live, 2),
            "live_cold_loop": cold,
            "live_per_warm_loop": warm_counts,
            "live_ms_frame_inside_interval_median": round(inside_ms, 2),
            "live_ms_frame_writing_a_cut_median": round(writing_ms, 2),
            "slice_ms_per_frame": round(slice_ms, 2),
            "convert_s": round(convert_s, 2),
            "bake_s": round(bake_s, 2),
        }
        if fps_handler is not None:
            result["fps"]["b_live_handler_writes"] = round(fps_handler, 1)
            result["ratios"]["live/handler_writes"] = float(f"{fps_live / fps_handler:.3g}")
        print(json.dumps(result, indent=2))
        write_json(args.json, result)
    finally:
        animanifold_blender.unregister()  # bpy as a module hangs at exit with classes registered
    return 0


if __name__ == "__main__":
    sys.exit(main())
