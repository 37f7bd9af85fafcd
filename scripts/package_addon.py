#!/usr/bin/env python3
"""Packs the Blender add-on into dist/animanifold_blender.zip.

The zip holds one folder, animanifold_blender/, with the add-on (bl_info for
Blender 3.4, blender_manifest.toml for 4.2+ extensions) and the animanifold
package with its compiled _core module inside it (animanifold_blender/animanifold/),
so it installs with Preferences › Add-ons › Install (or
bpy.ops.preferences.addon_install) without anything else on sys.path.

    python3 scripts/package_addon.py [--output dist/animanifold_blender.zip]

Run scripts/build.sh first: the compiled module is taken from python/animanifold/.
"""

from __future__ import annotations

import argparse
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ADDON = ROOT / "addon" / "animanifold_blender"
PACKAGE = ROOT / "python" / "animanifold"
SKIP_DIRS = {"__pycache__"}
SKIP_SUFFIXES = {".pyc", ".pyo"}


def _files(folder: Path):
    for path in sorted(folder.rglob("*")):
        if path.is_file() and not (set(path.relative_to(folder).parts) & SKIP_DIRS) and path.suffix not in SKIP_SUFFIXES:
            yield path


def package(output: Path) -> Path:
    cores = sorted(PACKAGE.glob("_core*.so")) + sorted(PACKAGE.glob("_core*.pyd"))
    if not cores:
        raise SystemExit(f"package_addon: no compiled module in {PACKAGE}: run scripts/build.sh first")
    for required in ("__init__.py", "blender_manifest.toml"):
        if not (ADDON / required).is_file():
            raise SystemExit(f"package_addon: {ADDON / required} is missing")
    if (ADDON / "animanifold").exists():
        raise SystemExit(f"package_addon: {ADDON / 'animanifold'} should not exist in the source tree")
    output.parent.mkdir(parents=True, exist_ok=True)
    tmp = output.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for path in _files(ADDON):
            zf.write(path, "animanifold_blender/" + path.relative_to(ADDON).as_posix())
        for path in _files(PACKAGE):
            if path.suffix in (".so", ".pyd") and path not in cores:
                continue
            zf.write(path, "animanifold_blender/animanifold/" + path.relative_to(PACKAGE).as_posix())
    tmp.replace(output)
    return output


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=ROOT / "dist" / "animanifold_blender.zip")
    args = parser.parse_args(argv)
    out = package(args.output)
    with zipfile.ZipFile(out) as zf:
        names = zf.namelist()
    print(f"package_addon: {out} ({len(names)} files, {out.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
