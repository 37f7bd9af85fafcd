"""The main job, headless: build the demo scene, convert its shape-key action into
an animation manifold, morph the scene's sphere into its torus (Morph Selected,
over the scene's frame range), bake both manifolds (node group; Alembic where
this Blender has it), save the .blend, and render a contact sheet of several
frames with Cycles on the CPU (the keyframe demo and the morph side by side in
each frame). Everything lands in out/ (or the folder given).

    python3 blender_scenes/run_main_job.py [--out out] [--frames 1,8,...]      # bpy 4.5
    blender -b --factory-startup --python-exit-code 1 --python blender_scenes/run_main_job.py -- [--out out]

The add-on is taken from the dev tree (addon/ and python/ beside this folder);
run scripts/build.sh first so the compiled module exists.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
for p in (str(ROOT / "python"), str(ROOT / "addon"), str(HERE)):
    if p not in sys.path:
        sys.path.insert(0, p)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from build_demo_scene import DEMO_NAME, MORPH_LOCATION, MORPH_SOURCE, MORPH_TARGET, build_demo_scene  # noqa: E402

CONTACT_FRAMES = (1, 7, 12, 18, 24, 30, 36, 48)  # the keyframes, and both ends of the morph
MORPH_SHEET_FRAMES = (1, 8, 15, 21, 28, 34, 41, 48)  # the morph's ends and 6 in-betweens, evenly


def _args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else (
        sys.argv[1:] if sys.argv and sys.argv[0].endswith(".py") else [])
    parser = argparse.ArgumentParser(description="animanifold main job (Blender)")
    parser.add_argument("--out", type=Path, default=ROOT / "out")
    parser.add_argument("--frames", default=",".join(map(str, CONTACT_FRAMES)), help="frames of the contact sheet")
    parser.add_argument("--resolution", default="320x240", help="per frame of the contact sheet")
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--sampling", choices=("ADAPTIVE", "KEYFRAMES", "EVERY_N"), default="ADAPTIVE",
                        help="Convert's sampling: within the default tolerance of the source (the add-on's default), "
                             "the action's keyframes, or every --step frames")
    parser.add_argument("--step", type=int, default=3)
    parser.add_argument("--segments", type=int, default=48, help="density of the demo sphere")
    parser.add_argument("--no-morph", dest="morph", action="store_false", help="leave out the sphere → torus morph")
    parser.add_argument("--morph-method", default=None,
                        help="Morph Selected's Method for the sphere → torus morph (skeleton, strip, field; "
                             "default: the add-on's default)")
    return parser.parse_args(argv)


def _run(op, **kwargs):
    result = op(**kwargs)
    if "FINISHED" not in result:
        raise SystemExit(f"main job: {op.idname_py()} returned {result}")


def _activate(*objects):
    """Selects `objects`, the last one active (Morph Selected's target, Bake's object)."""
    view_layer = bpy.context.view_layer
    for obj in view_layer.objects:
        obj.select_set(False)
    for obj in objects:
        obj.select_set(True)
    view_layer.objects.active = objects[-1]


def _frames_showing_noise(manifold) -> list[float]:
    """Of the whole frames next to the topological noise the morph's checks found, those that show
    it; the end frames stand for the inputs (their topology is the inputs')."""
    from animanifold_blender import morph_object

    if not manifold.validity["noise_frames"]:
        return []
    ends = [(frame.vertices, frame.faces) for frame in manifold.slices(list(manifold.time_range))]
    return morph_object.noise_on_whole_frames(manifold, *ends).noisy


def morph_demo(bake_kwargs, method: str | None = None) -> dict:
    """Morph Selected from the sphere to the torus over the scene range (with `method`, else the
    add-on's default), then Bake; the report."""
    import animanifold_blender
    from animanifold_blender import morph_object, ops_morph

    method = (method or ops_morph.BEST_METHOD).lower()
    source, target = bpy.data.objects[MORPH_SOURCE], bpy.data.objects[MORPH_TARGET]
    t = time.perf_counter()
    _activate(source, target)
    _run(bpy.ops.animanifold.morph_selected, method=method.upper())
    morph = bpy.context.active_object
    manifold = animanifold_blender.object_manifold.manifold_for(morph)
    validity = manifold.validity
    report = {"seconds": round(time.perf_counter() - t, 3), "object": morph.name, "method": method,
              "cache": morph.animanifold.cache_path, "tets": int(len(manifold.simplices)),
              "inputs": {o.name: {"vertices": len(o.data.vertices), "faces": len(o.data.polygons)} for o in (source, target)},
              "stage_seconds": dict(validity.get("stage_seconds", [])),
              "ends_reproduced": bool(validity["ends_reproduced"]),
              "end_distances": [validity["source_distance"], validity["target_distance"]],
              "inverted_simplices": int(validity["inverted_simplices"]),
              "oriented_manifold": bool(manifold.check().is_oriented_manifold),
              # what the frames are (morph_validity.hpp's checks): how often the topology changes
              # between the frames checked, and whether every check passed
              "frames_checked": int(validity["frames_checked"]),
              "topology_changes": int(validity["topology_changes"]),
              "all_checks_passed": morph_object.all_checks_passed(validity),
              # the whole frames next to the noise the checks found (between frames, too) that show it
              "frames_showing_noise": _frames_showing_noise(manifold)}
    t = time.perf_counter()
    _activate(morph)
    _run(bpy.ops.animanifold.bake, **bake_kwargs)
    report["bake_seconds"] = round(time.perf_counter() - t, 3)
    report["bake_collection"] = morph.animanifold.bake_collection.name
    return report


def render_contact_sheet(scene, frames, out: Path, resolution, samples, name: str = "contact_sheet") -> Path:
    """Renders each frame (Cycles, CPU) into out/<name>_frames/ and tiles them into out/<name>.png."""
    w, h = resolution
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    if hasattr(scene.cycles, "use_adaptive_sampling"):
        scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 2
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    frame_dir = out / ("frames" if name == "contact_sheet" else f"{name}_frames")
    frame_dir.mkdir(parents=True, exist_ok=True)
    tiles = []
    for f in frames:
        scene.frame_set(f)
        path = frame_dir / f"frame_{f:04d}.png"
        scene.render.filepath = str(path)
        bpy.ops.render.render(write_still=True)
        img = bpy.data.images.load(str(path))
        px = np.empty(w * h * 4, dtype=np.float32)
        img.pixels.foreach_get(px)
        tiles.append(px.reshape(h, w, 4))
        bpy.data.images.remove(img)
    cols = 4
    rows = (len(tiles) + cols - 1) // cols
    sheet = np.ones((rows * h, cols * w, 4), dtype=np.float32)
    for i, tile in enumerate(tiles):
        r, c = divmod(i, cols)
        # images are stored bottom-up: the first frame goes top-left
        y0 = (rows - 1 - r) * h
        sheet[y0:y0 + h, c * w:(c + 1) * w] = tile
    image = bpy.data.images.new(name, cols * w, rows * h, alpha=True)
    image.pixels.foreach_set(sheet.reshape(-1))
    target = out / f"{name}.png"
    image.filepath_raw = str(target)
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    return target


def render_morph_sheet(scene, out: Path, resolution, samples) -> Path:
    """The morph's in-betweens alone, close up (out/morph_sheet.png): MORPH_SHEET_FRAMES through a
    camera that the morph fills, the other objects left out of the render. The scene is left as it
    was (camera, what renders)."""
    morph = next(o for o in scene.objects if o.animanifold.is_manifold and o.name.startswith(MORPH_SOURCE))
    camera_data = bpy.data.cameras.new("MorphCloseUp")
    camera = bpy.data.objects.new("MorphCloseUp", camera_data)
    scene.collection.objects.link(camera)
    centre = np.array(MORPH_LOCATION)
    camera.location = tuple(centre + [0.0, -4.6, 0.5])
    camera.rotation_euler = (math.radians(84), 0.0, 0.0)
    others = [o for o in scene.objects if o.type == "MESH" and o is not morph and not o.hide_render]
    kept_camera = scene.camera
    try:
        scene.camera = camera
        for obj in others:
            obj.hide_render = True
        return render_contact_sheet(scene, MORPH_SHEET_FRAMES, out, resolution, samples, name="morph_sheet")
    finally:
        scene.camera = kept_camera
        for obj in others:
            obj.hide_render = False
        bpy.data.objects.remove(camera)
        bpy.data.cameras.remove(camera_data)


def main() -> int:
    args = _args()
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    frames = [int(f) for f in args.frames.split(",") if f]
    w, h = (int(v) for v in args.resolution.lower().split("x"))
    import animanifold_blender
    from animanifold_blender import ops_morph

    if args.morph_method and args.morph_method.lower() not in ops_morph.METHODS:
        raise SystemExit(f"run_main_job: unknown --morph-method {args.morph_method!r}; "
                         f"use one of {', '.join(ops_morph.METHODS)}")
    report = {"blender": bpy.app.version_string}
    began = time.perf_counter()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    animanifold_blender.register()
    try:
        t = time.perf_counter()
        src = build_demo_scene(segments=args.segments, rings=args.segments // 2, morph=args.morph)
        blend = out / "animanifold_demo.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(blend))
        report["source"] = {"name": src.name, "vertices": len(src.data.vertices), "faces": len(src.data.polygons)}

        t = time.perf_counter()
        _run(bpy.ops.animanifold.convert_action, sampling=args.sampling, step=args.step)
        man = bpy.data.objects[f"{DEMO_NAME}_manifold"]
        manifold = animanifold_blender.object_manifold.manifold_for(man)
        report["convert"] = {"seconds": round(time.perf_counter() - t, 3), "cache": man.animanifold.cache_path,
                             "tets": int(len(manifold.simplices)),
                             "keyframe_times": manifold.metadata["keyframe_times"], "sampling": args.sampling}
        if man.animanifold.max_deviation >= 0:  # measured by the Within Tolerance sampling
            diagonal = man.animanifold.source_size
            report["convert"]["deviation_percent"] = round(100 * man.animanifold.max_deviation / diagonal, 4)
            report["convert"]["deviation_frame"] = man.animanifold.deviation_frame

        t = time.perf_counter()
        scene = bpy.context.scene
        bake_kwargs = {"alembic": bool(bpy.app.alembic.supported), "use_mesh_cache": False}
        _run(bpy.ops.animanifold.bake, **bake_kwargs)
        report["bake"] = {"seconds": round(time.perf_counter() - t, 3), "frames": [scene.frame_start, scene.frame_end],
                          "collection": man.animanifold.bake_collection.name, "alembic": bake_kwargs["alembic"]}

        if args.morph:
            report["morph"] = morph_demo(bake_kwargs, args.morph_method)
        bpy.ops.wm.save_mainfile()
        report["blend"] = str(blend)

        t = time.perf_counter()
        sheet = render_contact_sheet(scene, frames, out, (w, h), args.samples)
        if args.morph:
            report["morph"]["sheet"] = {"frames": list(MORPH_SHEET_FRAMES),
                                        "path": str(render_morph_sheet(scene, out, (w, h), args.samples))}
        report["render"] = {"seconds": round(time.perf_counter() - t, 3), "frames": frames, "contact_sheet": str(sheet),
                            "engine": "CYCLES (CPU)", "samples": args.samples, "resolution": [w, h]}
        report["seconds"] = round(time.perf_counter() - began, 3)
        (out / "main_job.json").write_text(json.dumps(report, indent=2))
        print(json.dumps(report, indent=2))
    finally:
        # bpy as a module hangs at interpreter exit while Python classes or handlers
        # are registered: always unregister.
        animanifold_blender.unregister()
    return 0


if __name__ == "__main__":
    sys.exit(main())
