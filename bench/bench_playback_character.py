"""Playback of a skinned character, every way the add-on can show it, in one run: the source
(an Armature modifier evaluating a walk cycle), the live manifold (cold: the first loop, which
slices; warm: later loops), the node-group bake, the Alembic bake through a Mesh Sequence Cache,
and an OBJ sequence (Blender has no OBJ sequence player, so its figure is the rate
`wm.obj_import` loads the frames at). For each: frames/s, bytes per frame, and the largest
two-sided distance (vertex to surface, both ways) of an in-between frame from the source's
evaluated mesh, as % of the source's bounding-box diagonal, and the largest ratio of a frame's
triangles to the source's; for the live manifold also over the frames and half frames that are
not samples (Within Tolerance may sample every integer frame).

The character (blender_scenes/build_character.py) is a Skin-modifier figure subdivided to
~70k triangles at the default level, bound by bone envelopes, walking over frames 1-48;
Convert uses the add-on's default sampling (Within Tolerance).

    python3 bench/bench_playback_character.py [--levels 4] [--loops 3] [--sampling KEYFRAMES] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for p in (str(ROOT / "python"), str(ROOT / "addon"), str(ROOT / "blender_scenes"), str(ROOT / "bench")):
    if p not in sys.path:
        sys.path.insert(0, p)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from bench_playback import only_visible, playback_fps, warm  # noqa: E402
from build_character import build_character  # noqa: E402


def evaluated_surface(obj):
    """The object's evaluated mesh now, in world space: (vertices, triangles)."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        co = np.empty(3 * len(mesh.vertices))
        mesh.vertices.foreach_get("co", co)
        tris = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
        matrix = np.array(evaluated.matrix_world)
        v = co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
        return v, tris.reshape(-1, 3)
    finally:
        evaluated.to_mesh_clear()


def compare_frames(scene, obj, frames, source_surfaces, diagonal) -> tuple[float, float]:
    """The largest two-sided distance of `obj`'s frames from the source's (% of the diagonal),
    and the largest ratio of a frame's triangles to the source's."""
    from animanifold_blender.adaptive_sampling import two_sided_distance

    worst, ratio = 0.0, 0.0
    for f in frames:
        set_frame(scene, f)
        v, t = evaluated_surface(obj)
        worst = max(worst, two_sided_distance(v, t, *source_surfaces[f]))
        ratio = max(ratio, len(t) / len(source_surfaces[f][1]))
    return round(100.0 * worst / diagonal, 4), round(ratio, 3)


def set_frame(scene, frame: float) -> None:
    scene.frame_set(int(frame), subframe=float(frame - int(frame)))


def obj_sequence_load_fps(files) -> float:
    """Frames/s of loading an OBJ sequence with Blender's importer (each frame imported, then removed)."""
    start = time.perf_counter()
    for path in files:
        bpy.ops.wm.obj_import(filepath=path)
        for o in list(bpy.context.selected_objects):
            bpy.data.objects.remove(o)
    return len(files) / (time.perf_counter() - start)


