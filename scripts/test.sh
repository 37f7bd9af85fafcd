#!/usr/bin/env bash
# Runs every test: the complexity check, C++ (ctest) and Python (pytest, including the Blender tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
bash scripts/check-complexity.sh  # after the build, which installs lizard
bash scripts/check-stubs.sh
ctest --test-dir build --output-on-failure
python3 -m pytest "$@"
bash scripts/fuzz.sh  # 30 s per fuzz target (FUZZ_SECONDS, fixed seed): cache, mesh and arrays
