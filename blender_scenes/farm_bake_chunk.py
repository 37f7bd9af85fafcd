"""Bakes one chunk of frames of a manifold object: what a render-farm job runs
(Flamenco or a shell loop), one process per chunk, all reading the same .blend
and its manifold cache and writing per-frame files (OBJ/PLY) and/or one Alembic
file per chunk into a shared folder. The .blend itself is not saved unless
--save-as is given (a chunk's node-group bake then lands in that copy).

    blender -b scene.blend --factory-startup --python-exit-code 1 \\
        --python blender_scenes/farm_bake_chunk.py -- --start 1 --end 50 --export OBJ --directory //frames/
    python3 blender_scenes/farm_bake_chunk.py scene.blend --start 51 --end 100 --export PLY

Uses the installed add-on when it is enabled, else the one in this repository.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import bpy

ROOT = Path(__file__).resolve().parent.parent


def _args():
    if "--" in sys.argv:
        argv = sys.argv[sys.argv.index("--") + 1:]
    else:
        argv = sys.argv[1:] if sys.argv and sys.argv[0].endswith(".py") else []
    parser = argparse.ArgumentParser(description="bake a chunk of a manifold object's frames")
    parser.add_argument("blend", nargs="?", help="the .blend (python3 + bpy only; under blender pass it before --python)")
    parser.add_argument("--start", type=int, required=True)
    parser.add_argument("--end", type=int, required=True)
    parser.add_argument("--object", help="manifold object (default: the only one)")
    parser.add_argument("--export", choices=("NONE", "OBJ", "PLY"), default="OBJ")
    parser.add_argument("--alembic", action="store_true", help="also write <object>_<start>-<end>.abc")
    parser.add_argument("--directory", default="//animanifold_bake/")
    parser.add_argument("--save-as", help="save the .blend with this chunk's node-group bake here")
    return parser.parse_args(argv)


def _addon():
    """(module, registered_here)."""
    for name in list(sys.modules):
        if name.endswith("animanifold_blender") and hasattr(bpy.types, "ANIMANIFOLD_OT_bake"):
            return sys.modules[name], False
    for p in (str(ROOT / "python"), str(ROOT / "addon")):
        if p not in sys.path:
            sys.path.insert(0, p)
    import animanifold_blender

    animanifold_blender.register()
    return animanifold_blender, True


def main() -> int:
    args = _args()
    if args.blend:
        bpy.ops.wm.open_mainfile(filepath=args.blend)
    addon, registered = _addon()
    try:
        manifolds = [o for o in bpy.context.scene.objects if o.animanifold.is_manifold]
        if args.object:
            manifolds = [o for o in manifolds if o.name == args.object]
        if len(manifolds) != 1:
            print(f"farm_bake_chunk: need exactly one manifold object, found {[o.name for o in manifolds]}")
            return 2
        obj = manifolds[0]
        for o in bpy.context.view_layer.objects:
            o.select_set(False)
        obj.select_set(True)
        bpy.context.view_layer.objects.active = obj
        result = bpy.ops.animanifold.bake(use_scene_range=False, frame_start=args.start, frame_end=args.end,
                                          alembic=args.alembic, export=args.export, directory=args.directory)
        if "FINISHED" not in result:
            return 1
        if args.save_as:
            bpy.ops.wm.save_as_mainfile(filepath=args.save_as, copy=True)
        print(f"farm_bake_chunk: '{obj.name}' frames {args.start}–{args.end} baked")
        return 0
    finally:
        if registered:
            addon.unregister()  # bpy as a module hangs at exit with classes registered


if __name__ == "__main__":
    sys.exit(main())
