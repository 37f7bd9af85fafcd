"""Bakes one chunk of frames with the add-on's farm module (animanifold_blender.farm), from
this repository's add-on when Blender has none enabled. A thin wrapper kept for shell loops
over a source checkout; a render farm calls the shipped module itself (farm/openjd/).

    blender -b scene.blend --python-exit-code 1 --python blender_scenes/farm_bake_chunk.py -- \\
        bake-chunk --start 1 --end 50 --outputs obj --directory //frames/
    python3 blender_scenes/farm_bake_chunk.py scene.blend bake-chunk --start 51 --end 100 --outputs ply

Arguments are farm.main's (bake-chunk or assemble); under python3 + bpy the .blend comes first.
"""

from __future__ import annotations

import sys
from pathlib import Path

import bpy

ROOT = Path(__file__).resolve().parent.parent


def main() -> int:
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    if argv and argv[0].endswith(".blend"):
        bpy.ops.wm.open_mainfile(filepath=argv.pop(0))
    try:
        from animanifold_blender import farm
    except ImportError:  # no add-on enabled: this repository's
        sys.path[:0] = [str(ROOT / "python"), str(ROOT / "addon")]
        from animanifold_blender import farm
    farm.main(argv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
