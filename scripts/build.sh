#!/usr/bin/env bash
# Builds the core, the Python module (into python/animanifold/) and the C++
# tests in build/, incrementally, and regenerates the module's type stub
# python/animanifold/_core.pyi. Installs dependencies first when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# SANITIZED_TESTS=address,undefined adds the sanitized copy of our own units, C++ tests and
# Python module (cmake/sanitized_tests.cmake; scripts/test.sh sets it) and the ThreadSanitizer
# tests of the objects threads may share (cmake/thread_sanitized_tests.cmake); unset, the build
# has none of them.
sanitized_module=OFF
[ -n "${SANITIZED_TESTS:-}" ] && sanitized_module=ON
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DANIMANIFOLD_SANITIZED_TESTS="${SANITIZED_TESTS:-}" \
  -DANIMANIFOLD_SANITIZED_MODULE="$sanitized_module" -DANIMANIFOLD_THREAD_SANITIZED_TESTS="$sanitized_module" \
  > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j2 >> build.log 2>&1 || { tail -60 build.log; exit 1; }
rm -f build.log
# The committed stub follows the bindings (scripts/check-stubs.sh checks it).
stub=$(mktemp)
bash scripts/generate-stubs.sh > "$stub"
cmp -s "$stub" python/animanifold/_core.pyi || cp "$stub" python/animanifold/_core.pyi
rm -f "$stub"
