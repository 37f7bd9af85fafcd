#!/usr/bin/env bash
# Runs every test: the complexity check, C++ (ctest) and Python (pytest, including the Blender tests).
# The C++ tests and a fast subset of the Python tests also run once more with AddressSanitizer
# and UndefinedBehaviorSanitizer on our own units (cmake/sanitized_tests.cmake: ctest's
# "sanitized." cases, and scripts/sanitized-pytest.sh with the sanitized module). On a fresh
# clone that adds the sanitized build and both runs (bench/bench_ci_sanitized_tests.sh).
# SANITIZED_TESTS= leaves them out.
set -euo pipefail
cd "$(dirname "$0")/.."
export SANITIZED_TESTS="${SANITIZED_TESTS-address,undefined}"
bash scripts/build.sh
bash scripts/check-complexity.sh  # after the build, which installs lizard
bash scripts/check-stubs.sh
ctest --test-dir build --output-on-failure
# Two worker processes (pytest-xdist): much of a test's time is single-threaded (Python, TetGen's
# child, CGAL's fill), which one process would leave the second core idle through. pytest-benchmark,
# where installed, would warn that xdist disables it (an error under filterwarnings); no test uses it.
# Tests marked with one xdist_group share what they make (a cached morph) and run in one worker.
python3 -m pytest -n 2 --dist loadgroup -p no:benchmark "$@"
if [ -n "$SANITIZED_TESTS" ]; then  # a fast subset again, with the sanitized module
  bash scripts/sanitized-pytest.sh build/sanitized/python build/sanitized/logs "$SANITIZED_TESTS"
fi
bash scripts/fuzz.sh  # 30 s per fuzz target (FUZZ_SECONDS, fixed seed): cache, mesh and arrays
