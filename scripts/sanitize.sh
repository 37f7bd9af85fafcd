#!/usr/bin/env bash
# Builds the core, the Python module and the C++ tests with AddressSanitizer and
# UndefinedBehaviorSanitizer in build-asan/ (never build/), runs ctest there, then a Python
# smoke with the sanitized module (libasan preloaded into python3, leak checks off: CPython
# keeps its arenas for ever), and reports what the sanitizers found. Exit status 1 when they
# found anything. Not part of CI's 30 minutes: the first build takes ~15 min on two cores
# (ccache makes later ones incremental); see tests/fuzz/README.md for when to run it. CI runs
# the cheaper part of it, our own units' C++ tests (cmake/sanitized_tests.cmake).
#
#   bash scripts/sanitize.sh                  # build, ctest, Python smoke
#   SANITIZE=thread bash scripts/sanitize.sh  # ThreadSanitizer instead, in build-tsan/
#   SANITIZE_SCOPE=own bash scripts/sanitize.sh   # only our units instrumented, CGAL's not
#                                             # (a much shorter build; build-<asan|tsan>-own/)
#   SANITIZE_TESTS="tests/test_threads.py" bash scripts/sanitize.sh   # another Python subset
#   GTEST_FILTER='Stitch*' bash scripts/sanitize.sh                   # a ctest subset
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
SANITIZE="${SANITIZE:-address,undefined}"
SCOPE="${SANITIZE_SCOPE:-all}"
if [ "$SANITIZE" = thread ]; then build="$root/build-tsan"; else build="$root/build-asan"; fi
if [ "$SCOPE" = own ]; then
  build="$build-own"
  # The normal tree (Release, as build/, so ccache has it) plus sanitized copies of our own
  # units, tests and module (cmake/sanitized_tests.cmake sets their flags).
  scope_flags=(-DCMAKE_BUILD_TYPE=Release -DANIMANIFOLD_SANITIZED_TESTS="$SANITIZE" -DANIMANIFOLD_SANITIZED_MODULE=ON)
  python_dir="$build/sanitized/python"
  ctest_filter='^sanitized\.'
else
  # CMakePresets.json's asan or tsan preset: -O1 keeps the stacks readable and the build
  # short; NDEBUG as in release builds, so the sanitizers judge the code users run.
  if [ "$SANITIZE" = thread ]; then preset=tsan; else preset=asan; fi
  scope_flags=(--preset "$preset" -DANIMANIFOLD_SANITIZE="$SANITIZE")
  python_dir="$build/python"
  ctest_filter=''
fi
logs="$build/logs"
mkdir -p "$logs"

echo "sanitize: building $build (-fsanitize=$SANITIZE; log $logs/build.log)"
cmake -S . -B "$build" -G Ninja "${scope_flags[@]}" \
  -DANIMANIFOLD_BENCH=OFF -DANIMANIFOLD_MODULE_DIR="$build/python/animanifold" > "$logs/build.log" 2>&1 \
  || { tail -40 "$logs/build.log"; exit 1; }
cmake --build "$build" -j"${JOBS:-2}" >> "$logs/build.log" 2>&1 || { tail -60 "$logs/build.log"; exit 1; }

# Reports go to files (log_path), one per process, so that findings in the C++ tests, in
# python3 and in the CLI subprocesses the tests start are all counted. UBSan's checks go on
# after a report (it is compiled to recover), so one run lists every kind of finding.
rm -f "$logs"/asan.* "$logs"/ubsan.* "$logs"/tsan.*
export ASAN_OPTIONS="log_path=$logs/asan:detect_leaks=${DETECT_LEAKS:-0}:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="log_path=$logs/ubsan:print_stacktrace=1"
export TSAN_OPTIONS="log_path=$logs/tsan:second_deadlock_stack=1"

status=0
echo "sanitize: ctest (log $logs/ctest.log)"
ctest_args=(--test-dir "$build" --output-on-failure -j1 --timeout 900)
[ -n "${GTEST_FILTER:-$ctest_filter}" ] && ctest_args+=(-R "${GTEST_FILTER:-$ctest_filter}")
ctest "${ctest_args[@]}" > "$logs/ctest.log" 2>&1 || status=1
tail -3 "$logs/ctest.log"

# The Python side, with its own logs (the script clears them), counted apart from ctest's.
bash scripts/sanitized-pytest.sh "$python_dir" "$logs/python" "$SANITIZE" || status=1

bash scripts/sanitizer-findings.sh "$logs" sanitize || status=1
[ "$status" = 0 ] && echo "sanitize: no findings, every test passed"
exit "$status"
