#!/usr/bin/env bash
# The main job on the built-in demo: a procedural keyframe animation is
# stitched into an animation manifold, sliced into frames and written to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
PYTHONPATH=python python3 -m animanifold demo --output out "$@"
