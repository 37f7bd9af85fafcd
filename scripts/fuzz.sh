#!/usr/bin/env bash
# Runs the fuzz targets in tests/fuzz/ for a fixed budget (CI: FUZZ_SECONDS=30 each), on a copy
# of its seed corpus so the repository is not changed. A finding (an input that raises anything
# but the target's own error, runs out of memory or times out) fails the run; the input is left
# in $FUZZ_OUT for copying into tests/fuzz/regressions/<target>/. See tests/fuzz/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH="${FUZZ_SECONDS:-30}"
# A fixed seed makes CI explore the same inputs every run, so a red CI means a change broke
# something, not that this run was luckier; FUZZ_SEED=0 lets libFuzzer pick one (exploration).
SEED="${FUZZ_SEED:-1}"
OUT="${FUZZ_OUT:-$(mktemp -d)}"
# Default: the cache reader, the mesh reader and the array entry points (one round-robin
# target), 90 s in all; FUZZ_TARGETS="cache" runs one.
for target in ${FUZZ_TARGETS:-cache mesh arrays}; do
  corpus="$OUT/corpus-$target"
  mkdir -p "$corpus"
  cp tests/fuzz/corpus/"$target"/* "$corpus"/
  echo "fuzz: $target for ${SECONDS_EACH} s (findings go to $OUT)"
  log="$OUT/$target.log"
  # A morph (arrays) of two fuzzed tetrahedra can spend most of a minute meshing and mending
  # before it refuses them (a MeshingError: bounded, not a hang); the readers get 10 s.
  timeout=10
  [ "$target" = arrays ] && timeout=120
  if ! (cd "$OUT" && python3 "$OLDPWD/tests/fuzz/fuzz_$target.py" "$corpus" -max_total_time="$SECONDS_EACH" \
        -rss_limit_mb=1024 -timeout="$timeout" -keep_seed=1 -print_final_stats=1 -seed="$SEED") > "$log" 2>&1; then
    tail -40 "$log"; echo "fuzz: $target found a failing input (see $OUT)" >&2; exit 1
  fi
  grep -E "^Done" "$log"
done
[ -n "${FUZZ_OUT:-}" ] || rm -rf "$OUT"  # nothing found: nothing to keep
