#!/usr/bin/env bash
# What the sanitized C++ tests (cmake/sanitized_tests.cmake) add to a CI run on a fresh
# clone: builds a fresh tree without ccache as CI does (the normal targets first, then the
# sanitized ones, which reuse the CGAL objects), runs the sanitized ctest cases serially as
# scripts/test.sh runs ctest, and prints each step's wall time and CPU time (user + system of
# the compilers and tests). On a shared machine the wall times are only as good as the load
# allows (the load average is printed beside them); the CPU times hardly depend on it, and
# CPU / 2 bounds a parallel build's wall time on two idle cores from below.
#
#   bash bench/bench_ci_sanitized_tests.sh     # in build-ci-measure/, removed first
#   NORMAL_FROM_CCACHE=1 bash bench/...        # the normal part from ccache (a loaded machine:
#                                              # only the sanitized part is then measured fresh)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build-ci-measure}"
[ -n "${NORMAL_FROM_CCACHE:-}" ] || export CCACHE_DISABLE=1
rm -rf "$build" "$build".*.log
printf '%-46s %9s %9s   %s\n' step "wall (s)" "CPU (s)" "load average before / after"

step() {  # step NAME LOG COMMAND...: runs the command, prints its wall and CPU time
  local name=$1 log=$2 before
  shift 2
  before=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f '%e %U %S' -o "$build.time" "$@" > "$log" 2>&1 || echo "  ($name failed: see $log)"
  read -r wall user sys < <(tail -1 "$build.time")
  printf '%-46s %9.1f %9.1f   %s / %s\n' "$name" "$wall" "$(echo "$user + $sys" | bc)" "$before" \
    "$(cut -d' ' -f1 /proc/loadavg)"
}

step configure "$build.configure.log" cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DANIMANIFOLD_MODULE_DIR="$PWD/$build/python/animanifold" \
  -DANIMANIFOLD_SANITIZED_TESTS="${SANITIZED_TESTS:-address,undefined}" -DANIMANIFOLD_SANITIZED_MODULE=ON
# What scripts/build.sh builds: the module, the tests and the C++ benchmarks.
benches=$(find bench -maxdepth 1 -name 'bench_*.cpp' ! -name 'bench_vdb_morph.cpp' -printf '%f\n' | sed 's/\.cpp$//')
# shellcheck disable=SC2086
step "normal build (what build.sh builds)" "$build.normal.log" \
  cmake --build "$build" -j2 --target _core animanifold_tests $benches
export CCACHE_DISABLE=1
step "sanitized core (our own units only)" "$build.core.log" cmake --build "$build" -j2 --target animanifold_core_sanitized
step "sanitized tests (compile, link, discovery)" "$build.tests.log" cmake --build "$build" -j2 --target animanifold_tests_sanitized
step "sanitized ctest, serial" "$build.ctest.log" ctest --test-dir "$build" -R '^sanitized\.' --output-on-failure
grep -E "tests passed|tests failed" "$build.ctest.log" || true
step "sanitized module (the bindings)" "$build.module.log" cmake --build "$build" -j2 --target _core_sanitized
step "sanitized Python subset" "$build.pytest.log" \
  bash scripts/sanitized-pytest.sh "$build/sanitized/python" "$build/sanitized/logs" "${SANITIZED_TESTS:-address,undefined}"
tail -2 "$build.pytest.log" || true
