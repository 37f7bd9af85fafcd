#!/usr/bin/env bash
# The main job: builds the demo scene in Blender (bpy 4.5 as a Python module),
# converts its shape-key action into an animation manifold, bakes it (node group,
# Alembic), saves out/animanifold_demo.blend and renders out/contact_sheet.png
# with Cycles on the CPU. Extra arguments go to blender_scenes/run_main_job.py
# (e.g. --frames 1,12,24 --samples 16 --out somewhere).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
python3 scripts/package_addon.py
python3 blender_scenes/run_main_job.py --out out "$@"
