#!/usr/bin/env bash
# Runs a fast subset of the Python tests with a sanitized _core (libasan or libtsan preloaded
# into python3) and fails on any test failure or sanitizer report. Used by scripts/test.sh
# (CI: the module of cmake/sanitized_tests.cmake) and scripts/sanitize.sh (a whole sanitized tree).
#
#   bash scripts/sanitized-pytest.sh PYTHON_DIR LOG_DIR [address,undefined|thread]
#
# PYTHON_DIR holds the sanitized animanifold/_core*.so; the package's Python sources are copied
# beside it so that imports find that module. SANITIZE_TESTS names another subset.
set -euo pipefail
cd "$(dirname "$0")/.."
python_dir=$(realpath "$1")
logs=$(realpath -m "$2")
sanitize="${3:-address,undefined}"
mkdir -p "$logs"
find "$python_dir/animanifold" -maxdepth 1 -name '*.py' -delete
cp python/animanifold/*.py python/animanifold/*.pyi "$python_dir/animanifold/"

# Reports go to files (log_path), one per process, so that findings in python3 and in the CLI
# subprocesses the tests start are all counted; UBSan goes on after a report (the whole-tree
# build recovers), so one run lists every kind of finding. Leak checks stay off: CPython keeps
# its arenas for ever.
rm -f "$logs"/asan.* "$logs"/ubsan.* "$logs"/tsan.*
export ASAN_OPTIONS="log_path=$logs/asan:detect_leaks=0:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="log_path=$logs/ubsan:print_stacktrace=1"
export TSAN_OPTIONS="log_path=$logs/tsan:second_deadlock_stack=1"

if [ "$sanitize" = thread ]; then runtime=$(gcc -print-file-name=libtsan.so); else runtime=$(gcc -print-file-name=libasan.so); fi
# libstdc++ preloaded too: python3 does not link it, so the sanitizer would find no
# __cxa_throw to intercept when it starts, and abort at the first C++ exception.
runtime="$runtime $(gcc -print-file-name=libstdc++.so.6)"
# Our code behind the Python API, on hostile and ordinary inputs, in well under a minute:
# the fuzzers' corpora and regressions, the input and index checks, the error model, stitch,
# slice and prism frames, refine, subdivision, the cache, the memory limit and one Deformer
# shared by four threads.
tests=${SANITIZE_TESTS:-"tests/test_input_validation.py tests/test_vertex_index_range.py tests/test_fuzz_corpus.py \
  tests/test_errors.py tests/test_stitch.py tests/test_slice.py tests/test_slice_sequences.py tests/test_prism_frames.py \
  tests/test_refine.py tests/test_subdivide.py tests/test_cache.py tests/test_cache_hostile.py tests/test_memory_limit.py \
  tests/test_threads.py::test_one_deformer_deformed_from_four_threads_gives_the_sequential_results"}
# Not the morphs in threads: a morph forks TetGen's child, and gcc 12's libasan does not hold
# its allocator's lock across fork(), so a child forked while another thread allocates can
# wait for that lock for ever (seen: the child idle until the 600 s limit). Release builds
# use glibc's malloc, which does.
# The interpreter itself, not a wrapper script (pyenv's shim): bash segfaults with libtsan preloaded.
python=$(python3 -c 'import sys; print(sys.executable)')
echo "sanitized pytest (log $logs/pytest.log): $tests"
status=0
# pytest puts its `pythonpath` (python/) first; -o points it at the sanitized tree instead.
# shellcheck disable=SC2086
LD_PRELOAD="$runtime" "$python" -m pytest -q -p no:cacheprovider -o pythonpath="$python_dir" \
  $tests > "$logs/pytest.log" 2>&1 || status=1
tail -3 "$logs/pytest.log"
LD_PRELOAD="$runtime" PYTHONPATH="$python_dir" "$python" -c \
  "import animanifold._core as c, sys; sys.exit(0 if c.__file__.startswith('$python_dir') else 1)" \
  || { echo "sanitized pytest: python3 did not load the sanitized module" >&2; status=1; }

bash scripts/sanitizer-findings.sh "$logs" "sanitized pytest" || status=1
[ "$status" = 0 ] && echo "sanitized pytest: no findings, every test passed"
exit "$status"
