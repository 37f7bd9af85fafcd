#!/usr/bin/env bash
# Fails when the committed python/animanifold/_core.pyi is not what the built
# module generates (bindings changed without regenerating the stub). It
# compares with git's copy (the index: committed, or staged for the next
# commit), not the working file, because scripts/build.sh rewrites that one.
set -euo pipefail
cd "$(dirname "$0")/.."
stub=python/animanifold/_core.pyi
generated=$(mktemp)
committed=$(mktemp)
trap 'rm -f "$generated" "$committed"' EXIT
bash scripts/generate-stubs.sh > "$generated"
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  git show ":$stub" > "$committed"
else
  cp "$stub" "$committed"
fi
if ! diff -u --label "committed $stub" --label "generated from the build" "$committed" "$generated"; then
  echo "check-stubs: $stub is out of date with cpp/bindings." >&2
  echo "check-stubs: run 'bash scripts/build.sh' (it regenerates the stub), then commit $stub." >&2
  exit 1
fi
echo "check-stubs: $stub is up to date"