def measure(args, folder: Path) -> dict:
    scene = bpy.context.scene
    src = build_character(args.levels)
    frames = list(range(scene.frame_start, scene.frame_end + 1))
    halves = [f + 0.5 for f in frames[:-1]]  # subframes: in-between frames where samples are every frame
    source_surfaces = {}
    for f in frames + halves:
        set_frame(scene, f)
        source_surfaces[f] = evaluated_surface(src)
    allv = np.concatenate([v for v, _ in source_surfaces.values()])
    diagonal = float(np.linalg.norm(allv.max(0) - allv.min(0)))
    result = {"blender": bpy.app.version_string, "source_triangles": len(source_surfaces[frames[0]][1]),
              "frames": len(frames), "loops": args.loops, "fps": {}, "bytes_per_frame": {},
              "deviation_percent": {}, "largest_triangle_ratio": {}}

    def probe_faces(obj):
        return lambda: len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)

    result["fps"]["source"] = round(warm(playback_fps(scene, frames, args.loops, probe_faces(src))), 1)

    bpy.ops.wm.save_as_mainfile(filepath=str(folder / "character.blend"))
    t = time.perf_counter()
    assert bpy.ops.animanifold.convert_action(sampling=args.sampling) == {"FINISHED"}
    result["convert_s"] = round(time.perf_counter() - t, 2)
    man = bpy.data.objects[src.name + "_manifold"]
    from animanifold_blender import object_manifold

    manifold = object_manifold.manifold_for(man)
    result["samples"] = len(manifold.metadata["keyframe_times"])
    result["manifold_tets"] = int(len(manifold.simplices))
    only_visible(man, [o for o in scene.objects if o.type == "MESH"])
    live = playback_fps(scene, frames, args.loops, probe_faces(man))
    result["fps"]["live_cold"] = round(live[0], 1)
    result["fps"]["live_warm"] = round(warm(live), 1)
    result["bytes_per_frame"]["live (.amf cache)"] = os.path.getsize(bpy.path.abspath(man.animanifold.cache_path)) // len(frames)
    result["deviation_percent"]["live"], result["largest_triangle_ratio"]["live"] = compare_frames(
        scene, man, frames, source_surfaces, diagonal)
    # Frames and half frames that are not samples: in-between frames for certain (the bakes hold
    # integer frames only, so they are measured at those).
    between = [f for f in frames + halves if f not in set(manifold.metadata["keyframe_times"])]
    result["in_between_frames_measured"] = len(between)
    result["deviation_percent"]["live, in-between frames"], result["largest_triangle_ratio"][
        "live, in-between frames"] = compare_frames(scene, man, between, source_surfaces, diagonal)

    before = os.path.getsize(folder / "character.blend")
    assert bpy.ops.animanifold.bake(alembic=False) == {"FINISHED"}
    result["fps"]["node_group_bake"] = round(warm(playback_fps(scene, frames, args.loops, probe_faces(man))), 1)
    bpy.ops.wm.save_mainfile()
    result["bytes_per_frame"]["node_group_bake (.blend growth)"] = (os.path.getsize(folder / "character.blend") - before) // len(frames)
    result["deviation_percent"]["node_group_bake"], result["largest_triangle_ratio"]["node_group_bake"] = compare_frames(
        scene, man, frames, source_surfaces, diagonal)

    if bpy.app.alembic.supported:
        assert bpy.ops.animanifold.bake(alembic=True, use_mesh_cache=True) == {"FINISHED"}
        result["fps"]["alembic_mesh_cache"] = round(warm(playback_fps(scene, frames, args.loops, probe_faces(man))), 1)
        abc = [p for p in folder.rglob("*.abc")]
        result["bytes_per_frame"]["alembic"] = sum(p.stat().st_size for p in abc) // len(frames)
        result["deviation_percent"]["alembic_mesh_cache"], result["largest_triangle_ratio"]["alembic_mesh_cache"] = \
            compare_frames(scene, man, frames, source_surfaces, diagonal)

    from animanifold_blender import bake

    obj_dir = folder / "obj"
    objs = [f for f in bake.export_sequence(man, frames, str(obj_dir), "OBJ") if f.endswith(".obj")]
    result["bytes_per_frame"]["obj_sequence (.obj)"] = sum(os.path.getsize(f) for f in objs) // len(objs)
    result["fps"]["obj_sequence_load (wm.obj_import)"] = round(obj_sequence_load_fps(objs[:args.obj_frames]), 1)
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, default=4, help="subdivision level of the character (4: ~70k triangles)")
    parser.add_argument("--loops", type=int, default=3)
    parser.add_argument("--obj-frames", type=int, default=12, help="OBJ frames to load for the load rate")
    parser.add_argument("--sampling", default="ADAPTIVE", choices=["ADAPTIVE", "KEYFRAMES"],
                        help="Convert's sampling (ADAPTIVE: Within Tolerance, the default; KEYFRAMES: the walk's keys)")
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args()
    import animanifold_blender

    bpy.ops.wm.read_factory_settings(use_empty=True)
    animanifold_blender.register()
    try:
        with tempfile.TemporaryDirectory() as folder:
            result = measure(args, Path(folder))
    finally:
        animanifold_blender.unregister()  # bpy as a module hangs at exit with classes registered
    print(json.dumps(result, indent=2))
    if args.json is not None:
        args.json.write_text(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
